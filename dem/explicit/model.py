"""The explicit model: a scene prepared for dynamics (nodes, time step, neighbour list, advance).

The model holds the constant groups of arrays the kernels take (:class:`~dem.explicit.state.Bodies`,
:class:`~dem.explicit.state.Shapes`, :class:`~dem.explicit.state.Nodes`,
:class:`~dem.explicit.state.Law`) and one :class:`~dem.explicit.state.ExplicitState`, the part
that evolves; drivers advance it, snapshot and restore it, and checkpoints hold it.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import time

import numba
import numpy as np
import scipy.sparse
import scipy.sparse.csgraph
import scipy.spatial

from dem.contact_nodes import FACE_ANGLE_DEG, ContactNodes, build_level_sets, seed_contact_nodes
from dem.explicit.settings import (
    INDENTER_NODES_PER_RADIUS_INV,
    PARALLEL_MIN_ENTRIES,
    ExplicitSettings,
    RelaxationSettings,
    SimulationError,
)
from dem.explicit.state import (
    Bodies,
    Contacts,
    ExplicitState,
    Indenter,
    Law,
    Motion,
    Nodes,
    PairFrames,
    Scratch,
    Shapes,
)
from dem.explicit.step_check import StepCheck
from dem.explicit.timestep import ContactStiffness, choose_time_step, highest_frequency
from dem.explicit.unmodelled import (
    INDENTER_DEPTH_LIMIT,
    UnmodelledContactError,
    block_hulls,
    sphere_overlap,
    worst_overlap,
)
from dem.kernels.broadphase import build_pairs, carry_history, near_faces
from dem.kernels.contact_force import (
    MU_RULE_MEAN,
    MU_RULE_MIN,
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
from dem.kernels.interface_law import TOUCH
from dem.scene import Assembly, Scene
from dem.units import G

logger = logging.getLogger(__name__)


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
    OverlapError
        Blocks interpenetrate in the input (the toolkit's geometric check,
        :func:`dem.geometry.interfaces.find_interfaces`, which names the pairs and depths).
    ValueError
        A forced time step above the stable limit, bad settings, NaN in the scene, or every
        block fixed.
    """

    def __init__(
        self,
        scene: Scene,
        settings: ExplicitSettings,
        indenter_block: int | None = None,
        indenter_radius: float = 0.0,
        indenter_axis_xy: np.ndarray | None = None,
    ):
        require_free_block(scene)
        self.scene = scene
        self.settings = settings
        asm = scene.assembly
        asm.interfaces()  # raises OverlapError on interpenetrating blocks
        self.n_blocks = asm.n_blocks
        self.fixed = np.asarray(scene.supports.fixed, dtype=bool)
        self.mass_true = asm.mass.copy()
        self.inertia_true = asm.inertia.copy()
        self.bodies = _bodies(scene, settings)
        self.shapes = _shapes(asm, settings)
        self.hulls = block_hulls(asm.blocks, self.bodies.ref_centroid)
        self.indenter_block = indenter_block
        self.indenter_axis_xy = self._indenter_axis(indenter_block, indenter_axis_xy)
        self._seed_nodes(indenter_radius)
        n = self.n_blocks
        ref = self.bodies.ref_centroid
        quat = np.zeros((n, 4))
        quat[:, 0] = 1.0
        motion = Motion(ref.copy(), quat, np.zeros((n, 3)), np.zeros((n, 3)))
        empty = Contacts(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0),
                         np.zeros((0, 3)), ref.copy(), quat.copy())  # fmt: skip
        self.state = ExplicitState(motion, empty)
        self._new_scratch()
        self.rebuild()
        self.state.n_rebuilds = 0
        self._choose_step(with_indenter=indenter_radius > 0 and indenter_block is not None)
        self.parallel = (
            settings.parallel
            if settings.parallel is not None
            else (self.n_entries >= PARALLEL_MIN_ENTRIES and (os.cpu_count() or 1) > 1)
        )

    def _indenter_axis(self, block: int | None, axis_xy) -> np.ndarray | None:
        """``(x, y)`` of the indenter's path [m] (default the centre of ``block``'s top
        face), checked to pass over that free block; None without an indenter block."""
        if block is None:
            return None
        if not 0 <= block < self.n_blocks or self.fixed[block]:
            raise ValueError(f"indenter block {block} must be a free block")
        axis = self._top_centre(block)[:2] if axis_xy is None else np.asarray(axis_xy, dtype=float)
        self._check_axis_hits(block, axis)
        return axis

    def _seed_nodes(self, indenter_radius: float) -> None:
        """Seed the contact nodes (``nodes``), the kernels' surface nodes relative to the
        centroids (``surface``) and the indenter (``indenter``, inactive)."""
        settings, ref = self.settings, self.bodies.ref_centroid
        ind_spacing = settings.indenter_node_spacing
        if ind_spacing is None:
            ind_spacing = min(
                settings.node_spacing, INDENTER_NODES_PER_RADIUS_INV * indenter_radius
            )
        self.indenter_spacing = float(ind_spacing)
        self.nodes: ContactNodes = seed_contact_nodes(
            self.scene.assembly, self.fixed, settings.node_spacing, settings.margin,
            self.indenter_axis_xy, indenter_radius, ind_spacing, settings.node_layout,
        )  # fmt: skip
        nodes = self.nodes
        self.surface = Nodes(
            nodes.block,
            np.ascontiguousarray(nodes.point - ref[nodes.block]),
            np.ascontiguousarray(nodes.normal),
            nodes.area,
            np.ascontiguousarray(nodes.weight),
            np.ascontiguousarray(nodes.patch_centre - ref[nodes.block]),
            np.ascontiguousarray(nodes.patch_u),
            np.ascontiguousarray(nodes.patch_v),
        )
        k = len(nodes.indenter_block)
        self.indenter = Indenter(
            False, nodes.indenter_block,
            np.ascontiguousarray(nodes.indenter_point - ref[nodes.indenter_block]),
            nodes.indenter_area, np.zeros(3), 0.0, float(indenter_radius), np.zeros(3),
            float(settings.k_n), np.zeros((k, 3)),
        )  # fmt: skip

    def _choose_step(self, with_indenter: bool) -> None:
        """The highest frequency of the initial contacts (``with_indenter``: and of the
        indenter's), the time step and damping rates, and the contact law."""
        settings = self.settings
        self._frequency_indenter = self.indenter if with_indenter else None
        self.omega_max = highest_frequency(self._contact_stiffness())
        step = choose_time_step(self.omega_max, settings)
        self.dt, self.dt_critical = step["dt"], step["dt_critical"]
        self.alpha, self.beta = step["alpha"], step["beta"]
        self.step_check = StepCheck(self.omega_max)
        self._check_damping(self.alpha, "ExplicitSettings.global_damping")
        vertices = self.scene.assembly.arrays.vertices
        self.law = Law(
            float(settings.k_n), float(settings.k_t), self.beta,
            MU_RULE_MIN if settings.mu_rule == "min" else MU_RULE_MEAN,
            math.cos(math.radians(FACE_ANGLE_DEG)) if settings.contact_plane == "compatible"
            else 2.0,
            float(settings.margin),
            TOUCH * float(np.ptp(vertices, axis=0).max()),
        )  # fmt: skip

    # -- views of the state --------------------------------------------------------------------
    @property
    def pos(self) -> np.ndarray:
        """(n_blocks, 3) centroids [m] (the state's array: writes go to the state)."""
        return self.state.motion.pos

    @property
    def quat(self) -> np.ndarray:
        """(n_blocks, 4) quaternions, scalar first."""
        return self.state.motion.quat

    @property
    def vel(self) -> np.ndarray:
        """(n_blocks, 3) velocities [m/s]."""
        return self.state.motion.vel

    @property
    def omega(self) -> np.ndarray:
        """(n_blocks, 3) angular velocities, world frame [rad/s]."""
        return self.state.motion.omega

    @property
    def t(self) -> float:
        """Time [s]."""
        return self.state.t

    @property
    def constants(self) -> tuple[Nodes, Bodies, Shapes, Law]:
        """The model's constants as the kernels take them: (surface nodes, bodies, shapes,
        law)."""
        return self.surface, self.bodies, self.shapes, self.law

    @property
    def n_entries(self) -> int:
        """Entries in the neighbour list."""
        return len(self.state.contacts.node)

    @property
    def free_blocks(self) -> np.ndarray:
        return self.bodies.free_blocks

    @property
    def ref_centroid(self) -> np.ndarray:
        return self.bodies.ref_centroid

    @property
    def inv_mass(self) -> np.ndarray:
        return self.bodies.inv_mass

    @property
    def inertia_ref(self) -> np.ndarray:
        return self.bodies.inertia_ref

    def rotations(self) -> np.ndarray:
        """(n_blocks, 3, 3) rotation matrices of the current quaternions (a new array)."""
        rot = np.zeros((self.n_blocks, 3, 3))
        quat_to_rot(self.quat, rot)
        return rot

    # -- set-up ------------------------------------------------------------------------------
    def _top_centre(self, i: int) -> np.ndarray:
        blk = self.scene.assembly.blocks[i]
        top = int(np.argmax(blk.normals[:, 2]))
        return blk.vertices[blk.faces[top]].mean(axis=0)

    def _check_axis_hits(self, i: int, axis_xy: np.ndarray) -> None:
        blk = self.scene.assembly.blocks[i]
        xy = blk.vertices[:, :2]
        hull = scipy.spatial.ConvexHull(xy)
        # inside the block's plan: every hull facet inequality holds
        if np.any(hull.equations[:, :2] @ axis_xy + hull.equations[:, 2] > 1e-12 * blk.size):
            lo, hi = xy.min(axis=0), xy.max(axis=0)
            raise ValueError(
                f"IndentationSettings.axis_xy = {tuple(axis_xy)} m misses block {i}, whose plan "
                f"spans x {lo[0]:.4g}..{hi[0]:.4g} m, y {lo[1]:.4g}..{hi[1]:.4g} m"
            )

    # -- neighbour list ----------------------------------------------------------------------
    def rebuild(self) -> None:
        """Rebuild the contact entries and carry the shear history over (the next step checks
        the time step against them, :meth:`_check_step`), and refuse unmodelled overlaps."""
        motion, old = self.state.motion, self.state.contacts
        rot = np.empty((self.n_blocks, 3, 3))
        quat_to_rot(motion.quat, rot)
        node, block, weight = build_pairs(
            self.surface, motion.pos, rot, self.bodies, self.shapes, self.settings.margin
        )
        shear = np.zeros((len(node), 3))
        carry_history(old.node, old.block, old.shear, node, block, shear)
        self.state.contacts = Contacts(node, block, weight, shear, motion.pos.copy(),
                                       motion.quat.copy())  # fmt: skip
        self.state.n_rebuilds += 1
        self._new_scratch()
        self._refuse_unmodelled_contact(rot)

    def _check_step(self, alpha: float) -> None:
        """Check ``dt`` against the present entries with the global damping rate ``alpha``
        [1/s] (:mod:`dem.explicit.step_check`, which raises :class:`SimulationError` if it is
        unstable for them)."""
        system = self._contact_stiffness(self.rotations())
        self.step_check.check(system, self.dt, alpha, self.beta, self.t)
        self.step_checked = True

    def _contact_stiffness(self, rot: np.ndarray | None = None) -> ContactStiffness:
        """The present entries (and the indenter's where it sets the time step) at the
        rotations ``rot`` (n, 3, 3) (None: the reference orientation)."""
        k_n, k_t = self.settings.k_n, self.settings.k_t
        return ContactStiffness(self.bodies, self.surface, self.state.contacts, self.pos, k_n,
                                k_t, self._frequency_indenter, rot)  # fmt: skip

    def _refuse_unmodelled_contact(self, rot: np.ndarray) -> None:
        """Stop when two blocks overlap more than the model represents (:mod:`.unmodelled`);
        ``rot`` (n, 3, 3) are the current rotations."""
        motion, contacts = self.state.motion, self.state.contacts
        entry_pairs = np.column_stack([self.surface.block[contacts.node], contacts.block])
        a, b, depth, allowed = worst_overlap(
            self.hulls, self.bodies, self.shapes, motion.pos, rot, entry_pairs,
            self.settings.margin,
        )  # fmt: skip
        if depth <= allowed:
            return
        if allowed > self.settings.margin:
            why = ("their contact nodes do not hold them apart: an edge or a corner pressing "
                   "into a face between the nodes, or nodes taking the plane of a face beside "
                   "it (refine ExplicitSettings.node_spacing)")  # fmt: skip
        else:
            why = ("no contact node of the block that counts their contact is within the "
                   "margin of the other: a corner or edge that came in between the nodes "
                   "(refine ExplicitSettings.node_spacing; fixed blocks carry nodes only where "
                   "they are the narrower side of an interface)")  # fmt: skip
        raise UnmodelledContactError(
            f"blocks {a} and {b} overlap by {depth:.3e} m at t = {self.t:.6e} s (at most "
            f"{allowed:.3e} m is a contact the model represents): {why}, or the contact "
            "stiffness k_n is far too low for the load, and they are passing through each "
            "other. The run stops here: from this point its results would be wrong"
        )

    def _new_scratch(self) -> None:
        """Work arrays and block pairs (``scratch``, ``pairs``) for the current neighbour list
        (every entry is evaluated at the next step, which first checks the time step against
        them)."""
        self.step_checked = False
        self.scratch = Scratch.empty(self.n_blocks, self.n_entries)
        contacts = self.state.contacts
        rot_build = np.zeros((self.n_blocks, 3, 3))
        quat_to_rot(contacts.quat_build, rot_build)
        # face positions as int16 (less memory per entry) unless a block has more faces
        narrow = np.diff(self.shapes.face_ptr).max(initial=0) < 2**15
        near = np.empty((self.n_entries, 2), dtype=np.int16 if narrow else np.int64)
        near_faces(self.surface, contacts.node, contacts.block, contacts.pos_build, rot_build,
                   self.bodies, self.shapes, self.settings.margin, near)  # fmt: skip
        self.pairs = PairFrames.of_list(self.surface.block, contacts, near, self.n_blocks,
                                        self.shapes.face_ptr)  # fmt: skip

    # -- loads, motion measures, state ---------------------------------------------------------
    def set_external_wrench(self, wrench: np.ndarray) -> None:
        """Replace the external load (weight and other forces) on every block.

        Parameters
        ----------
        wrench : (n_blocks, 6) float
            Forces at the centroids [N] and moments about them [N m] (true, unscaled).
        """
        wrench = np.asarray(wrench, dtype=np.float64)
        if wrench.shape != (self.n_blocks, 6) or not np.all(np.isfinite(wrench)):
            raise ValueError(
                f"external wrench must be finite with shape ({self.n_blocks}, 6), got "
                f"{wrench.shape}"
            )
        self.bodies.ext_force[:] = wrench[:, :3]
        self.bodies.ext_torque[:] = wrench[:, 3:]

    def block_displacement(self, pos0: np.ndarray, quat0: np.ndarray) -> np.ndarray:
        """(n_blocks,) largest displacement of any point of each block since a pose [m].

        ``|c - c_0| + R angle`` with ``R`` the bounding radius and ``angle`` the rotation
        since ``(pos0, quat0)`` (an upper bound); zero for fixed blocks.
        """
        dq = np.abs(np.einsum("ij,ij->i", self.quat, quat0))
        angle = 2.0 * np.arccos(np.minimum(1.0, dq))
        out = np.linalg.norm(self.pos - pos0, axis=1) + self.bodies.radius * angle
        out[self.fixed] = 0.0
        return out

    def block_speed(self) -> np.ndarray:
        """(n_blocks,) ``|v| + |omega| R``: a bound on the speed of any point [m/s]."""
        spin = np.linalg.norm(self.omega, axis=1) * self.bodies.radius
        speed = np.linalg.norm(self.vel, axis=1) + spin
        speed[self.fixed] = 0.0
        return speed

    def snapshot(self) -> ExplicitState:
        """A copy of the state (poses, velocities, neighbour list, shear history, time)."""
        return self.state.copy()

    def restore(self, state: ExplicitState) -> None:
        """Continue from ``state`` (copied: the argument stays usable)."""
        self.state = state.copy()
        self._new_scratch()

    def check_supported(self) -> None:
        """Refuse free blocks that no chain of contacts connects to a support.

        A support is a fixed block or a block with all three translations restrained. Contacts
        are the entries of the neighbour list (nodes within ``margin`` of another block).

        Raises
        ------
        SimulationError
            Naming the unsupported blocks (all of them, grouped by connected cluster).
        """
        contacts = self.state.contacts
        a = self.surface.block[contacts.node]
        anchored = self.fixed | self.bodies.restrained[:, :3].all(axis=1)
        graph = scipy.sparse.coo_matrix(
            (np.ones(len(a)), (a, contacts.block)), shape=(self.n_blocks, self.n_blocks)
        )
        n_comp, label = scipy.sparse.csgraph.connected_components(graph, directed=False)
        held = np.zeros(n_comp, dtype=bool)
        held[label[anchored]] = True
        loose = np.flatnonzero(~held[label])
        if len(loose):
            groups = [np.flatnonzero(label == c).tolist() for c in np.unique(label[loose])]
            shown = "; ".join(str(g[:20]) + (" ..." if len(g) > 20 else "") for g in groups[:5])
            raise SimulationError(
                f"{len(loose)} blocks of scene {self.scene.name!r} have no support: no chain "
                f"of contacts within the margin ({self.settings.margin:.3e} m) reaches a fixed "
                f"or restrained block. Unsupported groups: {shown}. Fix the blocks "
                "(Supports.fixed), restrain them, or bring them into contact"
            )

    # -- forces ------------------------------------------------------------------------------
    def evaluate_contacts(self) -> Scratch:
        """Every entry's force, point and depth, and the blocks' contact wrenches, at the
        current state (state unchanged)."""
        scratch = Scratch.empty(self.n_blocks, self.n_entries)
        quat_to_rot(self.quat, scratch.rot)
        contacts = self.state.contacts._replace(shear=self.state.contacts.shear.copy())
        node_contacts(self.constants, (contacts, self.state.motion), 0.0, scratch, self.pairs,
                      True)  # fmt: skip
        return scratch

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
        sc = self.evaluate_contacts()
        ind = np.zeros((len(self.indenter.block), 3))
        if sphere is not None:
            centre, radius, velocity = sphere
            indenter = self.indenter._replace(
                radius=float(radius), velocity=np.asarray(velocity, float), out_force=ind
            )
            sphere_contacts(indenter, self.state.motion, sc.rot, np.asarray(centre, float),
                            self.beta, sc.force, sc.torque)  # fmt: skip
        return sc.force, sc.torque, sc.out_force, sc.out_point, ind

    def check_indenter(self, centre: np.ndarray, radius: float, start: bool = False) -> float:
        """Refuse an indenter that overlaps a block more than the model represents.

        With ``start`` the tip must be clear of every block (overlaps up to ``margin``).
        Later it may overlap a block where that block's indenter nodes feel it (the overlap
        less the depth of its deepest indenter node within ``margin`` plus the indenter node
        spacing; no node: the contact would be skipped), and by at most
        ``INDENTER_DEPTH_LIMIT * radius``. See :mod:`dem.explicit.unmodelled`.

        Parameters
        ----------
        centre : (3,) float
            Sphere centre [m].
        radius : float
            [m].
        start : bool
            The start of indentation.

        Returns
        -------
        float
            The largest overlap of the sphere with a block [m] (0 if none).

        Raises
        ------
        UnmodelledContactError
            Naming the block, the overlap and what is allowed.
        """
        centre = np.asarray(centre, dtype=float)
        blocks, depths = sphere_overlap(centre, radius, self.bodies, self.shapes, self.pos,
                                        self.rotations())  # fmt: skip
        if len(blocks) == 0:
            return 0.0
        margin = self.settings.margin
        felt = self._indenter_node_depth(centre, radius, blocks)
        checks = (
            (depths if start else np.zeros(len(blocks)), margin,
             "at the start of indentation: the tip must start clear of every block"),
            (depths - felt, margin + self.indenter_spacing,
             "where no indenter node of that block feels it (nodes are seeded on the free "
             "blocks' upward faces under the tip's path only), so the contact is skipped"),
            (depths, INDENTER_DEPTH_LIMIT * radius,
             f"more than {INDENTER_DEPTH_LIMIT:g} of its radius: k_n is far too low for the "
             "load, and from here the load measures the sphere's penalty, not the blocks "
             "(raise k_n or the tip radius)"),
        )  # fmt: skip
        for excess, allowed, why in checks:
            k = int(np.argmax(excess))
            if excess[k] > allowed:
                raise UnmodelledContactError(
                    f"the indenter (radius {radius:.3e} m, centre "
                    f"{np.round(centre, 9).tolist()} m) overlaps block {blocks[k]} by "
                    f"{depths[k]:.3e} m at t = {self.t:.6e} s ({excess[k]:.3e} m, at most "
                    f"{allowed:.3e} m is a contact the model represents) {why}"
                )
        return float(depths.max())

    def _indenter_node_depth(self, centre: np.ndarray, radius: float, blocks) -> np.ndarray:
        """(k,) depth of the deepest indenter node of each of ``blocks`` inside the sphere
        [m] (0 if none is inside)."""
        ind = self.indenter
        rot = self.rotations()[ind.block]
        points = self.pos[ind.block] + np.einsum("kij,kj->ki", rot, ind.r0)
        depth = radius - np.linalg.norm(points - centre, axis=1)
        felt = np.zeros(len(blocks))
        for k, b in enumerate(blocks):
            felt[k] = max(0.0, depth[ind.block == b].max(initial=0.0))
        return felt

    def kinetic_energy(self) -> float:
        """Kinetic energy of the free blocks with the inertial masses [J]."""
        return float(kinetic_energy(self.bodies, self.state.motion, self.scratch.rot))

    # -- stepping ----------------------------------------------------------------------------
    def advance(
        self,
        n_steps: int,
        alpha: float | None = None,
        indenter: dict | None = None,
        local_damping: float | None = None,
    ) -> np.ndarray:
        """Advance ``n_steps`` steps, rebuilding the neighbour list when needed.

        Parameters
        ----------
        n_steps : int
        alpha : float, optional
            Global damping rate [1/s] (default: the model's).
        indenter : dict, optional
            ``centre0`` (3,) [m], ``t0`` [s], ``radius`` [m], ``velocity`` (3,) [m/s].
        local_damping : float, optional
            Local damping coefficient (default: the settings').

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
        if alpha is None:
            alpha = self.alpha
        elif alpha != self.alpha:
            self._check_damping(alpha, "the global damping")
        sphere = self.indenter
        if indenter is not None:
            sphere = sphere._replace(
                active=True,
                centre0=np.asarray(indenter["centre0"], dtype=float),
                t0=float(indenter["t0"]),
                radius=float(indenter["radius"]),
                velocity=np.asarray(indenter["velocity"], dtype=float),
            )
        if local_damping is None:
            local_damping = self.settings.local_damping
        stepping = (self.dt, alpha, local_damping, self.parallel)
        left = int(n_steps)
        while left > 0:
            if not self.step_checked:
                self._check_step(alpha)
            with _dynamic_schedule(self.parallel):
                done, status, self.state.t = run_steps(
                    left, self.state.t, stepping, self.constants,
                    (self.state.contacts, self.state.motion), self.scratch, self.pairs, sphere, acc,
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

    def _check_damping(self, alpha: float, what: str) -> None:
        """Refuse a global damping rate ``alpha`` [1/s] that makes the time step unstable.

        The damping force ``-alpha m v`` is explicit: with ``h = omega_max dt`` and the top
        mode's damping per step ``a = (alpha + beta omega_max^2) dt`` (global plus contact
        dashpots), symplectic Euler is stable for ``h^2 + 2 a <= 4`` (``a <= 2`` for rigid
        motions); :func:`dem.explicit.timestep.choose_time_step` sets ``dt`` for the contact
        dashpots alone.
        """
        w, dt = self.omega_max, self.dt
        h = w * dt
        a = (alpha + self.beta * w * w) * dt
        if h * h + 2.0 * a <= 4.0:
            return
        ratio = alpha / (2.0 * w) if w > 0 else math.inf
        allowed = (4.0 - h * h - 2.0 * self.beta * w * w * dt) / (4.0 * h) if h > 0 else math.inf
        raise ValueError(
            f"{what} (rate alpha = {alpha:.3e} 1/s, damping ratio {ratio:.3g} at omega_max = "
            f"{w:.3e} rad/s) makes the explicit time step dt = {dt:.3e} s unstable: at this "
            f"step the damping ratio may be at most {allowed:.3g}; lower it (vibrations are "
            "damped without drag by local_damping), or lower dt / dt_safety"
        )

    def elastic_energy(self, current: bool = False) -> float:
        """Normal penalty energy ``sum 1/2 k_n d^2 w A`` [J].

        Of the last evaluated step (cheap), or with ``current`` re-evaluated at the present
        state (for energy balances).
        """
        depth = self.evaluate_contacts().out_depth if current else self.scratch.out_depth
        contacts = self.state.contacts
        return float(elastic_energy(contacts.node, contacts.weight, self.surface.area, depth,
                                    self.settings.k_n))  # fmt: skip

    def relax(self, relaxation: RelaxationSettings) -> dict:
        """Run under gravity until the kinetic energy is below the tolerance and every block
        is in balance (:meth:`unbalanced` at most ``relaxation.unbalanced_tol``).

        Returns
        -------
        dict
            ``steps``, ``kinetic`` [J], ``tolerance`` [J], ``unbalanced_ratio`` and
            ``unbalanced_block`` (the block most out of balance at the end, see
            :meth:`unbalanced`), ``wall_s``.

        Raises
        ------
        SimulationError
            With ``relaxation.require_convergence``: the kinetic energy did not meet its
            tolerance in ``max_steps`` steps, or it did but a block is still out of balance by
            more than ``relaxation.unbalanced_tol`` (otherwise both are logged as warnings).
        """
        self.check_supported()
        start = time.perf_counter()
        m_free = float(np.sum(1.0 / self.bodies.inv_mass[self.bodies.free_blocks]))
        tol = 0.5 * m_free * relaxation.ke_speed**2
        alpha = (
            self.alpha
            if relaxation.global_damping is None
            else 2.0 * relaxation.global_damping * self.omega_max
        )
        self._check_damping(alpha, "RelaxationSettings.global_damping")
        steps = 0
        chunk = self.settings.chunk_steps
        ke = self.kinetic_energy()
        start_pos = self.state.motion.pos.copy()
        balanced = math.isinf(relaxation.unbalanced_tol)
        while True:
            self.advance(chunk, alpha=alpha, local_damping=relaxation.local_damping)
            steps += chunk
            ke = self.kinetic_energy()
            at_rest = steps >= relaxation.min_steps and ke <= tol
            if at_rest and (balanced or self.unbalanced().max() <= relaxation.unbalanced_tol):
                break
            if steps >= relaxation.max_steps and ke <= tol:
                break  # at rest yet out of balance: _check_balance says so
            if steps >= relaxation.max_steps:
                message = (
                    f"relaxation did not converge in {steps} steps: kinetic energy {ke:.3e} J "
                    f"> tolerance {tol:.3e} J; {self._still_moving(start_pos)}"
                )
                if relaxation.require_convergence:
                    raise SimulationError(message)
                logger.warning("%s; going on", message)
                break
        info = {"steps": steps, "kinetic": ke, "tolerance": tol}
        info.update(self._check_balance(relaxation, converged=ke <= tol, viscous=alpha > 0))
        info["wall_s"] = time.perf_counter() - start
        return info

    def unbalanced(self) -> np.ndarray:
        """(n_blocks,) out-of-balance ratio of every block at the current state (0 if fixed).

        The net force on a block (external load plus contact forces, in the directions it may
        move), over the load it carries: the largest of its weight (under standard gravity if
        the scene has none), its external load, and the force passing through it (half the sum
        of the magnitudes of its contact forces: a light plate under a heavy block carries that
        block's weight). The net moment counts too, over that load times the block's bounding
        radius.
        """
        force, torque, entry_force, _, _ = self.contact_wrenches()
        bodies, contacts = self.bodies, self.state.contacts
        net = np.hstack([force + bodies.ext_force, torque + bodies.ext_torque])
        net[bodies.restrained] = 0.0
        magnitude = np.linalg.norm(entry_force, axis=1)
        through = 0.5 * (
            np.bincount(self.surface.block[contacts.node], magnitude, self.n_blocks)
            + np.bincount(contacts.block, magnitude, self.n_blocks)
        )
        g = float(np.linalg.norm(self.scene.loads.gravity)) or G
        carried = np.maximum.reduce(
            [self.mass_true * g, np.linalg.norm(bodies.ext_force, axis=1), through]
        )
        out = np.maximum(np.linalg.norm(net[:, :3], axis=1),
                         np.linalg.norm(net[:, 3:], axis=1) / bodies.radius)  # fmt: skip
        ratio = out / carried
        ratio[self.fixed] = 0.0
        return ratio

    def _check_balance(
        self, relaxation: RelaxationSettings, converged: bool, viscous: bool
    ) -> dict:
        """``unbalanced_ratio`` and ``unbalanced_block`` (:meth:`unbalanced`, the largest);
        above ``relaxation.unbalanced_tol`` raise or warn as for the kinetic energy
        (``converged``: it met its tolerance; ``viscous``: global viscous damping acted)."""
        ratio = self.unbalanced()
        worst = int(np.argmax(ratio))
        info = {"unbalanced_ratio": float(ratio[worst]), "unbalanced_block": worst}
        if ratio[worst] > relaxation.unbalanced_tol:
            message = (
                f"relaxation ended with block {worst} out of balance: its net force (or "
                f"moment over its radius) is {ratio[worst]:.3g} of the load it carries (tolerance "
                f"{relaxation.unbalanced_tol:.3g})"
            )
            if converged and viscous:
                message += (
                    f" after {relaxation.max_steps} steps although the kinetic energy met its "
                    "tolerance: the viscous damping holds it back (a block still dropping into "
                    "place sinks at g / alpha; with blocks of very different mass the lightest "
                    "sets the damping rate, which over-damps the heaviest: it creeps). Relax "
                    "with RelaxationSettings(global_damping=0, local_damping=0.7), or lower "
                    "ke_speed or global_damping"
                )
            elif converged:
                message += (
                    f" after {relaxation.max_steps} steps although the kinetic energy met its "
                    "tolerance, with no viscous damping: a block that moves slowly under a "
                    "force it cannot resist (sliding or rocking off: see limit.stands), or one "
                    "still settling; raise max_steps or lower ke_speed to tell them apart"
                )
            if relaxation.require_convergence:
                raise SimulationError(message)
            logger.warning("%s; going on", message)
        return info

    def _still_moving(self, start_pos: np.ndarray, n: int = 3) -> str:
        """The ``n`` fastest free blocks: speed and distance moved since ``start_pos`` (a block
        that drifts far is not held; one that only rattles in place needs more damping)."""
        free = self.bodies.free_blocks
        speed = np.linalg.norm(self.state.motion.vel[free], axis=1)
        moved = np.linalg.norm(self.state.motion.pos[free] - start_pos[free], axis=1)
        order = np.argsort(-speed, kind="stable")[:n]
        listed = ", ".join(
            f"block {free[i]} at {1e3 * speed[i]:.3g} mm/s, {1e3 * moved[i]:.3g} mm from its start"
            for i in order
        )
        return (
            f"fastest: {listed}. A block that keeps drifting is not held (a mechanism under "
            "gravity, or a scene that stands only marginally: see limit.stands)"
        )


@contextlib.contextmanager
def _dynamic_schedule(active: bool):
    """With ``active``, numba's parallel loops hand their iterations (the node loop's chunks)
    to the threads one at a time as they finish, instead of in equal shares decided up front:
    chunks differ in cost (separated entries are skipped) and on a shared machine a thread can
    lose its core for a while. Each chunk sums into its own buffer, so results do not depend on
    the schedule. (Set from Python: set in the kernel, numba would not cache it.)"""
    if not active:
        yield
        return
    previous = numba.set_parallel_chunksize(1)
    try:
        yield
    finally:
        numba.set_parallel_chunksize(previous)


def require_free_block(scene: Scene) -> None:
    """Refuse a scene whose blocks are all fixed (``ValueError``)."""
    if np.all(scene.supports.fixed):
        raise ValueError(
            f"every block of scene {scene.name!r} is fixed (Supports.fixed): nothing to simulate"
        )


def _bodies(scene: Scene, settings: ExplicitSettings) -> Bodies:
    """Per-block constants; inertial masses scaled by ``settings.mass_scaling``."""
    asm = scene.assembly
    fixed = np.asarray(scene.supports.fixed, dtype=bool)
    if settings.mu is not None:
        mu = np.full(asm.n_blocks, settings.mu)
    elif asm.mu is not None:
        mu = asm.mu.copy()
    else:
        raise ValueError("no friction coefficient: set ExplicitSettings.mu or scene mu")
    s = settings.mass_scaling
    inertia = np.ascontiguousarray(asm.inertia * s)
    dead = scene.dead_wrench
    return Bodies(
        free_blocks=np.flatnonzero(~fixed).astype(np.int64),
        ref_centroid=np.ascontiguousarray(asm.centroid, dtype=np.float64),
        radius=np.array(
            [np.linalg.norm(b.vertices - b.centroid, axis=1).max() for b in asm.blocks]
        ),  # fmt: skip
        inv_mass=1.0 / (asm.mass * s),
        inertia_ref=inertia,
        inertia_ref_inv=np.ascontiguousarray(np.linalg.inv(inertia)),
        restrained=np.ascontiguousarray(scene.supports.restrained, dtype=np.bool_),
        block_mu=np.ascontiguousarray(mu, dtype=np.float64),
        ext_force=np.ascontiguousarray(dead[:, :3]),
        ext_torque=np.ascontiguousarray(dead[:, 3:]),
    )


def _shapes(asm: Assembly, settings: ExplicitSettings) -> Shapes:
    """Face planes, and level-set grids if the settings ask for them (else placeholders)."""
    arrays = asm.arrays
    n = asm.n_blocks
    if settings.signed_distance == "level_set":
        ls = build_level_sets(asm, settings.level_set_spacing, 2 * settings.margin)
        grids = (ls.origin, ls.spacing, ls.dims, ls.ptr, ls.values)
    else:
        grids = (np.zeros((n, 3)), np.ones(n), np.full((n, 3), 2, dtype=np.int64),
                 np.zeros(n + 1, dtype=np.int64), np.zeros(1))  # fmt: skip
    return Shapes(arrays.face_ptr, arrays.face_normal, arrays.face_offset,
                  settings.signed_distance == "level_set", *grids)  # fmt: skip
