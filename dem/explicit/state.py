"""The arrays of an explicit model, grouped: what the kernels take and what checkpoints hold.

Each group is a ``NamedTuple`` of arrays (and a few scalars), so that a numba kernel receives it
as one typed argument and reads its fields by name (``motion.pos``), never by position. The
groups that never change during a run describe the model (:class:`Bodies`, :class:`Shapes`,
:class:`Nodes`, :class:`Law`); :class:`ExplicitState` holds what evolves (:class:`Motion`,
:class:`Contacts`, time) and is what a driver advances, snapshots, restores and checkpoints.

``n`` is the number of blocks, ``n_nodes`` of surface nodes, ``m`` of contact entries (node,
neighbour block) in the neighbour list, ``k`` of indenter nodes. Reference frame: the
configuration in which the scene was built (quaternion ``(1, 0, 0, 0)``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np


class Bodies(NamedTuple):
    """Per-block constants, and the external load the drivers set.

    Attributes
    ----------
    free_blocks : (n_free,) int64
        Blocks that are integrated (fixed blocks never move).
    ref_centroid : (n, 3) float64
        Centroids in the reference configuration [m].
    radius : (n,) float64
        Bounding radius about the centroid [m].
    inv_mass : (n,) float64
        Inverse inertial (possibly mass-scaled) mass [1/kg].
    inertia_ref, inertia_ref_inv : (n, 3, 3) float64
        Inertial inertia about the centroid, reference frame [kg m^2], and its inverse.
    restrained : (n, 6) bool
        Restrained world dofs ``(ux, uy, uz, rx, ry, rz)``.
    block_mu : (n,) float64
        Friction coefficient of each block.
    ext_force, ext_torque : (n, 3) float64
        External (true, unscaled) forces at the centroids [N] and moments [N m]; drivers
        overwrite them in place.
    """

    free_blocks: np.ndarray
    ref_centroid: np.ndarray
    radius: np.ndarray
    inv_mass: np.ndarray
    inertia_ref: np.ndarray
    inertia_ref_inv: np.ndarray
    restrained: np.ndarray
    block_mu: np.ndarray
    ext_force: np.ndarray
    ext_torque: np.ndarray


class Shapes(NamedTuple):
    """Signed distance data of every block (reference frame).

    Attributes
    ----------
    face_ptr : (n + 1,) int64
        Block ``b``'s faces are ``face_ptr[b]:face_ptr[b + 1]``.
    face_normal : (n_faces, 3) float64
        Outward unit normals.
    face_offset : (n_faces,) float64
        Plane offsets ``n . X = d`` [m].
    use_level_set : bool
        Use the level-set grids instead of the face planes.
    ls_origin : (n, 3) float64
        Grid corners [m].
    ls_spacing : (n,) float64
        Grid spacings [m].
    ls_dims : (n, 3) int64
        Grid points per axis.
    ls_ptr : (n + 1,) int64
        Offsets of each block's grid in ``ls_values``.
    ls_values : (n_values,) float64
        Signed distances [m], last axis fastest.
    """

    face_ptr: np.ndarray
    face_normal: np.ndarray
    face_offset: np.ndarray
    use_level_set: bool
    ls_origin: np.ndarray
    ls_spacing: np.ndarray
    ls_dims: np.ndarray
    ls_ptr: np.ndarray
    ls_values: np.ndarray


class Nodes(NamedTuple):
    """Surface nodes that act against neighbour blocks.

    Attributes
    ----------
    block : (n_nodes,) int64
        Owner block.
    r0 : (n_nodes, 3) float64
        Offset from the owner's centroid, reference frame [m].
    n0 : (n_nodes, 3) float64
        Outward normal of the owner's face, reference frame.
    area : (n_nodes,) float64
        Tributary area [m^2].
    weight : (n, n) float64
        Counting weight of nodes of block ``a`` against block ``b`` (1, 1/2 or 0).
    patch_r0, patch_u, patch_v : (n_nodes, 3) float64
        The box of face each node stands for (:func:`dem.contact_nodes.node_patches`): centre
        as an offset from the owner's centroid [m] and half sides along the face's axes [m],
        reference frame.
    """

    block: np.ndarray
    r0: np.ndarray
    n0: np.ndarray
    area: np.ndarray
    weight: np.ndarray
    patch_r0: np.ndarray
    patch_u: np.ndarray
    patch_v: np.ndarray


class Law(NamedTuple):
    """Scalars of the contact law (seed 000 Eqs. (1)-(2)) and of the neighbour list.

    Attributes
    ----------
    k_n, k_t : float
        Normal and tangential penalties [Pa/m].
    beta : float
        Stiffness-proportional normal dashpot [s].
    mu_rule : int
        How two blocks' coefficients combine (0 mean, 1 min).
    compat_cos : float
        Normal-compatible face planes (see :func:`dem.kernels.contact_force._compatible_plane`);
        above 1: off (nearest plane).
    margin : float
        Neighbour-list margin [m].
    touch : float
        Touching depth [m]: the part of a penetration within it carries no friction
        (:mod:`dem.kernels.contact_force`).
    """

    k_n: float
    k_t: float
    beta: float
    mu_rule: int
    compat_cos: float
    margin: float
    touch: float


class Motion(NamedTuple):
    """Poses and velocities of every block.

    Attributes
    ----------
    pos : (n, 3) float64
        Centroids [m].
    quat : (n, 4) float64
        Unit quaternions ``(w, x, y, z)`` from the reference frame to the world.
    vel : (n, 3) float64
        Centroid velocities [m/s].
    omega : (n, 3) float64
        Angular velocities, world frame [rad/s].
    """

    pos: np.ndarray
    quat: np.ndarray
    vel: np.ndarray
    omega: np.ndarray


class Contacts(NamedTuple):
    """The neighbour list and the friction history of its entries.

    Attributes
    ----------
    node, block : (m,) int64
        Node and neighbour block of each entry, sorted by node then block.
    weight : (m,) float64
        Counting weight of each entry.
    shear : (m, 3) float64
        Elastic shear displacement history [m].
    pos_build, quat_build : (n, 3), (n, 4) float64
        Poses when the list was built (it is rebuilt once a block drifts ``margin / 2``).
    """

    node: np.ndarray
    block: np.ndarray
    weight: np.ndarray
    shear: np.ndarray
    pos_build: np.ndarray
    quat_build: np.ndarray


class PairFrames(NamedTuple):
    """The block pairs of the neighbour list and their relative frames at the current step.

    Every entry belongs to the ordered pair ``(a, b)`` of its node's block and its neighbour.
    Per step, :func:`dem.kernels.contact_force.pair_frames` writes each pair's relative pose
    and velocity once, so that an entry needs no transform to test its node against ``b``'s
    face planes: ``n_g . X - d_g = face_v . r0 - face_d`` for the node's reference offset
    ``r0`` (``X`` the node in ``b``'s reference frame).

    Attributes
    ----------
    run_ptr : (r + 1,) int64
        Runs of consecutive entries of one pair: entries ``run_ptr[k]:run_ptr[k + 1]``
        belong to pair ``run_pair[k]`` (r,) int64 (entries stay in the list's order, by node,
        so a pair can have several runs; the loop handles a pair's data once per run).
    near_faces : (m, 2) int16 (int64 when a block has 2**15 faces or more)
        The one or two faces of ``b`` that can be the entry's nearest plane until the next
        rebuild, by their position among ``b``'s faces, in face order; the second -1 when one
        can, both -1 when more than two can (:func:`dem.kernels.broadphase.near_faces`).
    a, b : (p,) int64
        Node block and neighbour block of each pair.
    face_ptr : (p + 1,) int64
        Rows ``face_ptr[q]:face_ptr[q + 1]`` of the ``face_*`` arrays are pair ``q``'s rows,
        one per face of ``b`` in ``b``'s face order.
    arm : (p, 3) float64
        ``c_a - c_b`` [m].
    vel, omega : (p, 3) float64
        ``v_a - v_b - omega_b x arm`` [m/s] and ``omega_a - omega_b`` [rad/s]: the velocity of
        ``a``'s material point at ``c_a + r`` relative to ``b``'s is ``vel + omega x r``.
    to_b : (p, 3, 3) float64
        ``R_b^T R_a``; with ``shift`` (p, 3) ``R_b^T arm + C0_b`` [m]: ``X = to_b r0 + shift``.
    face_v : (pf, 3) float64
        ``R_a^T R_b n_g``: ``b``'s face normal in ``a``'s reference frame.
    face_u : (pf, 3) float64
        ``R_b n_g``: the face normal in the world.
    face_d : (pf,) float64
        ``d_g - n_g . C0_b - face_u . arm`` [m]: the plane's offset in ``a``'s reference
        frame.
    """

    run_ptr: np.ndarray
    run_pair: np.ndarray
    near_faces: np.ndarray
    a: np.ndarray
    b: np.ndarray
    face_ptr: np.ndarray
    arm: np.ndarray
    vel: np.ndarray
    omega: np.ndarray
    to_b: np.ndarray
    shift: np.ndarray
    face_v: np.ndarray
    face_u: np.ndarray
    face_d: np.ndarray

    @classmethod
    def of_list(cls, node_block: np.ndarray, contacts: Contacts, near_faces: np.ndarray,
                n_blocks: int, face_ptr: np.ndarray) -> PairFrames:  # fmt: skip
        """The pairs of a neighbour list (frames zero until the next step).

        Parameters
        ----------
        node_block : (n_nodes,) int64
            Owner block of each node.
        contacts : Contacts
        near_faces : (m, 2) int16 (int64 when a block has 2**15 faces or more)
            See the class.
        n_blocks : int
        face_ptr : (n_blocks + 1,) int64
            Faces of each block (CSR).
        """
        key = node_block[contacts.node] * n_blocks + contacts.block
        keys, entry = np.unique(key, return_inverse=True)
        entry = entry.reshape(-1)
        starts = np.flatnonzero(np.diff(entry, prepend=-1))
        a, b = keys // n_blocks, keys % n_blocks
        count = np.diff(face_ptr)[b]
        p, pf = len(keys), int(count.sum())
        return cls(
            np.append(starts, len(entry)).astype(np.int64), entry[starts].astype(np.int64),
            near_faces, a.astype(np.int64),
            b.astype(np.int64),
            np.concatenate([[0], np.cumsum(count)]).astype(np.int64),
            np.zeros((p, 3)), np.zeros((p, 3)), np.zeros((p, 3)), np.zeros((p, 3, 3)),
            np.zeros((p, 3)), np.zeros((pf, 3)), np.zeros((pf, 3)), np.zeros(pf),
        )  # fmt: skip


class Scratch(NamedTuple):
    """Work arrays of a step (overwritten every step; not part of the state).

    Attributes
    ----------
    rot : (n, 3, 3) float64
        Rotation matrices of the current quaternions.
    force, torque : (n, 3) float64
        Contact force [N] and moment about the centroid [N m] on each block.
    out_force, out_point : (m, 3) float64
        Force of each entry on its node's block [N] and its point [m] (written only when the
        contact kernel is asked to record them).
    out_depth : (m,) float64
        Penetration of each entry [m] (negative: separation).
    skip_gap, skip_drift : (m,) float64
        Separation of an entry when last evaluated, and ``drift[a] + drift[b]`` then [m]
        (0: evaluate); see :mod:`dem.kernels.contact_force`.
    drift : (n,) float64
        Bound on the distance any point of each block has moved since the scratch was made
        (accumulated every step) [m].
    """

    rot: np.ndarray
    force: np.ndarray
    torque: np.ndarray
    out_force: np.ndarray
    out_point: np.ndarray
    out_depth: np.ndarray
    skip_gap: np.ndarray
    skip_drift: np.ndarray
    drift: np.ndarray

    @classmethod
    def empty(cls, n_blocks: int, n_entries: int) -> Scratch:
        """Zeros: every entry is evaluated at the next step."""
        m = n_entries
        return cls(
            np.zeros((n_blocks, 3, 3)), np.zeros((n_blocks, 3)), np.zeros((n_blocks, 3)),
            np.zeros((m, 3)), np.zeros((m, 3)), np.zeros(m), np.zeros(m), np.zeros(m),
            np.zeros(n_blocks),
        )  # fmt: skip


class Indenter(NamedTuple):
    """A rigid frictionless sphere moving at constant velocity, and the nodes it can touch.

    Attributes
    ----------
    active : bool
        The sphere is present.
    block : (k,) int64
        Block of each indenter node.
    r0 : (k, 3) float64
        Node offsets from the block centroid, reference frame [m].
    area : (k,) float64
        Tributary areas [m^2].
    centre0 : (3,) float64
        Centre at time ``t0`` [m].
    t0 : float
        [s].
    radius : float
        [m].
    velocity : (3,) float64
        [m/s].
    k_n : float
        Penalty [Pa/m].
    out_force : (k, 3) float64
        Force on each node's block [N] (output).
    """

    active: bool
    block: np.ndarray
    r0: np.ndarray
    area: np.ndarray
    centre0: np.ndarray
    t0: float
    radius: float
    velocity: np.ndarray
    k_n: float
    out_force: np.ndarray


@dataclass(eq=False)
class ExplicitState:
    """Everything of a model that evolves in time.

    Attributes
    ----------
    motion : Motion
    contacts : Contacts
    t : float
        Time [s].
    n_rebuilds : int
        Neighbour-list builds so far.
    """

    motion: Motion
    contacts: Contacts
    t: float = 0.0
    n_rebuilds: int = 0

    def copy(self) -> ExplicitState:
        """A deep copy (arrays copied)."""
        return ExplicitState(
            Motion(*(a.copy() for a in self.motion)),
            Contacts(*(a.copy() for a in self.contacts)),
            self.t,
            self.n_rebuilds,
        )

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """Flat ``{name: array}`` (names ``motion.pos``, ``contacts.shear``, ``t``, ...)."""
        out = {f"{prefix}motion.{k}": v for k, v in self.motion._asdict().items()}
        out.update({f"{prefix}contacts.{k}": v for k, v in self.contacts._asdict().items()})
        out[f"{prefix}t"] = np.array(self.t)
        out[f"{prefix}n_rebuilds"] = np.array(self.n_rebuilds)
        return out

    @classmethod
    def from_arrays(cls, data, prefix: str = "") -> ExplicitState:
        """Inverse of :meth:`to_arrays` (``data`` maps names to arrays; KeyError if missing)."""
        motion = Motion(*(np.array(data[f"{prefix}motion.{k}"]) for k in Motion._fields))
        contacts = Contacts(*(np.array(data[f"{prefix}contacts.{k}"]) for k in Contacts._fields))
        return cls(motion, contacts, float(data[f"{prefix}t"]), int(data[f"{prefix}n_rebuilds"]))
