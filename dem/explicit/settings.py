"""Settings of the explicit solver and its drivers (frozen, validated on construction)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dem.units import MM

INDENTER_NODES_PER_RADIUS_INV = 0.1
"""Default indenter node spacing as a fraction of the tip radius."""
STOP_PERSIST = 0.2 * MM
"""Travel over which a drop below ``stop_below_peak_fraction`` must persist to stop [m]."""
PARALLEL_MIN_ENTRIES = 20000
"""Contact entries from which ``parallel=None`` evaluates them with ``prange``."""


class SimulationError(RuntimeError):
    """The explicit run failed (blow-up to NaN or inf, or a phase did not converge)."""


@dataclass(frozen=True)
class ExplicitSettings:
    """Settings of the explicit solver (SI units).

    Attributes
    ----------
    k_n : float
        Normal penalty, traction per penetration [Pa/m] (seed 000 Eq. (2); for TIS panels
        use :func:`dem.tis_stiffness.k_def` or :func:`dem.tis_stiffness.k_series`).
    kt_over_kn : float
        Tangential penalty ``k_t = kt_over_kn * k_n`` (seed 000 Eq. (1)); default 1. It must
        be positive: the friction force is that spring's, capped at ``mu N`` (with ``k_t = 0``
        there would be none whatever ``mu``; a frictionless scene has ``mu = 0``).
    node_spacing : float
        Grid spacing of surface nodes [m]; default 0.5 mm (seed 000 used 0.06 mm).
    indenter_node_spacing : float or None
        Node spacing under the indenter [m]; default the smaller of ``node_spacing`` and a tenth
        of the tip radius (the contact patch of the sphere is small).
    margin : float
        Neighbour-list and face-seeding margin [m]; default 0.1 mm. The list is rebuilt when a
        block has moved ``margin / 2``.
    mu : float or None
        Friction coefficient of every block, ``inf``: no sliding (as in the scene); None takes
        ``scene.assembly.mu`` (per block).
    mu_rule : {"mean", "min"}
        How two blocks' coefficients combine: the arithmetic mean (default) or the smaller.
    node_layout : {"centroid", "vertex"}
        One node at the centroid of each grid cell clipped to the face (midpoint rule;
        default), or nodes at the cell corners with equal shares of the cells' areas
        (trapezoidal rule, nodes on the face edges). The default is the layout whose peak
        load converges monotonically with the spacing.
    contact_plane : {"nearest", "compatible"}
        With face planes: penetration and normal from the nearest plane of the neighbour (the
        exact convex signed distance; default), or from the nearest plane among the
        neighbour's faces that face the node's own face, counting only the part of the
        node's patch of face that lies over the neighbour (keeps a conforming interface
        conforming next to the neighbour's edges; a node beside the neighbour carries
        nothing). With ``node_layout="vertex"`` and
        neighbours sharing edges (masonry), use "compatible": the nearest plane gives the
        nodes on a shared edge about zero depth, so a hinge there carries nothing.
    signed_distance : {"planes", "level_set"}
        Exact face planes of the convex blocks (default) or trilinear level-set grids.
    level_set_spacing : float
        Level-set grid spacing [m]; default 0.1 mm (seed 000 used 0.025 mm; memory grows as
        ``(block size / spacing)^3`` per block).
    dt : float or None
        Time step [s]; None: ``dt_safety`` times the stable limit. A forced ``dt`` above the
        stable limit raises ``ValueError``. The time step never changes during a run; contacts
        that appear later are checked against it (:mod:`dem.explicit.step_check`), and a run
        meeting a contact it is unstable for stops with :class:`SimulationError`.
    dt_safety : float
        Fraction of the stable limit of the contacts at the start; default 0.5 (room for
        contacts that appear later).
    mass_scaling : float
        Factor on inertial masses and inertias (weights stay true); default 1 (none).
    global_damping : float
        Global viscous damping as a damping ratio at the highest frequency ``omega_max``:
        ``alpha = 2 global_damping omega_max`` [1/s]; lower modes are damped more
        (``zeta = alpha / (2 omega)``). Default 0.02. The damping force is explicit: a ratio
        that makes the time step unstable (about 0.78 at the defaults) is refused.
    contact_damping : float
        Stiffness-proportional normal dashpot as a damping ratio at ``omega_max``
        (``beta = 2 contact_damping / omega_max``); default 0.1.
    local_damping : float
        Local (non-viscous) damping coefficient in [0, 1) (Cundall's, as in 3DEC and PFC; see
        :mod:`dem.kernels.integrate`): damps vibrations of every mode without resisting
        steady motion. Default 0 (off).
    parallel : bool or None
        Evaluate contact entries in parallel (``prange`` over chunks of entries); None: when
        there are at least ``PARALLEL_MIN_ENTRIES`` entries and more than one core. Default
        False (serial: the threads pay only with free cores; ``benchmarks/bench_explicit.py``
        compares the two).
    chunk_steps : int
        Steps per call of the compiled loop (checkpoints fall on chunk ends); default 200.
    progress_every_s : float
        Log progress at INFO level this often [s] of wall time; default 10.
    """

    k_n: float
    kt_over_kn: float = 1.0
    node_spacing: float = 0.5 * MM
    indenter_node_spacing: float | None = None
    margin: float = 0.1 * MM
    mu: float | None = None
    mu_rule: str = "mean"
    node_layout: str = "centroid"
    contact_plane: str = "nearest"
    signed_distance: str = "planes"
    level_set_spacing: float = 0.1 * MM
    dt: float | None = None
    dt_safety: float = 0.5
    mass_scaling: float = 1.0
    global_damping: float = 0.02
    contact_damping: float = 0.1
    local_damping: float = 0.0
    parallel: bool | None = False
    chunk_steps: int = 200
    progress_every_s: float = 10.0

    def __post_init__(self):
        positive = {
            "k_n": self.k_n,
            "kt_over_kn": self.kt_over_kn,
            "node_spacing": self.node_spacing,
            "margin": self.margin,
            "level_set_spacing": self.level_set_spacing,
            "mass_scaling": self.mass_scaling,
            "dt_safety": self.dt_safety,
            "progress_every_s": self.progress_every_s,
        }
        for name, value in positive.items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value}")
        for name in ("global_damping", "contact_damping"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {value}")
        if self.dt is not None and not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be finite and positive [s], got {self.dt}")
        spacing = self.indenter_node_spacing
        if spacing is not None and not (math.isfinite(spacing) and spacing > 0):
            raise ValueError(
                f"indenter_node_spacing must be finite and positive [m], got {spacing}"
            )
        if self.mu is not None and not self.mu >= 0:
            raise ValueError(f"mu must be >= 0 (inf: no sliding), got {self.mu}")
        if self.mu_rule not in ("mean", "min"):
            raise ValueError(f"mu_rule must be 'mean' or 'min', got {self.mu_rule!r}")
        if self.node_layout not in ("vertex", "centroid"):
            raise ValueError(
                f"node_layout must be 'vertex' or 'centroid', got {self.node_layout!r}"
            )
        if self.contact_plane not in ("compatible", "nearest"):
            raise ValueError(
                f"contact_plane must be 'compatible' or 'nearest', got {self.contact_plane!r}"
            )
        if self.signed_distance not in ("planes", "level_set"):
            raise ValueError(
                f"signed_distance must be 'planes' or 'level_set', got {self.signed_distance!r}"
            )
        if not (math.isfinite(self.local_damping) and 0 <= self.local_damping < 1):
            raise ValueError(f"local_damping must be in [0, 1), got {self.local_damping}")
        if self.dt_safety > 1:
            raise ValueError(f"dt_safety must be <= 1, got {self.dt_safety}")
        if int(self.chunk_steps) != self.chunk_steps or self.chunk_steps < 1:
            raise ValueError(f"chunk_steps must be a positive integer, got {self.chunk_steps}")

    @property
    def k_t(self) -> float:
        """Tangential penalty [Pa/m]."""
        return self.kt_over_kn * self.k_n


@dataclass(frozen=True)
class RelaxationSettings:
    """Relaxation under gravity (seed 000, Sec. 3).

    Attributes
    ----------
    ke_speed : float
        Stop when the kinetic energy is below ``1/2 M_free ke_speed^2`` [m/s]; default 1e-6.
    min_steps, max_steps : int
        Bounds on the number of steps; defaults 1000 and 200000. Reaching ``max_steps``
        without meeting the tolerance raises :class:`SimulationError`.
    global_damping : float or None
        Damping ratio at ``omega_max`` during relaxation (None: the solver's value).
    local_damping : float or None
        Local (non-viscous) damping coefficient in [0, 1) during relaxation (None: the solver's
        value, :attr:`ExplicitSettings.local_damping`). With ``global_damping=0`` a block that
        still has to drop into place falls at ``1 - local_damping`` of its free acceleration,
        where the viscous damping of the default lets it sink at ``g / alpha``, slow enough to
        pass for rest.
    require_convergence : bool
        Raise when ``max_steps`` pass without meeting the tolerance (default); otherwise log a
        warning and go on (a panel without interlock, theta = 0, never comes to rest). The
        same for a block out of balance at the end (``unbalanced_tol``).
    unbalanced_tol : float
        Largest out-of-balance ratio accepted at the end of relaxation: a free block's net
        force (external load plus contact forces), or net moment over its bounding radius, as
        a fraction of the load it carries (its weight for a block resting on supports; see
        :meth:`dem.explicit.model.ExplicitModel.unbalanced`). Default 1e-2; inf: no check.
        The kinetic energy alone misses a heavy block that creeps under over-damping, and
        under local damping a block that passes a moment of slow motion: relaxation goes on
        until both criteria hold.
    """

    ke_speed: float = 1e-6
    min_steps: int = 1000
    max_steps: int = 200000
    global_damping: float | None = 0.1
    local_damping: float | None = None
    require_convergence: bool = True
    unbalanced_tol: float = 1e-2

    def __post_init__(self):
        if not (math.isfinite(self.ke_speed) and self.ke_speed > 0):
            raise ValueError(
                f"RelaxationSettings.ke_speed must be finite and positive [m/s], got "
                f"{self.ke_speed}"
            )
        for name in ("min_steps", "max_steps"):
            value = getattr(self, name)
            if int(value) != value or value < (1 if name == "max_steps" else 0):
                raise ValueError(
                    f"RelaxationSettings.{name} must be an integer >= "
                    f"{1 if name == 'max_steps' else 0}, got {value}"
                )
        if self.max_steps < self.min_steps:
            raise ValueError(
                f"RelaxationSettings.max_steps ({self.max_steps}) must be >= min_steps "
                f"({self.min_steps})"
            )
        if self.global_damping is not None and not (
            math.isfinite(self.global_damping) and self.global_damping >= 0
        ):
            raise ValueError(
                f"RelaxationSettings.global_damping must be finite and >= 0, got "
                f"{self.global_damping}"
            )
        if not self.unbalanced_tol > 0:
            raise ValueError(
                f"RelaxationSettings.unbalanced_tol must be positive, got {self.unbalanced_tol}"
            )
        if self.local_damping is not None and not 0 <= self.local_damping < 1:
            raise ValueError(
                f"RelaxationSettings.local_damping must be in [0, 1), got {self.local_damping}"
            )


@dataclass(frozen=True)
class IndentationSettings:
    """A rigid frictionless sphere driven down at constant speed (seed 000, Sec. 3).

    Attributes
    ----------
    block : int or None
        Block under the indenter; None: ``scene.meta["central_block"]``.
    axis_xy : (2,) tuple or None
        ``(x, y)`` of the indenter path [m]; None: the centre of the block's top face.
    tip_radius : float
        [m]; default 1.25 mm (seed 000: a "2.5 mm spherical tip", read as its diameter).
    speed : float
        [m/s]; default 5 mm/s (seed 000: 3-6 mm/s).
    max_deflection : float
        Stop at this travel [m]; default 6 mm.
    record_interval : float
        Travel between recorded points [m]; default 5 um.
    ultimate_fraction : float
        ``P / P_max`` below which the block is out (see the module docstring); default 0.1.
    out_confirm : float
        Travel with ``P`` below that fraction needed to call the block out and stop [m];
        default 0.3 mm.
    snapshot_interval : float
        Travel between snapshots of the interface resultants [m] (plus one at the peak);
        default 0.1 mm.
    stop_when_out : bool
        Stop once the block is out (default True).
    stop_below_peak_fraction : float or None
        Stop early, once ``P`` has fallen below this fraction of the peak so far after the peak
        (for studies of the peak load only); default None.
    """

    block: int | None = None
    axis_xy: tuple | None = None
    tip_radius: float = 1.25 * MM
    speed: float = 5.0 * MM
    max_deflection: float = 6.0 * MM
    record_interval: float = 5e-3 * MM
    ultimate_fraction: float = 0.1
    out_confirm: float = 0.3 * MM
    snapshot_interval: float = 0.1 * MM
    stop_when_out: bool = True
    stop_below_peak_fraction: float | None = None

    def __post_init__(self):
        for name in (
            "tip_radius",
            "speed",
            "max_deflection",
            "record_interval",
            "out_confirm",
            "snapshot_interval",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value}")
        if not 0 < self.ultimate_fraction < 1:
            raise ValueError("ultimate_fraction must be in (0, 1)")
        fraction = self.stop_below_peak_fraction
        if fraction is not None and not 0 < fraction < 1:
            raise ValueError(f"stop_below_peak_fraction must be in (0, 1), got {fraction}")
        if self.axis_xy is not None and (
            np.shape(self.axis_xy) != (2,) or not np.all(np.isfinite(self.axis_xy))
        ):
            raise ValueError(f"axis_xy must be a finite (x, y) pair [m], got {self.axis_xy}")
