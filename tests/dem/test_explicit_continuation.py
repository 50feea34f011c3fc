"""The explicit multiplier's error bar and its continuation to rigid joints.

Closed forms: a block of width ``b`` and height ``h`` on a fixed base, loaded by its weight
along +x times ``lambda``, tips at ``b / h`` (mu large); a column of three such blocks at
``b / (3 h)``. The extrapolation is checked on multipliers that follow
``lambda(k) = lambda_rigid - C k^-p`` exactly.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from dem.estimate import Estimate
from dem.explicit import RigidContinuation, masonry_settings, simulate_lateral
from dem.explicit.continuation import ORDER_RANGE, _extrapolate, bracket_estimate
from dem.explicit.lateral import LiveLoadRamp
from dem.scenes import stack, voussoir_arch
from limit.solve import limit_analysis

DRIVER = LiveLoadRamp(step=0.05, max_lambda=1.0, refinements=4)


def levels(rigid, c, p, ratio, n, bar=1e-4):
    return [Estimate(rigid - c * ratio ** (-p * j), {"load step": bar}) for j in range(n)]


@pytest.mark.parametrize("p", [0.7, 1.0, 2.0])
def test_three_levels_measure_the_order_and_extrapolate_exactly(p):
    est = _extrapolate(levels(0.3, 0.05, p, 10.0, 3), 10.0)
    np.testing.assert_allclose(est.value, 0.3, rtol=1e-12)
    assert "from the last three" in est.notes
    assert est.sources["stiffest level: load step"] == 1e-4


def test_two_levels_assume_order_one_with_a_bar_down_to_half():
    """Order 1 assumed: exact for p = 1, and the bar holds the truth for p = 1/2."""
    for p in (ORDER_RANGE[0], 1.0):
        est = _extrapolate(levels(0.3, 0.05, p, 10.0, 2, bar=0.0), 10.0)
        assert est.contains(0.3)
    exact = _extrapolate(levels(0.3, 0.05, 1.0, 10.0, 2, bar=0.0), 10.0)
    np.testing.assert_allclose(exact.value, 0.3, rtol=1e-12)


def test_bracket_estimate_spans_the_detection_below_the_bracket():
    res = SimpleNamespace(collapsed=True, lambda_stable=0.30, lambda_moving=0.31,
                          detection_lambda=0.002)  # fmt: skip
    est = bracket_estimate(res)
    np.testing.assert_allclose([est.lo, est.hi], [0.298, 0.31], rtol=1e-12)
    assert bracket_estimate(SimpleNamespace(collapsed=False)) is None


def test_loading_rate_measured_and_the_bar_holds_b_over_h():
    """A column of three 0.2 x 0.2 x 0.4 boxes: 1/6, within the bar at the material
    stiffness (rigid joints: the lean is negligible); the loading rate source is measured."""
    scene = stack(3, 0.2, 0.2, 0.4)
    settings = masonry_settings(scene, joint_stiffness=None)
    res = simulate_lateral(scene, settings, DRIVER, error="cheap")
    assert set(res.estimate.sources) == {"load step", "detection", "loading rate"}
    assert res.estimate.omitted == ("time step", "node spacing")  # not paid for: named
    assert math.isfinite(res.estimate.error) and res.estimate.cost_s > 0
    assert res.estimate.contains(1.0 / 6.0)
    assert res.rigid is None


@pytest.mark.parametrize("start", [0.15, 0.2])
def test_warm_start_brackets_b_over_h_from_below_and_from_above(start):
    """A column of three 0.2 x 0.2 x 0.4 boxes with rigid joints (1/6): a warm start below
    the collapse steps on from it; one above finds motion at once and bisects down from it;
    both brackets hold 1/6 and are ``step / 2^refinements`` wide."""
    scene = stack(3, 0.2, 0.2, 0.4)
    settings = masonry_settings(scene, joint_stiffness=None)
    driver = LiveLoadRamp(step=0.01, max_lambda=1.0, refinements=2, start=start)
    res = simulate_lateral(scene, settings, driver)
    assert res.lambda_moving - res.lambda_stable <= 0.01 / 4 * (1 + 1e-9)
    assert res.lambda_stable - res.detection_lambda <= 1.0 / 6.0 <= res.lambda_moving


def test_continuation_of_a_soft_column_reaches_b_over_h():
    """The same column with soft joints (default settings) leans and tips below 1/6; its
    continuation to rigid joints holds 1/6 within its bar, from at least two levels."""
    scene = stack(3, 0.2, 0.2, 0.4)
    res = simulate_lateral(scene, driver=DRIVER, continuation=RigidContinuation(rtol=0.02))
    assert res.estimate.value < 1.0 / 6.0
    assert len(res.levels) >= 2 and res.levels[1]["factor"] == 10.0
    assert res.rigid.contains(1.0 / 6.0), res.rigid


@pytest.mark.slow
def test_arch_of_twenty_voussoirs_rigid_limit_within_one_percent():
    """Voussoir arch, span 2 m, ring 0.2 m, 20 voussoirs: the rigid limit of the explicit run
    holds the limit analysis multiplier (rigid blocks) within its bar, and the bar is below
    1 % of it."""
    scene = voussoir_arch(2.0, 0.2, 20)
    expected = limit_analysis(scene).lam
    driver = LiveLoadRamp(step=0.125 * expected, max_lambda=1.25 * expected, refinements=4)
    res = simulate_lateral(scene, driver=driver, continuation=RigidContinuation())
    assert res.rigid.contains(expected), (res.rigid, expected)
    assert res.rigid.error <= 0.01 * expected


@pytest.mark.slow
def test_full_budget_measures_time_step_and_node_spacing():
    """The full error budget adds the time step and the node spacing (a run each at half of
    it); the column's bar still holds 1/6."""
    scene = stack(3, 0.2, 0.2, 0.4)
    settings = masonry_settings(scene, joint_stiffness=None)
    res = simulate_lateral(scene, settings, DRIVER, error="full")
    assert {"loading rate", "time step", "node spacing"} <= set(res.estimate.sources)
    assert math.isfinite(res.estimate.error) and res.estimate.contains(1.0 / 6.0)
