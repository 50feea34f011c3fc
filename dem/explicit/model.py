"""The explicit model: a scene prepared for dynamics (nodes, time step, neighbour list, advance)."""

from __future__ import annotations

import logging
import math
import os
import time

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph

from dem.contact_nodes import FACE_ANGLE_DEG, ContactNodes, build_level_sets, seed_contact_nodes
from dem.explicit.settings import (
    EDGE_TOL,
    INDENTER_NODES_PER_RADIUS_INV,
    PARALLEL_MIN_ENTRIES,
    ExplicitSettings,
    RelaxationSettings,
    SimulationError,
)
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

logger = logging.getLogger(__name__)

STATE_ARRAYS = ("pos", "quat", "vel", "omega", "pos_build", "quat_build", "pair_node",
                "pair_block", "pair_weight", "pair_shear")  # fmt: skip
"""Model attributes that make up the dynamic state (with ``t``)."""


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

    # -- loads, motion measures, snapshots ---------------------------------------------------
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
        self.ext_force[:] = wrench[:, :3]
        self.ext_torque[:] = wrench[:, 3:]

    def block_displacement(self, pos0: np.ndarray, quat0: np.ndarray) -> np.ndarray:
        """(n_blocks,) largest displacement of any point of each block since a pose [m].

        ``|c - c_0| + R angle`` with ``R`` the bounding radius and ``angle`` the rotation
        since ``(pos0, quat0)`` (an upper bound); zero for fixed blocks.
        """
        dq = np.abs(np.einsum("ij,ij->i", self.quat, quat0))
        angle = 2.0 * np.arccos(np.minimum(1.0, dq))
        out = np.linalg.norm(self.pos - pos0, axis=1) + self.radius * angle
        out[self.fixed] = 0.0
        return out

    def block_speed(self) -> np.ndarray:
        """(n_blocks,) ``|v| + |omega| R``: a bound on the speed of any point [m/s]."""
        speed = np.linalg.norm(self.vel, axis=1) + np.linalg.norm(self.omega, axis=1) * self.radius
        speed[self.fixed] = 0.0
        return speed

    def snapshot(self) -> dict:
        """A copy of the dynamic state (poses, velocities, neighbour list, shear, time)."""
        snap = {name: getattr(self, name).copy() for name in STATE_ARRAYS}
        snap["t"] = self.t
        snap["n_rebuilds"] = self.n_rebuilds
        return snap

    def restore(self, snap: dict) -> None:
        """Return to a state taken by :meth:`snapshot` (the snapshot stays usable)."""
        for name in STATE_ARRAYS:
            setattr(self, name, snap[name].copy())
        self.t = float(snap["t"])
        self.n_rebuilds = int(snap["n_rebuilds"])
        m = len(self.pair_node)
        self.out_force = np.zeros((m, 3))
        self.out_point = np.zeros((m, 3))
        self.out_depth = np.zeros(m)

    def check_supported(self) -> None:
        """Refuse free blocks that no chain of contacts connects to a support.

        A support is a fixed block or a block with all three translations restrained. Contacts
        are the entries of the neighbour list (nodes within ``margin`` of another block).

        Raises
        ------
        SimulationError
            Naming the unsupported blocks (all of them, grouped by connected cluster).
        """
        a = self.node_block[self.pair_node]
        b = self.pair_block
        anchored = self.fixed | self.restrained[:, :3].all(axis=1)
        graph = scipy.sparse.coo_matrix(
            (np.ones(len(a)), (a, b)), shape=(self.n_blocks, self.n_blocks)
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
