"""What a static collapse analysis returns, and the errors it raises."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dem.estimate import Estimate
from dem.kernels.interface_law import (
    STATE_CRUSHED,
    STATE_DETACHED,
    STATE_FLEXURE,
    STATE_SHEAR,
)
from dem.static.adaptive_grid import GridRefinement

COLLAPSE_TERMINATIONS = ("plateau", "softening", "snap_back")
"""Terminations that are a collapse; the others (``"max_steps"``, ``"stalled"``,
``"no_mechanism"``) are not."""


class StaticSolverError(RuntimeError):
    """The static analysis cannot go on: singular stiffness, no equilibrium, NaN.

    Attributes
    ----------
    blocks : list of int
        Blocks identified as the cause (largest residual, unsupported), possibly empty.
    interfaces : list of int
        Interfaces identified as the cause (NaN actions, changing state), possibly empty.
    lam : float or None
        Load multiplier reached.
    """

    def __init__(self, message, blocks=(), interfaces=(), lam=None):
        super().__init__(message)
        self.blocks = [int(b) for b in blocks]
        self.interfaces = [int(i) for i in interfaces]
        self.lam = lam


@dataclass(frozen=True, eq=False)
class StaticResult:
    """Outcome of :func:`dem.static.solve_collapse`.

    Attributes
    ----------
    lambda_max : float
        Largest live-load multiplier reached [-, or Pa for a pressure pattern]: the collapse
        multiplier if ``collapsed``, else only the end of a partial path (``math.inf`` when
        no mechanism exists).
    collapsed : bool
        True only if the path ended in a collapse (``termination`` in
        :data:`COLLAPSE_TERMINATIONS`).
    pushover_lambda : (n_points,) float
        Multiplier along the path, starting at 0 after the dead load.
    pushover_control : (n_points,) float
        Control displacement ``c`` (live-load-weighted mean displacement) [m].
    pushover_monitor : (n_points,) float
        Displacement of the monitored dof [m or rad].
    monitor : tuple of (int, int)
        ``(block, dof)`` monitored.
    interface_state : (m,) int64
        State at the end (the mechanism): 0 elastic, bit 1 shear, bit 2 flexure, bit 8
        crushed, 4 detached.
    interface_state_at_peak : (m,) int64
        State at the converged point of ``lambda_max``.
    interface_forces : (m, 6) float
        ``(N, V1, V2, M1, M2, M3)`` [N, N m] in the interface frame at ``lambda_max``.
    interface_forces_end : (m, 6) float
        The same at the end.
    mechanism : (n_blocks, 6) float
        Incremental displacements of the last step, scaled to a largest translation of 1
        (zero for fixed blocks and restrained dofs).
    displacements : (n_blocks, 6) float
        Total displacements at the end [m, rad].
    displacements_at_peak : (n_blocks, 6) float
        At ``lambda_max``.
    block_a, block_b : (m,) int64
        Blocks of each interface.
    n_steps, n_iterations : int
        Converged live steps, Newton iterations in all.
    n_loose_steps : int
        Steps accepted with the law's ``accept_tolerance`` rather than ``tolerance``.
    n_cascades : int
        Brittle cracking cascades (no equilibrium path even for the smallest step): the cracks
        of the failed trial are kept and the path restarts from the last equilibrium.
    n_arc_steps : int
        Steps constrained along the direction of the previous increment, after the fixed
        control ``c`` failed at its smallest step (:mod:`dem.static.path`).
    n_failed_iterations : int
        The part of ``n_iterations`` spent in the live steps' Newton solves that did not
        converge (a step cut and retried, or a predicted start abandoned for the last
        equilibrium): where the time of a slow run goes.
    failure : str
        Why the run did not collapse ("" if it did).
    termination : str
        A collapse: ``"plateau"``, ``"softening"``, ``"snap_back"`` (lambda and ``c`` both
        falling for ``plateau_steps`` steps, lambda below the peak by more than a plateau may
        rise). No collapse: ``"max_steps"`` (lambda still rising), ``"stalled"`` (no step
        converged even at the smallest increment) or ``"no_mechanism"`` (the live load does
        no work on any motion the joints allow: lambda is unbounded).
    certificate : str
        What certifies a ``"plateau"`` end: ``"limit point"`` (the tangent at the last
        equilibrium is singular in a direction the live load works on,
        :mod:`dem.static.certificate`) or ``"upper bound"`` (the peak meets the limit
        analysis' upper bound within ``plateau_rise``, :mod:`dem.static.upper_bound`); ""
        for every other termination (softening and
        snap-back are past a peak; the others are no collapse).
    wall_s : float
        Wall time [s] of the run that gave ``lambda_max`` (the error estimate's extra runs
        are in ``lambda_estimate.cost_s``).
    lambda_estimate : Estimate
        ``lambda_max`` with its half-width by source (:func:`dem.static.solve_collapse`,
        ``error``): ``"end of path"`` (how much lambda may still rise: ``inf`` on a path that
        does not approach a limit yet), ``"load step"``, ``"residual"``; a half-width
        ``inf`` under ``"not estimated"`` with ``error="none"``.
    settings : dict
    fibre_grid : GridRefinement or None
        The fibre grids the analysis ran on, coarse to fine (this result is the finest), and
        the last change of lambda, the bound on the grid's error
        (:mod:`dem.static.adaptive_grid`); None for one run on a fixed grid.
    """

    lambda_max: float
    collapsed: bool
    pushover_lambda: np.ndarray
    pushover_control: np.ndarray
    pushover_monitor: np.ndarray
    monitor: tuple[int, int]
    interface_state: np.ndarray
    interface_state_at_peak: np.ndarray
    interface_forces: np.ndarray
    interface_forces_end: np.ndarray
    mechanism: np.ndarray
    displacements: np.ndarray
    displacements_at_peak: np.ndarray
    block_a: np.ndarray
    block_b: np.ndarray
    n_steps: int
    n_iterations: int
    n_loose_steps: int
    n_cascades: int
    n_arc_steps: int
    n_failed_iterations: int
    failure: str
    termination: str
    certificate: str
    wall_s: float
    lambda_estimate: Estimate
    settings: dict = field(default_factory=dict)
    fibre_grid: GridRefinement | None = None

    @property
    def pushover(self) -> tuple[np.ndarray, np.ndarray]:
        """``(control displacement [m], lambda)`` along the path."""
        return self.pushover_control, self.pushover_lambda


class NoCollapseError(StaticSolverError):
    """The analysis ended without a collapse: its largest lambda is not a collapse multiplier.

    Raised by :func:`dem.static.solve_collapse` with ``on_failure="raise"`` (the default).

    Attributes
    ----------
    reason : str
        Why: ``"no mechanism: ..."`` (the live load does no work on any motion the joints
        allow), ``"still rising at x % of the initial slope after max_steps = n"``, or
        ``"stalled: ..."`` (no converged step even at the smallest increment).
    result : StaticResult
        The partial path, with ``collapsed = False`` and its ``termination``.
    """

    def __init__(self, reason: str, result: StaticResult):
        super().__init__(
            f"no collapse ({result.termination}): {reason}; lambda reached "
            f"{result.lambda_max:.6g} is not a collapse multiplier",
            lam=result.lambda_max,
        )
        self.reason = reason
        self.result = result


def state_labels(state: np.ndarray) -> np.ndarray:
    """Damage-map category of each interface: "elastic", "shear", "flexural", "crushed",
    "detached".

    Flexure (rocking hinge) wins over shear when both bits are set, as in seed 001 Figs. 20-21;
    crushing wins over both.
    """
    state = np.asarray(state)
    out = np.full(state.shape, "elastic", dtype=object)
    out[(state & STATE_SHEAR) > 0] = "shear"
    out[(state & STATE_FLEXURE) > 0] = "flexural"
    out[(state & STATE_CRUSHED) > 0] = "crushed"
    out[state == STATE_DETACHED] = "detached"
    return out
