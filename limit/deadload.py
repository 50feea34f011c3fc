r"""Does the structure stand under its dead load? A certified yes or no, with the culprits.

The dead-load check solves the static programme with the dead load as the load pattern and
no other load, its multiplier capped at one:

.. math::

    \rho^* = \max\{\rho \le 1 : A_{eq} f + \rho F_D = 0,\ f_k \in \mathcal{Y}_k\}.

The feasible multipliers form an interval ``[0, rho*]`` (``rho = 0, f = 0`` is admissible and
the set is convex), so the structure stands if and only if :math:`\rho^* = 1`: the returned
forces are then an admissible equilibrium of the dead load, certified like any solution
(:mod:`limit.certificates`). When :math:`\rho^* < 1` the dual bound (below one) proves that no
admissible equilibrium exists, and the equilibrium duals are a mechanism on which the dead load
does positive work (the Farkas certificate of the infeasible programme, seed 001, Sec. 2 by
duality). Its fastest blocks and the interfaces that open or slide most are named.

A yes proves that an admissible equilibrium exists, in the associated sense of the limit
analysis. For dry, non-dilatant joints that is necessary, not sufficient: the equilibrium may
rest on clamping forces that nothing supplies. A block fitted exactly between two walls,
pressed by nothing, stands by this check (friction on clamping forces of any size), while both
static DEM laws, which load its joints from zero, find it sliding down (``DeadLoadError``).

When the capped programme fails numerically, the check solves the full dead load as a
feasibility programme (the multiplier fixed at one), whose equilibrium is certified by its
primal residuals alone: there is nothing to optimise. Only a "yes" comes from it; without the
capped programme's dual bound a "no" is not proven, and the check says it is undecided.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from dem.scene import Loads, Scene
from limit.certificates import Certificate
from limit.clarabel import LimitResult, solve_static
from limit.errors import DeadLoadInfeasibleError, LimitAnalysisError, NumericalFailureError
from limit.matrices import equilibrium_matrix
from limit.problems import LimitSettings, StaticProblem, build_static_problem, checked_inputs

__all__ = ["StandsResult", "stands", "unsupported_blocks", "dead_load_error", "INVOLVED"]

INVOLVED = 0.25
"""A block (interface) is named when its speed (relative speed) in the dead-load mechanism is at
least this fraction of the largest one."""

STANDS_TOL = 1e-6
"""``rho* >= 1 - STANDS_TOL`` counts as standing (the cap is reached to solver accuracy)."""


@dataclass(frozen=True)
class StandsResult:
    r"""Outcome of :func:`stands`.

    Attributes
    ----------
    stands : bool
        The dead load has an admissible equilibrium (associated; not sufficient for dry
        friction without clamping, see the module notes).
    load_factor : float
        :math:`\rho^*`: the largest fraction of the dead load that has an admissible
        equilibrium, capped at 1 [-].
    certificate : Certificate or None
        Residuals of the capped programme (primal: the equilibrium when it stands; dual bound
        ``certificate.dual_objective < 1`` when it does not), or of the programme with the
        dead load fixed when the capped one failed (primal residuals only,
        ``certificate.worst(feasibility=True)``). None when decided without a
        solve (nothing loaded, or a block without any support).
    blocks : tuple of int
        When it does not stand: the blocks that move most in the dead-load mechanism.
    interfaces : tuple of int
        When it does not stand: the interfaces with the largest relative motion.
    velocities : (n_blocks, 6) float or None
        The mechanism, normalised to unit dead-load power ``F_D . u = 1`` [m/s, rad/s].
    reason : str
        One sentence in structural words.
    wall_s : float
        [s].
    """

    stands: bool
    load_factor: float
    certificate: Certificate | None
    blocks: tuple = ()
    interfaces: tuple = ()
    velocities: np.ndarray | None = None
    reason: str = ""
    wall_s: float = 0.0


def unsupported_blocks(scene: Scene) -> tuple[np.ndarray, str]:
    """Loaded free blocks that nothing can hold: all of them when the scene has no support,
    else those that share no face (interface) with another block: edge and corner
    contacts carry nothing in the interface model. Returns ``(blocks, reason)`` (empty when
    none)."""
    sup = scene.supports
    free = sup.free_dofs
    loaded = (np.abs(scene.dead_wrench) * free).any(axis=1)
    if not sup.has_any:
        return np.flatnonzero(loaded), (
            "the scene has no supports (no fixed block, no restrained dof): nothing carries "
            "the dead load, so the structure falls down by itself."
        )
    interfaces = scene.assembly.interfaces()
    interfaces.warn_edge_contacts()
    touched = np.zeros(scene.n_blocks, dtype=bool)
    touched[interfaces.block_a] = True
    touched[interfaces.block_b] = True
    lonely = np.flatnonzero(~touched & loaded)
    if lonely.size:
        return lonely, (
            f"blocks {lonely[:10].tolist()} touch no other block on a face and are loaded on a "
            "free dof: they fall down by themselves (missing support; an interface is a pair "
            "of coplanar faces, so a contact on an edge or a corner only carries nothing)."
        )
    return lonely, ""


def _dead_load_scene(scene: Scene) -> Scene:
    """The scene whose live pattern is the dead load and which carries nothing else."""
    n = scene.n_blocks
    zero = np.zeros((n, 6))
    loads = Loads(np.zeros(3), zero, scene.dead_wrench)
    return Scene(scene.assembly, scene.supports, loads, scene.name, scene.meta)


def _dead_load_programme(
    scene: Scene, settings: LimitSettings, mu: np.ndarray | None, fixed: bool
) -> StaticProblem:
    """The static programme of the dead load alone, its multiplier (lambda = lam_scale * lam)
    capped at one, or ``fixed`` at one."""
    sp_ = build_static_problem(_dead_load_scene(scene), settings)
    if mu is not None:
        sp_.set_friction(np.asarray(mu, dtype=float))
    one = 1.0 / sp_.lam_scale
    bound = sp_.lam == one if fixed else sp_.lam <= one
    sp_.problem = cp.Problem(sp_.problem.objective, [*sp_.problem.constraints, bound])
    return sp_


def _solve_fixed(
    scene: Scene, settings: LimitSettings, mu: np.ndarray | None, failure: Exception
) -> LimitResult:
    """The check once the capped programme failed numerically: the full dead load as a
    feasibility programme, certified by its primal residuals. With the resultant model's
    power cones, the capped one can stall (Clarabel's 'insufficient progress')
    where the fixed one still finds a certified equilibrium."""
    try:
        return solve_static(_dead_load_programme(scene, settings, mu, fixed=True), feasibility=True)
    except LimitAnalysisError as exc:
        raise NumericalFailureError(
            f"dead-load check undecided: the programme with the dead load capped at one failed "
            f"({failure}), and the one with the full dead load gave no certified answer "
            f"({exc})"
        ) from exc


def _ranked(values: np.ndarray) -> tuple[int, ...]:
    """Indices with ``values >= INVOLVED * max``, largest first."""
    top = float(np.max(values, initial=0.0))
    if top <= 0:
        return ()
    idx = np.flatnonzero(values >= INVOLVED * top)
    return tuple(int(i) for i in idx[np.argsort(-values[idx], kind="stable")])


def _involved(scene: Scene, vel: np.ndarray) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """Blocks and interfaces that move most in the mechanism ``vel`` (n_blocks, 6)."""
    size = np.array([b.size for b in scene.assembly.blocks])
    speed = np.linalg.norm(vel[:, :3], axis=1) + size * np.linalg.norm(vel[:, 3:], axis=1)
    interfaces = scene.assembly.interfaces()
    if interfaces.n_interfaces == 0:
        return _ranked(speed), ()
    # relative motion at each interface: H u = -A_eq^T u (limit.matrices)
    jump = -(equilibrium_matrix(scene.assembly.centroid, interfaces).T @ vel.ravel())
    jump = jump.reshape(-1, 6)
    arm = np.sqrt(interfaces.area)
    rel = np.linalg.norm(jump[:, :3], axis=1) + arm * np.linalg.norm(jump[:, 3:], axis=1)
    return _ranked(speed), _ranked(rel)


def stands(
    scene: Scene, settings: LimitSettings | None = None, mu: np.ndarray | None = None
) -> StandsResult:
    """Check that a scene stands under its dead load (no live load is needed or used).

    Parameters
    ----------
    scene : Scene
    settings : LimitSettings, optional
        Interface model and strengths, as for :func:`limit.limit_analysis`.
    mu : (n_interfaces,) float, optional
        Friction coefficient of each interface [-] in place of the scene's and
        ``settings.mu`` (the reduced friction of :func:`limit.bounds_and_estimates`).

    Returns
    -------
    StandsResult
        ``stands`` with its certificate; when it does not stand, the blocks and interfaces of
        the dead-load mechanism (module notes).

    Raises
    ------
    NumericalFailureError
        Neither the capped programme nor the one with the full dead load has a certified
        answer, or the capped one's answer is undecided (below one but with a dual bound that
        does not prove it).
    """
    settings = checked_inputs(scene, settings)
    t0 = time.perf_counter()
    lonely, reason = unsupported_blocks(scene)
    if lonely.size:
        return StandsResult(
            False, 0.0, None, tuple(lonely.tolist()), (), None, reason, time.perf_counter() - t0
        )
    if not np.any(scene.dead_wrench[scene.supports.free_dofs] != 0):
        return StandsResult(
            True, 1.0, None, reason="no dead load on any free dof", wall_s=time.perf_counter() - t0
        )
    how = ""
    try:
        res = solve_static(_dead_load_programme(scene, settings, mu, fixed=False))
    except NumericalFailureError as exc:
        res = _solve_fixed(scene, settings, mu, exc)
        how = " (found with the dead load fixed: the capped programme failed numerically)"
    wall = time.perf_counter() - t0
    if how or res.lam >= 1.0 - STANDS_TOL:  # the fixed programme is feasible: it stands
        return StandsResult(
            True,
            min(res.lam, 1.0),
            res.certificate,
            reason="the dead load has a certified admissible equilibrium" + how,
            wall_s=wall,
        )
    if not res.certificate.dual_objective < 1.0:
        raise NumericalFailureError(
            f"dead-load check undecided: the largest carried fraction {res.lam:.6g} < 1 but "
            f"its dual bound {res.certificate.dual_objective:.6g} does not prove it"
        )
    blocks, faces = _involved(scene, res.velocities)
    reason = (
        f"at most {res.lam:.3g} of the dead load has an admissible equilibrium (dual bound "
        f"{res.certificate.dual_objective:.3g}): the structure falls down by itself"
    )
    return StandsResult(
        False, res.lam, res.certificate, blocks, faces, res.velocities, reason, wall
    )


def _named(check: StandsResult) -> str:
    shown = f"blocks most involved: {list(check.blocks[:10])}"
    if check.interfaces:
        shown += f", interfaces: {list(check.interfaces[:10])}"
    return shown


def dead_load_error(scene: Scene, settings: LimitSettings, message: str) -> Exception:
    """The :class:`DeadLoadInfeasibleError` of a scene whose programme was infeasible, naming
    the blocks and interfaces of its dead-load mechanism (:func:`stands`); a
    :class:`NumericalFailureError` when the dead-load check finds that it stands after all."""
    check = stands(scene, settings)
    if check.stands:
        return NumericalFailureError(
            f"the solver reported no equilibrium under the dead load, but the dead-load check "
            f"finds a certified one: numerical trouble, not a structural answer. ({message})"
        )
    return DeadLoadInfeasibleError(f"{message} {_named(check)}.", check.blocks, check.interfaces)


def require_standing(scene: Scene, settings: LimitSettings) -> None:
    """Refuse a multiplier of a scene whose dead load alone is not carried.

    The admissible multipliers form an interval; when it does not contain 0 (the structure
    stands only while the live load props it), its largest point is no collapse multiplier.
    Skipped when ``settings.dead_load_check`` is off.

    Raises
    ------
    DeadLoadInfeasibleError
        Naming the blocks and interfaces of the dead-load mechanism.
    """
    if not settings.dead_load_check:
        return
    check = stands(scene, settings)
    if not check.stands:
        raise DeadLoadInfeasibleError(
            f"no equilibrium under the dead load alone ({check.reason}); the live load can "
            f"prop the structure, but then the largest multiplier is no collapse multiplier. "
            f"{_named(check)}.",
            check.blocks,
            check.interfaces,
        )
