r"""Static DEM of rigid blocks with elastic-plastic interfaces, followed to collapse.

The incremental analysis of seed 001 (Sec. 2.3), in general form:

- unknowns: the 6 dofs ``(ux, uy, uz, rx, ry, rz)`` of every free block about its centroid;
  fixed blocks and restrained dofs are eliminated, not penalised;
- kinematics: ``q = H U`` from the actual interface and block centroids (Eq. (3) and
  (A1)-(A3) are the running-bond special case), ``H`` from :mod:`dem.geometry.compatibility`;
- interface law, selectable (:class:`StaticSettings`): ``"resultant"``, the seed's
  elastic-perfectly-plastic law on ``(N, V1, V2, M1, M2, M3)``
  (:mod:`dem.kernels.interface_law`), or ``"fibre"``, a grid of no-tension Mohr-Coulomb
  springs per interface (:mod:`dem.kernels.fibre_law`);
- equilibrium ``H^T f(q) = F_D + \lambda F_L``, the dead load applied first (load control),
  then the live load followed by indirect displacement control: each step prescribes the
  increment of the work-conjugate control displacement ``c = w^T U`` (``w`` the live pattern
  normalised by its total force, so ``c`` is the live-load-weighted mean displacement [m]) and
  solves the bordered Newton system for ``(dU, d lambda)``, which stays regular at the limit
  point. The step adapts to the Newton iteration count; the analysis stops on a plateau (the
  mechanism: ``d lambda / dc`` a small fraction of the initial slope for a few steps) or on a
  drop after the peak.

Units SI: m, N, Pa, rad.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.optimize import linprog

from dem.collapse_criteria import CollapseCriteria
from dem.geometry.interfaces import Interfaces
from dem.kernels.fibre_law import fibre_law
from dem.kernels.interface_law import (
    STATE_DETACHED,
    STATE_ELASTIC,
    STATE_FLEXURE,
    STATE_SHEAR,
    resultant_law,
)
from dem.kernels.stiffness import (
    block_forces,
    local_compatibility,
    relative_motion,
    stiffness_triplets,
)
from dem.scene import DOFS, Scene

logger = logging.getLogger(__name__)

__all__ = [
    "ALPHA_TABLE_A1",
    "STATE_DETACHED",
    "STATE_ELASTIC",
    "STATE_FLEXURE",
    "STATE_SHEAR",
    "StaticResult",
    "StaticSettings",
    "StaticSolverError",
    "NoCollapseError",
    "COLLAPSE_TERMINATIONS",
    "solve_collapse",
    "state_labels",
]

INTERFACE_MODELS = ("resultant", "fibre")
ON_FAILURE = ("raise", "return")
COLLAPSE_TERMINATIONS = ("plateau", "softening", "snap_back")
"""Terminations that are a collapse; the others (``"max_steps"``, ``"stalled"``,
``"no_mechanism"``) are not."""

ALPHA_TABLE_A1 = np.array(
    [
        # l1/l2, alpha(f1 only), alpha(f1 = f2), alpha(f2 only)   -- seed 001 Table A1
        [0.1, 1.00, 2.00, 2.56],
        [0.2, 1.05, 1.90, 2.44],
        [0.5, 1.25, 1.70, 1.92],
        [1.0, 1.43, 1.43, 1.43],
        [2.0, 1.92, 1.70, 1.25],
        [5.0, 2.44, 1.90, 1.05],
        [10.0, 2.56, 2.00, 1.00],
    ]
)
"""Exponents of seed 001 Eq. (A5) by interface aspect ratio and shear direction."""


class StaticSolverError(RuntimeError):
    """The static analysis cannot go on: singular stiffness, no convergence, NaN.

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


class NoCollapseError(StaticSolverError):
    """The analysis ended without a collapse: its largest lambda is not a collapse multiplier.

    Raised by :func:`solve_collapse` with ``on_failure="raise"`` (the default).

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


@dataclass(frozen=True)
class StaticSettings:
    """Settings of :func:`solve_collapse`.

    Attributes
    ----------
    interface_model : {"resultant", "fibre"}
        Seed 001's resultant law, or the grid of Coulomb springs.
    kn, kt : float
        Normal and tangential stiffness per unit area [Pa/m]. Default: seed 001 Sec. 2.1
        (2.4 MPa/mm and 1 MPa/mm). The collapse load of rigid blocks does not depend on them.
    kr : float or None
        Rotational stiffness per unit area [Pa/m]; None: ``kn`` (seed 001, ``k_r = k_n``).
    mu : float or None
        Friction coefficient; None: the smaller of the two blocks' ``Assembly.mu``.
    tensile_strength : float
        [Pa]; 0 for dry joints.
    cohesion : float or None
        [Pa]; None: ``mu * tensile_strength`` (seed 001, Sec. 2.1).
    tension_at_supports : bool
        Whether interfaces with a fixed block get the tensile strength and cohesion (False
        models a support as a dry hinge).
    alpha : float or None
        Exponent of Eq. (A5); None: seed Table A1 (column ``f1 = f2``) at each interface's
        aspect ratio (resultant model only).
    fibre_points : int
        Gauss-Lobatto points per side of a rectangular interface (fibre model): the outer
        springs lie on the edges, so rocking about an edge is exact.
    load_step : float
        First live-load increment as a fraction of ``lambda_scale = |F_D| / |F_L|`` (total
        dead over total live force): for a live load equal to the weight, ``d lambda``.
    max_step_factor : float
        Largest control increment, in first increments.
    max_steps : int
        Live-load steps at most.
    max_iterations : int
        Newton iterations per step before the step is cut.
    target_iterations : int
        Iterations the step size adapts to.
    tolerance : float
        Relative residual ``|R| / (|F_D| + |lambda F_L|)`` for convergence.
    accept_tolerance : float or None
        A step whose Newton iterations stall (cycling at a kink of the law, e.g. a joint at
        ``N -> 0``) is accepted if its best relative residual is below this; the residual is
        of the total equilibrium, so the error does not accumulate. Counted in
        ``StaticResult.n_loose_steps``. None: 1e-4 for the fibre law, ``tolerance`` (no loose
        step) for the resultant law, where loosely converged steps committed plastic states
        from which no shorter step converged (seed 001 S6 and S1-S2-S3 with return walls as
        blocks stopped at 0.121 and 0.143; without loose steps they go on to 0.159 and 0.166,
        where their paths flatten).
    tangent_floor : float or None
        Fraction of the elastic stiffness kept by yielded components of the iteration matrix
        (the residual uses the exact law, so every converged point is an equilibrium of it;
        where frictional equilibrium is not unique the path taken can still depend on the
        floor: seed 001 S1-S2-S3 with return walls, resultant law, 0.1738 / 0.1677 / 0.1743 for
        1e-3 / 1e-4 / 1e-5, S15 within 0.06 %). None:
        1e-4 for the resultant law, 1e-9 for the fibre law. With a near-zero floor, blocks
        held only by yielded joints make the resultant law's tangent nearly singular and the
        Newton steps huge: on seed 001's S11 1e-9 stalls the path, while 1e-6 to 1e-3 give the
        same lambda_max to 0.01 % (1e-4 the fastest). The fibre law, whose yielded springs are
        a part of each joint only, converges best near the consistent tangent (S11 with return
        walls: 51 steps at 1e-9, no plateau within 400 steps at 1e-4).
    predictor : bool or None
        Start each live step from the last increment scaled to the new one (falling back to
        the last equilibrium if Newton fails from there). None: on for the resultant law,
        off for the fibre law. Resultant law, seed 001 S13 with a fixed column: without it
        the first iterate of every step unloaded the same two dozen joints that keep yielding,
        and the path crept to ``max_steps`` at lambda = 0.048; with it, a plateau at 0.087 in
        45 steps. The fibre law converges from the last equilibrium in a few iterations, and
        the predictor's longer steps made its lambda_max vary by 1.7 % with the load step
        (S15 with return walls; 0.2 % without).
    min_step_ratio : float
        Smallest control increment, relative to the first, before giving up a step.
    plateau_slope : float
        A step is on the collapse plateau when ``d lambda / d c`` is below this fraction of
        the initial secant slope (measured back over at least the control length at which
        the residual tolerance's noise in lambda is a tenth of the allowed rise).
    plateau_steps : int
        Consecutive plateau steps that end the analysis, if they also span this many first
        control increments.
    softening_drop : float
        End when lambda falls below ``(1 - softening_drop) lambda_max``.
    plateau_rise : float
        A plateau also needs lambda to have risen by less than this fraction of itself since
        half the present control displacement (:mod:`dem.collapse_criteria`): slow frictional
        hardening is not taken for the collapse.
    dead_steps : int
        Increments of the dead load.
    monitor : tuple of (int, int) or None
        ``(block, dof)`` whose displacement the pushover also records; None: the free block
        with the largest live-direction translation in the mechanism.
    on_failure : {"raise", "return"}
        When the analysis ends without a collapse (no mechanism exists, ``max_steps`` reached
        while lambda still rises, or a step that converges at no increment): raise
        :class:`NoCollapseError` (its ``result`` holds the partial path), or return the
        partial path with ``collapsed = False``, its ``termination`` and the reason in
        ``failure``.
    """

    interface_model: str = "resultant"
    kn: float = 2.4e9
    kt: float = 1.0e9
    kr: float | None = None
    mu: float | None = None
    tensile_strength: float = 0.0
    cohesion: float | None = None
    tension_at_supports: bool = True
    alpha: float | None = None
    fibre_points: int = 5
    load_step: float = 0.01
    max_step_factor: float = 200.0
    max_steps: int = 400
    max_iterations: int = 30
    target_iterations: int = 10
    tolerance: float = 1e-6
    accept_tolerance: float | None = None
    tangent_floor: float | None = None
    predictor: bool | None = None
    min_step_ratio: float = 1e-4
    plateau_slope: float = 2e-3
    plateau_steps: int = 4
    softening_drop: float = 0.2
    plateau_rise: float = 1e-3
    dead_steps: int = 1
    monitor: tuple[int, int] | None = None
    on_failure: str = "raise"

    def __post_init__(self):
        if self.on_failure == "stop":
            raise ValueError(
                "on_failure='stop' is no longer accepted: use 'return' to get the partial "
                "path back flagged collapsed=False, or 'raise' (default) for a NoCollapseError"
            )
        if self.on_failure not in ON_FAILURE:
            raise ValueError(f"on_failure must be one of {ON_FAILURE}, got {self.on_failure!r}")
        if self.interface_model not in INTERFACE_MODELS:
            raise ValueError(
                f"interface_model must be one of {INTERFACE_MODELS}, got {self.interface_model!r}"
            )
        for name in ("kn", "kt", "load_step", "tolerance", "accept_tolerance", "max_step_factor"):
            v = getattr(self, name)
            if name == "accept_tolerance" and v is None:
                continue
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a finite positive number, got {v!r}")
        for name in ("kr", "cohesion"):
            v = getattr(self, name)
            if v is not None and not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be None or finite and >= 0, got {v!r}")
        if self.kr is not None and self.kr <= 0:
            raise ValueError(f"kr must be positive, got {self.kr}")
        if self.mu is not None and not (math.isfinite(self.mu) and self.mu >= 0):
            raise ValueError(f"mu must be None or finite and >= 0, got {self.mu!r}")
        if not (math.isfinite(self.tensile_strength) and self.tensile_strength >= 0):
            raise ValueError(f"tensile_strength must be >= 0 [Pa], got {self.tensile_strength}")
        if self.alpha is not None and not (math.isfinite(self.alpha) and self.alpha >= 1):
            raise ValueError(f"alpha must be None or >= 1, got {self.alpha}")
        for name in (
            "fibre_points",
            "max_steps",
            "max_iterations",
            "target_iterations",
            "plateau_steps",
            "dead_steps",
        ):
            v = getattr(self, name)
            low = 2 if name == "fibre_points" else 1
            if isinstance(v, bool) or int(v) != v or v < low:
                raise ValueError(f"{name} must be an integer >= {low}, got {v!r}")
        for name in (
            "tangent_floor",
            "min_step_ratio",
            "plateau_slope",
            "softening_drop",
            "plateau_rise",
        ):
            v = getattr(self, name)
            if name == "tangent_floor" and v is None:
                continue
            if not (math.isfinite(v) and 0 <= v < 1):
                raise ValueError(f"{name} must be in [0, 1), got {v!r}")


@dataclass(frozen=True, eq=False)
class StaticResult:
    """Outcome of :func:`solve_collapse`.

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
        State at the end (the mechanism): 0 elastic, bit 1 shear, bit 2 flexure, 4 detached.
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
        Steps accepted with ``accept_tolerance`` rather than ``tolerance``.
    n_cascades : int
        Brittle cracking cascades (no equilibrium path even for the smallest step): the cracks
        of the failed trial are kept and the path restarts from the last equilibrium.
    n_arc_steps : int
        Steps constrained along the direction of the previous increment, after the fixed
        control ``c`` failed at its smallest step (see :func:`solve_collapse`).
    failure : str
        Why the run did not collapse ("" if it did).
    termination : str
        A collapse: ``"plateau"``, ``"softening"``, ``"snap_back"`` (lambda and ``c`` both
        falling for ``plateau_steps`` steps, lambda below the peak by more than a plateau may
        rise). No collapse: ``"max_steps"`` (lambda still rising), ``"stalled"`` (no step
        converged even at the smallest increment) or ``"no_mechanism"`` (the live load does
        no work on any motion the joints allow: lambda is unbounded).
    wall_s : float
        Wall time [s].
    settings : dict
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
    failure: str
    termination: str
    wall_s: float
    settings: dict = field(default_factory=dict)

    @property
    def pushover(self) -> tuple[np.ndarray, np.ndarray]:
        """``(control displacement [m], lambda)`` along the path."""
        return self.pushover_control, self.pushover_lambda


def state_labels(state: np.ndarray) -> np.ndarray:
    """Damage-map category of each interface: "elastic", "shear", "flexural", "detached".

    Flexure (rocking hinge) wins over shear when both bits are set, as in seed 001 Figs. 20-21.
    """
    state = np.asarray(state)
    out = np.full(state.shape, "elastic", dtype=object)
    out[(state & STATE_SHEAR) > 0] = "shear"
    out[(state & STATE_FLEXURE) > 0] = "flexural"
    out[state == STATE_DETACHED] = "detached"
    return out


# ----------------------------------------------------------------------------------------------
# model set-up
# ----------------------------------------------------------------------------------------------


def interface_alpha(l1: np.ndarray, l2: np.ndarray, alpha: float | None = None) -> np.ndarray:
    """Exponent of seed 001 Eq. (A5) per interface.

    ``alpha`` if given, else seed Table A1, column ``f1 = f2`` (between the two single-shear
    columns; 1.43 for square interfaces), interpolated in ``log(l1 / l2)``.
    """
    if alpha is not None:
        return np.full(len(l1), float(alpha))
    ratio = np.clip(l1 / l2, ALPHA_TABLE_A1[0, 0], ALPHA_TABLE_A1[-1, 0])
    return np.interp(np.log(ratio), np.log(ALPHA_TABLE_A1[:, 0]), ALPHA_TABLE_A1[:, 2])


def _lobatto(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Lobatto points and weights on [-1, 1] (``n >= 2``)."""
    if n == 2:
        return np.array([-1.0, 1.0]), np.array([1.0, 1.0])
    inner = np.polynomial.legendre.Legendre.basis(n - 1).deriv().roots()
    x = np.concatenate([[-1.0], np.sort(inner.real), [1.0]])
    p = np.polynomial.legendre.Legendre.basis(n - 1)(x)
    w = 2.0 / (n * (n - 1) * p**2)
    return x, w


def _fibre_grid(interfaces: Interfaces, n_pts: int):
    """Spring positions and areas of every interface (Lobatto grid on rectangles)."""
    x, w = _lobatto(n_pts)
    ptr = [0]
    pos_all, area_all = [], []
    for k in range(interfaces.n_interfaces):
        poly = interfaces.local_polygon(k)
        lo, hi = poly.min(0), poly.max(0)
        size = hi - lo
        area = interfaces.area[k]
        if abs(size[0] * size[1] - area) <= 1e-6 * area:
            c = 0.5 * (lo + hi)
            g1, g2 = np.meshgrid(c[0] + 0.5 * size[0] * x, c[1] + 0.5 * size[1] * x, indexing="ij")
            wa = np.outer(w, w).ravel() * 0.25 * size[0] * size[1]
            pos = np.column_stack([g1.ravel(), g2.ravel()])
        else:
            # general convex polygon: midpoint cells of the bounding box inside the polygon
            n_cells = 4 * n_pts
            t = (np.arange(n_cells) + 0.5) / n_cells
            g1, g2 = np.meshgrid(lo[0] + size[0] * t, lo[1] + size[1] * t, indexing="ij")
            pts = np.column_stack([g1.ravel(), g2.ravel()])
            inside = np.ones(len(pts), dtype=bool)
            for i in range(len(poly)):
                e = poly[(i + 1) % len(poly)] - poly[i]
                r = pts - poly[i]
                inside &= e[0] * r[:, 1] - e[1] * r[:, 0] >= -1e-12 * size.max() ** 2
            pos = pts[inside]
            wa = np.full(len(pos), area / max(len(pos), 1))
        pos_all.append(pos)
        area_all.append(wa)
        ptr.append(ptr[-1] + len(pos))
    return (
        np.array(ptr, dtype=np.int64),
        np.ascontiguousarray(np.concatenate(pos_all)),
        np.concatenate(area_all),
    )


class _Model:
    """Arrays of one scene for the kernels, and the committed interface state."""

    def __init__(self, scene: Scene, settings: StaticSettings):
        self.scene = scene
        self.settings = settings
        assembly = scene.assembly
        itf = assembly.interfaces()
        if itf.n_interfaces == 0:
            raise ValueError("the scene has no interfaces: every block is isolated")
        self.itf = itf
        n = assembly.n_blocks
        self.n_blocks = n
        free = scene.supports.free_dofs
        if not free.any():
            raise ValueError("the scene has no free dof: every block is fixed or restrained")
        self.dof_index = np.full((n, 6), -1, dtype=np.int64)
        self.dof_index[free] = np.arange(int(free.sum()))
        self.n_free = int(free.sum())
        self.free_mask = free
        self._check_supported()

        self.a = np.ascontiguousarray(itf.block_a, dtype=np.int64)
        self.b = np.ascontiguousarray(itf.block_b, dtype=np.int64)
        self.B = local_compatibility(
            self.a,
            self.b,
            np.ascontiguousarray(itf.centroid, dtype=np.float64),
            np.ascontiguousarray(assembly.centroid, dtype=np.float64),
            np.ascontiguousarray(itf.frame, dtype=np.float64),
        )
        m = itf.n_interfaces
        self.m = m
        s = settings
        kr = s.kn if s.kr is None else s.kr
        area = itf.area
        j11, j22 = itf.second_moments[:, 0], itf.second_moments[:, 1]
        self.k = np.ascontiguousarray(
            np.column_stack(
                [s.kn * area, s.kt * area, s.kt * area, kr * j22, kr * j11, s.kt * (j11 + j22)]
            )
        )
        if s.mu is not None:
            mu = np.full(m, float(s.mu))
        elif assembly.mu is not None:
            mu = np.minimum(assembly.mu[self.a], assembly.mu[self.b])
        else:
            raise ValueError("no friction coefficient: set StaticSettings.mu or Assembly.mu")
        self.mu = np.ascontiguousarray(mu, dtype=np.float64)
        sigma_t = s.tensile_strength
        cohesion = self.mu * sigma_t if s.cohesion is None else np.full(m, s.cohesion)
        tension = np.full(m, sigma_t)
        if not s.tension_at_supports:
            fixed = scene.supports.fixed
            at_support = fixed[self.a] | fixed[self.b]
            tension[at_support] = 0.0
            cohesion = np.where(at_support, 0.0, cohesion)
        self.sigma_t = np.ascontiguousarray(tension, dtype=np.float64)
        self.cohesion_stress = np.ascontiguousarray(cohesion, dtype=np.float64)
        lever = np.zeros((m, 4))
        dims = np.zeros((m, 2))
        for i in range(m):
            poly = itf.local_polygon(i)
            lo, hi = poly.min(0), poly.max(0)
            lever[i] = (-lo[1], hi[1], hi[0], -lo[0])
            dims[i] = hi - lo
        self.lever = lever
        self.dims = dims
        self.alpha = np.ascontiguousarray(interface_alpha(dims[:, 0], dims[:, 1], s.alpha))
        self.f_t = np.ascontiguousarray(self.sigma_t * area)
        self.c_force = np.ascontiguousarray(self.cohesion_stress * area)
        if s.interface_model == "fibre":
            self.spring_ptr, self.spring_pos, self.spring_area = _fibre_grid(itf, s.fibre_points)
            ns = len(self.spring_area)
            self.kn_arr = np.full(m, s.kn)
            self.kt_arr = np.full(m, s.kt)
            self.slip = np.zeros((ns, 2))
            self.spring_broken = np.zeros(ns, dtype=np.bool_)
        else:
            self.qp = np.zeros((m, 6))
            self.broken = np.zeros(m, dtype=np.bool_)

        # loads on the unknowns
        self.F_dead = scene.dead_wrench[free]
        self.F_live = scene.loads.live_wrench[free]
        is_force = np.broadcast_to(np.arange(6) < 3, (n, 6))[free]
        live_force = np.abs(self.F_live[is_force]).sum()
        if live_force == 0:
            raise ValueError("the live load is zero on every free dof: nothing to scale")
        dead_force = np.abs(self.F_dead[is_force]).sum()
        self.lambda_scale = dead_force / live_force if dead_force > 0 else 1.0
        # control c = w . u: the live-load-weighted mean displacement [m]
        self.w = self.F_live / live_force
        self.state = np.zeros(m, dtype=np.int64)
        self.linear = _LinearSolver()
        self.tangent_floor = s.tangent_floor
        if s.tangent_floor is None:
            self.tangent_floor = 1e-4 if s.interface_model == "resultant" else 1e-9
        self.dead_norm = float(np.linalg.norm(self.F_dead))
        self.live_norm = float(np.linalg.norm(self.F_live))
        self.accept_tolerance = s.accept_tolerance
        if s.accept_tolerance is None:
            self.accept_tolerance = s.tolerance if s.interface_model == "resultant" else 1e-4
        self.predictor = s.predictor
        if s.predictor is None:
            self.predictor = s.interface_model == "resultant"

    # -- supports -----------------------------------------------------------------------------
    def _check_supported(self):
        """Every block must reach a support through interfaces, else K is singular."""
        itf = self.itf
        n = self.n_blocks
        graph = sp.coo_matrix((np.ones(itf.n_interfaces), (itf.block_a, itf.block_b)), shape=(n, n))
        n_comp, label = sp.csgraph.connected_components(graph, directed=False)
        held = self.scene.supports.fixed | self.scene.supports.restrained.any(axis=1)
        for comp in range(n_comp):
            members = np.flatnonzero(label == comp)
            if not held[members].any():
                raise StaticSolverError(
                    f"blocks {members[:10].tolist()}{' ...' if len(members) > 10 else ''} "
                    "reach no support through their interfaces: the stiffness is singular "
                    "(a mechanism before any load). Fix a block or add a foundation.",
                    blocks=members,
                )

    # -- interface law ------------------------------------------------------------------------
    def evaluate(self, U: np.ndarray, floor: float | None = None):
        """Trial actions, tangents, states and block forces for total block dofs ``U``."""
        m = self.m
        q = np.empty((m, 6))
        relative_motion(self.B, self.a, self.b, U, q)
        f = np.empty((m, 6))
        D = np.empty((m, 6, 6))
        state = np.empty(m, dtype=np.int64)
        if floor is None:
            floor = self.tangent_floor
        if self.settings.interface_model == "resultant":
            qp = np.empty((m, 6))
            broken = np.empty(m, dtype=np.bool_)
            resultant_law(
                q,
                self.qp,
                self.broken,
                self.k,
                self.lever,
                self.f_t,
                self.c_force,
                self.mu,
                self.dims,
                self.alpha,
                floor,
                f,
                qp,
                broken,
                state,
                D,
            )
            trial = (qp, broken)
        else:
            slip = np.empty_like(self.slip)
            broken = np.empty_like(self.spring_broken)
            fibre_law(
                q,
                self.spring_ptr,
                self.spring_pos,
                self.spring_area,
                self.slip,
                self.spring_broken,
                self.kn_arr,
                self.kt_arr,
                self.mu,
                self.cohesion_stress,
                self.sigma_t,
                floor,
                f,
                slip,
                broken,
                state,
                D,
            )
            trial = (slip, broken)
        F = np.empty((self.n_blocks, 6))
        block_forces(self.B, self.a, self.b, f, F)
        return f, D, state, trial, F[self.free_mask]

    def commit(self, trial, state):
        if self.settings.interface_model == "resultant":
            self.qp, self.broken = trial[0].copy(), trial[1].copy()
        else:
            self.slip, self.spring_broken = trial[0].copy(), trial[1].copy()
        self.state = state.copy()

    def commit_breaks(self, trial) -> bool:
        """Keep only the tensile failures of a trial state; True if there are new ones."""
        if self.settings.interface_model == "resultant":
            new = trial[1] & ~self.broken
            self.broken = self.broken | trial[1]
        else:
            new = trial[1] & ~self.spring_broken
            self.spring_broken = self.spring_broken | trial[1]
        return bool(new.any())

    def snapshot(self):
        if self.settings.interface_model == "resultant":
            return (self.qp.copy(), self.broken.copy(), self.state.copy())
        return (self.slip.copy(), self.spring_broken.copy(), self.state.copy())

    def restore(self, snap):
        if self.settings.interface_model == "resultant":
            self.qp, self.broken = snap[0].copy(), snap[1].copy()
        else:
            self.slip, self.spring_broken = snap[0].copy(), snap[1].copy()
        self.state = snap[2].copy()

    def _pattern(self, bordered: bool):
        """CSC structure of K (or of the bordered matrix) and the slot of every triplet.

        The triplets of ``H^T D H`` keep their order and positions between iterations (only
        the values change), so the sparse structure is built once and each assembly is a
        ``bincount`` of the values into it.
        """
        key = "bordered" if bordered else "plain"
        cache = self.__dict__.setdefault("_patterns", {})
        if key in cache:
            return cache[key]
        n = self.n_free
        rows, cols, _ = stiffness_triplets(
            self.B, np.ones((self.m, 6, 6)), self.a, self.b, self.dof_index
        )
        size = n
        extra_rows = np.zeros(0, dtype=np.int64)
        extra_cols = np.zeros(0, dtype=np.int64)
        extra_vals = np.zeros(0)
        if bordered:
            size = n + 1
            nz_f = np.flatnonzero(self.F_live)
            nz_w = np.flatnonzero(self.w)
            extra_rows = np.concatenate([nz_f, np.full(len(nz_w), n)])
            extra_cols = np.concatenate([np.full(len(nz_f), n), nz_w])
            extra_vals = np.concatenate([-self.F_live[nz_f], self.w[nz_w]])
        all_rows = np.concatenate([rows, extra_rows])
        all_cols = np.concatenate([cols, extra_cols])
        keys, inverse = np.unique(all_cols * size + all_rows, return_inverse=True)
        indices = (keys % size).astype(np.int32)
        indptr = np.searchsorted(keys // size, np.arange(size + 1)).astype(np.int32)
        n_trip = len(rows)
        const = np.bincount(inverse[n_trip:], weights=extra_vals, minlength=len(keys))
        cache[key] = (size, indices, indptr, inverse[:n_trip], const, len(keys))
        return cache[key]

    def stiffness(self, D: np.ndarray, bordered: bool = False) -> sp.csc_matrix:
        """``K = H^T D H`` on the unknowns, or the bordered matrix ``[[K, -F_L], [w^T, 0]]``."""
        size, indices, indptr, inverse, const, nnz = self._pattern(bordered)
        _, _, vals = stiffness_triplets(self.B, D, self.a, self.b, self.dof_index)
        data = np.bincount(inverse, weights=vals, minlength=nnz) + const
        return sp.csc_matrix((data, indices, indptr), shape=(size, size))

    def full(self, u_free: np.ndarray) -> np.ndarray:
        U = np.zeros((self.n_blocks, 6))
        U[self.free_mask] = u_free
        return U

    def block_of_dof(self, i: int) -> tuple[int, str]:
        blk, dof = np.argwhere(self.dof_index == i)[0]
        return int(blk), DOFS[int(dof)]


# ----------------------------------------------------------------------------------------------
# Newton iterations
# ----------------------------------------------------------------------------------------------


def _factor(A: sp.csc_matrix):
    """Sparse LU (symmetric-mode ordering: the pattern of H^T D H is symmetric)."""
    try:
        return spla.splu(
            A,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.01,
            options={"SymmetricMode": True},
        )
    except RuntimeError as exc:  # "Factor is exactly singular"
        return exc


class _LinearSolver:
    """Solves with the current tangent, reusing an older LU as a GMRES preconditioner.

    Between two Newton iterations only the interfaces that change state change the tangent:
    a low-rank update, which GMRES preconditioned with the previous factorisation resolves in
    a few iterations. A new factorisation is made when GMRES does not reach ``rtol`` within
    ``max_krylov`` iterations.
    """

    def __init__(self, rtol: float = 1e-10, max_krylov: int = 30):
        self.lu = None
        self.rtol = rtol
        self.max_krylov = max_krylov
        self.n_factor = 0
        self.n_krylov = 0
        self.n_tries = 0

    def solve(self, A: sp.csc_matrix, rhs: np.ndarray):
        # Krylov reuse pays only if it mostly succeeds: stop trying after many failures
        useful = self.n_tries < 10 or self.n_krylov >= 0.5 * self.n_tries
        if useful and self.lu is not None and self.lu.shape == A.shape:
            self.n_tries += 1
            lu = self.lu
            M = spla.LinearOperator(A.shape, matvec=lu.solve, dtype=float)
            x0 = lu.solve(rhs)
            if np.all(np.isfinite(x0)):
                x, info = spla.gmres(
                    A,
                    rhs,
                    x0=x0,
                    rtol=self.rtol,
                    atol=0.0,
                    restart=self.max_krylov,
                    maxiter=1,
                    M=M,
                )
                res = np.linalg.norm(A @ x - rhs)
                if info == 0 and np.isfinite(res) and res <= 10 * self.rtol * np.linalg.norm(rhs):
                    self.n_krylov += 1
                    return x
        lu = _factor(A)
        if isinstance(lu, Exception):
            return lu
        self.lu = lu
        self.n_factor += 1
        return lu.solve(rhs)


def _check_finite(model: _Model, f: np.ndarray, R: np.ndarray, lam: float):
    if np.all(np.isfinite(f)) and np.all(np.isfinite(R)):
        return
    bad_itf = np.flatnonzero(~np.isfinite(f).all(axis=1))
    bad_dof = np.flatnonzero(~np.isfinite(R))
    blocks = sorted({model.block_of_dof(int(i))[0] for i in bad_dof[:20]})
    raise StaticSolverError(
        f"NaN or inf at lambda = {lam:.6g}: interfaces {bad_itf[:10].tolist()}, blocks "
        f"{blocks[:10]}",
        blocks=blocks,
        interfaces=bad_itf[:10],
        lam=lam,
    )


def _bordered(K: sp.csc_matrix, F_live: np.ndarray, w: np.ndarray) -> sp.csc_matrix:
    n = K.shape[0]
    Kc = K.tocoo()
    nz_f = np.flatnonzero(F_live)
    nz_w = np.flatnonzero(w)
    rows = np.concatenate([Kc.row, nz_f, np.full(len(nz_w), n)])
    cols = np.concatenate([Kc.col, np.full(len(nz_f), n), nz_w])
    vals = np.concatenate([Kc.data, -F_live[nz_f], w[nz_w]])
    return sp.csc_matrix((vals, (rows, cols)), shape=(n + 1, n + 1))


@dataclass
class _Newton:
    """Outcome of :func:`_newton`."""

    converged: bool
    u: np.ndarray
    lam: float
    f: np.ndarray
    state: np.ndarray
    trial: tuple
    iterations: int
    residual: np.ndarray
    floor: float
    singular: str = ""
    loose: bool = False


def _newton(
    model,
    settings,
    u0,
    lam0,
    dead_target=None,
    dc=None,
    floor0=None,
    max_iterations=None,
    guess=None,
    w=None,
):
    """Newton iterations with a damped tangent (Levenberg-Marquardt on the tangent floor).

    Load control (``dead_target`` given, lambda fixed) or displacement control (``dc``: the
    increment of ``c = w . u`` from ``u0``; lambda is an unknown, bordered system).

    Yielded and open components of the tangent keep a fraction ``floor`` of their elastic
    stiffness. An iterate that raises the residual is rejected and the floor grows tenfold
    (a stiffer, shorter step); an accepted one lowers it tenfold down to
    ``StaticSettings.tangent_floor``, so the iteration ends with the consistent tangent. The floor
    changes only the iteration matrix: the residual uses the exact interface law.
    """
    floor_min = model.tangent_floor
    floor = floor_min if floor0 is None else max(floor0, floor_min)
    ref = model.dead_norm + 1e-300
    fl = model.live_norm
    u = u0.copy()
    lam = lam0
    if w is None:
        w = model.w
    c_target = None if dc is None else float(w @ u0) + dc
    if guess is not None:
        # start from a predicted point (the constraint still counts from u0)
        u = guess[0].copy()
        lam = guess[1]

    def residual(u_, lam_, floor_):
        f_, D_, st_, tr_, Fint = model.evaluate(model.full(u_), floor_)
        target = dead_target if dead_target is not None else model.F_dead + lam_ * model.F_live
        R_ = target - Fint
        _check_finite(model, f_, R_, lam_)
        return f_, D_, st_, tr_, R_

    f, D, state, trial, R = residual(u, lam, floor)
    r_norm = np.linalg.norm(R)
    first = True
    best = None
    n_iter = 0
    if max_iterations is None:
        max_iterations = settings.max_iterations
    for n_iter in range(1, max_iterations + 1):
        tol = settings.tolerance * (ref + abs(lam) * fl)
        if not first and r_norm <= tol:
            return _Newton(True, u, lam, f, state, trial, n_iter - 1, R, floor)
        if dc is None:
            A = model.stiffness(D)
            rhs = R
        else:
            if w is model.w:
                A = model.stiffness(D, bordered=True)
            else:
                A = _bordered(model.stiffness(D), model.F_live, w)
            rhs = np.concatenate([R, [c_target - w @ u]])
        sol = model.linear.solve(A, rhs)
        if isinstance(sol, Exception):
            if floor < 1.0:
                floor = min(10.0 * floor, 1.0)
                f, D, state, trial, R = residual(u, lam, floor)
                continue
            return _Newton(False, u, lam, f, state, trial, n_iter, R, floor, str(sol))
        if not np.all(np.isfinite(sol)):
            floor = min(10.0 * floor, 1.0)
            f, D, state, trial, R = residual(u, lam, floor)
            continue
        # backtracking along the Newton direction (the constraint row is linear, so a partial
        # step keeps a proportional constraint residual)
        for step_len in (1.0, 0.5, 0.25, 0.125, 1 / 32, 1 / 256):
            u_new = u + step_len * sol[: model.n_free]
            lam_new = lam if dc is None else lam + step_len * sol[-1]
            f1, D1, st1, tr1, R1 = residual(u_new, lam_new, floor)
            r1 = np.linalg.norm(R1)
            if first or r1 <= r_norm:
                break
        if first or r1 <= r_norm or floor >= 1.0:
            u, lam, f, D, state, trial, R, r_norm = u_new, lam_new, f1, D1, st1, tr1, R1, r1
            first = False
            if dc is None or abs(c_target - w @ u) <= 1e-9 * abs(dc):
                if best is None or r_norm < best[0]:
                    best = (r_norm, u, lam, f, state, trial, R)
            if floor > floor_min:
                # the lower floor takes effect at the next evaluation (saves one evaluation)
                floor = max(0.1 * floor, floor_min)
        else:
            floor = min(10.0 * floor, 1.0)
            f, D, state, trial, R = residual(u, lam, floor)
    tol = settings.tolerance * (ref + abs(lam) * fl)
    if not first and r_norm <= tol:
        return _Newton(True, u, lam, f, state, trial, n_iter, R, floor)
    # stalled near a kink of the law (typically the apex of a joint's cone at N -> 0): accept
    # the best iterate if its residual is below the looser tolerance
    if best is not None and best[0] <= model.accept_tolerance * (ref + abs(best[2]) * fl):
        r_b, u_b, lam_b, f_b, st_b, tr_b, R_b = best
        return _Newton(True, u_b, lam_b, f_b, st_b, tr_b, n_iter, R_b, floor, loose=True)
    return _Newton(False, u, lam, f, state, trial, n_iter, R, floor)


def _newton_dead(model: _Model, settings: StaticSettings):
    """Equilibrium under the dead load (load control, ``dead_steps`` increments)."""
    u = np.zeros(model.n_free)
    n_iter = 0
    f = None
    for step in range(1, settings.dead_steps + 1):
        target = model.F_dead * step / settings.dead_steps
        # the dead load starts from unloaded joints with no friction capacity: allow more
        # iterations than a live step
        out = _newton(
            model, settings, u, 0.0, dead_target=target, max_iterations=4 * settings.max_iterations
        )
        n_iter += out.iterations
        if not out.converged:
            R = out.residual
            blk, dof = model.block_of_dof(int(np.argmax(np.abs(R))))
            changing = np.flatnonzero(out.state != STATE_ELASTIC)
            why = f" ({out.singular})" if out.singular else ""
            raise StaticSolverError(
                f"no equilibrium under the dead load after {out.iterations} iterations{why} "
                f"(residual {np.linalg.norm(R):.3e}, largest at block {blk} {dof}): the "
                "assembly may be a mechanism under its own weight",
                blocks=[blk],
                interfaces=changing[:10],
                lam=0.0,
            )
        u, f = out.u, out.f
        model.commit(out.trial, out.state)
    return u, f, n_iter


def _no_mechanism(model: _Model) -> str:
    """Why no collapse mechanism exists, or "" if one may.

    A mechanism is a motion ``U`` of the free dofs that opens no interface: the normal gap
    ``dn + phi1 y2 - phi2 y1`` is >= 0 at every corner of every interface polygon (sliding is
    free: zero-dilatancy friction and tensile strength only dissipate). If the live load does
    no positive work on any such motion, no multiplier can make the assembly collapse
    (kinematic theorem with the least restrictive joints): a linear program, solved before
    the live load.
    """
    rows = []
    for k in range(model.m):
        poly = model.itf.local_polygon(k)
        g = np.zeros((len(poly), 6))
        g[:, 0] = 1.0
        g[:, 3] = poly[:, 1]
        g[:, 4] = -poly[:, 0]
        rows.append((k, g @ model.B[k]))
    n = model.n_free
    r_idx, c_idx, vals = [], [], []
    n_rows = 0
    for k, gb in rows:
        dofs = np.concatenate([model.dof_index[model.a[k]], model.dof_index[model.b[k]]])
        keep = dofs >= 0
        for row in gb:
            nz = keep & (row != 0.0)
            r_idx.append(np.full(int(nz.sum()), n_rows))
            c_idx.append(dofs[nz])
            vals.append(-row[nz])
            n_rows += 1
    G = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(r_idx), np.concatenate(c_idx))), shape=(n_rows, n)
    )
    # translations bounded by 1 m, rotations by 1 / L rad (L the assembly's size)
    size = float(np.ptp(model.scene.assembly.centroid, axis=0).max()) or 1.0
    is_rot = np.broadcast_to(np.arange(6) >= 3, (model.n_blocks, 6))[model.free_mask]
    bound = np.where(is_rot, 1.0 / size, 1.0)
    res = linprog(
        -model.F_live,
        A_ub=G,
        b_ub=np.zeros(n_rows),
        bounds=np.column_stack([-bound, bound]),
        method="highs",
    )
    if res.status != 0:
        logger.debug("mechanism check inconclusive (%s): the path decides", res.message)
        return ""
    work = -float(res.fun)
    scale = float(np.abs(model.F_live) @ bound)
    if work > 1e-7 * scale:
        return ""
    return (
        "no mechanism: the live load does no positive work on any motion that opens no joint "
        f"(largest work {work:.3e} of at most {scale:.3e}), so no multiplier makes the assembly "
        "collapse (it points into the supports or is carried by them)"
    )


def _still_rising(criteria: CollapseCriteria, settings: StaticSettings) -> str:
    """The reason of a ``max_steps`` end: how fast lambda still rises."""
    window = settings.plateau_steps * criteria.dc0
    slope = criteria.secant_slope(window)
    if slope is None:
        slope = criteria.secant_slope(0.0)
    ratio = 0.0 if slope is None or not criteria.slope0 else slope / criteria.slope0
    reason = (
        f"still rising at {100 * ratio:.2g} % of the initial slope after max_steps = "
        f"{settings.max_steps}"
    )
    logger.warning(reason)
    return reason


@dataclass
class _Path:
    """The path of a run, for :func:`_finish`."""

    lams: np.ndarray
    ctrl: np.ndarray
    history: np.ndarray
    last_du: np.ndarray
    u: np.ndarray
    peak: dict
    counts: tuple


def _finish(model, settings, path: _Path, termination: str, failure: str, start: float):
    """The :class:`StaticResult` of a run; raise :class:`NoCollapseError` per ``on_failure``."""
    scene = model.scene
    mech = model.full(path.last_du)
    scale = np.abs(mech[:, :3]).max()
    mech = mech / scale if scale > 0 else mech
    if settings.monitor is not None:
        mon = (int(settings.monitor[0]), int(settings.monitor[1]))
        if not (0 <= mon[0] < model.n_blocks and 0 <= mon[1] < 6):
            raise ValueError(f"monitor {settings.monitor} is not a (block, dof) of the scene")
    else:
        live_dir = scene.loads.live_wrench[:, :3].sum(axis=0)
        dof = int(np.argmax(np.abs(live_dir)))
        mon = (int(np.argmax(np.abs(mech[:, dof]))), dof)
    idx = model.dof_index[mon]
    monitor_path = path.history[:, idx] if idx >= 0 else np.zeros(len(path.history))
    f_end, _, state_end, _, _ = model.evaluate(model.full(path.u))
    wall = time.perf_counter() - start
    n_steps, n_iter, n_loose, n_cascades, n_arc = path.counts
    peak = path.peak
    collapsed = termination in COLLAPSE_TERMINATIONS
    logger.info(
        "%s: lambda_max = %.6g after %d steps, %d iterations, %.2f s (%s)",
        "collapse" if collapsed else "no collapse",
        peak["lam"],
        n_steps,
        n_iter,
        wall,
        termination,
    )
    result = StaticResult(
        lambda_max=float(peak["lam"]),
        collapsed=collapsed,
        pushover_lambda=path.lams,
        pushover_control=path.ctrl,
        pushover_monitor=np.asarray(monitor_path, dtype=float),
        monitor=mon,
        interface_state=model.state.copy(),
        interface_state_at_peak=peak["state"],
        interface_forces=peak["f"],
        interface_forces_end=f_end,
        mechanism=mech,
        displacements=model.full(path.u),
        displacements_at_peak=model.full(peak["u"]),
        block_a=model.a.copy(),
        block_b=model.b.copy(),
        n_steps=n_steps,
        n_iterations=n_iter,
        n_loose_steps=n_loose,
        n_cascades=n_cascades,
        n_arc_steps=n_arc,
        failure="" if collapsed else failure,
        termination=termination,
        wall_s=wall,
        settings=asdict(settings),
    )
    if not collapsed and settings.on_failure == "raise":
        raise NoCollapseError(failure, result)
    return result


def solve_collapse(scene: Scene, settings: StaticSettings | None = None) -> StaticResult:
    r"""Dead load, then the live load to collapse (seed 001, Sec. 2.3).

    Parameters
    ----------
    scene : Scene
        Blocks, supports, dead load (self weight + ``dead_wrench``) and the live pattern
        ``live_wrench`` scaled by lambda.
    settings : StaticSettings, optional

    Returns
    -------
    StaticResult

    Raises
    ------
    ValueError
        Bad inputs (no interfaces, no free dof, no friction coefficient, zero live load).
    StaticSolverError
        Unsupported blocks (singular stiffness before any load), no equilibrium under the dead
        load, NaN; the message names the blocks or interfaces involved.
    NoCollapseError
        With ``on_failure="raise"`` (default): the run ended without a collapse (no mechanism
        exists, ``max_steps`` reached while lambda still rises, or stalled); ``reason`` says
        which and ``result`` holds the partial path.

    Notes
    -----
    Each live step solves, for the increment of the control displacement ``\Delta c``,

    .. math::

        \begin{bmatrix} K_t & -F_L \\ w^T & 0 \end{bmatrix}
        \begin{bmatrix} \delta U \\ \delta\lambda \end{bmatrix} =
        \begin{bmatrix} F_D + \lambda F_L - H^T f(U) \\ c_0 + \Delta c - w^T U \end{bmatrix},

    with the consistent tangent ``K_t = H^T D H`` of the interface laws.

    The control is ``w = F_L / |F_L|_1`` (the live-load-weighted mean displacement) until a step
    fails even at ``min_step_ratio`` times its first size away from a plateau. Near some peaks
    the path turns in ``c`` or a local mechanism forms that ``c`` hardly measures; Newton then
    keeps crossing a joint's kink (seed 001 S15 with return walls, resultant law: the step
    shrank to 1e-4 of the first while lambda still rose at 1.5 % of the initial slope). From
    there on ``w`` is the unit direction of the previous increment (the updated normal plane
    of Riks' method), with steps measured in the length of the first increment; this follows
    the path through limit points and snap-backs (S15 then ends on a plateau at 0.1925, 0.6 %
    above where it stalled). The plateau slope is taken over a stretch of path long enough to
    resolve the tolerance noise, and a plateau must span ``plateau_steps`` first increments.

    Limitations found on the seed 001 specimens: kinematics are small-displacement, so the
    fibre law's rocking uplift against immovable supports (fixed columns) builds unbounded
    arching. The resultant law has no uplift (its hinges rotate about the joint centroid), so
    with fixed columns the wall rather overturns about its base, sliding along the column.
    """
    start = time.perf_counter()
    settings = StaticSettings() if settings is None else settings
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a dem.scene.Scene, got {type(scene).__name__}")
    model = _Model(scene, settings)
    u, f_dead, n_iter = _newton_dead(model, settings)
    logger.debug("dead load: %d iterations", n_iter)

    lam = 0.0
    us = [u.copy()]
    # first increment: the elastic control displacement of d lambda = load_step * lambda_scale
    peak = dict(lam=0.0, u=u.copy(), f=f_dead.copy(), state=model.state.copy())
    no_mechanism = _no_mechanism(model)
    if no_mechanism:
        path = _Path(
            lams=np.zeros(1),
            ctrl=np.array([float(model.w @ u)]),
            history=u[None, :].copy(),
            last_du=np.zeros_like(u),
            u=u,
            peak=dict(peak, lam=math.inf),
            counts=(0, n_iter, 0, 0, 0),
        )
        return _finish(model, settings, path, "no_mechanism", no_mechanism, start)
    _, D, _, _, _ = model.evaluate(model.full(u), 1.0)  # elastic stiffness
    lu = _factor(model.stiffness(D))
    if isinstance(lu, Exception):
        raise StaticSolverError(f"singular stiffness after the dead load: {lu}", lam=0.0)
    dlam0 = settings.load_step * model.lambda_scale
    dc0 = float(model.w @ lu.solve(model.F_live)) * dlam0
    if not (math.isfinite(dc0) and dc0 > 0):
        raise StaticSolverError(
            "the live load does no work on the elastic response (control increment "
            f"{dc0:.3e} m): the live pattern is carried without displacement",
            lam=0.0,
        )
    dc = dc0
    dc_max = settings.max_step_factor * dc0
    criteria = CollapseCriteria(
        float(model.w @ u),
        dc0,
        settings.plateau_slope,
        settings.plateau_steps,
        settings.softening_drop,
        settings.plateau_rise,
    )
    termination = "max_steps"
    last_du = np.zeros_like(u)
    n_steps = 0
    floor = None
    n_loose = 0
    n_cascades = 0
    dc_cascade = dc0
    failure = ""
    last_dlam = 0.0
    last_dc = 0.0
    # constraint of the steps: the fixed control w until a step fails at the smallest size,
    # then the direction of the last increment (updated normal plane, StaticSettings notes)
    w_step = model.w
    dc_ref = dc0
    du_norm_first = 0.0  # length of the first increment: the step unit along the path
    n_arc = 0
    while n_steps < settings.max_steps:
        out = None
        if model.predictor and last_dc > 0:
            # predictor: the last increment scaled to this one (StaticSettings.predictor)
            scale = dc / last_dc
            out = _newton(
                model,
                settings,
                u,
                lam,
                dc=dc,
                floor0=floor,
                guess=(u + scale * last_du, lam + scale * last_dlam),
                max_iterations=settings.target_iterations,
                w=w_step,
            )
        if out is None or not out.converged:
            if out is not None:
                n_iter += out.iterations
            out = _newton(model, settings, u, lam, dc=dc, floor0=floor, w=w_step)
        if not out.converged:
            last_dc = 0.0
            if dc >= 0.5 * dc_cascade * (1 + 1e-12):
                dc_cascade = dc
            dc *= 0.5
            if dc < settings.min_step_ratio * dc_ref:
                # the smallest step fails: that is the collapse only if the path was already
                # on the plateau for a while (else report the failure, not a false peak)
                if criteria.near_plateau:
                    termination = "plateau"
                    logger.warning(
                        "step cut below the minimum on the plateau at lambda = %.6g: "
                        "taken as collapse",
                        lam,
                    )
                    break
                if model.commit_breaks(out.trial):
                    # brittle cascade (mortar cracking that snaps back): keep the cracks of
                    # the failed trial, re-start from the last equilibrium; lambda drops
                    n_cascades += 1
                    logger.info("cracking cascade at lambda = %.6g: cracks kept", lam)
                    dc = dc_cascade
                    continue
                du_norm = float(np.linalg.norm(last_du))
                if w_step is model.w and du_norm_first > 0 and du_norm > 0:
                    # the path turns away from the fixed control (a limit point in c, or a
                    # local mechanism the load-weighted mean hardly sees): follow it along
                    # the normal plane of its last increment instead
                    logger.info("control switched to the path direction at lambda = %.6g", lam)
                    w_step = last_du / du_norm
                    dc_ref = du_norm_first
                    dc = dc_cascade = dc_ref
                    dc_max = settings.max_step_factor * dc_ref
                    continue
                blk, dof = model.block_of_dof(int(np.argmax(np.abs(out.residual))))
                changing = np.flatnonzero(out.state != model.state)
                message = (
                    f"no convergence at lambda = {lam:.6g} after cutting the step to "
                    f"{dc:.3e} m (largest residual at block {blk} {dof}; {len(changing)} "
                    f"interfaces changing state, e.g. {changing[:5].tolist()})"
                )
                termination = "stalled"
                failure = f"stalled: {message}"
                break
            continue
        u_new, lam_new, f, state, its = out.u, out.lam, out.f, out.state, out.iterations
        floor = out.floor
        n_loose += int(out.loose)
        model.commit(out.trial, state)
        n_iter += its
        n_steps += 1
        last_du = u_new - u
        dlam = lam_new - lam
        last_dlam, last_dc = dlam, dc
        if n_steps == 1:
            du_norm_first = float(np.linalg.norm(last_du))
        if w_step is not model.w:
            n_arc += 1
            w_step = last_du / np.linalg.norm(last_du)
        u, lam = u_new, lam_new
        us.append(u.copy())
        if lam > peak["lam"]:
            peak = dict(lam=lam, u=u.copy(), f=f.copy(), state=state.copy())
        # lambda is known to the residual tolerance the step met (relative to the loads)
        tol = model.accept_tolerance if out.loose else settings.tolerance
        lam_noise = tol * (model.dead_norm + abs(lam) * model.live_norm) / model.live_norm
        end = criteria.add(lam, float(model.w @ u), lam_noise, out.loose)
        if end is not None:
            termination = end
            break
        # a loose step stalled at a kink of the law, which a shorter step does not remove
        growth = 1.0 if out.loose else math.sqrt(settings.target_iterations / max(its, 1))
        dc = min(dc * min(max(growth, 0.5), 2.0), dc_max)
    else:
        failure = _still_rising(criteria, settings)

    path = _Path(
        lams=np.array(criteria.lams),
        ctrl=np.array(criteria.ctrl),
        history=np.array(us),
        last_du=last_du,
        u=u,
        peak=peak,
        counts=(n_steps, n_iter, n_loose, n_cascades, n_arc),
    )
    return _finish(model, settings, path, termination, failure, start)
