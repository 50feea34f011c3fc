"""Explicit LS-DEM-style dynamics of rigid convex blocks, with a spherical indenter (seed 000).

The model (seed 000, Sec. 2): rigid blocks (6 dofs each, quaternions), fixed boundary blocks
not integrated, contact by surface nodes with tributary areas and a traction penalty
``k_n d A n`` (Eq. (2)), regularised Coulomb friction with shear history (Eq. (1)), global
viscous damping and an explicit (symplectic Euler) time step chosen from the stiffness and
masses actually present. Two phases: relaxation under gravity until the kinetic energy is
below a tolerance, then a rigid sphere driven down at constant speed onto a block, recording
the indenter load ``P`` against its travel ``delta``.

Counting, contact law and integration are documented in :mod:`dem.contact_nodes`,
:mod:`dem.kernels.contact_force` and :mod:`dem.kernels.integrate`.

Definitions of the results (:class:`IndentationResult`):

- ``delta`` [m]: indenter travel since the start of indentation, where the sphere just touches
  the top of the loaded block in its relaxed pose.
- ``load`` ``P`` [N]: mean indenter force over each recording interval, ``Delta W / Delta
  delta`` with ``W`` the work done by the indenter (so the area under the curve is ``W``).
- peak load ``P_max`` [N] and deflection at peak ``delta_peak`` [m]: the largest recorded ``P``
  and its ``delta``.
- ultimate deflection ``delta_u`` [m]: the first ``delta`` after the peak at which ``P`` falls
  to ``ultimate_fraction * P_max`` and stays there for ``out_confirm`` of further travel (the
  loaded block has slipped out); NaN if the run ended before.
- loading energy ``LE`` [J]: the work of the indenter up to ``delta_u`` (up to the end of the
  run if ``delta_u`` was not reached), ``int_0^{delta_u} P d delta``.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import os
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import scipy.linalg

from dem.contact_nodes import FACE_ANGLE_DEG, ContactNodes, build_level_sets, seed_contact_nodes
from dem.kernels.broadphase import build_pairs, carry_history
from dem.kernels.contact_force import (
    MU_RULE_MEAN,
    MU_RULE_MIN,
    accumulate_wrenches,
    elastic_energy,
    node_contacts,
    sphere_contacts,
)
from dem.kernels.integrate import (
    STATUS_NOT_FINITE,
    STATUS_REBUILD,
    kinetic_energy,
    quat_to_rot,
    run_steps,
)
from dem.scene import Scene
from dem.units import MM

logger = logging.getLogger(__name__)

INDENTER_NODES_PER_RADIUS_INV = 0.1
"""Default indenter node spacing as a fraction of the tip radius."""
EDGE_TOL = 1e-6
"""Lateral tolerance of the compatible-plane contact, relative to the node spacing: nodes on an
edge shared with the neighbour's face count as inside."""
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
        Tangential penalty ``k_t = kt_over_kn * k_n`` (seed 000 Eq. (1)); default 1.
    node_spacing : float
        Grid spacing of surface nodes [m]; default 0.5 mm (seed 000 used 0.06 mm).
    indenter_node_spacing : float or None
        Node spacing under the indenter [m]; default the smaller of ``node_spacing`` and a tenth
        of the tip radius (the contact patch of the sphere is small).
    margin : float
        Neighbour-list and face-seeding margin [m]; default 0.1 mm. The list is rebuilt when a
        block has moved ``margin / 2``.
    mu : float or None
        Friction coefficient of every block; None takes ``scene.assembly.mu`` (per block).
    mu_rule : {"mean", "min"}
        How two blocks' coefficients combine: the arithmetic mean (default) or the smaller.
    node_layout : {"centroid", "vertex"}
        One node at the centroid of each grid cell clipped to the face (midpoint rule;
        default), or nodes at the cell corners with equal shares of the cells' areas
        (trapezoidal rule, nodes on the face edges). On the 5 x 5 panel the centroid layout
        converges monotonically in the peak load, the vertex layout does not.
    contact_plane : {"nearest", "compatible"}
        With face planes: penetration and normal from the nearest plane of the neighbour (the
        exact convex signed distance; default), or from the nearest plane among the
        neighbour's faces that face the node's own face (keeps a conforming interface
        conforming next to the neighbour's edges).
    signed_distance : {"planes", "level_set"}
        Exact face planes of the convex blocks (default) or trilinear level-set grids.
    level_set_spacing : float
        Level-set grid spacing [m]; default 0.1 mm (seed 000 used 0.025 mm; memory grows as
        ``(block size / spacing)^3``: the 49 blocks of the 5 x 5 panel need about 5 GB at
        0.025 mm, 100 MB at 0.1 mm).
    dt : float or None
        Time step [s]; None: ``dt_safety`` times the stable limit. A forced ``dt`` above the
        stable limit raises ``ValueError``.
    dt_safety : float
        Fraction of the stable limit; default 0.5.
    mass_scaling : float
        Factor on inertial masses and inertias (weights stay true); default 1 (none).
    global_damping : float
        Global viscous damping as a damping ratio at the highest frequency ``omega_max``:
        ``alpha = 2 global_damping omega_max`` [1/s]; lower modes are damped more
        (``zeta = alpha / (2 omega)``). Default 0.02.
    contact_damping : float
        Stiffness-proportional normal dashpot as a damping ratio at ``omega_max``
        (``beta = 2 contact_damping / omega_max``); default 0.1.
    parallel : bool or None
        Evaluate contact entries in parallel (``prange`` over chunks of entries); None: when
        there are at least ``PARALLEL_MIN_ENTRIES`` entries and more than one core. Default
        False: on the shared 2-core machine the threads lose to the serial loop (see
        ``benchmarks/bench_explicit.py``).
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
    parallel: bool | None = False
    chunk_steps: int = 200
    progress_every_s: float = 10.0

    def __post_init__(self):
        positive = {
            "k_n": self.k_n,
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
        for name in ("kt_over_kn", "global_damping", "contact_damping"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {value}")
        if self.dt is not None and not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be finite and positive [s], got {self.dt}")
        if self.indenter_node_spacing is not None and not self.indenter_node_spacing > 0:
            raise ValueError("indenter_node_spacing must be positive [m]")
        if self.mu is not None and not (math.isfinite(self.mu) and self.mu >= 0):
            raise ValueError(f"mu must be finite and >= 0, got {self.mu}")
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
    require_convergence : bool
        Raise when ``max_steps`` pass without meeting the tolerance (default); otherwise log a
        warning and go on (a panel without interlock, theta = 0, never comes to rest).
    """

    ke_speed: float = 1e-6
    min_steps: int = 1000
    max_steps: int = 200000
    global_damping: float | None = 0.1
    require_convergence: bool = True

    def __post_init__(self):
        if not self.ke_speed > 0:
            raise ValueError(f"ke_speed must be positive [m/s], got {self.ke_speed}")
        if self.min_steps < 0 or self.max_steps < self.min_steps:
            raise ValueError("need 0 <= min_steps <= max_steps")


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


@dataclass
class IndentationResult:
    """P-delta curve, summary numbers, poses and interface forces of an indentation run.

    See the module docstring for the definitions. Arrays over records have length ``k``.

    Attributes
    ----------
    delta, load : (k,) float
        Indenter travel [m] and load [N].
    time : (k,) float
        [s] since the start of indentation.
    kinetic, elastic, work : (k,) float
        Kinetic energy, normal penalty energy and indenter work [J].
    block_pos, block_quat : (k, n_blocks, 3), (k, n_blocks, 4) float
        Poses of all blocks at every record.
    peak_load, deflection_at_peak, ultimate_deflection, loading_energy, energy_to_peak : float
        [N], [m], [m], [J], [J].
    snapshots : list of dict
        ``delta`` [m], ``pairs`` (p, 2) int, ``force`` (p, 3) [N] resultant on the first block
        of each pair, ``point`` (p, 3) [m] its point (force-weighted mean of nodal points).
    peak_state : dict
        Nodal forces at the peak record (see :func:`export_peak_state`).
    info : dict
        dt, omega_max, nodes, entries, steps, wall times, cost per node per step, settings.
    """

    delta: np.ndarray
    load: np.ndarray
    time: np.ndarray
    kinetic: np.ndarray
    elastic: np.ndarray
    work: np.ndarray
    block_pos: np.ndarray
    block_quat: np.ndarray
    peak_load: float
    deflection_at_peak: float
    ultimate_deflection: float
    loading_energy: float
    energy_to_peak: float
    snapshots: list = field(default_factory=list)
    peak_state: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)


def curve_summary(
    delta: np.ndarray, load: np.ndarray, ultimate_fraction: float, out_confirm: float
) -> dict:
    """Peak load, deflection at peak, ultimate deflection and loading energy of a P-delta curve.

    Parameters
    ----------
    delta, load : (k,) float
        [m], [N], with ``delta`` increasing.
    ultimate_fraction, out_confirm : float
        See :class:`IndentationSettings`.

    Returns
    -------
    dict
        ``peak_load`` [N], ``deflection_at_peak`` [m], ``ultimate_deflection`` [m] (NaN if not
        reached), ``loading_energy`` [J], ``energy_to_peak`` [J].
    """
    delta = np.asarray(delta, dtype=float)
    load = np.asarray(load, dtype=float)
    if len(delta) == 0:
        nan = float("nan")
        return dict(peak_load=nan, deflection_at_peak=nan, ultimate_deflection=nan,
                    loading_energy=nan, energy_to_peak=nan)  # fmt: skip
    k_peak = int(np.argmax(load))
    p_max = float(load[k_peak])
    ultimate = float("nan")
    k_end = len(delta) - 1
    below = load <= ultimate_fraction * p_max
    for k in range(k_peak + 1, len(delta)):
        if not below[k]:
            continue
        rest = np.flatnonzero(~below[k:])
        end = delta[k + rest[0]] if len(rest) else delta[-1]
        if end - delta[k] >= out_confirm or (not len(rest) and end - delta[k] >= out_confirm):
            ultimate = float(delta[k])
            k_end = k
            break
    d0 = np.concatenate([[0.0], delta])
    p0 = np.concatenate([[load[0]], load])
    energy = float(np.trapezoid(p0[: k_end + 2], d0[: k_end + 2]))
    energy_peak = float(np.trapezoid(p0[: k_peak + 2], d0[: k_peak + 2]))
    return dict(peak_load=p_max, deflection_at_peak=float(delta[k_peak]),
                ultimate_deflection=ultimate, loading_energy=energy,
                energy_to_peak=energy_peak)  # fmt: skip


class ExplicitModel:
    """A scene prepared for explicit dynamics: nodes, flat arrays, time step and state.

    Parameters
    ----------
    scene : Scene
    settings : ExplicitSettings
    indenter_block : int or None
        Block whose top face the indenter will load (nodes are seeded under its path).
    indenter_radius : float
        [m].
    indenter_axis_xy : (2,) float, optional
        ``(x, y)`` of the indenter's vertical path [m]; default the centre of the top face of
        ``indenter_block``.

    Raises
    ------
    ValueError
        Overlapping blocks in the input, a forced time step above the stable limit, bad
        settings, or NaN in the scene.
    """

    def __init__(
        self,
        scene: Scene,
        settings: ExplicitSettings,
        indenter_block: int | None = None,
        indenter_radius: float = 0.0,
        indenter_axis_xy: np.ndarray | None = None,
    ):
        self.scene = scene
        self.settings = settings
        asm = scene.assembly
        n = asm.n_blocks
        arrays = asm.arrays
        self.n_blocks = n
        self.fixed = np.asarray(scene.supports.fixed, dtype=bool)
        self.free_blocks = np.flatnonzero(~self.fixed).astype(np.int64)
        self.restrained = np.ascontiguousarray(scene.supports.restrained, dtype=np.bool_)
        self.ref_centroid = np.ascontiguousarray(asm.centroid, dtype=np.float64)
        self.face_ptr = arrays.face_ptr
        self.face_normal = arrays.face_normal
        self.face_offset = arrays.face_offset
        self.radius = np.array(
            [np.linalg.norm(b.vertices - b.centroid, axis=1).max() for b in asm.blocks]
        )
        # inertial (scaled) and true mass properties
        s = settings.mass_scaling
        self.mass_true = asm.mass.copy()
        self.inertia_true = asm.inertia.copy()
        self.inv_mass = 1.0 / (self.mass_true * s)
        self.inertia_ref = np.ascontiguousarray(self.inertia_true * s)
        self.inertia_ref_inv = np.ascontiguousarray(np.linalg.inv(self.inertia_ref))
        dead = scene.dead_wrench
        self.ext_force = np.ascontiguousarray(dead[:, :3])
        self.ext_torque = np.ascontiguousarray(dead[:, 3:])
        if settings.mu is not None:
            mu = np.full(n, settings.mu)
        elif asm.mu is not None:
            mu = asm.mu.copy()
        else:
            raise ValueError("no friction coefficient: set ExplicitSettings.mu or scene mu")
        self.block_mu = np.ascontiguousarray(mu, dtype=np.float64)
        self.mu_rule = MU_RULE_MIN if settings.mu_rule == "min" else MU_RULE_MEAN

        self.indenter_block = indenter_block
        axis_xy = None
        if indenter_block is not None:
            if not 0 <= indenter_block < n or self.fixed[indenter_block]:
                raise ValueError(f"indenter block {indenter_block} must be a free block")
            axis_xy = (
                self._top_centre(indenter_block)[:2]
                if indenter_axis_xy is None
                else np.asarray(indenter_axis_xy, dtype=float)
            )
        self.indenter_axis_xy = axis_xy
        ind_spacing = settings.indenter_node_spacing
        if ind_spacing is None:
            ind_spacing = min(
                settings.node_spacing, INDENTER_NODES_PER_RADIUS_INV * indenter_radius
            )
        self.nodes: ContactNodes = seed_contact_nodes(
            asm, self.fixed, settings.node_spacing, settings.margin, axis_xy,
            indenter_radius, ind_spacing, settings.node_layout,
        )  # fmt: skip
        nodes = self.nodes
        self.node_block = nodes.block
        self.node_r0 = np.ascontiguousarray(nodes.point - self.ref_centroid[nodes.block])
        self.node_area = nodes.area
        self.node_n0 = np.ascontiguousarray(nodes.normal)
        self.edge_tol = EDGE_TOL * settings.node_spacing
        self.compat_cos = (
            math.cos(math.radians(FACE_ANGLE_DEG))
            if settings.contact_plane == "compatible"
            else 2.0
        )
        self.weight = np.ascontiguousarray(nodes.weight)
        self.ind_block = nodes.indenter_block
        self.ind_r0 = np.ascontiguousarray(
            nodes.indenter_point - self.ref_centroid[nodes.indenter_block]
        )
        self.ind_area = nodes.indenter_area
        if settings.signed_distance == "level_set":
            ls = build_level_sets(asm, settings.level_set_spacing, 2 * settings.margin)
            self.ls = (ls.origin, ls.spacing, ls.dims, ls.ptr, ls.values)
        else:
            self.ls = (np.zeros((n, 3)), np.ones(n), np.full((n, 3), 2, dtype=np.int64),
                       np.zeros(n + 1, dtype=np.int64), np.zeros(1))  # fmt: skip

        # state (reference configuration, at rest)
        self.t = 0.0
        self.pos = self.ref_centroid.copy()
        self.quat = np.zeros((n, 4))
        self.quat[:, 0] = 1.0
        self.vel = np.zeros((n, 3))
        self.omega = np.zeros((n, 3))
        self.rot = np.zeros((n, 3, 3))
        self.force = np.zeros((n, 3))
        self.torque = np.zeros((n, 3))
        self.pair_shear = np.zeros((0, 3))
        self.pair_node = np.zeros(0, dtype=np.int64)
        self.pair_block = np.zeros(0, dtype=np.int64)
        self.rebuild()
        self.n_rebuilds = 0
        self.beta = 0.0
        if len(self.pair_node):
            self._check_overlap()
        self.omega_max = self._omega_max(indenter_radius > 0 and indenter_block is not None)
        self._choose_time_step()
        self.parallel = (
            settings.parallel
            if settings.parallel is not None
            else (len(self.pair_node) >= PARALLEL_MIN_ENTRIES and (os.cpu_count() or 1) > 1)
        )

    # -- set-up ------------------------------------------------------------------------------
    def _top_centre(self, i: int) -> np.ndarray:
        blk = self.scene.assembly.blocks[i]
        top = int(np.argmax(blk.normals[:, 2]))
        return blk.vertices[blk.faces[top]].mean(axis=0)

    def _check_overlap(self) -> None:
        out_force = np.zeros((len(self.pair_node), 3))
        out_point = np.zeros_like(out_force)
        depth = np.zeros(len(self.pair_node))
        self._evaluate(out_force, out_point, depth, self.pair_shear.copy(), dt=0.0)
        tol = 1e-6 * float(np.median(self.radius))
        bad = depth * (self.pair_weight > 0) > tol
        if np.any(bad):
            e = int(np.argmax(depth))
            a = int(self.node_block[self.pair_node[e]])
            b = int(self.pair_block[e])
            raise ValueError(
                f"blocks overlap in the input: a node of block {a} lies {depth[e]:.3e} m inside "
                f"block {b} ({int(bad.sum())} nodes inside other blocks)"
            )

    def _omega_max(self, with_indenter: bool) -> float:
        """Highest natural frequency with every candidate contact closed [rad/s].

        Each entry adds ``k A w J^T J`` with ``J`` the 3 x 12 map from the two blocks' dofs to
        the relative displacement of the node, and ``k = max(k_n, k_t)`` in every direction
        (an upper bound on the normal plus tangential stiffness); indenter nodes add their own
        ``k_n A`` to the loaded block. ``omega_max^2`` is the largest eigenvalue of
        ``K x = omega^2 M x`` over the free dofs.
        """
        st = self.settings
        k = max(st.k_n, st.k_t)
        free_index = -np.ones(self.n_blocks, dtype=np.int64)
        free_index[self.free_blocks] = np.arange(len(self.free_blocks))
        nf = len(self.free_blocks)
        if nf == 0:
            return 0.0
        K = np.zeros((6 * nf, 6 * nf))
        points = self.pos[self.node_block[self.pair_node]] + self.node_r0[self.pair_node]
        stiff = k * self.node_area[self.pair_node] * self.pair_weight
        owners = self.node_block[self.pair_node]
        sides = [(owners, 1.0), (self.pair_block, -1.0)]
        if with_indenter and len(self.ind_block):
            pts_i = self.pos[self.ind_block] + self.ind_r0
            points = np.concatenate([points, pts_i])
            stiff = np.concatenate([stiff, st.k_n * self.ind_area])
            owners = np.concatenate([owners, self.ind_block])
            sides = [(owners, 1.0), (np.concatenate([self.pair_block, self.ind_block]), 0.0)]
        jac = []
        for blk, sign in sides:
            r = points - self.pos[blk]
            J = np.zeros((len(points), 3, 6))
            J[:, :, :3] = np.eye(3)
            # u + theta x r = u - skew(r) theta
            J[:, 0, 4], J[:, 0, 5] = r[:, 2], -r[:, 1]
            J[:, 1, 3], J[:, 1, 5] = -r[:, 2], r[:, 0]
            J[:, 2, 3], J[:, 2, 4] = r[:, 1], -r[:, 0]
            jac.append((blk, sign * J))
        for bi, Ji in jac:
            for bj, Jj in jac:
                fi, fj = free_index[bi], free_index[bj]
                ok = (fi >= 0) & (fj >= 0) & (stiff > 0)
                if not np.any(ok) or not np.any(Ji[ok]) or not np.any(Jj[ok]):
                    continue
                blocks = np.einsum("m,mki,mkj->mij", stiff[ok], Ji[ok], Jj[ok])
                key = fi[ok] * nf + fj[ok]
                acc = np.zeros((nf * nf, 6, 6))
                np.add.at(acc, key, blocks)
                acc = acc.reshape(nf, nf, 6, 6).transpose(0, 2, 1, 3).reshape(6 * nf, 6 * nf)
                K += acc
        if not np.any(K):
            return 0.0
        M = np.zeros((6 * nf, 6 * nf))
        for j, i in enumerate(self.free_blocks):
            M[6 * j : 6 * j + 3, 6 * j : 6 * j + 3] = np.eye(3) / self.inv_mass[i]
            M[6 * j + 3 : 6 * j + 6, 6 * j + 3 : 6 * j + 6] = self.inertia_ref[i]
        top = scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[6 * nf - 1, 6 * nf - 1])[
            0
        ]
        return float(math.sqrt(max(top, 0.0)))

    def _choose_time_step(self) -> None:
        st = self.settings
        w = self.omega_max
        if w > 0:
            zeta = st.contact_damping
            self.dt_critical = 2.0 / w * (math.sqrt(1.0 + zeta * zeta) - zeta)
            self.beta = 2.0 * zeta / w
            self.alpha = 2.0 * st.global_damping * w
        else:
            self.dt_critical = math.inf
            self.beta = 0.0
            self.alpha = 0.0
        if st.dt is not None:
            if st.dt > self.dt_critical:
                raise ValueError(
                    f"time step dt={st.dt:.3e} s is above the stable limit "
                    f"{self.dt_critical:.3e} s (omega_max={w:.3e} rad/s)"
                )
            self.dt = float(st.dt)
        elif math.isfinite(self.dt_critical):
            self.dt = st.dt_safety * self.dt_critical
        else:
            raise ValueError("no contact stiffness in the scene: give ExplicitSettings.dt")

    # -- neighbour list ----------------------------------------------------------------------
    def rebuild(self) -> None:
        """Rebuild the contact entries and carry the shear history over."""
        quat_to_rot(self.quat, self.rot)
        node, block, weight = build_pairs(
            self.node_block, self.node_r0, self.pos, self.rot, self.ref_centroid, self.radius,
            self.face_ptr, self.face_normal, self.face_offset, self.weight,
            self.settings.margin,
        )  # fmt: skip
        shear = np.zeros((len(node), 3))
        carry_history(self.pair_node, self.pair_block, self.pair_shear, node, block, shear)
        self.pair_node, self.pair_block, self.pair_weight, self.pair_shear = (
            node, block, weight, shear,
        )  # fmt: skip
        m = len(node)
        self.out_force = np.zeros((m, 3))
        self.out_point = np.zeros((m, 3))
        self.out_depth = np.zeros(m)
        self.pos_build = self.pos.copy()
        self.quat_build = self.quat.copy()
        self.n_rebuilds = getattr(self, "n_rebuilds", 0) + 1

    # -- forces ------------------------------------------------------------------------------
    def _evaluate(self, out_force, out_point, out_depth, shear, dt):
        quat_to_rot(self.quat, self.rot)
        node_contacts(
            self.pair_node, self.pair_block, self.pair_weight, shear, self.node_block,
            self.node_r0, self.node_n0, self.node_area, self.pos, self.rot, self.vel,
            self.omega, self.ref_centroid, self.face_ptr, self.face_normal, self.face_offset,
            self.settings.signed_distance == "level_set", *self.ls, self.block_mu,
            self.mu_rule, self.compat_cos, self.edge_tol, self.settings.k_n, self.settings.k_t,
            self.beta, dt, out_force,
            out_point, out_depth,
        )  # fmt: skip

    def contact_wrenches(self, sphere: tuple | None = None) -> tuple[np.ndarray, ...]:
        """Contact forces and moments on every block at the current state (no state change).

        Parameters
        ----------
        sphere : (centre (3,), radius, velocity (3,)) or None
            Include the indenter.

        Returns
        -------
        force, torque : (n_blocks, 3)
            [N], [N m] about the current centroids.
        entry_force, entry_point : (m, 3)
            Force on each entry's node block [N] and its point [m].
        indenter_force : (k, 3)
            Force of the indenter on each indenter node's block [N].
        """
        m = len(self.pair_node)
        ef, ep, ed = np.zeros((m, 3)), np.zeros((m, 3)), np.zeros(m)
        self._evaluate(ef, ep, ed, self.pair_shear.copy(), dt=0.0)
        force = np.zeros((self.n_blocks, 3))
        torque = np.zeros((self.n_blocks, 3))
        accumulate_wrenches(self.pair_node, self.pair_block, self.node_block, self.pos, ef, ep,
                            force, torque)  # fmt: skip
        ind = np.zeros((len(self.ind_block), 3))
        if sphere is not None:
            centre, radius, velocity = sphere
            sphere_contacts(
                self.ind_block, self.ind_r0, self.ind_area, self.pos, self.rot, self.vel,
                self.omega, np.asarray(centre, float), float(radius),
                np.asarray(velocity, float), self.settings.k_n, self.beta, force, torque, ind,
            )  # fmt: skip
        return force, torque, ef, ep, ind

    def kinetic_energy(self) -> float:
        """Kinetic energy of the free blocks with the inertial masses [J]."""
        return float(
            kinetic_energy(
                self.free_blocks,
                self.inv_mass,
                self.inertia_ref,
                self.quat,
                self.vel,
                self.omega,
                self.rot,
            )  # fmt: skip
        )

    # -- stepping ----------------------------------------------------------------------------
    def advance(
        self, n_steps: int, alpha: float | None = None, indenter: dict | None = None
    ) -> np.ndarray:
        """Advance ``n_steps`` steps, rebuilding the neighbour list when needed.

        Parameters
        ----------
        n_steps : int
        alpha : float, optional
            Global damping rate [1/s] (default: the model's).
        indenter : dict, optional
            ``centre0`` (3,) [m], ``t0`` [s], ``radius`` [m], ``velocity`` (3,) [m/s].

        Returns
        -------
        (3,) float
            ``[P at the last step, indenter work in these steps, largest P]`` [N, J, N].

        Raises
        ------
        SimulationError
            If the state becomes NaN or inf.
        """
        acc = np.zeros(3)
        alpha = self.alpha if alpha is None else alpha
        ind = indenter or {}
        active = indenter is not None
        centre0 = np.asarray(ind.get("centre0", np.zeros(3)), dtype=float)
        velocity = np.asarray(ind.get("velocity", np.zeros(3)), dtype=float)
        ind_force = np.zeros((len(self.ind_block), 3))
        left = int(n_steps)
        while left > 0:
            done, status, self.t = run_steps(
                left, self.dt, self.t, self.free_blocks, alpha, self.inv_mass,
                self.inertia_ref, self.inertia_ref_inv, self.ext_force, self.ext_torque,
                self.restrained, self.pos, self.quat, self.vel, self.omega, self.rot,
                self.force, self.torque, self.ref_centroid, self.face_ptr, self.face_normal,
                self.face_offset, self.radius, self.settings.signed_distance == "level_set",
                *self.ls, self.node_block, self.node_r0, self.node_n0, self.node_area,
                self.pair_node, self.pair_block, self.pair_weight, self.pair_shear,
                self.out_force, self.out_point, self.out_depth, self.block_mu, self.mu_rule,
                self.compat_cos, self.edge_tol, self.settings.k_n, self.settings.k_t, self.beta,
                self.parallel, active,
                self.ind_block, self.ind_r0, self.ind_area, centre0,
                float(ind.get("t0", 0.0)), float(ind.get("radius", 0.0)), velocity,
                self.settings.k_n, ind_force, self.pos_build, self.quat_build,
                self.settings.margin, acc,
            )  # fmt: skip
            left -= done
            if status == STATUS_NOT_FINITE:
                raise SimulationError(
                    f"the state became NaN or inf at t={self.t:.6e} s: the run blew up "
                    f"(dt={self.dt:.3e} s, stable limit {self.dt_critical:.3e} s)"
                )
            if status == STATUS_REBUILD:
                self.rebuild()
        return acc

    def elastic_energy(self, current: bool = False) -> float:
        """Normal penalty energy ``sum 1/2 k_n d^2 w A`` [J].

        Of the last evaluated step (cheap), or with ``current`` re-evaluated at the present
        state (for energy balances).
        """
        depth = self.out_depth
        if current:
            m = len(self.pair_node)
            depth = np.zeros(m)
            self._evaluate(np.zeros((m, 3)), np.zeros((m, 3)), depth, self.pair_shear.copy(), 0.0)
        return float(elastic_energy(self.pair_node, self.pair_weight, self.node_area, depth,
                                    self.settings.k_n))  # fmt: skip

    def relax(self, relaxation: RelaxationSettings) -> dict:
        """Run under gravity until the kinetic energy is below the tolerance.

        Returns
        -------
        dict
            ``steps``, ``kinetic`` [J], ``tolerance`` [J], ``wall_s``.
        """
        start = time.perf_counter()
        m_free = float(np.sum(1.0 / self.inv_mass[self.free_blocks]))
        tol = 0.5 * m_free * relaxation.ke_speed**2
        alpha = (
            self.alpha
            if relaxation.global_damping is None
            else 2.0 * relaxation.global_damping * self.omega_max
        )
        steps = 0
        chunk = self.settings.chunk_steps
        ke = self.kinetic_energy()
        while True:
            self.advance(chunk, alpha=alpha)
            steps += chunk
            ke = self.kinetic_energy()
            if steps >= relaxation.min_steps and ke <= tol:
                break
            if steps >= relaxation.max_steps:
                message = (
                    f"relaxation did not converge in {steps} steps: kinetic energy {ke:.3e} J "
                    f"> tolerance {tol:.3e} J"
                )
                if relaxation.require_convergence:
                    raise SimulationError(message)
                logger.warning("%s; going on", message)
                break
        return {"steps": steps, "kinetic": ke, "tolerance": tol,
                "wall_s": time.perf_counter() - start}  # fmt: skip


def interface_resultants(
    pair_node: np.ndarray,
    pair_block: np.ndarray,
    node_block: np.ndarray,
    entry_force: np.ndarray,
    entry_point: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Resultant force between each pair of blocks in contact (for force chains).

    Returns
    -------
    pairs : (p, 2) int64
        ``(i, j)`` with ``i < j``.
    force : (p, 3) float
        Resultant force on block ``i`` from block ``j`` [N].
    point : (p, 3) float
        Force-magnitude-weighted mean of the nodal points [m].
    """
    a = node_block[pair_node]
    b = pair_block
    mag = np.linalg.norm(entry_force, axis=1)
    act = mag > 0
    if not np.any(act):
        return np.zeros((0, 2), dtype=np.int64), np.zeros((0, 3)), np.zeros((0, 3))
    a, b, f, p, mag = a[act], b[act], entry_force[act], entry_point[act], mag[act]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    f = np.where((a == lo)[:, None], f, -f)
    keys, inverse = np.unique(lo * (int(b.max()) + int(a.max()) + 2) + hi, return_inverse=True)
    force = np.zeros((len(keys), 3))
    np.add.at(force, inverse, f)
    wsum = np.zeros(len(keys))
    np.add.at(wsum, inverse, mag)
    point = np.zeros((len(keys), 3))
    np.add.at(point, inverse, p * mag[:, None])
    point /= wsum[:, None]
    pairs = np.zeros((len(keys), 2), dtype=np.int64)
    pairs[inverse, 0] = lo
    pairs[inverse, 1] = hi
    return pairs, force, point


def _to_reference(model: ExplicitModel, blocks: np.ndarray, points: np.ndarray) -> np.ndarray:
    """World points on given blocks mapped to the reference configuration [m]."""
    quat_to_rot(model.quat, model.rot)
    rel = points - model.pos[blocks]
    return np.einsum("mji,mj->mi", model.rot[blocks], rel) + model.ref_centroid[blocks]


def export_peak_state(model: ExplicitModel, sphere: tuple) -> dict:
    """Every nodal force at the model's current state, on both sides, for FEM post-processing.

    Points are given in the reference configuration of their block (the frame of
    ``block_vertices``); vectors (forces, gravity, accelerations, angular velocities) in the
    world frame; ``quaternion`` maps each block's reference frame to the world,
    ``v_world = R v_ref`` (``fem_check.loads.read_point_state`` reads this layout).

    Returns
    -------
    dict
        ``block`` (k,) int64; ``point`` (k, 3) [m], reference configuration of that block;
        ``force`` (k, 3) [N] acting on that block at that point (each block-block node force
        appears twice, once per side, plus the indenter's nodal forces; support reactions are
        not included); ``gravity`` (3,) [m/s^2]; ``acceleration`` (n_blocks, 6) linear
        [m/s^2] and angular [rad/s^2] accelerations of the centroids and
        ``angular_velocity`` (n_blocks, 3) [rad/s], such that with the true mass and inertia
        (``density``), in each block's reference frame, ``sum R^T force + m R^T gravity =
        m R^T a`` and ``sum (point - C0) x R^T force = I alpha' + omega' x I omega'``
        (primes: ``R^T`` times the world vectors) for every free block (zero for fixed blocks;
        ``a`` includes what global damping and mass scaling add to the motion);
        ``quaternion`` (n_blocks, 4) scalar first; ``fixed`` (n_blocks,) bool; ``density``
        (n_blocks,) [kg/m^3]; ``block_vertices`` (n_vert, 3) [m] with ``vert_ptr``
        (n_blocks + 1,); ``centroid`` (n_blocks, 3) [m], reference centroids.
    """
    force, torque, ef, ep, ind = model.contact_wrenches(sphere)
    a_blk = model.node_block[model.pair_node]
    act = np.linalg.norm(ef, axis=1) > 0
    blocks = np.concatenate([a_blk[act], model.pair_block[act]])
    points = np.concatenate([ep[act], ep[act]])
    forces = np.concatenate([ef[act], -ef[act]])
    act_i = np.linalg.norm(ind, axis=1) > 0
    quat_to_rot(model.quat, model.rot)
    if np.any(act_i):
        ib = model.ind_block[act_i]
        ipts = model.pos[ib] + np.einsum("mij,mj->mi", model.rot[ib], model.ind_r0[act_i])
        blocks = np.concatenate([blocks, ib])
        points = np.concatenate([points, ipts])
        forces = np.concatenate([forces, ind[act_i]])
    ref_points = _to_reference(model, blocks, points)
    rot = model.rot.copy()
    asm = model.scene.assembly
    gravity = np.asarray(model.scene.loads.gravity, dtype=float)
    acc = np.zeros((model.n_blocks, 6))
    omega = np.zeros((model.n_blocks, 3))
    for i in model.free_blocks:
        r = rot[i]
        m = model.mass_true[i]
        acc[i, :3] = (force[i] + model.ext_force[i]) / m
        iw = r @ model.inertia_true[i] @ r.T
        w = model.omega[i]
        moment = torque[i] + model.ext_torque[i]
        acc[i, 3:] = np.linalg.solve(iw, moment - np.cross(w, iw @ w))
        omega[i] = w
    arrays = asm.arrays
    return {
        "block": blocks.astype(np.int64),
        "point": ref_points,
        "force": forces,
        "gravity": gravity,
        "acceleration": acc,
        "angular_velocity": omega,
        "quaternion": model.quat.copy(),
        "fixed": model.fixed.copy(),
        "density": asm.density.copy(),
        "block_vertices": arrays.vertices.copy(),
        "vert_ptr": arrays.vert_ptr.copy(),
        "centroid": model.ref_centroid.copy(),
    }


# -- indentation driver with checkpoints -------------------------------------------------------

_STATE_ARRAYS = ("pos", "quat", "vel", "omega", "pos_build", "quat_build", "pair_node",
                 "pair_block", "pair_weight", "pair_shear")  # fmt: skip


def _settings_key(scene: Scene, settings, relaxation, indentation) -> str:
    payload = json.dumps(
        [scene.to_dict(), asdict(settings), asdict(relaxation), asdict(indentation)],
        sort_keys=True,
        default=str,
    )
    return hashlib.sha256(payload.encode()).hexdigest()[:16]


def simulate_indentation(
    scene: Scene,
    settings: ExplicitSettings,
    indentation: IndentationSettings | None = None,
    relaxation: RelaxationSettings | None = None,
    checkpoint: str | Path | None = None,
    checkpoint_every_s: float = 60.0,
    stop_after_chunks: int | None = None,
) -> IndentationResult:
    """Relax a scene under gravity, then indent one block at constant speed.

    Parameters
    ----------
    scene : Scene
    settings : ExplicitSettings
    indentation : IndentationSettings, optional
    relaxation : RelaxationSettings, optional
    checkpoint : path, optional
        ``.npz`` file. If it exists and was written for the same scene and settings, the run
        resumes from it; it is rewritten every ``checkpoint_every_s`` of wall time and at the
        end. A resumed run gives the same curve as an uninterrupted one.
    checkpoint_every_s : float
        [s] of wall time.
    stop_after_chunks : int, optional
        Testing hook: abandon the run after this many chunks of the indentation phase (after
        writing a checkpoint), raising ``KeyboardInterrupt``.

    Returns
    -------
    IndentationResult
    """
    indentation = indentation or IndentationSettings()
    relaxation = relaxation or RelaxationSettings()
    wall0 = time.perf_counter()
    block = indentation.block
    if block is None:
        if "central_block" not in scene.meta:
            raise ValueError("IndentationSettings.block is None and the scene has no central_block")
        block = int(scene.meta["central_block"])
    model = ExplicitModel(scene, settings, block, indentation.tip_radius, indentation.axis_xy)
    setup_s = time.perf_counter() - wall0
    key = _settings_key(scene, settings, relaxation, indentation)
    ckpt = Path(checkpoint) if checkpoint is not None else None
    st = _RunState.from_file(ckpt, key, model) if ckpt is not None and ckpt.exists() else None
    if st is None:
        st = _RunState(key=key)
        relax_info = model.relax(relaxation)
        st.relax = relax_info
        top = model.scene.assembly.blocks[block]
        quat_to_rot(model.quat, model.rot)
        top_world = top.vertices @ model.rot[block].T + (
            model.pos[block] - model.rot[block] @ model.ref_centroid[block]
        )
        shift = model.pos[block] - model.ref_centroid[block]
        centre_xy = (
            model._top_centre(block)[:2] + shift[:2]
            if indentation.axis_xy is None
            else np.asarray(indentation.axis_xy, dtype=float)
        )
        st.centre0 = np.array(
            [centre_xy[0], centre_xy[1], top_world[:, 2].max() + indentation.tip_radius]
        )
        st.t0 = model.t
        if ckpt is not None:
            st.save(ckpt, model)
    else:
        logger.info("resumed from %s at delta=%.4g mm", ckpt, st.delta_now / MM)
    velocity = np.array([0.0, 0.0, -indentation.speed])
    ind = {"centre0": st.centre0, "t0": st.t0, "radius": indentation.tip_radius,
           "velocity": velocity}  # fmt: skip
    steps_per_record = max(1, round(indentation.record_interval / (indentation.speed * model.dt)))
    n_steps_total = math.ceil(indentation.max_deflection / (indentation.speed * model.dt))
    last_ckpt = time.perf_counter()
    last_log = time.perf_counter()
    loop_start = time.perf_counter()
    steps_start = st.steps
    chunks = 0
    while st.steps < n_steps_total and not st.finished:
        n = min(steps_per_record, n_steps_total - st.steps)
        acc = model.advance(n, indenter=ind)
        st.steps += n
        st.work += acc[1]
        delta = indentation.speed * (model.t - st.t0)
        d_prev = st.delta_now
        p_mean = acc[1] / (delta - d_prev) if delta > d_prev else acc[0]
        st.delta_now = delta
        st.record(model, delta, p_mean, acc[1])
        if delta >= st.next_snapshot:
            _, _, ef, ep, _ = model.contact_wrenches(None)
            pairs, force, point = interface_resultants(
                model.pair_node, model.pair_block, model.node_block, ef, ep
            )
            st.snapshots.append({"delta": delta, "pairs": pairs, "force": force,
                                 "point": point, "kind": "run"})  # fmt: skip
            st.next_snapshot += indentation.snapshot_interval
        if p_mean > st.best_load:
            st.best_load = p_mean
            st.peak = {name: getattr(model, name).copy() for name in _STATE_ARRAYS}
            st.peak["t"] = np.array(model.t)
        if indentation.stop_when_out:
            summary = curve_summary(np.array(st.delta), np.array(st.load),
                                    indentation.ultimate_fraction, indentation.out_confirm) \
                if st.below_since(indentation) else None  # fmt: skip
            if summary is not None and math.isfinite(summary["ultimate_deflection"]):
                st.finished = True
        if indentation.stop_below_peak_fraction is not None:
            # the drop must persist over STOP_PERSIST of travel (not an impact transient)
            if p_mean < indentation.stop_below_peak_fraction * st.best_load:
                if st.below_from is None:
                    st.below_from = delta
                elif delta - st.below_from >= STOP_PERSIST:
                    st.finished = True
            else:
                st.below_from = None
        now = time.perf_counter()
        if now - last_log >= settings.progress_every_s:
            rate = (st.steps - steps_start) / (now - loop_start)
            eta = (n_steps_total - st.steps) / rate if rate > 0 else float("nan")
            logger.info(
                "indent %s: delta=%.4f mm P=%.3f N (peak %.3f N) %.0f steps/s, at most %.0f s "
                "left", scene.name, delta / MM, p_mean, st.best_load, rate, eta,
            )  # fmt: skip
            last_log = now
        chunks += 1
        if ckpt is not None and (
            now - last_ckpt >= checkpoint_every_s
            or (stop_after_chunks is not None and chunks >= stop_after_chunks)
        ):
            st.save(ckpt, model)
            last_ckpt = now
        if stop_after_chunks is not None and chunks >= stop_after_chunks:
            raise KeyboardInterrupt(f"stopped after {chunks} chunks (test hook)")
    st.finished = True
    loop_s = time.perf_counter() - loop_start
    if ckpt is not None:
        st.save(ckpt, model)
    wall_s = time.perf_counter() - wall0
    return _make_result(model, st, indentation, settings, relaxation, ind, wall_s, setup_s,
                        loop_s, st.steps - steps_start)  # fmt: skip


@dataclass
class _RunState:
    """Everything of an indentation run that a checkpoint must hold besides the model state."""

    key: str
    steps: int = 0
    work: float = 0.0
    delta_now: float = 0.0
    best_load: float = -math.inf
    finished: bool = False
    centre0: np.ndarray = field(default_factory=lambda: np.zeros(3))
    t0: float = 0.0
    relax: dict = field(default_factory=dict)
    delta: list = field(default_factory=list)
    load: list = field(default_factory=list)
    time: list = field(default_factory=list)
    kinetic: list = field(default_factory=list)
    elastic: list = field(default_factory=list)
    work_hist: list = field(default_factory=list)
    poses_pos: list = field(default_factory=list)
    poses_quat: list = field(default_factory=list)
    entries: list = field(default_factory=list)
    peak: dict = field(default_factory=dict)
    snapshots: list = field(default_factory=list)
    next_snapshot: float = 0.0
    below_from: float | None = None

    def record(self, model: ExplicitModel, delta: float, load: float, dwork: float) -> None:
        self.delta.append(delta)
        self.load.append(load)
        self.time.append(model.t - self.t0)
        self.kinetic.append(model.kinetic_energy())
        self.elastic.append(model.elastic_energy())
        self.work_hist.append(self.work)
        self.poses_pos.append(model.pos.copy())
        self.poses_quat.append(model.quat.copy())
        self.entries.append(int(np.count_nonzero(model.out_depth > 0)))

    def below_since(self, ind: IndentationSettings) -> bool:
        """Cheap pre-test: the loads over the last ``out_confirm`` of travel (and the record
        just before it) are all below the ultimate fraction of the peak."""
        if len(self.load) < 2 or self.best_load <= 0:
            return False
        d = np.asarray(self.delta)
        first = int(np.searchsorted(d, d[-1] - ind.out_confirm, side="left"))
        if first < 1:
            return False
        tail = np.asarray(self.load[first - 1 :])
        return bool(np.all(tail <= ind.ultimate_fraction * self.best_load))

    def save(self, path: Path, model: ExplicitModel) -> None:
        data = {name: getattr(model, name) for name in _STATE_ARRAYS}
        data.update({f"peak_{k}": v for k, v in self.peak.items()})
        scalars = {
            "key": self.key, "steps": self.steps, "work": self.work, "delta_now": self.delta_now,
            "best_load": self.best_load, "finished": self.finished, "t0": self.t0,
            "t": model.t, "relax": self.relax, "n_rebuilds": model.n_rebuilds,
            "next_snapshot": self.next_snapshot,
            "below_from": self.below_from,
            "snapshots": [(snap["delta"], snap["kind"]) for snap in self.snapshots],
        }  # fmt: skip
        for k, snap in enumerate(self.snapshots):
            for name in ("pairs", "force", "point"):
                data[f"snap{k}_{name}"] = snap[name]
        data["scalars"] = np.array(json.dumps(scalars, default=float))
        data["centre0"] = self.centre0
        for name in ("delta", "load", "time", "kinetic", "elastic", "work_hist", "entries"):
            data[f"rec_{name}"] = np.asarray(getattr(self, name))
        n = model.n_blocks
        data["rec_pos"] = np.asarray(self.poses_pos).reshape(-1, n, 3)
        data["rec_quat"] = np.asarray(self.poses_quat).reshape(-1, n, 4)
        tmp = path.with_name(path.name + ".tmp.npz")
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(tmp, **data)
        os.replace(tmp, path)

    @classmethod
    def from_file(cls, path: Path, key: str, model: ExplicitModel) -> _RunState | None:
        with np.load(path) as data:
            scalars = json.loads(str(data["scalars"]))
            if scalars["key"] != key:
                logger.warning("checkpoint %s is for other settings: starting afresh", path)
                return None
            for name in _STATE_ARRAYS:
                setattr(model, name, data[name].copy())
            m = len(model.pair_node)
            model.out_force = np.zeros((m, 3))
            model.out_point = np.zeros((m, 3))
            model.out_depth = np.zeros(m)
            model.t = float(scalars["t"])
            model.n_rebuilds = int(scalars["n_rebuilds"])
            st = cls(key=key)
            for name in (
                "steps",
                "work",
                "delta_now",
                "best_load",
                "finished",
                "t0",
                "relax",
                "next_snapshot",
            ):
                setattr(st, name, scalars[name])
            st.steps = int(st.steps)
            st.centre0 = data["centre0"].copy()
            for name in ("delta", "load", "time", "kinetic", "elastic", "work_hist", "entries"):
                setattr(st, name, data[f"rec_{name}"].tolist())
            st.poses_pos = list(data["rec_pos"].copy())
            st.poses_quat = list(data["rec_quat"].copy())
            st.peak = {k[5:]: data[k].copy() for k in data.files if k.startswith("peak_")}
            st.snapshots = [
                {"delta": d, "kind": kind, **{n: data[f"snap{k}_{n}"].copy()
                                              for n in ("pairs", "force", "point")}}
                for k, (d, kind) in enumerate(scalars["snapshots"])
            ]  # fmt: skip
        return st


def _make_result(model, st, indentation, settings, relaxation, ind, wall_s, setup_s, loop_s,
                 steps_run) -> IndentationResult:  # fmt: skip
    delta = np.asarray(st.delta)
    load = np.asarray(st.load)
    summary = curve_summary(delta, load, indentation.ultimate_fraction, indentation.out_confirm)
    pos = np.asarray(st.poses_pos).reshape(-1, model.n_blocks, 3)
    quat = np.asarray(st.poses_quat).reshape(-1, model.n_blocks, 4)
    snapshots = list(st.snapshots)
    peak_state = {}
    if st.peak:
        saved = {name: getattr(model, name).copy() for name in _STATE_ARRAYS}
        saved_t = model.t
        for name in _STATE_ARRAYS:
            setattr(model, name, st.peak[name].copy())
        model.t = float(st.peak["t"])
        _resize_out(model)
        centre = st.centre0 + ind["velocity"] * (model.t - st.t0)
        sphere = (centre, indentation.tip_radius, ind["velocity"])
        peak_state = export_peak_state(model, sphere)
        peak_state["delta"] = np.array(indentation.speed * (model.t - st.t0))
        peak_state["load"] = np.array(st.best_load)
        _, _, ef, ep, _ = model.contact_wrenches(sphere)
        pairs, force, point = interface_resultants(
            model.pair_node, model.pair_block, model.node_block, ef, ep
        )
        snapshots.append({"delta": float(peak_state["delta"]), "pairs": pairs, "force": force,
                          "point": point, "kind": "peak"})  # fmt: skip
        for name in _STATE_ARRAYS:
            setattr(model, name, saved[name])
        model.t = saved_t
        _resize_out(model)
    snapshots.sort(key=lambda snap: snap["delta"])
    n_nodes = model.nodes.n_nodes + len(model.ind_block)
    info = {
        "dt": model.dt,
        "dt_critical": model.dt_critical,
        "omega_max": model.omega_max,
        "alpha": model.alpha,
        "beta": model.beta,
        "n_nodes": n_nodes,
        "n_entries": int(len(model.pair_node)),
        "steps_indentation": int(st.steps),
        "steps_relaxation": int(st.relax.get("steps", 0)),
        "relax": st.relax,
        "parallel": bool(model.parallel),
        "wall_s": wall_s,
        "setup_s": setup_s,
        "loop_s": loop_s,
        "steps_this_session": int(steps_run),
        "cost_per_node_step_s": loop_s / max(1, steps_run) / max(1, n_nodes),
        "cost_per_entry_step_s": loop_s / max(1, steps_run) / max(1, len(model.pair_node)),
        "settings": asdict(settings),
        "indentation": asdict(indentation),
        "relaxation": asdict(relaxation),
        "loaded_block": int(model.indenter_block),
    }
    return IndentationResult(
        delta=delta, load=load, time=np.asarray(st.time), kinetic=np.asarray(st.kinetic),
        elastic=np.asarray(st.elastic), work=np.asarray(st.work_hist), block_pos=pos,
        block_quat=quat, snapshots=snapshots, peak_state=peak_state, info=info, **summary,
    )  # fmt: skip


def _resize_out(model: ExplicitModel) -> None:
    m = len(model.pair_node)
    model.out_force = np.zeros((m, 3))
    model.out_point = np.zeros((m, 3))
    model.out_depth = np.zeros(m)
