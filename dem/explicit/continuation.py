"""The explicit lateral multiplier with its error: the bracket, the loading rate, and the
continuation in joint stiffness to rigid blocks.

The explicit DEM answers for blocks with the material's joint stiffness ``k_n`` and large
displacements; the rigid-block methods (limit analysis, static DEM) for rigid blocks in small
displacements. A soft structure leans before it collapses and carries less. Both numbers
are reported:

- at the material stiffness, :func:`bracket_estimate`: the middle of
  ``(lambda_stable - detection, lambda_moving]`` with that half-width (sources "load step" and
  "detection"), plus the sources the error budget measures by a second run
  (:func:`rerun_source`): "loading rate", twice the change of that middle when the same
  driver ramps at half the rate (a quasi-static answer does not move); "time step" (half the
  time step) and "node spacing" (half the spacing), each twice its change
  (:data:`dem.estimate.HALVED_RERUN_FACTOR`: the bound of the run's own error for an order of
  at least 1, the rule the indentation's reruns follow too);
- the rigid limit, :func:`rigid_limit`: the driver run again at ``k_n`` times ``ratio``,
  ``ratio^2``, ... (each run starts its ramp just below the softer run's multiplier, which the
  stiffer structure exceeds, and scales its inertial masses by up to ``max_mass_scaling``: the
  collapse of a quasi-static load does not depend on the masses, and the driver's speed
  threshold and detection bound follow the scaling) and extrapolated to ``k_n -> inf``. The
  multiplier approaches the rigid value as ``k_n^-p``: ``p`` is measured from the last three
  levels (Aitken's delta-squared) when they give a plausible order (``ORDER_RANGE``), else
  ``p = 1`` is assumed with a bar that also holds for ``p = 1/2``; the bar is the distance
  from the stiffest level (Richardson, :func:`dem.estimate.richardson`) plus that level's own
  bar. Levels are added until the bar is below ``rtol`` of the value.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, replace

from dem.estimate import HALVED_RERUN_FACTOR, Estimate, richardson

logger = logging.getLogger(__name__)

ASSUMED_ORDER = 1.0
"""Order ``p`` of ``lambda(k) = lambda_rigid - C k^-p`` assumed when it cannot be measured: the
elastic lean and the sinking of the edge nodes of a hinge are proportional to ``1 / k``."""
ORDER_RANGE = (0.5, 3.0)
"""Orders accepted as measured from three levels; below the range the levels are not yet in
the asymptotic regime (the softest level still far from it)."""


@dataclass(frozen=True)
class RigidContinuation:
    """Settings of the continuation to rigid blocks.

    Attributes
    ----------
    ratio : float
        Factor on ``k_n`` from one level to the next; default 10.
    max_levels : int
        Most levels beyond the material stiffness; default 3.
    rtol : float
        Stop once the rigid estimate's half-width is below this fraction of it; default 0.01.
    max_mass_scaling : float
        Largest factor on the inertial masses of a stiffer level (the level at ``k_n`` times
        ``f`` scales them by ``min(f, max_mass_scaling)``); default 30. The detection bound of
        a scaled run grows with the scaling (:mod:`dem.explicit.lateral`), which caps it.
    """

    ratio: float = 10.0
    max_levels: int = 3
    rtol: float = 0.01
    max_mass_scaling: float = 30.0

    def __post_init__(self):
        if not (math.isfinite(self.ratio) and self.ratio > 1):
            raise ValueError(f"RigidContinuation.ratio must be > 1, got {self.ratio}")
        if int(self.max_levels) != self.max_levels or self.max_levels < 1:
            raise ValueError(f"RigidContinuation.max_levels must be >= 1, got {self.max_levels}")
        if not (math.isfinite(self.rtol) and self.rtol > 0):
            raise ValueError(f"RigidContinuation.rtol must be > 0, got {self.rtol}")
        if not (math.isfinite(self.max_mass_scaling) and self.max_mass_scaling >= 1):
            raise ValueError(
                f"RigidContinuation.max_mass_scaling must be >= 1, got {self.max_mass_scaling}"
            )


def bracket_estimate(result) -> Estimate | None:
    """The collapse multiplier of one run as an estimate: the middle of
    ``[lambda_stable - detection_lambda, lambda_moving]`` (None without a collapse)."""
    if not result.collapsed:
        return None
    lo = result.lambda_stable - result.detection_lambda
    hi = result.lambda_moving
    sources = {"load step": 0.5 * (hi - result.lambda_stable),
               "detection": 0.5 * result.detection_lambda}  # fmt: skip
    return Estimate(0.5 * (lo + hi), sources, notes="middle of the explicit bracket")


def rerun(run, settings, driver, factor: float = 1.0, mass_scaling: float = 1.0, **fields):
    """``run(settings, driver)`` with ``k_n`` times ``factor``, the inertial masses times
    ``mass_scaling`` and the driver's ``fields`` replaced; (result, driver)."""
    settings = replace(settings, k_n=settings.k_n * factor,
                       mass_scaling=settings.mass_scaling * mass_scaling)  # fmt: skip
    driver = replace(driver, develop=False, **fields)
    return run(settings, driver), driver


SOURCES = {
    "loading rate": ({}, {"ramp": 2.0}),
    "time step": ({"dt_safety": 0.5}, {}),
    "node spacing": ({"node_spacing": 0.5, "margin": 0.5}, {}),
}
"""Error sources measured by a second run: name -> (settings fields, driver fields) and the
factor on each (the ramp time doubled: half the loading rate; the time step halved; the node
spacing halved, with the margin that follows it)."""

BUDGET_SOURCES = {"none": (), "cheap": ("loading rate",),
                  "full": ("loading rate", "time step", "node spacing")}  # fmt: skip
"""The sources each error budget measures (:data:`dem.estimate.ErrorBudget`)."""


def rerun_source(run, settings, driver, result, name: str) -> tuple[float, float]:
    """Half-width [-] of source ``name`` of :data:`SOURCES` and its cost [s]:
    :data:`~dem.estimate.HALVED_RERUN_FACTOR` times the change of the bracket's middle when
    the run is repeated with that change (warm start one step below ``lambda_stable``);
    ``run(settings, driver) -> LateralResult`` runs the driver."""
    wall0 = time.perf_counter()
    settings_fields, driver_fields = SOURCES[name]
    changed = replace(settings, **{k: getattr(settings, k) * f for k, f in settings_fields.items()})
    fields = {k: (result.info["ramp_s"] if k == "ramp" else getattr(driver, k)) * f
              for k, f in driver_fields.items()}  # fmt: skip
    start = max(0.0, result.lambda_stable - driver.step)
    other, _ = rerun(run, changed, driver, start=start, **fields)
    base, moved = bracket_estimate(result), bracket_estimate(other)
    if moved is None:
        logger.warning("with the %s changed no collapse was found below %.4g: that source is "
                       "unbounded", name, driver.max_lambda)  # fmt: skip
        return math.inf, time.perf_counter() - wall0
    return HALVED_RERUN_FACTOR * abs(moved.value - base.value), time.perf_counter() - wall0


def rigid_limit(run, settings, driver, result, material: Estimate, cont: RigidContinuation):
    """The rigid-block multiplier extrapolated from runs at stiffer joints (module notes);
    ``run(settings, driver) -> LateralResult`` runs the driver, ``result`` is the run at the
    material stiffness.

    Returns
    -------
    rigid : Estimate or None
        None when a stiffer level finds no collapse. Its bar is the extrapolation and the
        stiffest level's bracket; the stiff levels are not rerun, so the loading rate, time
        step and node spacing are in ``rigid.omitted``.
    levels : list of dict
        Per level: ``factor`` on ``k_n``, ``mass_scaling``, ``lambda_stable``,
        ``lambda_moving``, ``value`` and ``error`` (the bracket's), ``wall_s``.
    """
    wall0 = time.perf_counter()
    values, levels = [material], [_level(1.0, 1.0, result, bracket_estimate(result))]
    previous, rigid = result, None
    width = driver.step / 2**driver.refinements
    for j in range(1, cont.max_levels + 1):
        factor = cont.ratio**j
        scaling = min(factor, cont.max_mass_scaling)
        step = max(4.0 * width, _increment(values))
        start = max(0.0, previous.lambda_stable - width)
        level, used = rerun(
            run, settings, driver, factor, scaling, step=step, start=start,
            refinements=max(0, math.ceil(math.log2(step / width) - 1e-9)),
            max_lambda=max(driver.max_lambda, start + 2.0 * step),
        )  # fmt: skip
        estimate = bracket_estimate(level)
        if estimate is None:
            logger.warning("at %g times k_n no collapse below %.4g: no rigid limit", factor,
                           used.max_lambda)  # fmt: skip
            return None, levels
        values.append(estimate)
        levels.append(_level(factor, scaling, level, estimate))
        rigid = _extrapolate(values, cont.ratio)
        # the stiff levels are not rerun: their rate, time step and node spacing are named
        rigid = Estimate(rigid.value, rigid.sources, time.perf_counter() - wall0, rigid.notes,
                         BUDGET_SOURCES["full"])  # fmt: skip
        if rigid.error <= cont.rtol * abs(rigid.value):
            break
        previous = level
    return rigid, levels


def _increment(values: list[Estimate]) -> float:
    """The next level's expected rise of the multiplier: the last rise (0 with one level)."""
    if len(values) < 2:
        return 0.0
    return abs(values[-1].value - values[-2].value)


def _extrapolate(values: list[Estimate], ratio: float) -> Estimate:
    """``lambda`` at ``k_n -> inf`` from the levels' estimates (module notes): Richardson on
    the last two levels with the order measured from the last three when it lies in
    ``ORDER_RANGE``, else with ``ASSUMED_ORDER`` and a bar that holds down to the range's
    lowest order; plus the stiffest level's own bar."""
    last = values[-1]
    order = None
    if len(values) >= 3:
        d1 = values[-2].value - values[-3].value
        d2 = values[-1].value - values[-2].value
        if d1 * d2 > 0 and abs(d2) < abs(d1):
            measured = math.log(d1 / d2) / math.log(ratio)
            if ORDER_RANGE[0] <= measured <= ORDER_RANGE[1]:
                order = measured
    if order is not None:
        ext = richardson(values[-2].value, last.value, ratio, order)
        width, how = ext.error, f"order {order:.3g} from the last three levels"
    else:
        ext = richardson(values[-2].value, last.value, ratio, ASSUMED_ORDER)
        low = richardson(values[-2].value, last.value, ratio, ORDER_RANGE[0])
        width = max(ext.error, abs(low.value - ext.value))
        how = f"order {ASSUMED_ORDER:g} assumed, bar down to order {ORDER_RANGE[0]:g}"
    sources = {"joint stiffness (extrapolation)": width}
    sources.update({f"stiffest level: {k}": w for k, w in last.sources.items()})
    return Estimate(ext.value, sources, notes=f"{len(values)} levels, ratio {ratio:g}, {how}")


def _level(factor, scaling, result, estimate: Estimate) -> dict:
    return {
        "factor": factor,
        "mass_scaling": scaling,
        "lambda_stable": result.lambda_stable,
        "lambda_moving": result.lambda_moving,
        "value": estimate.value,
        "error": estimate.error,
        "wall_s": result.wall_s,
    }
