"""Smoke tests of the `fem-patch` and `fem-strip` cases (quick versions)."""

from validation.__main__ import CASES
from validation.report import write_results


def test_fem_patch_case_quick(tmp_path):
    rows, notes = CASES["fem-patch"](quick=True)
    assert notes
    patch = [r for r in rows if r.quantity.startswith("patch test")]
    assert len(patch) == 4
    for row in patch:  # closed form: uniform stress, to round-off
        assert row.ours <= 1e-10, row.quantity
    rates = {r.quantity[12:14]: r.ours for r in rows if "observed rate" in r.quantity}
    # a priori: the cut error falls at least like h^p (P1: 1, P2: 2); 0.3 of slack for the
    # unstructured, non-nested meshes of three sizes
    assert rates["P1"] > 0.7 and rates["P2"] > 1.7
    for row in rows:  # a rate of at least p is a bound, met within the fit's bar
        if "observed rate" in row.quantity:
            assert row.reference_kind == "lower bound" and row.reference_inside, row.quantity
    write_results("fem-patch", rows, quick=True, wall_s=0.0, out_dir=tmp_path)


def test_fem_strip_prism_is_exact():
    """theta = 0: the strip is a prism, whose shortening is sigma L / E exactly."""
    from validation.cases.fem import YOUNG, strip_stiffness

    r = strip_stiffness(0.0, 2.0e-3)
    assert abs(r["E_eff"] / YOUNG - 1.0) < 1e-10
    assert r["M"] == 6 and abs(r["length"] - 0.05) < 1e-15


def test_a_vanishing_error_bar_holds_0_only_while_the_error_converges():
    """Errors C h^p (p >= 0.5, the least order fem_check reads as convergence) have 0 in the
    bar at every level; errors that level off at 0.01 above 0 do not."""
    from validation.cases.fem import vanishing_error_bar, vanishing_error_bars

    hs = [1.6e-3, 1.1e-3, 0.8e-3]
    for p in (0.5, 1.0, 2.0):
        errors = [0.3 * h**p for h in hs]
        assert all(e.contains(0.0) for e in vanishing_error_bars(errors, hs, p))
    stalled = [0.01 + 5.0 * h for h in hs]
    assert not any(e.contains(0.0) for e in vanishing_error_bars(stalled, hs, 1.0))
    assert vanishing_error_bar(0.01, 0.02, 1e-3, 2e-3).contains(0.0)  # halves: order 1
    assert not vanishing_error_bar(0.01, 0.011, 1e-3, 2e-3).contains(0.0)
