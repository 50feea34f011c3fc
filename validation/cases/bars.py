"""Error bars the validation cases compute themselves, where no method gives one.

- :func:`exact`: a count or a value that is exact by construction (source ``"exact"``, 0);
- :func:`round_off`: a value that is exact up to float64 round-off, measured by evaluating it
  again on a rigidly moved copy (every rounding changes, the value must not): the bar is the
  difference, at least one machine epsilon of the value;
- :func:`two_levels`: a value at the finer of two discretisation levels, with the difference
  to the coarser level as its bar (the finer level's error when the value converges
  monotonically at order at least 1: :math:`|s_h - s_\\infty| \\le |s_h - s_{2h}|`);
- :func:`residual`: a residual whose exact value is 0 (an imbalance, a violation, a distance
  to a closed form), with the bar its computation's own accuracy allows: the round-off of its
  terms (:func:`sum_round_off`) or the tolerance it was solved to. The reference 0 lies in
  that bar exactly when the residual is no larger than that accuracy, so the row is a check
  that can fail.

No bar here is a guess: each is computed from the case's own runs, or is zero by
construction, or is :meth:`dem.estimate.Estimate.unknown`.
"""

from __future__ import annotations

import math

import numpy as np

from dem.estimate import Estimate
from dem.scene import Assembly

EPS = float(np.finfo(float).eps)
MOVE_ROTATION = (0.3, -0.2, 0.5)
"""Rotation vector [rad] of the moved copy (any rotation that is not a symmetry will do)."""


def exact(value: float, why: str = "") -> Estimate:
    """A value exact by construction (a count, an identity): bar 0, source ``"exact"``."""
    return Estimate(float(value), {"exact": 0.0}, notes=why)


def moved_copy(assembly: Assembly, offset: float = 0.37) -> Assembly:
    """The assembly rotated by :data:`MOVE_ROTATION` and shifted by ``offset`` [m] along each
    axis, rebuilt from its vertices (volumes, interfaces recomputed)."""
    from scipy.spatial.transform import Rotation

    rot = Rotation.from_rotvec(MOVE_ROTATION).as_matrix()
    vertices = [b.vertices @ rot.T + offset for b in assembly.blocks]
    return Assembly.from_convex_blocks(vertices, assembly.density, assembly.mu)


def round_off(value: float, again: float, what: str = "") -> Estimate:
    """``value`` with the round-off bar ``max(|value - again|, eps |value|)``, ``again`` being
    the same quantity evaluated on a rigidly moved copy."""
    width = max(abs(value - again), EPS * abs(value))
    return Estimate(float(value), {"round-off": width}, notes=f"moved copy gives {again!r} {what}")


def two_levels(fine: float, coarse: float, source: str, notes: str = "") -> Estimate:
    """``fine`` with the bar ``|fine - coarse|`` named ``source`` (module notes), and one
    machine epsilon of round-off (two levels that agree to the last bit still round)."""
    if not (math.isfinite(fine) and math.isfinite(coarse)):
        return Estimate.unknown(fine, f"{source}: a level is not finite")
    sources = {source: abs(fine - coarse), "round-off": EPS * abs(fine)}
    return Estimate(float(fine), sources, notes=notes)


def static_lambda(result, scale: float = 1.0) -> Estimate:
    """The static DEM's collapse multiplier times ``scale`` with the solver's own error bar
    (``StaticResult.lambda_estimate``: end of path, load step, residual, fibre grid), every
    source scaled too."""
    own = result.lambda_estimate
    sources = {k: w * abs(scale) for k, w in own.sources.items()}
    return Estimate(result.lambda_max * scale, sources, own.cost_s, own.notes)


def proportion(count: int, n: int) -> Estimate:
    """The fraction ``count / n`` of a sample as an estimate of the population's, with the
    half-width that covers its 95 % Wilson score interval (source ``"sampling"``)."""
    from scipy.stats import binomtest

    if n < 1:
        raise ValueError(f"a proportion needs n >= 1 samples, got {n}")
    p = count / n
    ci = binomtest(count, n).proportion_ci(confidence_level=0.95, method="wilson")
    half = max(ci.high - p, p - ci.low, 0.0)
    return Estimate(p, {"sampling": half}, notes=f"Wilson 95 % [{ci.low:.4g}, {ci.high:.4g}]")


def sum_round_off(abs_terms, n_terms) -> float:
    """Bound [unit of the terms] on the rounding of a sum of ``n_terms`` floats whose absolute
    values add to ``abs_terms`` (either may be an array: the largest product counts):
    :math:`\\gamma_n \\sum |x_i|` with :math:`\\gamma_n \\approx n\\,\\epsilon` (Higham,
    *Accuracy and Stability of Numerical Algorithms*, 2nd ed., Sec. 4.2); ``n_terms`` should
    count the operations that made each term too."""
    bound = np.asarray(n_terms, dtype=float) * EPS * np.abs(np.asarray(abs_terms, dtype=float))
    return float(np.max(bound, initial=0.0))


def residual(value: float, bound: float, source: str, notes: str = "") -> Estimate:
    """A residual whose exact value is 0, with the half-width ``bound`` (>= 0, same unit) named
    ``source`` (``"round-off"`` for :func:`sum_round_off`, ``"solver tolerance"`` for the
    tolerance the value was solved to; module notes)."""
    bound = float(bound)
    if not (math.isfinite(bound) and bound >= 0.0):
        raise ValueError(f"residual bound must be finite and >= 0, got {bound!r}")
    return Estimate(float(value), {source: bound}, notes=notes)


def diagnostic(value: float) -> Estimate:
    """A row whose value is itself a discrepancy (two routes, a residual, a fitted check
    against 0): its own bar would need the routes' bars, which are not estimated, so it is
    unknown and says why."""
    return Estimate.unknown(value, "a discrepancy between two computations: no bar of its own")


def per_unit(estimate: Estimate | None, unit: float, value: float | None = None) -> Estimate:
    """``estimate`` in a table's unit (every half-width divided by ``unit`` too, the omitted
    sources kept); without an estimate, ``value / unit`` with an unknown bar."""
    if estimate is None:
        if value is None:
            raise ValueError("per_unit needs an estimate or a value")
        return Estimate.unknown(value / unit, "the method gives no error bar for this value")
    sources = {k: w / abs(unit) for k, w in estimate.sources.items()}
    return Estimate(
        estimate.value / unit, sources, estimate.cost_s, estimate.notes, estimate.omitted
    )
