r"""Limit analysis of a scene: structural checks, then the static programme.

.. math::

    \lambda^+ = \max\{\lambda \ge 0 : A_{eq} f + F_D + \lambda F_L = 0,\ f_k \in
    \mathcal{Y}_k\}

(see :mod:`limit.problems`). With associated (normality) flow this is the collapse multiplier
of the rigid-perfectly-plastic assembly; with non-associated (zero-dilatancy) Coulomb
friction it is an upper bound on the collapse multiplier (Radenkovic's first theorem;
:mod:`limit.estimates`).

Outcomes, told apart by type (:mod:`limit.errors`): a certified :class:`LimitResult`;
:class:`~limit.errors.DeadLoadInfeasibleError` when the structure falls down by itself (no
equilibrium at ``lambda = 0``), naming the blocks and interfaces of the dead-load mechanism
(:mod:`limit.deadload`); :class:`~limit.errors.NoMechanismError` when the live load is carried
for every multiplier; :class:`~limit.errors.NumericalFailureError` when no solve passes its
certificate (status map and retries: :mod:`limit.clarabel`).

A scene without interfaces is no special case: its free blocks are held by their restrained
dofs alone, so a live load on a free dof gives ``lambda = 0`` (the mechanism moves that dof)
and a dead load on one a :class:`~limit.errors.DeadLoadInfeasibleError`.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np

from dem.estimate import ErrorBudget, Estimate, check_error_budget
from dem.scene import Scene
from limit.clarabel import (
    ACCEPTED,
    MSG_INFEASIBLE,
    MSG_UNBOUNDED,
    TIGHTENED,
    LimitResult,
    run_clarabel,
    solve_static,
    structural_error,
)
from limit.deadload import dead_load_error, require_standing, unsupported_blocks
from limit.errors import (
    DeadLoadInfeasibleError,
    LimitAnalysisError,
    NoMechanismError,
    NumericalFailureError,
)
from limit.lambda_error import outer_polygon_factor
from limit.matrices import (
    equilibrium_matrix,
    interface_friction,
    interface_vertices,
    vertex_force_matrix,
)
from limit.problems import (
    LimitSettings,
    StaticProblem,
    build_kinematic_problem,
    build_static_problem,
    checked_inputs,
)

__all__ = [
    "ACCEPTED",
    "LimitAnalysisError",
    "LimitResult",
    "check_scene",
    "kinematic_analysis",
    "limit_analysis",
    "solve_static",
]

logger = logging.getLogger(__name__)

KINEMATIC_OUTCOMES = {
    # by conic duality the kinematic programme is unbounded where the static one is infeasible
    "unbounded": (DeadLoadInfeasibleError, MSG_INFEASIBLE),
    "infeasible": (NoMechanismError, MSG_UNBOUNDED),
}


def check_scene(scene: Scene) -> None:
    """Structural checks before solving, in plain words.

    Raises
    ------
    DeadLoadInfeasibleError
        No support at all, or loaded blocks that touch no other block on a face (named).
    NoMechanismError
        The live load does no work on any free dof.
    """
    lonely, reason = unsupported_blocks(scene)
    if lonely.size:
        raise DeadLoadInfeasibleError(reason, blocks=lonely)
    live = scene.loads.live_wrench
    if not np.any(live[scene.supports.free_dofs] != 0):
        raise NoMechanismError(
            "the live load is zero on every free dof: it never does work, so the multiplier is "
            "unbounded (no collapse mechanism); define a live load on free blocks."
        )


def limit_analysis(
    scene: Scene,
    settings: LimitSettings | None = None,
    certify: bool = True,
    error: ErrorBudget = "cheap",
) -> LimitResult:
    """Associated static limit analysis of a scene (build, solve, certify).

    Parameters
    ----------
    scene : Scene
    settings : LimitSettings, optional
    certify : bool
    error : {"none", "cheap", "full"}
        What to spend on ``lambda_estimate`` (:mod:`limit.lambda_error`). ``"none"``: an
        unknown error. ``"cheap"`` and ``"full"``: the solver's error from the certificate,
        which costs nothing more, and with a ``friction_polygon`` the polygon's error
        measured against the exact cones (one more programme compiled and solved with
        Clarabel's second-order cones: it costs about what the polygon's own solve costs,
        and unlike the outer polygon's bracket it is not loose where the load points at a
        polygon corner; the bracket is the fallback if the exact cones fail).

    Returns
    -------
    LimitResult
        ``lam`` is the associated collapse multiplier of the chosen interface model: an upper
        bound for non-associated (zero-dilatancy) friction. ``lambda_estimate`` its error bar.

    Raises
    ------
    TypeError
        ``scene`` is no Scene or ``settings`` no LimitSettings (as at every entry point).
    DeadLoadInfeasibleError
        The structure falls down by itself, even if some live load would prop it
        (``settings.dead_load_check``); ``blocks`` and ``interfaces`` name its dead-load
        mechanism.
    NoMechanismError
        The live load is carried for every multiplier.
    NumericalFailureError
        No certified optimum after the retries of :func:`limit.clarabel.solve_static`.
    """
    settings = checked_inputs(scene, settings)
    check_error_budget(error)
    check_scene(scene)
    t0 = time.perf_counter()
    sp_ = build_static_problem(scene, settings)
    sp_.extra["build_s"] = time.perf_counter() - t0
    try:
        result = solve_static(sp_, certify=certify)
    except DeadLoadInfeasibleError as exc:
        raise dead_load_error(scene, settings, str(exc)) from exc
    require_standing(scene, settings)
    if error == "none":
        result.lambda_estimate = Estimate.unknown(result.lam, "error budget 'none'")
    elif settings.friction_polygon is not None:
        result.lambda_estimate = polygon_error(scene, settings, result, sp_)
    return result


def polygon_error(
    scene: Scene, settings: LimitSettings, result: LimitResult, sp_: StaticProblem
) -> Estimate:
    """``result.lambda_estimate`` with the ``"friction polygon"`` source measured: the
    distance to the optimum with the exact cones, plus that solve's own solver error; if the
    exact-cone programme fails, the outer polygon's bracket (:func:`polygon_bracket` of the
    compiled programme ``sp_``)."""
    t0 = time.perf_counter()
    try:
        exact = solve_static(build_static_problem(scene, settings.with_(friction_polygon=None)))
    except LimitAnalysisError as exc:
        logger.info("exact-cone programme failed (%s): the outer polygon brackets instead", exc)
        return polygon_bracket(sp_, result)
    width = abs(exact.lam - result.lam) + exact.lambda_estimate.error
    return result.lambda_estimate.with_source(
        "friction polygon", width, cost_s=time.perf_counter() - t0
    )


def polygon_bracket(sp_: StaticProblem, result: LimitResult) -> Estimate:
    """``result.lambda_estimate`` with the ``"friction polygon"`` source: the width of
    ``[lambda, lambda_out]``, where ``lambda_out`` is the optimum of the programme with every
    friction coefficient divided by ``cos(pi / k)``, whose polygons contain the exact cones
    (:mod:`limit.lambda_error`), plus that solve's own solver error. The compiled programme
    ``sp_`` is re-solved with the larger coefficients and restored."""
    t0 = time.perf_counter()
    mu = sp_.mu_interface
    sp_.set_friction(mu * outer_polygon_factor(sp_.settings.friction_polygon))
    try:
        outer = solve_static(sp_)
        width = max(outer.lam - result.lam, 0.0) + outer.lambda_estimate.error
    except LimitAnalysisError as exc:
        logger.info("outer friction polygon failed: %s", exc)
        width = math.inf
    finally:
        sp_.set_friction(mu)
    return result.lambda_estimate.with_source(
        "friction polygon", width, cost_s=time.perf_counter() - t0
    )


def kinematic_analysis(scene: Scene, settings: LimitSettings | None = None) -> tuple:
    """Solve the kinematic programme of the vertex model (:func:`build_kinematic_problem`).

    Returns
    -------
    lam : float
        The kinematic multiplier (equal to the static one by conic duality).
    velocities : (n_blocks, 6) float
        The mechanism, normalised to unit live-load power.
    status : str

    Raises
    ------
    DeadLoadInfeasibleError, NoMechanismError
        With the structural message of the static programme: the kinematic programme is
        unbounded below when the structure falls by itself and infeasible when no mechanism
        exists (no blocks are named here: use :func:`limit.stands`). Also, as for
        :func:`limit_analysis`, when the dead load alone is not carried but some live load
        props the structure (``settings.dead_load_check``): the kinematic optimum is then the
        top of the propped interval, no collapse multiplier.
    NumericalFailureError
        Still inaccurate after a solve with tighter tolerances.
    """
    settings = checked_inputs(scene, settings)
    check_scene(scene)
    kp = build_kinematic_problem(scene, settings)
    status, _ = run_clarabel(kp.problem, settings)
    if status.endswith("_inaccurate"):
        status, _ = run_clarabel(kp.problem, settings, TIGHTENED)
    err = structural_error(status, KINEMATIC_OUTCOMES, f"kinematic status {status}")
    if err is not None:
        raise err
    if status != "optimal":
        raise NumericalFailureError(f"no certified optimum: kinematic status {status!r}")
    require_standing(scene, settings)
    u = np.asarray(kp.velocity.value, float) * kp.row_scale
    live = scene.loads.live_wrench.ravel()[kp.free]
    u = u / float(live @ u)
    vel = np.zeros(6 * scene.n_blocks)
    vel[kp.free] = u
    lam = float(kp.problem.value) * kp.lam_scale
    vel = vel.reshape(-1, 6)
    _check_mechanism(scene, settings, vel, lam, kp.lam_scale)
    return lam, vel, status


def _check_mechanism(
    scene: Scene, settings: LimitSettings, vel: np.ndarray, lam: float, unit: float
):
    """Certify the kinematic answer from the mechanism itself, in SI: every corner's
    velocity conjugate to its compression is at least mu times the one conjugate to its
    friction (normality), to ``cert_tol`` of the largest; and the work balance
    ``lambda = -(F_D + A_eq f_t) . u / F_L . u`` gives back ``lam`` (to ``cert_tol`` of
    ``lam`` or of ``unit``, the programme's scale of lambda). An admissible mechanism bounds
    the collapse multiplier from above, whatever the solver's accuracy."""
    interfaces = scene.assembly.interfaces()
    a_eq_u = equilibrium_matrix(scene.assembly.centroid, interfaces).T @ vel.ravel()
    w = vertex_force_matrix(interfaces).T @ a_eq_u
    w_p, w_t = w[0::3], np.hypot(w[1::3], w[2::3])
    vi, _ = interface_vertices(interfaces)
    mu = interface_friction(interfaces, scene.assembly.mu, settings.mu)[vi]
    finite = np.isfinite(mu)
    # mu = inf: the corner only opens (w_t = 0, w_p >= 0)
    excess = np.where(finite, np.where(finite, mu, 0.0) * w_t - w_p, np.maximum(w_t, -w_p))
    scale = float(np.abs(w).max(initial=0.0)) or 1.0
    f_t = np.zeros(6 * interfaces.n_interfaces)
    f_t[0::6] = settings.tensile_strength * interfaces.area
    dead, live = scene.dead_wrench.ravel(), scene.loads.live_wrench.ravel()
    lam_work = -(float(dead @ vel.ravel()) + float(f_t @ a_eq_u)) / float(live @ vel.ravel())
    worst = float(excess.max(initial=0.0)) / scale
    if worst > settings.cert_tol:
        raise NumericalFailureError(
            f"the kinematic mechanism is not admissible: a corner slides beyond mu times its "
            f"opening by {worst:.2e} of the largest corner velocity"
        )
    if not abs(lam_work - lam) <= settings.cert_tol * max(abs(lam), unit):
        raise NumericalFailureError(
            f"the kinematic multiplier {lam:.9g} fails its check: the work balance of its "
            f"mechanism gives {lam_work:.9g}"
        )
