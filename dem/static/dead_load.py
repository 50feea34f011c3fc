r"""The dead load, applied in increments with automatic cutting.

The dead load ``F_D`` (self weight and any dead wrench) is applied as ``t F_D`` with ``t``
from 0 to 1 under load control (:mod:`dem.static.newton`), each increment a Newton solve from
the last equilibrium, committed before the next (friction is path dependent: the joints see
the weight build up). The first increment is ``1 / dead_steps`` of the dead load; an increment
that fails is halved, one that converged within half of ``target_iterations`` is doubled for
the next. The dead load is not carried when an increment of ``dead_min_step`` of it fails:
:class:`DeadLoadError` then says how much of it was carried and names the blocks.

Where the whole dead load converges in one solve, the result is that solve's. One solve from
unloaded joints (no friction capacity) decides every joint's state at once: on seed 001 S23
(resultant law, return walls of blocks) it converged under one OpenBLAS kernel and stalled
under two others.

For dry joints the equilibrium of rigid blocks does not depend on the size of the load, so an
assembly that cannot stand fails at the smallest increment already ("no part of the dead
load"); a failure after a part was carried points at strength that is lost on the way
(mortar cracking) or at a Newton stall the minimum increment did not resolve.
"""

from __future__ import annotations

import numpy as np

from dem.kernels.interface_law import TOUCH
from dem.static.model import model_extent
from dem.static.newton import Constraint, Corrector, Iterate, Outcome
from dem.static.result import StaticSolverError

N_BLOCKS_NAMED = 10  # blocks an error names at most
RESOLVED_CLOSURE = 1e3  # the dead load must close some joint by this many touching gaps


class DeadLoadError(StaticSolverError):
    """The dead load is not carried (see :mod:`dem.static.dead_load`).

    Attributes
    ----------
    fraction : float
        Part of the dead load carried (the last equilibrium) [-].
    blocks : list of int
        The blocks that move most in the failed increment, then the block of the largest
        residual if not among them.
    """

    def __init__(self, message, fraction, blocks=(), interfaces=()):
        super().__init__(message, blocks=blocks, interfaces=interfaces, lam=0.0)
        self.fraction = float(fraction)


def solve_dead_load(corrector: Corrector) -> tuple[Iterate, int]:
    """Equilibrium under the dead load, committed; and the Newton iterations it took.

    Raises
    ------
    DeadLoadError
        An increment of ``dead_min_step`` of the dead load found no equilibrium.
    """
    model, settings = corrector.model, corrector.settings
    point = Iterate(np.zeros(model.n_free), 0.0, None, None)
    t, dt, n_iter = 0.0, 1.0 / settings.dead_steps, 0
    while t < 1.0:
        dt = min(dt, 1.0 - t)
        if 1.0 - t - dt < 1e-9:  # no sliver left for the last increment
            dt = 1.0 - t
        out = _increment(corrector, point, t + dt)
        n_iter += out.iterations
        if out.converged:
            model.law.commit(out.point.ev.law)
            point, t = out.point, t + dt
            if out.iterations <= settings.target_iterations // 2:
                dt *= 2.0
            continue
        if dt <= settings.dead_min_step * (1.0 + 1e-9):
            raise _not_carried(corrector, point, out, t, dt)
        dt = max(0.5 * dt, settings.dead_min_step)
    check_closure(model, point)
    return point, n_iter


def check_closure(model, point: Iterate) -> None:
    """Refuse a dead load that closes no joint by more than ``RESOLVED_CLOSURE`` touching gaps.

    The interface laws take gaps within the touching gap (``TOUCH`` times the model's extent,
    :mod:`dem.kernels.interface_law`) as touching, with no friction: where the elastic
    closures are that small (joint stiffness far above the loads' pressure over round-off),
    a joint in full contact would count as barely touching and a block on the ground would
    slide at a vanishing multiplier instead of ``mu``. The collapse load does not depend on
    ``k_n``, so a lower one loses nothing.
    """
    if model.dead_norm == 0.0:
        return
    kn = model.settings.kn
    closure = float(np.max(-point.ev.law.f[:, 0] / (kn * model.itf.area)))
    touch = TOUCH * model_extent(model.scene)
    if 0.0 < closure < RESOLVED_CLOSURE * touch:  # (no joint pressed: held by restraints)
        raise ValueError(
            f"the dead load closes the joints by {closure:.3e} m at most, within "
            f"{RESOLVED_CLOSURE:g} touching gaps ({touch:.1e} m: round-off at the model's "
            f"size): kn = {kn:.3e} Pa/m is too stiff for these loads (or the blocks too light) "
            f"for the interface laws to tell contact from touching; lower kn to "
            f"{kn * closure / (10 * RESOLVED_CLOSURE * touch):.1e} Pa/m or less (the collapse "
            "load does not depend on it)"
        )


def _increment(corrector: Corrector, point: Iterate, t: float) -> Outcome:
    """Newton from ``point`` to the equilibrium under ``t F_D``."""
    con = Constraint(dead_target=corrector.model.F_dead * t)
    # the dead load starts from unloaded joints with no friction capacity: allow more
    # iterations than a live step
    start = Iterate(point.u, 0.0, None, None)  # evaluated afresh against the new target
    return corrector.solve(start, con, max_iterations=4 * corrector.settings.max_iterations)


def _not_carried(
    corrector: Corrector, point: Iterate, out: Outcome, t: float, dt: float
) -> DeadLoadError:
    """The error of an increment ``dt`` from ``t`` that found no equilibrium."""
    model = corrector.model
    R = out.point.residual
    blk, dof = model.block_of_dof(int(np.argmax(np.abs(R))))
    move = np.linalg.norm(model.full(out.point.u - point.u)[:, :3], axis=1)
    moving = [int(b) for b in np.argsort(-move)[:N_BLOCKS_NAMED] if move[b] > 0]
    blocks = moving if blk in moving else [*moving[: N_BLOCKS_NAMED - 1], blk]
    changing = np.flatnonzero(out.point.ev.law.state != model.law.state)
    why = f"; {out.singular}" if out.singular else ""
    if t == 0.0:
        what = (
            f"no equilibrium under any part of the dead load (an increment of {dt:.3g} of it "
            "failed): the assembly is likely a mechanism under its own weight (the equilibrium "
            "of rigid blocks on dry joints does not depend on the size of the load), unless "
            "the Newton iteration stalls (limit.stands certifies which)"
        )
    else:
        what = (
            f"the dead load is carried up to {100 * t:.4g} % only (the next increment of "
            f"{dt:.3g} of it found no equilibrium): strength lost on the way, or a Newton stall"
        )
    return DeadLoadError(
        f"{what} (after {out.iterations} iterations, residual {np.linalg.norm(R):.3e}, "
        f"largest at block {blk} {dof}{why}); blocks moving most: {blocks}",
        fraction=t,
        blocks=blocks,
        interfaces=changing[:N_BLOCKS_NAMED],
    )
