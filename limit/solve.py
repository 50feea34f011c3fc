r"""Solve the static programme with Clarabel: status map, certificates, :class:`LimitResult`.

.. math::

    \lambda^+ = \max\{\lambda \ge 0 : A_{eq} f + F_D + \lambda F_L = 0,\ f_k \in
    \mathcal{Y}_k\}

(see :mod:`limit.problems`). With associated (normality) flow this is the collapse multiplier
of the rigid-perfectly-plastic assembly; with non-associated (zero-dilatancy) Coulomb
friction it is an upper bound on the collapse multiplier (Radenkovic's first theorem;
:mod:`limit.estimates`).

Status vocabulary (cvxpy's): ``optimal`` is accepted; ``optimal_inaccurate`` is accepted with a
warning and recorded in :attr:`LimitResult.status`; ``infeasible`` (no equilibrium under the
dead load alone: the structure falls down by itself), ``unbounded`` (no collapse mechanism:
the live load is carried for any multiplier) and anything else raise
:class:`limit.errors.LimitAnalysisError` with a message in structural words. A returned
solution is also rejected when its certificate (:mod:`limit.certificates`) exceeds
``settings.cert_tol``.
"""

from __future__ import annotations

import logging
import time
import warnings
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np

from dem.scene import Scene
from limit.certificates import (
    Certificate,
    conic_certificate,
    equilibrium_residual,
    yield_residual,
)
from limit.errors import LimitAnalysisError
from limit.matrices import rocking_constraints
from limit.problems import (
    LimitSettings,
    StaticProblem,
    build_kinematic_problem,
    build_static_problem,
)

logger = logging.getLogger(__name__)

__all__ = [
    "LimitResult",
    "limit_analysis",
    "kinematic_analysis",
    "solve_static",
    "check_scene",
    "ACCEPTED",
]

ACCEPTED = ("optimal", "optimal_inaccurate")

MSG_INFEASIBLE = (
    "no equilibrium under the dead load alone (lambda = 0 is infeasible): the structure "
    "falls down by itself. A block may lack support (missing foundation or restraint), hang "
    "past its supports, or need more friction than mu provides."
)
MSG_UNBOUNDED = (
    "the live load is carried for every multiplier (unbounded): no collapse mechanism exists. "
    "The live load acts only on supported or restrained degrees of freedom, or rigid supports "
    "with unlimited compressive strength carry it by arching (set compressive_strength)."
)


@dataclass
class LimitResult:
    """A certified solution of the static programme.

    Attributes
    ----------
    lam : float
        Load multiplier [-] (or [Pa] for a unit-pressure live load).
    status : str
        ``"optimal"`` or ``"optimal_inaccurate"``.
    is_inaccurate : bool
    model, friction : str
        Interface model and friction mode of the programme.
    interface_forces : (m, 6) float
        ``(N, V1, V2, M1, M2, M3)`` at collapse [N, N m], ``N > 0`` tension.
    vertex_forces : (p, 3) float or None
        ``(p, s1, s2)`` at each polygon corner [N] (vertex model).
    velocities : (n_blocks, 6) float
        Collapse mechanism from the equilibrium duals: block velocities ``(u, omega)``
        [m/s, rad/s] normalised to unit live-load power ``F_L . u = 1``; zero on supported
        dofs.
    dead_power : float
        ``F_D . u`` [W] (for the associated problem ``-dead_power`` equals ``lam``).
    certificate : Certificate
    compile_s, solve_s, wall_s : float
        cvxpy compilation, Clarabel and total time [s].
    n_blocks, n_free_dofs, n_interfaces, n_cones : int
    settings : dict
    """

    lam: float
    status: str
    is_inaccurate: bool
    model: str
    friction: str
    interface_forces: np.ndarray
    vertex_forces: np.ndarray | None
    velocities: np.ndarray
    dead_power: float
    certificate: Certificate
    compile_s: float
    solve_s: float
    wall_s: float
    n_blocks: int
    n_free_dofs: int
    n_interfaces: int
    n_cones: int
    settings: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """Scalars for a validation row."""
        return {
            "lam": self.lam,
            "status": self.status,
            "model": self.model,
            "n_blocks": self.n_blocks,
            "n_interfaces": self.n_interfaces,
            "solve_s": self.solve_s,
            "wall_s": self.wall_s,
            "certificate_worst": self.certificate.worst(),
            "duality_gap": self.certificate.duality_gap,
        }


def check_scene(scene: Scene) -> None:
    """Structural checks before solving; raise :class:`LimitAnalysisError` in plain words."""
    sup = scene.supports
    if not sup.has_any:
        raise LimitAnalysisError(
            "the scene has no supports (no fixed block, no restrained dof): nothing carries "
            "the dead load, so the structure falls down by itself."
        )
    interfaces = scene.assembly.interfaces()
    touched = np.zeros(scene.n_blocks, dtype=bool)
    touched[interfaces.block_a] = True
    touched[interfaces.block_b] = True
    free = sup.free_dofs
    dead = scene.dead_wrench
    lonely = np.flatnonzero(~touched & free.any(axis=1) & (np.abs(dead) * free).any(axis=1))
    if lonely.size:
        raise LimitAnalysisError(
            f"blocks {lonely[:10].tolist()} touch no other block and are loaded on a free dof: "
            "they fall down by themselves (missing support)."
        )
    live = scene.loads.live_wrench
    if not np.any(live[free] != 0):
        raise LimitAnalysisError(
            "the live load is zero on every free dof: it never does work, so the multiplier is "
            "unbounded (no collapse mechanism); define a live load on free blocks."
        )


def _clarabel_options(settings: LimitSettings, refine: bool = True) -> dict:
    t = settings.tol
    return {
        "tol_gap_abs": t,
        "tol_gap_rel": t,
        "tol_feas": t,
        "tol_ktratio": max(t, 1e-8),
        "max_iter": settings.max_iter,
        "iterative_refinement_enable": refine,
        **settings.clarabel,
    }


def _run_clarabel(
    problem: cp.Problem,
    settings: LimitSettings,
    label: str,
    msg_infeasible: str,
    msg_unbounded: str,
    refine: bool = True,
    warn: bool = True,
) -> str:
    """Solve with Clarabel and map the status: return ``optimal`` or ``optimal_inaccurate``
    (with a warning if ``warn``); raise :class:`LimitAnalysisError` with the structural message
    otherwise. ``refine``: Clarabel's iterative refinement of every KKT solve.
    """
    try:
        opts = _clarabel_options(settings, refine)
        problem.solve(solver=cp.CLARABEL, ignore_dpp=True, **opts)
    except cp.error.SolverError as exc:
        raise LimitAnalysisError(f"Clarabel failed: {exc}") from exc
    status = problem.status
    if status in ("infeasible", "infeasible_inaccurate"):
        raise LimitAnalysisError(f"{msg_infeasible} [{label} status {status}]")
    if status in ("unbounded", "unbounded_inaccurate"):
        raise LimitAnalysisError(f"{msg_unbounded} [{label} status {status}]")
    if status not in ACCEPTED:
        raise LimitAnalysisError(f"no certified optimum: {label} status {status!r}")
    if status == "optimal_inaccurate" and warn:
        warnings.warn(f"limit analysis: {label} status optimal_inaccurate", stacklevel=3)
    return status


def solve_static(sp_: StaticProblem, certify: bool = True) -> LimitResult:
    """Solve a compiled programme, map its status and certify the solution.

    Parameters
    ----------
    sp_ : StaticProblem
    certify : bool
        Compute the certificate and reject it above ``settings.cert_tol``.

    Raises
    ------
    LimitAnalysisError
        Infeasible, unbounded, solver failure, or a failed certificate.
    """
    settings = sp_.settings
    implied = sp_.extra.get("implied_sign")
    if implied is not None and np.any(np.asarray(sp_.mu.value)[implied] <= 0):
        raise ValueError(
            "mu was set to zero at corners whose p >= 0 row was left out as implied by the "
            "friction cone: build the programme with mu = 0 in its settings instead"
        )
    t0 = time.perf_counter()
    # A programme of second-order cones only (vertex model) is first solved without Clarabel's
    # iterative refinement of the KKT solves, which costs 15-25 % on large walls and changed no
    # certified result we measured; the refinement is switched back on, and the programme
    # solved again, when that fast solve is inaccurate, fails, or fails its certificate.
    rejected_s = 0.0
    if sp_.model == "vertex" and "iterative_refinement_enable" not in settings.clarabel:
        try:
            status = _run_clarabel(
                sp_.problem,
                settings,
                "solver",
                MSG_INFEASIBLE,
                MSG_UNBOUNDED,
                refine=False,
                warn=False,
            )
            if status == "optimal":
                return _read_solution(sp_, status, certify, t0)
        except LimitAnalysisError as exc:
            logger.info("solve without iterative refinement rejected (%s); refining", exc)
        stats = sp_.problem.solver_stats
        rejected_s = float(stats.solve_time or 0.0) if stats else 0.0
    status = _run_clarabel(sp_.problem, settings, "solver", MSG_INFEASIBLE, MSG_UNBOUNDED)
    return _read_solution(sp_, status, certify, t0, rejected_s)


def _read_solution(
    sp_: StaticProblem, status: str, certify: bool, t0: float, rejected_s: float = 0.0
) -> LimitResult:
    """Forces, mechanism and certificate of the solved programme (timed from ``t0``; the
    Clarabel time ``rejected_s`` of a rejected first solve is added to ``solve_s``)."""
    settings = sp_.settings
    wall = time.perf_counter() - t0
    stats = sp_.problem.solver_stats
    solve_s = float(stats.solve_time) if stats and stats.solve_time is not None else wall
    solve_s += rejected_s
    if status == "optimal_inaccurate":
        logger.warning("solver status optimal_inaccurate (%s model)", sp_.model)

    lam = float(sp_.lam.value) * sp_.lam_scale
    f = sp_.interface_forces()
    vertex_forces = None
    if sp_.model == "vertex":
        nv = len(sp_.vertex_iface)
        vertex_forces = np.stack([np.ravel(v.value) for v in sp_.x_vars[:3]], axis=1)
        vertex_forces = vertex_forces * sp_.weight
        assert vertex_forces.shape == (nv, 3)
    # equilibrium duals -> block velocities (z = -y for cvxpy's Equality)
    z = -np.asarray(sp_.equilibrium.dual_value, dtype=float)
    u_free = z * sp_.row_scale
    live_power = float(sp_.live @ u_free)
    if live_power != 0:
        u_free = u_free / live_power
    vel = np.zeros(6 * sp_.scene.n_blocks)
    vel[sp_.free] = u_free
    dead_eff = sp_.dead + sp_.a_eq @ sp_.f_offset
    dead_power = float(dead_eff @ u_free)

    cert = _certificate(sp_, f, vertex_forces, lam) if certify else None
    if cert is not None and cert.worst() > settings.cert_tol:
        raise LimitAnalysisError(
            f"the solution failed its certificate (worst relative residual {cert.worst():.2e} "
            f"> cert_tol {settings.cert_tol:.1e}): {cert.to_dict()}"
        )
    return LimitResult(
        lam=lam,
        status=status,
        is_inaccurate=status == "optimal_inaccurate",
        model=sp_.model,
        friction=sp_.friction,
        interface_forces=f.reshape(-1, 6),
        vertex_forces=vertex_forces,
        velocities=vel.reshape(-1, 6),
        dead_power=dead_power,
        certificate=cert,
        compile_s=max(wall - solve_s, 0.0) + float(sp_.extra.get("build_s", 0.0)),
        solve_s=solve_s,
        wall_s=wall + float(sp_.extra.get("build_s", 0.0)),
        n_blocks=sp_.scene.n_blocks,
        n_free_dofs=int(sp_.free.sum()),
        n_interfaces=sp_.interfaces.n_interfaces,
        n_cones=sp_.n_cones,
        settings=settings.to_dict(),
    )


def _certificate(sp_: StaticProblem, f, vertex_forces, lam) -> Certificate:
    conic = conic_certificate(sp_.problem)
    eq = equilibrium_residual(sp_.a_eq, f.ravel(), sp_.dead, sp_.live, lam, sp_.row_scale)
    if sp_.friction == "coulomb" and sp_.settings.friction_polygon is None:
        mu_now = np.asarray(sp_.mu.value, float)
        tensile = sp_.settings.tensile_strength * sp_.interfaces.area
        if sp_.model == "vertex":
            shifted = vertex_forces.copy()
            yres = yield_residual(
                "vertex",
                f.reshape(-1, 6),
                None,
                None,
                tensile,
                sp_.weight,
                vertex_forces=shifted,
                vertex_mu=mu_now,
            )
        else:
            alpha = sp_.settings.torsion_alpha if sp_.settings.torsion == "interaction" else None
            g, h, owner = rocking_constraints(sp_.interfaces)
            yres = yield_residual(
                "resultant",
                f.reshape(-1, 6),
                mu_now,
                sp_.c_t,
                tensile,
                sp_.weight,
                alpha=alpha,
                rocking=(g, h, owner),
            )
    else:
        yres = float("nan")
    return Certificate(
        primal_residual=conic["primal_residual"],
        equilibrium_residual=eq,
        yield_residual=yres,
        dual_cone_residual=conic["dual_cone_residual"],
        stationarity=conic["stationarity"],
        duality_gap=conic["duality_gap"],
        complementarity=conic["complementarity"],
        dual_objective=conic["dual_objective"] * sp_.lam_scale,
    )


def limit_analysis(
    scene: Scene, settings: LimitSettings | None = None, certify: bool = True
) -> LimitResult:
    """Associated static limit analysis of a scene (build, solve, certify).

    Parameters
    ----------
    scene : Scene
    settings : LimitSettings, optional
    certify : bool

    Returns
    -------
    LimitResult
        ``lam`` is the associated collapse multiplier of the chosen interface model: an upper
        bound for non-associated (zero-dilatancy) friction.
    """
    settings = settings or LimitSettings()
    check_scene(scene)
    t0 = time.perf_counter()
    sp_ = build_static_problem(scene, settings)
    sp_.extra["build_s"] = time.perf_counter() - t0
    return solve_static(sp_, certify=certify)


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
    LimitAnalysisError
        With the structural message of the static programme: the kinematic programme is
        unbounded below when the structure falls by itself and infeasible when no mechanism
        exists.
    """
    settings = settings or LimitSettings()
    check_scene(scene)
    kp = build_kinematic_problem(scene, settings)
    # by conic duality the kinematic programme is unbounded where the static one is infeasible
    status = _run_clarabel(kp.problem, settings, "kinematic", MSG_UNBOUNDED, MSG_INFEASIBLE)
    u = np.asarray(kp.velocity.value, float) * kp.row_scale
    live = scene.loads.live_wrench.ravel()[kp.free]
    u = u / float(live @ u)
    vel = np.zeros(6 * scene.n_blocks)
    vel[kp.free] = u
    return float(kp.problem.value) * kp.lam_scale, vel.reshape(-1, 6), status
