"""Smoke test of the `explicit-vs-static` case (slow: a wall of seed 001 takes minutes)."""

import pytest

from validation.__main__ import CASES


@pytest.mark.slow
def test_explicit_vs_static_quick_brackets_and_bounds():
    """The closed forms lie in the explicit brackets (within the detection margin), the static
    DEM's lambda of the small scenes equals the closed form, and no explicit stable multiplier
    exceeds the limit-analysis upper bound."""
    rows, notes = CASES["explicit-vs-static"](quick=True)
    assert "legitimately differ" in notes
    small = [r for r in rows if r.source.startswith("closed form")]
    assert len(small) == 3
    for row in small:
        assert row.extra["bracket_holds_reference"], row.quantity
        assert row.extra["static_fibre"] == pytest.approx(row.reference, rel=0.02), row.quantity
    for row in rows:
        assert row.extra["within_upper"] is not False, row.quantity
