r"""Geometric safety factor by bisection, against closed forms of a block on a slope.

A ``b x h`` block on a plane tilted by ``theta`` with friction ``mu`` stands iff
``tan(theta) <= mu`` (no sliding) and ``tan(theta) <= b / h`` (its weight's line of action
falls inside the base: moments about the downhill toe). So the least width is
``b* = h tan(theta)`` when ``mu > tan(theta)``, the least friction ``mu* = tan(theta)`` when
``b / h > tan(theta)``, and the steepest slope ``theta* = atan(min(mu, b / h))``.
"""

import math

import pytest

from limit.errors import NumericalFailureError
from limit.problems import LimitSettings
from limit.safety import geometric_safety_factor
from tests.limit._scenes import tilted_block

H, THETA = 0.5, math.radians(20.0)


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_least_width_of_a_block_on_a_slope(model):
    res = geometric_safety_factor(
        lambda b: tilted_block(b, H, THETA, mu=1.0),
        0.05,
        0.5,
        actual=0.3,
        settings=LimitSettings(interface_model=model),
    )
    expected = H * math.tan(THETA)  # 0.182 m
    assert res.stands_above
    assert res.critical == pytest.approx(expected, rel=1e-3)
    assert res.bracket[0] <= expected * (1 + 1e-6) and res.bracket[1] >= expected * (1 - 1e-6)
    assert res.factor == pytest.approx(0.3 / expected, rel=1e-3)
    assert res.standing.stands and not res.falling.stands
    assert res.falling.certificate.dual_objective < 1.0


def test_least_friction_and_steepest_slope():
    mu = geometric_safety_factor(lambda m: tilted_block(0.4, 0.2, THETA, mu=m), 0.1, 1.0)
    assert mu.critical == pytest.approx(math.tan(THETA), rel=1e-3)
    # stands below the critical slope: atan(min(mu, b / h)) = atan(0.6)
    slope = geometric_safety_factor(
        lambda deg: tilted_block(0.4, 0.2, math.radians(deg), mu=0.6), 5.0, 60.0, actual=20.0
    )
    expected = math.degrees(math.atan(0.6))
    assert not slope.stands_above
    assert slope.critical == pytest.approx(expected, rel=1e-3)
    assert slope.factor == pytest.approx(expected / 20.0, rel=1e-3)


def test_a_bracket_that_does_not_straddle_is_refused():
    with pytest.raises(ValueError, match="stands at both ends"):
        geometric_safety_factor(lambda b: tilted_block(b, H, THETA, mu=1.0), 0.3, 0.5)
    with pytest.raises(ValueError, match="lo < hi"):
        geometric_safety_factor(lambda b: tilted_block(b, H, THETA, mu=1.0), 0.5, 0.3)


def test_errors_are_told_apart_by_type(monkeypatch):
    """A numerical failure stops the bisection naming the parameter; a builder's ValueError
    passes through unchanged."""
    import limit.safety as safety

    def failing(scene, settings):
        raise NumericalFailureError("no certified optimum")

    monkeypatch.setattr(safety, "stands", failing)
    with pytest.raises(NumericalFailureError, match=r"at parameter 0.05"):
        geometric_safety_factor(lambda b: tilted_block(b, H, THETA, mu=1.0), 0.05, 0.5)
    monkeypatch.undo()

    def bad_build(b):
        if b > 0.4:
            raise ValueError("thickness_mm too large for the frame")
        return tilted_block(b, H, THETA, mu=1.0)

    with pytest.raises(ValueError, match="too large"):
        geometric_safety_factor(bad_build, 0.05, 0.5)
