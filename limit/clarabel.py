r"""Solve a compiled static programme with Clarabel: status map, retries, certificate.

Status vocabulary (cvxpy's). ``optimal`` is read and certified (:mod:`limit.certificates`).
``optimal_inaccurate``, a solver error or a failed certificate is retried, first with
Clarabel's iterative refinement (when the first solve went without it), then with
interior-point steps capped at :data:`SHORT_STEP` of the way to the cone boundary (a
different, more central path: a stall, Clarabel's ``InsufficientProgress`` or
``AlmostSolved`` with steps shrunk to nothing, recurs identically in a repeated solve), then
with tolerances a hundred times tighter and twice the iterations. Every
``optimal_inaccurate`` point is certified as it comes; when no attempt ends ``optimal``, the
certified one with the smallest worst residual is returned with that status and one warning,
and without any a single :class:`~limit.errors.NumericalFailureError` lists every attempt.
``infeasible`` raises :class:`~limit.errors.DeadLoadInfeasibleError` (the structure falls
down by itself) and ``unbounded`` :class:`~limit.errors.NoMechanismError` (no collapse
mechanism); their ``_inaccurate`` variants are retried first.
"""

from __future__ import annotations

import logging
import time
import warnings
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np

from dem.estimate import Estimate
from limit.certificates import (
    LOCAL_TOL,
    Certificate,
    conic_certificate,
    equilibrium_residual,
    local_residual,
    yield_violations,
)
from limit.errors import (
    DeadLoadInfeasibleError,
    LimitAnalysisError,
    NoMechanismError,
    NumericalFailureError,
)
from limit.lambda_error import solver_estimate
from limit.matrices import rocking_constraints
from limit.problems import LimitSettings, StaticProblem

logger = logging.getLogger(__name__)

__all__ = [
    "ACCEPTED",
    "MSG_INFEASIBLE",
    "MSG_UNBOUNDED",
    "STATIC_OUTCOMES",
    "Attempt",
    "LimitResult",
    "run_clarabel",
    "solve_static",
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

STATIC_OUTCOMES = {
    "infeasible": (DeadLoadInfeasibleError, MSG_INFEASIBLE),
    "unbounded": (NoMechanismError, MSG_UNBOUNDED),
}
"""Structural outcome of each terminal status of the static programme: (error type, message)."""

TIGHTEN = 1e-2
"""Factor on Clarabel's tolerances in the last attempt."""

SHORT_STEP = 0.9
"""Clarabel's ``max_step_fraction`` in the short-step attempt (its default is 0.99)."""


@dataclass(frozen=True)
class Attempt:
    """One Clarabel solve: ``refine`` its KKT solves, tolerances times ``tol_factor``,
    iteration limit times ``iter_factor``, steps capped at ``max_step`` (Clarabel's default
    when None)."""

    label: str
    refine: bool = True
    tol_factor: float = 1.0
    iter_factor: int = 1
    max_step: float | None = None

    def options(self, settings: LimitSettings) -> dict:
        t = max(settings.tol * self.tol_factor, 1e-14)
        step = {} if self.max_step is None else {"max_step_fraction": self.max_step}
        return {
            "tol_gap_abs": t,
            "tol_gap_rel": t,
            "tol_feas": t,
            "tol_ktratio": max(t, 1e-8),
            "max_iter": settings.max_iter * self.iter_factor,
            "iterative_refinement_enable": self.refine,
            **step,
            **settings.clarabel,
        }


REFINED = Attempt("refined")
SHORT_STEPS = Attempt("short steps", max_step=SHORT_STEP)
TIGHTENED = Attempt("tightened", tol_factor=TIGHTEN, iter_factor=2)


@dataclass
class LimitResult:
    """A certified solution of the static programme.

    Attributes
    ----------
    lam : float
        Load multiplier [-] (or [Pa] for a unit-pressure live load).
    status : str
        ``"optimal"`` or ``"optimal_inaccurate"`` (certified after the retries).
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
    certificate : Certificate or None
        None only when the caller asked for no certificate and the solve was ``optimal``.
    compile_s, solve_s, wall_s : float
        cvxpy compilation, Clarabel (all attempts) and total time [s].
    n_blocks, n_free_dofs, n_interfaces, n_cones : int
    settings : dict
    attempts : list of (str, str)
        ``(attempt, status)`` of every Clarabel solve, in order.
    lambda_estimate : Estimate
        ``lam`` with the half-width of the interval that holds the exact optimum of this
        programme, by source (:mod:`limit.lambda_error`): the solver's duality gap and
        feasibility shift, and the friction polygon's bracket where
        :func:`limit.limit_analysis` computed one. Unknown (``inf``) without a certificate.
        It is not the distance to the non-associated collapse multiplier
        (:mod:`limit.estimates`).
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
    certificate: Certificate | None
    compile_s: float
    solve_s: float
    wall_s: float
    n_blocks: int
    n_free_dofs: int
    n_interfaces: int
    n_cones: int
    settings: dict = field(default_factory=dict)
    attempts: list = field(default_factory=list)
    lambda_estimate: Estimate | None = None

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
            "lambda_estimate": None
            if self.lambda_estimate is None
            else self.lambda_estimate.to_dict(),
        }


def run_clarabel(
    problem: cp.Problem, settings: LimitSettings, attempt: Attempt = REFINED
) -> tuple[str, float]:
    """One Clarabel solve; return cvxpy's status (``"solver_error"`` when Clarabel raised)
    and the solver time [s]. cvxpy's own warning on an inaccurate status is silenced: the
    status is returned, and :func:`solve_static` retries, refuses or warns once itself.

    Every solve starts a new Clarabel solver (``warm_start=False``). cvxpy's default would
    hand a re-solved problem (new parameter values, or the next attempt) to the solver of the
    previous solve through Clarabel's data update, which keeps the Ruiz equilibration
    computed for the first data; with capacities that changed by orders of magnitude (the
    fixed-capacity iteration) that scaling no longer fits and Clarabel can fail where a new
    solver on the same data converges. A re-solve is thus the same as a fresh solve."""
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Solution may be inaccurate")
            problem.solve(
                solver=cp.CLARABEL,
                ignore_dpp=True,
                warm_start=False,
                **attempt.options(settings),
            )
    except cp.error.SolverError as exc:
        logger.info("Clarabel failed (%s attempt): %s", attempt.label, exc)
        return "solver_error", 0.0
    stats = problem.solver_stats
    solve_s = float(stats.solve_time) if stats and stats.solve_time is not None else 0.0
    return problem.status, solve_s


def structural_error(status: str, outcomes: dict, history: str) -> LimitAnalysisError | None:
    """The structural error of an infeasible or unbounded status (None for other statuses)."""
    base = status.removesuffix("_inaccurate")
    if base not in outcomes:
        return None
    cls, msg = outcomes[base]
    return cls(f"{msg} [{history}]")


def attempts_for(sp_: StaticProblem) -> tuple[Attempt, ...]:
    """The Clarabel attempts of a programme, in order: one of second-order cones only (vertex
    model) is first solved without iterative refinement of the KKT solves (the certificate
    decides whether that solve is good enough; refinement is the next attempt)."""
    if sp_.model == "vertex" and "iterative_refinement_enable" not in sp_.settings.clarabel:
        return (Attempt("fast", refine=False), REFINED, SHORT_STEPS, TIGHTENED)
    return (REFINED, SHORT_STEPS, TIGHTENED)


def solve_static(
    sp_: StaticProblem, certify: bool = True, feasibility: bool = False
) -> LimitResult:
    """Solve a compiled programme, map its status and certify the solution (module notes).

    Parameters
    ----------
    sp_ : StaticProblem
    certify : bool
        Compute the certificate of an ``optimal`` solve and reject it above
        ``settings.cert_tol``. An ``optimal_inaccurate`` one is always certified.
    feasibility : bool
        The programme only asks whether a point exists (its multiplier is fixed): a solution
        is certified by its primal residuals alone (:meth:`Certificate.worst`).

    Raises
    ------
    DeadLoadInfeasibleError, NoMechanismError
        The programme is infeasible (falls down by itself) or unbounded (no mechanism).
    NumericalFailureError
        No attempt gave a solution that passes its certificate.
    """
    settings = sp_.settings
    implied = sp_.extra.get("implied_sign")
    if implied is not None and np.any(np.asarray(sp_.mu.value)[implied] <= 0):
        raise ValueError(
            "mu was set to zero at corners whose p >= 0 row was left out as implied by the "
            "friction cone: build the programme with mu = 0 in its settings instead"
        )
    t0 = time.perf_counter()
    solve_s = 0.0
    history: list[tuple[str, str]] = []
    failure = rejected = ""
    best: LimitResult | None = None
    attempts = attempts_for(sp_)
    for i, attempt in enumerate(attempts):
        last = i == len(attempts) - 1
        status, dt = run_clarabel(sp_.problem, settings, attempt)
        solve_s += dt
        history.append((attempt.label, status))
        text = ", ".join(f"{a} {s}" for a, s in history)
        err = structural_error(status, STATIC_OUTCOMES, f"solver status: {text}")
        # an accurate infeasible/unbounded answer of a refined solve is final; an inaccurate
        # one, or one from the fast solve, is tried again while attempts remain
        accurate = attempt.refine and not status.endswith("_inaccurate")
        if err is not None and (accurate or last):
            raise err
        if status not in ACCEPTED:
            failure = f"solver status {status}"
            continue
        result = _read_solution(sp_, status, certify or status != "optimal", t0, solve_s)
        cert = result.certificate
        if cert is not None and not _certified(cert, settings, feasibility):
            failure = rejected = _certificate_failure(cert, settings, feasibility)
            logger.info("%s attempt rejected: %s", attempt.label, failure)
            continue
        if status == "optimal":
            result.attempts = history
            return result
        if best is None or cert.worst(feasibility) < best.certificate.worst(feasibility):
            best = result
    if best is not None:
        _retime(best, sp_, t0, solve_s)
        best.attempts = history
        warnings.warn(
            f"limit analysis: Clarabel ended optimal_inaccurate ({text}); the point passed "
            f"its certificate (worst residual {best.certificate.worst(feasibility):.1e} <= "
            f"cert_tol {settings.cert_tol:.0e}) and is returned with that status",
            stacklevel=2,
        )
        return best
    raise NumericalFailureError(
        f"no certified optimum after {len(history)} Clarabel solves ({text}); last: {failure}"
        + (f"; before it, {rejected}" if rejected and rejected != failure else "")
        + ". "
        "Try a tighter LimitSettings.tol, more max_iter, or rescale the scene (units)."
    )


def _retime(result: LimitResult, sp_: StaticProblem, t0: float, solve_s: float) -> None:
    """Set the times of a result read before the last attempt to those of the whole solve
    (started at ``t0``; ``solve_s`` is the Clarabel time of every attempt)."""
    wall = time.perf_counter() - t0
    build_s = float(sp_.extra.get("build_s", 0.0))
    result.solve_s = solve_s
    result.compile_s = max(wall - solve_s, 0.0) + build_s
    result.wall_s = wall + build_s


def _certificate_failure(cert: Certificate, settings: LimitSettings, feasibility: bool) -> str:
    """Why a certificate failed, in words."""
    worst = cert.worst(feasibility)
    if worst > settings.cert_tol:
        what = "primal residual" if feasibility else "relative residual"
        why = f"worst {what} {worst:.2e} > cert_tol {settings.cert_tol:.1e}"
    else:
        why = (
            f"residual relative to the loads of its own blocks {cert.local_residual:.2e} > "
            f"LOCAL_TOL {LOCAL_TOL:.0e}: a block much lighter than the whole is not resolved"
        )
    return f"the solution failed its certificate ({why}): {cert.to_dict()}"


def _certified(cert: Certificate, settings: LimitSettings, feasibility: bool = False) -> bool:
    """Every residual (primal ones only for a ``feasibility`` programme) within ``cert_tol``
    of the total weight, and within :data:`LOCAL_TOL` of the loads of the blocks concerned."""
    worst = cert.worst(feasibility)
    return worst <= settings.cert_tol and not cert.local_residual > LOCAL_TOL


def _read_solution(
    sp_: StaticProblem, status: str, certify: bool, t0: float, solve_s: float
) -> LimitResult:
    """Forces, mechanism and certificate of the solved programme (timed from ``t0``;
    ``solve_s`` is the Clarabel time of every attempt so far)."""
    settings = sp_.settings
    wall = time.perf_counter() - t0
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
    cert = static_certificate(sp_, f, vertex_forces, lam) if certify else None
    build_s = float(sp_.extra.get("build_s", 0.0))
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
        compile_s=max(wall - solve_s, 0.0) + build_s,
        solve_s=solve_s,
        wall_s=wall + build_s,
        n_blocks=sp_.scene.n_blocks,
        n_free_dofs=int(sp_.free.sum()),
        n_interfaces=sp_.interfaces.n_interfaces,
        n_cones=sp_.n_cones,
        settings=settings.to_dict(),
        lambda_estimate=solver_estimate(lam, cert),
    )


def static_certificate(sp_: StaticProblem, f, vertex_forces, lam) -> Certificate:
    """Certificate of a solved static programme: the conic residuals of
    :func:`conic_certificate`, the equilibrium and the interface strength recomputed in SI,
    both also relative to the loads of the blocks concerned (:func:`local_residual`)."""
    conic = conic_certificate(sp_.problem)
    eq = equilibrium_residual(sp_.a_eq, f.ravel(), sp_.dead, sp_.live, lam, sp_.row_scale)
    viol = _interface_violations(sp_, f, vertex_forces)
    yres = float("nan") if viol is None else float(np.max(viol, initial=0.0)) / sp_.weight
    return Certificate(
        primal_residual=conic["primal_residual"],
        equilibrium_residual=eq,
        yield_residual=yres,
        dual_cone_residual=conic["dual_cone_residual"],
        stationarity=conic["stationarity"],
        duality_gap=conic["duality_gap"],
        complementarity=conic["complementarity"],
        dual_objective=conic["dual_objective"] * sp_.lam_scale,
        local_residual=_local_residual(sp_, f, lam, viol),
        feasibility_shift=conic["feasibility_shift"] * sp_.lam_scale,
        stationarity_shift=conic["stationarity_shift"] * sp_.lam_scale,
        dual_cone_shift=conic["dual_cone_shift"] * sp_.lam_scale,
    )


def _interface_violations(sp_: StaticProblem, f, vertex_forces) -> np.ndarray | None:
    """Strength violation of each interface [N] (:func:`yield_violations`); None for the
    fixed-capacity programme and inscribed polygons (not the Coulomb cone)."""
    if sp_.friction != "coulomb" or sp_.settings.friction_polygon is not None:
        return None
    # the Parameter holds 0 where mu = inf (no cone): the residual must see inf there
    mu_set = sp_.mu_interface[sp_.vertex_iface] if sp_.model == "vertex" else sp_.mu_interface
    mu_now = np.where(np.isfinite(mu_set), np.asarray(sp_.mu.value, float), np.inf)
    tensile = sp_.settings.tensile_strength * sp_.interfaces.area
    if sp_.model == "vertex":
        corner = yield_violations(
            "vertex", f.reshape(-1, 6), None, None, tensile,
            vertex_forces=vertex_forces, vertex_mu=mu_now,
        )  # fmt: skip
        viol = np.full(sp_.interfaces.n_interfaces, -np.inf)
        np.maximum.at(viol, sp_.vertex_iface, corner)
        return viol
    alpha = sp_.settings.torsion_alpha if sp_.settings.torsion == "interaction" else None
    return yield_violations(
        "resultant", f.reshape(-1, 6), mu_now, sp_.c_t, tensile,
        alpha=alpha, rocking=rocking_constraints(sp_.interfaces),
    )  # fmt: skip


def _local_residual(sp_: StaticProblem, f, lam: float, viol: np.ndarray | None) -> float:
    """:func:`local_residual` of the solution: per-block equilibrium residuals (moments
    divided by the block size) and interface violations against each block's own loads
    ``|F_D| + lambda |F_L|`` [N]."""
    n = sp_.scene.n_blocks
    rows = np.flatnonzero(sp_.free)
    owner, dof = rows // 6, rows % 6
    sizes = np.array([b.size for b in sp_.scene.assembly.blocks])
    r = np.abs(sp_.a_eq @ f.ravel() + sp_.dead + lam * sp_.live)
    r = np.where(dof < 3, r, r / sizes[owner])
    block_res = np.zeros(n)
    np.maximum.at(block_res, owner, r)
    dead = sp_.scene.dead_wrench.reshape(-1, 6)[:, :3]
    live = sp_.scene.loads.live_wrench.reshape(-1, 6)[:, :3]
    # without any dead load (the dead-load check, whose live pattern is the dead load) the
    # loads vanish with lambda (a structure that falls): lambda is then taken no smaller
    # than its unit
    scale = abs(lam) if np.any(sp_.dead) else max(abs(lam), sp_.lam_scale)
    load = np.linalg.norm(dead, axis=1) + scale * np.linalg.norm(live, axis=1)
    load = np.where(sp_.scene.supports.fixed, np.inf, load)
    itf = sp_.interfaces
    violation = np.zeros(itf.n_interfaces) if viol is None else viol
    return local_residual(block_res, violation, itf.block_a, itf.block_b, load)
