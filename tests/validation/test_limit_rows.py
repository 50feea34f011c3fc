"""Estimate (b)'s row: a value with the bar of its iteration's tail where the steps shrink, a
value-less diagnostic where they do not (no fixed point to bound)."""

from types import SimpleNamespace

import pytest

from dem.estimate import Estimate
from limit.estimates import IterativeEstimate
from limit.problems import LimitSettings
from validation.cases.limit import _iterative_row


def _row(history, converged=False):
    lam = history[-1]
    last = SimpleNamespace(lambda_estimate=Estimate(lam, {"solver": 1e-9}))
    it = IterativeEstimate(lam, list(history), converged, False, 0.1, len(history) - 1, 0.5, last)
    b = SimpleNamespace(iterative=it, issues=[])
    return _iterative_row("wall estimate (b) [-]", b, 0.4, "seed", LimitSettings(), 10, 1.0, {})


def test_shrinking_steps_give_a_bar_that_holds_the_geometric_limit():
    """Steps 0.05, 0.01, 0.001 shrink by 0.1: the geometric fixed point
    0.439 - 0.1 / 0.9 * 0.001 lies in the bar (and the last step would not)."""
    row = _row([0.5, 0.45, 0.44, 0.439])
    limit = 0.439 - 0.1 / 0.9 * 0.001
    assert row.ours == pytest.approx(0.439) and row.estimate.contains(limit)
    assert row.ours_error < 0.001


def test_steps_that_do_not_shrink_leave_no_value():
    """A cycle 0.5, 0.4, 0.5, 0.4 has no fixed point to bound: the row has no value (so no
    `± ?`), says why, and keeps the last iterate and the history beside it."""
    row = _row([0.5, 0.4, 0.5, 0.4, 0.5])
    assert row.ours is None and row.ours_error is None and row.reference_inside is None
    assert "no fixed point in 4 updates" in row.extra["note"]
    assert "last iterate was 0.5" in row.extra["note"]
    assert row.extra["history"] == [0.5, 0.4, 0.5, 0.4, 0.5]


def test_a_converged_iteration_keeps_its_value():
    row = _row([0.5, 0.41, 0.41], converged=True)
    assert row.ours == pytest.approx(0.41) and row.ours_error < 1e-6
