"""Verlet-style neighbour lists of (surface node, neighbour block) contact entries.

An entry ``(i, b)`` is kept when node ``i`` (of block ``a``) lies within ``margin`` of block
``b``'s face planes, ``max_f (n_f . X - d_f) < margin`` (a lower bound on the distance, so no
contact is missed), and the counting weight ``weight[a, b]`` is non-zero. The list stays valid
while no block has moved more than ``margin / 2`` (translation plus rotation times its bounding
radius) since it was built: two blocks then approach each other by at most ``margin``. A node
is tested only against the blocks whose bounding spheres come within ``margin`` of its own
block's (:func:`near_blocks`): a rebuild costs the nodes times their block's neighbours, not
times every block.

Entries are sorted by node, then block, which lets the shear history of entries that survive a
rebuild be carried over by a merge.
"""

import math

import numpy as np
from numba import njit

from dem.kernels.signed_distance import convex_sdf_one


@njit(cache=True)
def _node_world(i, node_block, node_r0, pos, rot):
    a = node_block[i]
    r0x, r0y, r0z = node_r0[i, 0], node_r0[i, 1], node_r0[i, 2]
    x0 = pos[a, 0] + rot[a, 0, 0] * r0x + rot[a, 0, 1] * r0y + rot[a, 0, 2] * r0z
    x1 = pos[a, 1] + rot[a, 1, 0] * r0x + rot[a, 1, 1] * r0y + rot[a, 1, 2] * r0z
    x2 = pos[a, 2] + rot[a, 2, 0] * r0x + rot[a, 2, 1] * r0y + rot[a, 2, 2] * r0z
    return x0, x1, x2


@njit(cache=True)
def node_candidate_count(i, nodes, pos, rot, bodies, shapes, margin, near, out_blocks):
    """Neighbour blocks of node ``i`` within ``margin``, written to ``out_blocks``; returns count.

    Parameters
    ----------
    i : int
        Node index.
    nodes : Nodes
        ``block`` and ``r0`` (offsets from the owner's centroid, reference frame [m]).
    pos : (n_blocks, 3) float64
        Centroids [m].
    rot : (n_blocks, 3, 3) float64
        Rotations.
    bodies : Bodies
        ``ref_centroid`` [m] and bounding ``radius`` [m] of each block.
    shapes : Shapes
        Reference-frame face planes (CSR by block).
    margin : float
        [m].
    near : ((n_blocks + 1,) int64, (k,) int64)
        The candidate blocks of each block, CSR (:func:`near_blocks`).
    out_blocks : (n_blocks,) int64
        Scratch output.
    """
    node_block, node_r0 = nodes.block, nodes.r0
    ref_centroid, radius = bodies.ref_centroid, bodies.radius
    face_ptr, face_normal, face_offset = shapes.face_ptr, shapes.face_normal, shapes.face_offset
    a = node_block[i]
    x0, x1, x2 = _node_world(i, node_block, node_r0, pos, rot)
    count = 0
    near_ptr, near_block = near
    for k in range(near_ptr[a], near_ptr[a + 1]):
        b = near_block[k]
        dx = x0 - pos[b, 0]
        dy = x1 - pos[b, 1]
        dz = x2 - pos[b, 2]
        reach = radius[b] + margin
        if dx * dx + dy * dy + dz * dz > reach * reach:
            continue
        X0 = rot[b, 0, 0] * dx + rot[b, 1, 0] * dy + rot[b, 2, 0] * dz + ref_centroid[b, 0]
        X1 = rot[b, 0, 1] * dx + rot[b, 1, 1] * dy + rot[b, 2, 1] * dz + ref_centroid[b, 1]
        X2 = rot[b, 0, 2] * dx + rot[b, 1, 2] * dy + rot[b, 2, 2] * dz + ref_centroid[b, 2]
        phi, _ = convex_sdf_one(X0, X1, X2, face_normal, face_offset, face_ptr[b], face_ptr[b + 1])
        if phi < margin:
            out_blocks[count] = b
            count += 1
    return count


@njit(cache=True)
def near_blocks(pos, radius, weight, margin):
    """The blocks each block's nodes can be within ``margin`` of: ``b != a`` with
    ``weight[a, b] != 0`` whose bounding sphere comes within ``margin`` of ``a``'s (every node
    of ``a`` lies in ``a``'s sphere, so no other block can be within ``margin`` of it).

    Parameters
    ----------
    pos : (n_blocks, 3) float64
        Centroids [m].
    radius : (n_blocks,) float64
        Bounding radii [m].
    weight : (n_blocks, n_blocks) float64
        Counting weights.
    margin : float
        [m].

    Returns
    -------
    ptr : (n_blocks + 1,) int64
    blocks : (k,) int64
        Block ``a``'s candidates are ``blocks[ptr[a]:ptr[a + 1]]``, ascending.
    """
    n = pos.shape[0]
    ptr = np.zeros(n + 1, dtype=np.int64)
    blocks = np.empty(n * n, dtype=np.int64)
    k = 0
    for a in range(n):
        for b in range(n):
            if b == a or weight[a, b] == 0.0:
                continue
            dx = pos[a, 0] - pos[b, 0]
            dy = pos[a, 1] - pos[b, 1]
            dz = pos[a, 2] - pos[b, 2]
            reach = radius[a] + radius[b] + margin
            if dx * dx + dy * dy + dz * dz <= reach * reach:
                blocks[k] = b
                k += 1
        ptr[a + 1] = k
    return ptr, blocks[:k]


@njit(cache=True)
def build_pairs(nodes, pos, rot, bodies, shapes, margin):
    """All entries within ``margin`` (two passes: count, then fill).

    Parameters are those of :func:`node_candidate_count` without the node, the candidates
    (made here, :func:`near_blocks`, from ``nodes.weight``) and the scratch.

    Returns
    -------
    pair_node, pair_block : (m,) int64
        Sorted by node, then block.
    pair_weight : (m,) float64
    """
    node_block, weight = nodes.block, nodes.weight
    n_nodes = node_block.shape[0]
    n_blocks = pos.shape[0]
    scratch = np.empty(n_blocks, dtype=np.int64)
    near = near_blocks(pos, bodies.radius, weight, margin)
    counts = np.zeros(n_nodes, dtype=np.int64)
    for i in range(n_nodes):
        counts[i] = node_candidate_count(i, nodes, pos, rot, bodies, shapes, margin, near,
                                         scratch)  # fmt: skip
    total = 0
    for i in range(n_nodes):
        total += counts[i]
    pair_node = np.empty(total, dtype=np.int64)
    pair_block = np.empty(total, dtype=np.int64)
    pair_weight = np.empty(total, dtype=np.float64)
    k = 0
    for i in range(n_nodes):
        if counts[i] == 0:
            continue
        c = node_candidate_count(i, nodes, pos, rot, bodies, shapes, margin, near, scratch)
        a = node_block[i]
        for j in range(c):
            pair_node[k] = i
            pair_block[k] = scratch[j]
            pair_weight[k] = weight[a, scratch[j]]
            k += 1
    return pair_node, pair_block, pair_weight


@njit(cache=True)
def carry_history(old_node, old_block, old_shear, new_node, new_block, out_shear):
    """Copy the shear history of entries present in both sorted lists; new entries start at 0.

    Parameters
    ----------
    old_node, old_block : (m_old,) int64
        Previous entries, sorted by (node, block).
    old_shear : (m_old, 3) float64
        Their histories [m].
    new_node, new_block : (m_new,) int64
        New entries, sorted by (node, block).
    out_shear : (m_new, 3) float64
        Filled in place.

    Returns
    -------
    int
        Number of entries carried over.
    """
    i = 0
    carried = 0
    m_old = old_node.shape[0]
    for k in range(new_node.shape[0]):
        key_n = new_node[k]
        key_b = new_block[k]
        while i < m_old and (
            old_node[i] < key_n or (old_node[i] == key_n and old_block[i] < key_b)
        ):
            i += 1
        if i < m_old and old_node[i] == key_n and old_block[i] == key_b:
            out_shear[k, 0] = old_shear[i, 0]
            out_shear[k, 1] = old_shear[i, 1]
            out_shear[k, 2] = old_shear[i, 2]
            carried += 1
        else:
            out_shear[k, 0] = 0.0
            out_shear[k, 1] = 0.0
            out_shear[k, 2] = 0.0
    return carried


@njit(cache=True)
def block_drift_one(pos, quat, pos_build, quat_build, radius, i):
    """Largest displacement of any point of block ``i`` since the build [m] (upper bound).

    ``|c - c_build| + radius * angle``, with ``angle`` the rotation angle of
    ``q q_build^{-1}``.
    """
    dx = pos[i, 0] - pos_build[i, 0]
    dy = pos[i, 1] - pos_build[i, 1]
    dz = pos[i, 2] - pos_build[i, 2]
    # scalar part of q * conj(q_build)
    w = (
        quat[i, 0] * quat_build[i, 0]
        + quat[i, 1] * quat_build[i, 1]
        + quat[i, 2] * quat_build[i, 2]
        + quat[i, 3] * quat_build[i, 3]
    )
    w = min(1.0, abs(w))
    angle = 2.0 * math.acos(w)
    return math.sqrt(dx * dx + dy * dy + dz * dz) + radius[i] * angle


@njit(cache=True)
def needs_rebuild(pos, quat, pos_build, quat_build, radius, margin):
    """True when some block has drifted more than ``margin / 2`` since the last build."""
    for i in range(pos.shape[0]):
        if block_drift_one(pos, quat, pos_build, quat_build, radius, i) > 0.5 * margin:
            return True
    return False


FACE_GAP_MARGINS = 3.0
"""A face whose plane distance is this many margins below the nearest plane's at the build
cannot become the nearest before the next rebuild (see :func:`near_faces`)."""


@njit(cache=True)
def near_faces(nodes, entry_node, entry_block, pos_build, rot_build, bodies, shapes, margin,
               out):  # fmt: skip
    """The one or two faces of the neighbour that can be a node's nearest plane until the next
    rebuild.

    Until the list is rebuilt every block moves less than ``margin / 2`` (any point within its
    bounding radius, :func:`needs_rebuild`), so an entry's node moves less than ``1.5 margin``
    in its neighbour's reference frame (the neighbour's material point under the node is
    within ``radius + margin`` of its centroid) and each plane distance changes by less than
    that. A face whose distance at the build is more than ``FACE_GAP_MARGINS * margin`` below
    the largest can then never be the largest: the convex signed distance is the largest of
    the other faces' distances, exactly, for the whole period, and its maximising face is the
    first of them in face order to reach it (no excluded face ties with it).

    Parameters
    ----------
    nodes : Nodes
    entry_node, entry_block : (m,) int64
        The entries.
    pos_build : (n_blocks, 3) float64
        Centroids at the build [m].
    rot_build : (n_blocks, 3, 3) float64
        Rotations at the build.
    bodies, shapes : Bodies, Shapes
    margin : float
        [m].
    out : (m, 2) int16 (or wider)
        Written: the candidate faces by their position among the neighbour's faces (0 for its
        first face), in face order; ``out[e, 1] = -1`` when there is one, both -1 when there
        are more than two.
    """
    face_ptr, face_normal, face_offset = shapes.face_ptr, shapes.face_normal, shapes.face_offset
    ref_centroid = bodies.ref_centroid
    gap = FACE_GAP_MARGINS * margin
    for e in range(entry_node.shape[0]):
        b = entry_block[e]
        x0, x1, x2 = _node_world(entry_node[e], nodes.block, nodes.r0, pos_build, rot_build)
        dx = x0 - pos_build[b, 0]
        dy = x1 - pos_build[b, 1]
        dz = x2 - pos_build[b, 2]
        rb = rot_build[b]
        X0 = rb[0, 0] * dx + rb[1, 0] * dy + rb[2, 0] * dz + ref_centroid[b, 0]
        X1 = rb[0, 1] * dx + rb[1, 1] * dy + rb[2, 1] * dz + ref_centroid[b, 1]
        X2 = rb[0, 2] * dx + rb[1, 2] * dy + rb[2, 2] * dz + ref_centroid[b, 2]
        best, _ = convex_sdf_one(X0, X1, X2, face_normal, face_offset, face_ptr[b],
                                 face_ptr[b + 1])  # fmt: skip
        out[e, 0] = out[e, 1] = -1
        n_near = 0
        for g in range(face_ptr[b], face_ptr[b + 1]):
            dist = (
                face_normal[g, 0] * X0
                + face_normal[g, 1] * X1
                + face_normal[g, 2] * X2
                - face_offset[g]
            )
            if dist >= best - gap:
                if n_near < 2:
                    out[e, n_near] = g - face_ptr[b]
                n_near += 1
        if n_near > 2:
            out[e, 0] = out[e, 1] = -1
