r"""Bounds and estimates of the collapse multiplier with non-associated Coulomb friction.

Dry joints slide without dilatancy, so the normality rule of the static programme
(:mod:`limit.problems`) does not hold and its solution is not the collapse multiplier. What
is proven, and what is not:

upper bound (proven)
    The associated solution :math:`\lambda^+` (Radenkovic's first theorem: the
    non-associated collapse multiplier never exceeds the associated one of the same yield
    surface).
lower bound (proven)
    Radenkovic's second theorem: the associated solution with the plastic potential as yield
    surface bounds the non-associated multiplier from below. For zero dilatancy the
    potential through the apex of the Coulomb cone is the frictionless joint, so
    :math:`\lambda^- = \lambda^+(\mu = 0)`. Out-of-plane loaded walls usually give 0 (and no
    value at all when the frictionless structure cannot carry its own weight).
estimate (a), not a bound
    The associated problem with the reduced friction :math:`\mu^* = \mu / \sqrt{1 + \mu^2}`
    (:math:`\tan\varphi^* = \sin\varphi`), the friction of a non-dilatant joint in the
    Davis-type reduction.
estimate (b), not a bound
    A sequence of convex problems with a modified failure surface (after Gilbert, Casapulla
    and Ahmed 2006): the friction capacity of every cone is frozen at
    :math:`\mu\,c^{(k-1)}` from the normal forces of the previous solution, which makes the
    surface flat in the normal direction (so normality gives zero dilatancy); the capacities
    are updated with relaxation ``omega`` until lambda and the normal forces settle. The whole
    history of lambda and a convergence flag are returned; the iteration may cycle (the normal
    forces of a programme are not unique), in which case it is reported as not converged. A
    last iterate that is neither converged nor admissible and lies above the upper bound is
    withdrawn (no estimate, with a note): it cannot be the non-associated multiplier.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from dem.estimate import Estimate
from dem.scene import Scene
from limit.deadload import require_standing, stands
from limit.errors import (
    DeadLoadInfeasibleError,
    InconsistentBoundsError,
    LimitAnalysisError,
    NoMechanismError,
)
from limit.lambda_error import iteration_tail
from limit.problems import LimitSettings, StaticProblem, build_static_problem, checked_inputs
from limit.solve import LimitResult, check_scene, limit_analysis, solve_static

logger = logging.getLogger(__name__)

__all__ = [
    "reduced_friction",
    "IterativeEstimate",
    "iterative_estimate",
    "frictionless_lower_bound",
    "frictionless_lower_estimate",
    "Bounds",
    "bounds_and_estimates",
]


def reduced_friction(mu: float) -> float:
    r""":math:`\mu^* = \mu/\sqrt{1+\mu^2}` (:math:`\tan\varphi^* = \sin\varphi`) [-].

    ``mu = inf`` (a joint that cannot slide) stays inf: no sliding, no dilatancy question.
    """
    return float(_reduced(np.array([float(mu)]))[0])


def _reduced(mu: np.ndarray) -> np.ndarray:
    finite = np.isfinite(mu)
    safe = np.where(finite, mu, 0.0)
    return np.where(finite, safe / np.sqrt(1.0 + safe**2), np.inf)


def _finite(mu: np.ndarray) -> np.ndarray:
    """``mu`` with 0 where it is inf: those joints have no friction cone to size."""
    return np.where(np.isfinite(mu), mu, 0.0)


def default_updates(scene: Scene) -> int:
    """Default budget of capacity updates of estimate (b): ``max(30, 2 n_free)``, since the
    iteration settles a few blocks per update."""
    return max(MIN_UPDATES, 2 * int(np.count_nonzero(~scene.supports.fixed)))


MIN_UPDATES = 30
"""Smallest default budget of capacity updates."""


def _refuse_renamed(kw: dict) -> None:
    if "max_iter" in kw:
        raise TypeError(
            "max_iter was renamed max_updates: the budget of capacity updates of estimate (b) "
            "(LimitSettings.max_iter is Clarabel's iteration limit, a different thing)"
        )
    if kw:
        raise TypeError(f"unexpected keyword arguments {sorted(kw)}")


@dataclass
class IterativeEstimate:
    """History of the fixed-capacity iteration (estimate (b)).

    Attributes
    ----------
    lam : float or None
        Last multiplier (an estimate, not a bound) [-]; None when it was withdrawn
        (``note``).
    history : list of float
        lambda of the associated start and of every iteration.
    converged : bool
        ``|lam_k - lam_{k-1}| <= tol max(1, |lam_k|)`` and the normal forces changed by less
        than ``tol`` (relative to the weight) in the last step.
    admissible : bool
        The last iterate satisfies the Coulomb condition with its own normal forces (to
        ``tol`` relative to the weight): it is then statically admissible for the associated
        problem, so ``lam <= `` the associated upper bound.
    coulomb_excess : float
        Largest ``|V| - mu c`` of the last iterate with its own normal forces, over ``W``.
    n_iter : int
    omega : float
        Relaxation of the capacity update.
    result : LimitResult or None
        The last solve (forces and mechanism of the estimate).
    failure : str
        Why the iteration stopped early ("" when it did not).
    wall_s : float
    note : str
        Why ``lam`` was withdrawn ("" when it was not): :func:`bounds_and_estimates` withdraws
        a last iterate that is neither converged nor admissible and lies above the upper
        bound, which the non-associated multiplier never exceeds.
    """

    lam: float | None
    history: list
    converged: bool
    admissible: bool
    coulomb_excess: float
    n_iter: int
    omega: float
    result: LimitResult | None
    failure: str = ""
    wall_s: float = 0.0
    note: str = ""

    @property
    def estimate(self) -> Estimate | None:
        """``lam`` with its error bar: the last solve's solver error and the ``"iteration"``
        tail of the history (:mod:`limit.lambda_error`); None when ``lam`` is."""
        if self.lam is None:
            return None
        base = (
            Estimate.unknown(self.lam, "no solve of the iteration")
            if self.result is None
            else self.result.lambda_estimate
        )
        tail = iteration_tail(self.history, resolution=2.0 * base.error)
        sources = {**base.sources, "iteration": tail}
        return Estimate(self.lam, sources, base.cost_s, base.notes)

    def withdraw_above(self, upper: float, lam_unit: float) -> None:
        """Withdraw ``lam`` if it is neither converged nor admissible and lies above the
        ``upper`` bound (an admissible or converged iterate above it is left for the
        ordering check: that would be an inconsistency, not a cut iteration)."""
        if self.converged or self.admissible or not _above(self.lam, upper, lam_unit):
            return
        self.note = (
            f"no estimate (b): the last iterate {self.lam:.6g} lies above the upper bound "
            f"{upper:.6g}; it did not converge in {self.n_iter} updates and violates Coulomb "
            f"with its own normal forces (excess {self.coulomb_excess:.2g} W)"
            + (f"; {self.failure}" if self.failure else "")
        )
        self.lam = None


def _above(a: float | None, b: float | None, unit: float, rtol: float = 1e-6) -> bool:
    """``a > b`` beyond a relative allowance (absolute in units of lambda ``unit``)."""
    return a is not None and b is not None and a > b * (1 + rtol) + rtol * unit


def _normal_capacity(sp_: StaticProblem, result: LimitResult) -> np.ndarray:
    """Scaled normal force carrying friction: corner ``p`` (vertex) or ``c = f_t - N``."""
    if sp_.model == "vertex":
        return np.maximum(result.vertex_forces[:, 0], 0.0) / sp_.weight
    f_t = sp_.settings.tensile_strength * sp_.interfaces.area
    return np.maximum(f_t - result.interface_forces[:, 0], 0.0) / sp_.weight


def _coulomb_excess(fixed: StaticProblem, result: LimitResult, cap_n: np.ndarray) -> float:
    """Largest shear (and, resultant model, torsion) excess over ``mu c`` with the iterate's
    own normal forces, relative to the weight."""
    mu = _finite(fixed.mu_interface)  # mu = inf: never slides, so never in excess
    if fixed.model == "vertex":
        s = np.linalg.norm(result.vertex_forces[:, 1:], axis=1) / fixed.weight
        s = np.where(np.isfinite(fixed.mu_interface[fixed.vertex_iface]), s, 0.0)
        return float(np.max(s - mu[fixed.vertex_iface] * cap_n, initial=0.0))
    f = result.interface_forces
    v = np.linalg.norm(f[:, 1:3], axis=1) / fixed.weight
    m3 = np.abs(f[:, 5]) / fixed.weight
    cap = mu * cap_n
    fin = np.isfinite(fixed.mu_interface)
    out = np.where(fin, np.maximum(v - cap, m3 - fixed.c_t * cap), 0.0)
    if fixed.settings.torsion == "interaction":
        alpha = fixed.settings.torsion_alpha
        with np.errstate(divide="ignore", invalid="ignore"):
            lhs = (m3 / (fixed.c_t * cap)) ** alpha + (v / cap) ** 2
        # where cap = 0 the shear and torsion terms above already measure the excess
        safe = np.where(cap > 0, lhs, 1.0)
        out = np.maximum(out, np.where(fin & (cap > 0), cap * (np.sqrt(safe) - 1.0), 0.0))
    return float(np.max(out, initial=0.0))


def _set_capacity(fixed: StaticProblem, cap_n: np.ndarray, mu: np.ndarray) -> None:
    mu = _finite(mu)  # cones with mu = inf are not in the programme
    if fixed.model == "vertex":
        fixed.capacity["shear"].value = mu[fixed.vertex_iface] * cap_n
    else:
        fixed.capacity["shear"].value = mu * cap_n
        fixed.capacity["torsion"].value = fixed.c_t / fixed.length * mu * cap_n


def iterative_estimate(
    scene: Scene,
    settings: LimitSettings | None = None,
    max_updates: int | None = None,
    omega: float = 0.5,
    tol: float = 1e-4,
    start: LimitResult | None = None,
    **renamed,
) -> IterativeEstimate:
    """Estimate (b): fixed-capacity iteration from the associated solution.

    Parameters
    ----------
    scene : Scene
    settings : LimitSettings, optional
    max_updates : int, optional
        Largest number of capacity updates (re-solves); default :func:`default_updates`.
        (``max_iter`` is refused: it names Clarabel's limit in :class:`LimitSettings`.)
    omega : float
        Relaxation in (0, 1]: ``c_cap <- (1 - omega) c_cap + omega c_new``.
    tol : float
        Convergence tolerance on lambda and the normal forces (relative) [-].
    start : LimitResult, optional
        The associated solution (computed if not given).

    Returns
    -------
    IterativeEstimate
    """
    _refuse_renamed(renamed)
    settings = checked_inputs(scene, settings)
    if not 0 < omega <= 1:
        raise ValueError(f"omega must lie in (0, 1], got {omega}")
    if not 0 < tol < 1:
        raise ValueError(f"tol must lie in (0, 1), got {tol}")
    if max_updates is None:
        max_updates = default_updates(scene)
    if isinstance(max_updates, bool) or not isinstance(max_updates, int) or max_updates < 1:
        raise ValueError(f"max_updates must be an integer >= 1, got {max_updates!r}")
    t0 = time.perf_counter()
    if start is None:
        start = limit_analysis(scene, settings)
    fixed = build_static_problem(scene, settings, friction="fixed_capacity")
    mu = fixed.mu_interface
    cap = _normal_capacity(fixed, start)
    history = [start.lam]
    converged, failure, result = False, "", None
    excess = math.inf
    n_iter = 0
    for n_iter in range(1, max_updates + 1):  # noqa: B007 (n_iter is reported)
        _set_capacity(fixed, cap, mu)
        try:
            result = solve_static(fixed)
        except LimitAnalysisError as exc:
            failure = f"iteration {n_iter}: {exc}"
            logger.info("fixed-capacity iteration stopped: %s", failure)
            break
        history.append(result.lam)
        new = _normal_capacity(fixed, result)
        excess = _coulomb_excess(fixed, result, new)
        change = float(np.max(np.abs(new - cap), initial=0.0))
        cap = (1 - omega) * cap + omega * new
        if abs(history[-1] - history[-2]) <= tol * max(1.0, abs(history[-1])) and change <= tol:
            converged = True
            break
    return IterativeEstimate(
        lam=history[-1],
        history=history,
        converged=converged,
        admissible=bool(excess <= tol),
        coulomb_excess=float(excess),
        n_iter=n_iter,
        omega=omega,
        result=result,
        failure=failure,
        wall_s=time.perf_counter() - t0,
    )


def frictionless_lower_bound(
    scene: Scene, settings: LimitSettings | None = None
) -> tuple[float | None, str]:
    """Radenkovic's lower bound: the associated multiplier with ``mu = 0``.

    Returns
    -------
    lam : float or None
        The bound, or None when the frictionless structure cannot stand (no lower bound
        other than the trivial statement that nothing is proven).
    note : str
    """
    est, note = frictionless_lower_estimate(scene, settings)
    return (None if est is None else est.value), note


def frictionless_lower_estimate(
    scene: Scene, settings: LimitSettings | None = None
) -> tuple[Estimate | None, str]:
    """:func:`frictionless_lower_bound` with its solver error (:mod:`limit.lambda_error`); a
    bound within ten solver tolerances of zero is read as zero (interior-point solvers stop
    just inside the cone), and what was cut off is its ``"round-off"`` source. An unbounded
    bound (``inf``) is exact."""
    # the dead-load check of the caller concerns mu, not the frictionless structure
    settings = checked_inputs(scene, settings).with_(mu=0.0, dead_load_check=True)
    try:
        res = limit_analysis(scene, settings)
    except NoMechanismError:
        return Estimate(math.inf), "frictionless structure carries any live load"
    except DeadLoadInfeasibleError:
        return None, "frictionless structure cannot carry its dead load: no lower bound"
    note = "frictionless (Radenkovic) lower bound"
    if res.lam > settings.tol * 10:
        return res.lambda_estimate, note
    zero = Estimate(0.0, res.lambda_estimate.sources, notes=res.lambda_estimate.notes)
    return zero.with_source("round-off", abs(res.lam)), note


def _reduced_estimate(
    scene: Scene, settings: LimitSettings, sp_: StaticProblem
) -> tuple[Estimate | None, str]:
    """Estimate (a) on the compiled associated programme ``sp_`` (its friction is restored).

    The associated problem with ``mu*`` has a collapse multiplier only if the structure
    stands with ``mu*``: otherwise its admissible multipliers, if any, form an interval that
    does not contain 0 (the live load props it) and the largest one is no estimate. That is
    checked with :func:`limit.stands` at ``mu*`` (one more solve of the same size), whatever
    ``settings.dead_load_check`` says (it concerns the friction ``mu``).

    Returns
    -------
    lam : Estimate or None
        The estimate [-] with its solver error, None when there is none.
    note : str
    """
    mu = sp_.mu_interface
    mu_star = _reduced(mu)  # inf stays inf: no cone
    sp_.set_friction(mu_star)
    try:
        lam = solve_static(sp_).lambda_estimate
        check = stands(scene, settings, mu=mu_star)
    except LimitAnalysisError as exc:
        logger.info("reduced-friction estimate failed: %s", exc)
        return None, f"no estimate (a): {exc}"
    finally:
        sp_.set_friction(mu)
    if not check.stands:
        why = f"with mu* the structure cannot carry its dead load ({check.reason})"
        return None, f"{why}: no estimate (a)"
    return lam, "associated multiplier with mu* = mu / sqrt(1 + mu^2) per interface"


@dataclass
class Bounds:
    """Upper bound, estimates and lower bound of one scene and interface model.

    Attributes
    ----------
    model : str
    upper : float
        Associated multiplier (proven upper bound for zero-dilatancy friction).
    reduced_mu : float or None
        Estimate (a), associated problem with ``mu*``.
    reduced_mu_estimate : Estimate or None
        Estimate (a) with its solver error (:mod:`limit.lambda_error`).
    lower_estimate : Estimate or None
        The lower bound with its solver error (:func:`frictionless_lower_estimate`).
    iterative : IterativeEstimate or None
        Estimate (b).
    lower : float or None
        Frictionless lower bound (None: no bound).
    lower_note : str
    associated : LimitResult
        The associated solution (forces and mechanism).
    wall_s : dict
        Wall time of each part [s].
    reduced_note : str
        Why estimate (a) is None, or what it is.
    lam_unit : float
        The multiplier at which the live load's force equals the dead weight (``W / |F_L|``,
        the programme's scale of lambda) [unit of lambda]; the absolute allowance of
        :meth:`ordering_issues` is relative to it.
    issues : list of str
        Violations of the theorems' ordering (:meth:`ordering_issues`); empty when consistent.
    """

    model: str
    upper: float
    reduced_mu: float | None
    iterative: IterativeEstimate | None
    lower: float | None
    lower_note: str
    associated: LimitResult
    wall_s: dict = field(default_factory=dict)
    issues: list = field(default_factory=list)
    reduced_note: str = ""
    lam_unit: float = 1.0
    reduced_mu_estimate: Estimate | None = None
    lower_estimate: Estimate | None = None

    @property
    def upper_estimate(self) -> Estimate:
        """The upper bound with its error bar (the solver's error of the associated
        programme, :attr:`LimitResult.lambda_estimate`)."""
        return self.associated.lambda_estimate

    @property
    def consistent(self) -> bool:
        return not self.issues

    def ordering_issues(self, rtol: float = 1e-6) -> list[str]:
        """Where the numbers break what the theorems prove (module notes).

        Every estimate lies at or below the upper bound: estimate (a) because ``mu* <= mu``
        shrinks every cone, estimate (b) because the non-associated collapse multiplier it
        estimates never exceeds the associated one (an iterate above it, admissible or not,
        is no estimate). The frictionless lower bound lies below all of them (its set is
        contained in every other).
        """

        def above(a, b):
            return _above(a, b, self.lam_unit, rtol)

        it = self.iterative
        named = {
            "estimate (a)": self.reduced_mu,
            "estimate (b)": None if it is None else it.lam,
        }
        out = []
        for name, value in named.items():
            if above(value, self.upper):
                out.append(f"{name} {value:.6g} is above the upper bound {self.upper:.6g}")
            if above(self.lower, value):
                out.append(f"the lower bound {self.lower:.6g} is above {name} {value:.6g}")
        if above(self.lower, self.upper):
            out.append(f"the lower bound {self.lower:.6g} is above the upper {self.upper:.6g}")
        return out

    def estimates_below_upper(self, rtol: float = 1e-6) -> bool:
        """Both estimates (whether or not the iterate is admissible) lie at or below the
        upper bound."""
        return not any("above the upper bound" in x for x in self.ordering_issues(rtol))

    def to_dict(self) -> dict:
        it = self.iterative
        return {
            "model": self.model,
            "upper": self.upper,
            "reduced_mu": self.reduced_mu,
            "reduced_note": self.reduced_note,
            "iterative": None if it is None else it.lam,
            "iterative_history": None if it is None else it.history,
            "iterative_converged": None if it is None else it.converged,
            "iterative_admissible": None if it is None else it.admissible,
            "iterative_failure": None if it is None else it.failure,
            "iterative_note": None if it is None else it.note,
            "lower": self.lower,
            "lower_note": self.lower_note,
            "upper_estimate": _dict(self.upper_estimate),
            "reduced_mu_estimate": _dict(self.reduced_mu_estimate),
            "lower_estimate": _dict(self.lower_estimate),
            "iterative_estimate": None if it is None else _dict(it.estimate),
            "issues": self.issues,
            "wall_s": self.wall_s,
        }


def _dict(estimate: Estimate | None) -> dict | None:
    return None if estimate is None else estimate.to_dict()


def bounds_and_estimates(
    scene: Scene,
    settings: LimitSettings | None = None,
    iterate: bool = True,
    max_updates: int | None = None,
    omega: float = 0.5,
    lower: bool = True,
    strict: bool = True,
    **renamed,
) -> Bounds:
    """Upper bound, estimates (a) and (b), and the formal lower bound of a scene.

    Parameters
    ----------
    scene : Scene
    settings : LimitSettings, optional
        ``settings.mu`` or the scene's friction; the reduced friction of estimate (a) is
        derived from the same value (per interface).
    iterate : bool
        Run estimate (b).
    max_updates, omega : see :func:`iterative_estimate`.
    lower : bool
        Compute the frictionless lower bound.
    strict : bool
        Raise :class:`~limit.errors.InconsistentBoundsError` when the numbers break the
        theorems' ordering (:meth:`Bounds.ordering_issues`). With ``strict=False`` the
        Bounds is returned with its ``issues`` listed and ``consistent`` false.

    Raises
    ------
    InconsistentBoundsError
        ``strict`` and an ordering issue; the error carries the Bounds as ``bounds``.
    """
    _refuse_renamed(renamed)
    settings = checked_inputs(scene, settings)
    check_scene(scene)
    times = {}
    t = time.perf_counter()
    sp_ = build_static_problem(scene, settings)
    upper = solve_static(sp_)
    require_standing(scene, settings)
    times["upper"] = time.perf_counter() - t
    t = time.perf_counter()
    reduced, reduced_note = _reduced_estimate(scene, settings, sp_)
    times["reduced_mu"] = time.perf_counter() - t
    it = None
    if iterate:
        it = iterative_estimate(scene, settings, max_updates=max_updates, omega=omega, start=upper)
        it.withdraw_above(upper.lam, sp_.lam_scale)
        times["iterative"] = it.wall_s
    lo, note = None, "not computed"
    if lower:
        t = time.perf_counter()
        lo, note = frictionless_lower_estimate(scene, settings)
        times["lower"] = time.perf_counter() - t
    bounds = Bounds(
        model=settings.interface_model,
        upper=upper.lam,
        reduced_mu=None if reduced is None else reduced.value,
        reduced_mu_estimate=reduced,
        iterative=it,
        lower=None if lo is None else lo.value,
        lower_estimate=lo,
        lower_note=note,
        associated=upper,
        reduced_note=reduced_note,
        lam_unit=sp_.lam_scale,
        wall_s=times,
    )
    bounds.issues = bounds.ordering_issues()
    if bounds.issues and strict:
        raise InconsistentBoundsError(
            f"inconsistent bounds ({settings.interface_model} model): "
            + "; ".join(bounds.issues)
            + ". Pass strict=False to inspect them (Bounds.issues).",
            bounds,
        )
    return bounds
