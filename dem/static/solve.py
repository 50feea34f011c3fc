"""``solve_collapse``: dead load, mechanism check, path to collapse, result."""

from __future__ import annotations

import logging
import math
import time
from dataclasses import replace

import numpy as np
from threadpoolctl import threadpool_limits

from dem.estimate import ErrorBudget, Estimate, check_error_budget
from dem.scene import Scene
from dem.static.adaptive_grid import refine_fibre_grid
from dem.static.dead_load import solve_dead_load
from dem.static.mechanism import no_mechanism_reason
from dem.static.model import Model
from dem.static.newton import Corrector, Iterate
from dem.static.path import PathFollower, Peak
from dem.static.result import COLLAPSE_TERMINATIONS, NoCollapseError, StaticResult
from dem.static.settings import StaticSettings

logger = logging.getLogger(__name__)

PATH_SENSITIVE_ENDS = ("snap_back", "softening")
"""Ends at a peak that an instability left behind. Which step sequence reaches such a peak
decides where it lies (the frictional path dependence; and the round-off at the joints' kinks:
another sparse LU or BLAS kernel moves it), by far more than the change between neighbouring
steps shows; so every budget but ``"none"`` buys these ends a probe run (:data:`PATH_PROBE`)."""

PATH_PROBE = 1e-3
"""Relative change of the load step in the probe run of a path-sensitive end: too small to
move a smooth path's peak by more than a thousandth of its load-step error, it changes every
step of the sequence, so the peak moves by about the spread that round-off and the step
sequence give it."""

PROBE_SPREAD_FACTOR = 2.0
"""The probe's change of the peak is one sample of the difference of two peaks drawn from the
spread (about 1.1 standard deviations on average for a normal spread): twice it is about two
standard deviations."""


@threadpool_limits.wrap(limits=1, user_api="blas")
def solve_collapse(
    scene: Scene, settings: StaticSettings | None = None, *, error: ErrorBudget = "cheap"
) -> StaticResult:
    r"""Dead load, then the live load to collapse (seed 001, Sec. 2.3).

    Parameters
    ----------
    scene : Scene
        Blocks, supports, dead load (self weight + ``dead_wrench``) and the live pattern
        ``live_wrench`` scaled by lambda.
    settings : StaticSettings, optional
    error : {"none", "cheap", "full"}
        What ``lambda_estimate`` spends: ``"cheap"`` the sources the path gives for free
        (:meth:`dem.static.path.PathFollower.error_sources`), and for an end past a peak
        (:data:`PATH_SENSITIVE_ENDS`) a probe run at a load step changed by
        :data:`PATH_PROBE`: twice its change of ``lambda_max`` is the ``"step sequence"``
        source; ``"full"`` also a second run at twice the load step, whose change of
        ``lambda_max`` bounds the load-step error (first order: the error of the finer run
        is about the change); ``"none"`` nothing.

    Returns
    -------
    StaticResult
        ``collapsed`` says whether ``lambda_max`` is a collapse multiplier.

    Raises
    ------
    ValueError
        Bad inputs (no interfaces, no free dof, no friction coefficient, zero live load).
    StaticSolverError
        Unsupported blocks (singular stiffness before any load), NaN; the message names the
        blocks or interfaces involved. :class:`dem.static.DeadLoadError` (a subclass): the
        dead load is not carried (:mod:`dem.static.dead_load`).
    NoCollapseError
        With ``on_failure="raise"`` (default): the run ended without a collapse (no mechanism
        exists, ``max_steps`` reached while lambda still rises, or stalled); ``reason`` says
        which and ``result`` holds the partial path.

    Notes
    -----
    The path following (control, step size, cascades, end) is described in
    :mod:`dem.static.path`, the Newton corrector in :mod:`dem.static.newton`, the mechanism
    check in :mod:`dem.static.mechanism`.

    The BLAS runs on one thread during the call: the path's vector operations (norms, dot
    products, GMRES's Arnoldi steps) are far too short for threads, whose start-up and waits
    made them slower than serial many times over on a shared machine, and the sparse LU gains
    nothing from them; one thread also makes the reductions' order, and so the result, the
    same on every machine.

    Limitations found on the seed 001 specimens: kinematics are small-displacement, so the
    rocking uplift of either law (both hinge a joint on its edges) against immovable supports
    (fixed columns) builds unbounded arching unless a ``compressive_strength`` bounds it.
    """
    check_error_budget(error)
    settings = StaticSettings() if settings is None else settings
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a dem.scene.Scene, got {type(scene).__name__}")
    if not isinstance(settings, StaticSettings):
        raise TypeError(
            f"settings must be a dem.static.StaticSettings, got {type(settings).__name__}"
        )
    law = settings.law_settings
    if getattr(law, "grid_tolerance", None) is not None:
        return _solve_on_refined_grids(scene, settings, error)
    result = _solve(scene, settings, error)
    if result.collapsed and error != "none" and result.termination in PATH_SENSITIVE_ENDS:
        probe = 1.0 + PATH_PROBE
        result = _with_rerun_error(
            scene, settings, result, probe, "step sequence", PROBE_SPREAD_FACTOR
        )
    if result.collapsed and error == "full":
        result = _with_rerun_error(scene, settings, result, 2.0, "load step")
    if not result.collapsed and settings.on_failure == "raise":
        raise NoCollapseError(result.failure, result)
    return result


def _solve(scene: Scene, settings: StaticSettings, error: str) -> StaticResult:
    """One run to collapse (or not), with its free error sources unless ``error="none"``."""
    start = time.perf_counter()
    model = Model(scene, settings)
    corrector = Corrector(model, settings)
    dead, n_iter = solve_dead_load(corrector)
    logger.debug("dead load: %d iterations", n_iter)
    reason = "" if settings.compressive_strength else no_mechanism_reason(model)
    if reason:
        path, termination = _Unloaded(model, dead, n_iter), "no_mechanism"
    else:
        path = PathFollower(model, corrector, dead, n_iter)
        termination, reason = path.run()
    result = _finish(model, path, termination, reason, start)
    if error == "none":
        estimate = Estimate.unknown(result.lambda_max, 'error="none"')
    else:
        estimate = Estimate(result.lambda_max, path.error_sources(termination))
    return replace(result, lambda_estimate=estimate)


def _with_rerun_error(
    scene: Scene,
    settings: StaticSettings,
    result: StaticResult,
    factor: float,
    source: str,
    widen: float = 1.0,
) -> StaticResult:
    """``result`` whose ``source`` is ``widen`` times the change of ``lambda_max`` in a rerun
    at ``factor`` times the load step (``inf`` if the rerun does not collapse), not less than
    the free bound."""
    rerun = _solve(scene, replace(settings, load_step=factor * settings.load_step), "none")
    change = abs(rerun.lambda_max - result.lambda_max) if rerun.collapsed else math.inf
    change *= widen
    est = result.lambda_estimate
    width = max(change, est.sources.get(source, 0.0))
    note = (
        f"{source}: change of lambda_max at {factor:g} times the load step "
        f"({rerun.lambda_max:.6g}, {rerun.termination})"
    )
    notes = f"{est.notes}; {note}" if est.notes else note
    estimate = replace(est.with_source(source, width, rerun.wall_s), notes=notes)
    return replace(result, lambda_estimate=estimate)


def _solve_on_refined_grids(scene: Scene, settings: StaticSettings, error: str) -> StaticResult:
    """The fibre law on grids refined until lambda settles (:mod:`dem.static.adaptive_grid`);
    the result of the finest grid, with the grids and the last change of lambda (its
    ``"fibre grid"`` error source; the coarser grids' time is the estimate's cost)."""
    start = time.perf_counter()
    once = replace(settings, on_failure="return")
    result, refinement = refine_fibre_grid(once, lambda s: solve_collapse(scene, s, error=error))
    wall = time.perf_counter() - start
    estimate = result.lambda_estimate
    if error != "none":
        for name, width in refinement.error_sources().items():
            estimate = estimate.with_source(name, width, max(wall - result.wall_s, 0.0))
    result = replace(
        result,
        fibre_grid=refinement,
        lambda_estimate=estimate,
        wall_s=wall,
        settings=settings.to_dict(),
    )
    if not result.collapsed:
        # the coarser grids' collapses are part of what the user needs to read the failure
        result = replace(result, failure=f"{result.failure} ({refinement.describe()})")
        if settings.on_failure == "raise":
            raise NoCollapseError(result.failure, result)
    return result


class _Unloaded:
    """The path of a run that never starts (no mechanism): the dead-load point only, with
    an unbounded multiplier."""

    def __init__(self, model: Model, dead: Iterate, n_iter: int):
        self.point = dead
        self.history = [dead.u.copy()]
        self.peak = Peak(math.inf, dead.u.copy(), dead.ev.law.f.copy(), model.law.state.copy())
        self.last_du = np.zeros_like(dead.u)
        self.c0 = float(model.w @ dead.u)
        self.n_steps, self.n_iterations = 0, n_iter
        self.n_loose = self.n_cascades = self.n_arc = self.n_failed_iterations = 0
        self.certificate = ""

    def pushover(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(1), np.array([self.c0])

    def error_sources(self, termination: str) -> dict[str, float]:
        """None: the multiplier is unbounded, exactly."""
        return {}


def _monitor(model: Model, settings: StaticSettings, mech: np.ndarray) -> tuple[int, int]:
    """The ``(block, dof)`` recorded along the pushover."""
    if settings.monitor is not None:
        mon = (int(settings.monitor[0]), int(settings.monitor[1]))
        if not (0 <= mon[0] < model.n_blocks and 0 <= mon[1] < 6):
            raise ValueError(f"monitor {settings.monitor} is not a (block, dof) of the scene")
        return mon
    live_dir = model.scene.loads.live_wrench[:, :3].sum(axis=0)
    dof = int(np.argmax(np.abs(live_dir)))
    return int(np.argmax(np.abs(mech[:, dof]))), dof


def _finish(model: Model, path, termination: str, reason: str, start: float) -> StaticResult:
    """The :class:`StaticResult` of a run (its ``lambda_estimate`` not yet estimated)."""
    settings = model.settings
    mech = model.full(path.last_du)
    scale = np.abs(mech[:, :3]).max()
    mech = mech / scale if scale > 0 else mech
    mon = _monitor(model, settings, mech)
    idx = model.dof_index[mon]
    history = np.array(path.history)
    lams, ctrl = path.pushover()
    end = model.evaluate(path.point.u, settings.law_settings.tangent_floor)
    collapsed = termination in COLLAPSE_TERMINATIONS
    peak = path.peak
    result = StaticResult(
        lambda_max=float(peak.lam),
        collapsed=collapsed,
        pushover_lambda=lams,
        pushover_control=ctrl,
        pushover_monitor=history[:, idx] if idx >= 0 else np.zeros(len(history)),
        monitor=mon,
        interface_state=model.law.state.copy(),
        interface_state_at_peak=peak.state,
        interface_forces=peak.f,
        interface_forces_end=end.law.f,
        mechanism=mech,
        displacements=model.full(path.point.u),
        displacements_at_peak=model.full(peak.u),
        block_a=model.a.copy(),
        block_b=model.b.copy(),
        n_steps=path.n_steps,
        n_iterations=path.n_iterations,
        n_loose_steps=path.n_loose,
        n_cascades=path.n_cascades,
        n_arc_steps=path.n_arc,
        n_failed_iterations=path.n_failed_iterations,
        failure="" if collapsed else reason,
        termination=termination,
        certificate=path.certificate if termination == "plateau" else "",
        wall_s=time.perf_counter() - start,
        lambda_estimate=Estimate.unknown(float(peak.lam)),
        settings=settings.to_dict(),
    )
    logger.info(
        "%s: lambda_max = %.6g after %d steps, %d iterations, %.2f s (%s)",
        "collapse" if collapsed else "no collapse",
        result.lambda_max,
        result.n_steps,
        result.n_iterations,
        result.wall_s,
        termination,
    )
    return result
