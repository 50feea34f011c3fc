"""The error bars validation cases compute themselves (validation.cases.bars)."""

import math

import numpy as np
import pytest

from dem.estimate import Estimate
from dem.scenes import stack
from validation.cases.bars import (
    EPS,
    diagnostic,
    exact,
    moved_copy,
    per_unit,
    proportion,
    round_off,
    two_levels,
)


def test_exact_and_round_off_bars():
    assert exact(7).error == 0.0 and exact(7).sources == {"exact": 0.0}
    assert round_off(2.0, 2.0 + 3e-15).error == pytest.approx(3e-15, rel=1e-6)
    assert round_off(2.0, 2.0).error == 2.0 * EPS  # at least one epsilon of the value


def test_a_moved_copy_keeps_volumes_to_round_off():
    """Rigid motion changes every rounding but not the volume: the difference is round-off,
    and the exact volume 0.4 x 0.3 x 0.5 x 2 lies within the bar."""
    scene = stack(2, 0.4, 0.3, 0.5)
    volume = scene.assembly.volume[:2].sum()
    moved = moved_copy(scene.assembly).volume[:2].sum()
    est = round_off(volume, moved)
    assert 0 < est.error < 1e-12 and est.contains(0.4 * 0.3 * 0.5 * 2)


def test_two_levels_bound_a_first_order_sequence():
    """s_h = 1 + h: the bar of the h = 0.1 level against h = 0.2 is 0.1 and holds the limit 1
    (|s_h - s_inf| = |s_h - s_2h| at order 1)."""
    est = two_levels(1.1, 1.2, "grid")
    assert est.error == pytest.approx(0.1) and est.contains(1.0)
    assert math.isinf(two_levels(1.0, math.inf, "grid").error)


def test_a_proportion_carries_its_wilson_interval():
    """3 of 10: Wilson 95 % interval [0.1078, 0.6032] (closed form (p + z^2/2n +- z sqrt(p(1-p)/n
    + z^2/4n^2)) / (1 + z^2/n), z = 1.95996)."""
    z, n, p = 1.959964, 10, 0.3
    centre = (p + z**2 / (2 * n)) / (1 + z**2 / n)
    half = z * math.sqrt(p * (1 - p) / n + z**2 / (4 * n**2)) / (1 + z**2 / n)
    est = proportion(3, 10)
    assert est.value == 0.3
    assert est.error == pytest.approx(max(centre + half - p, p - centre + half), rel=1e-5)
    with pytest.raises(ValueError, match="n >= 1"):
        proportion(0, 0)


def test_per_unit_scales_every_source_and_marks_a_missing_bar():
    est = per_unit(Estimate(2000.0, {"gap": 10.0, "polygon": 4.0}), 1000.0)
    assert est.value == 2.0 and est.sources == {"gap": 0.01, "polygon": 0.004}
    bare = per_unit(None, 1000.0, 2000.0)
    assert bare.value == 2.0 and math.isinf(bare.error)
    partial = per_unit(Estimate(2000.0, {"rate": 10.0}, omitted=("time step",)), 1000.0)
    assert partial.omitted == ("time step",) and not partial.complete


def test_a_discrepancy_has_no_bar_of_its_own():
    assert math.isinf(diagnostic(1e-12).error)
    np.testing.assert_allclose(exact(0.5).value, 0.5)


def test_sum_round_off_bounds_the_rounding_of_a_sum():
    """2000 terms of magnitudes from 1e-6 to 1e6, summed left to right, differ from the exact
    (rational) sum by less than n eps sum |x| (Higham Sec. 4.2)."""
    from fractions import Fraction

    import numpy as np

    from validation.cases.bars import sum_round_off

    x = np.random.default_rng(3).normal(size=2000) * 10.0 ** np.arange(-6, 6, 0.006)
    total = 0.0
    for v in x:
        total += float(v)
    exact = float(sum(Fraction(float(v)) for v in x))
    assert abs(total - exact) <= sum_round_off(np.sum(np.abs(x)), len(x))
    assert sum_round_off(np.sum(np.abs(x)), len(x)) > 0


def test_residual_bar_contains_zero_only_within_the_bound():
    import pytest

    from validation.cases.bars import residual

    assert residual(1e-12, 1e-10, "solver tolerance").contains(0.0)
    assert not residual(1e-9, 1e-10, "solver tolerance").contains(0.0)
    with pytest.raises(ValueError, match="bound"):
        residual(0.0, float("inf"), "round-off")
