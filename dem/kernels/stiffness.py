"""Interface kinematics and the sparse stiffness ``K = H^T D H`` (numba).

Every interface couples two blocks through a dense 6 x 12 block ``B_k`` of the compatibility
matrix ``H`` (seed 001, Eq. (A2)): columns 0-5 are the dofs of ``block_a``, 6-11 those of
``block_b``; rows are ``(dn, dt1, dt2, phi1, phi2, phi3)``. The blocks come from the same kernel
that writes the triplets of ``H`` (:mod:`dem.kernels.triplets`), so the two cannot disagree.
"""

import numpy as np
from numba import njit

from dem.kernels.triplets import ENTRIES_PER_INTERFACE, compatibility_triplets_one


@njit(cache=True)
def local_compatibility(block_a, block_b, iface_centroid, block_centroid, frame):
    """Dense compatibility blocks of all interfaces.

    Parameters
    ----------
    block_a, block_b : (m,) int64
    iface_centroid : (m, 3) float64
        [m].
    block_centroid : (n_blocks, 3) float64
        [m].
    frame : (m, 3, 3) float64
        Rows ``n, t1, t2``.

    Returns
    -------
    (m, 6, 12) float64
        ``q_k = B_k (U_a, U_b)``.
    """
    m = block_a.shape[0]
    out = np.zeros((m, 6, 12))
    rows = np.empty(ENTRIES_PER_INTERFACE, dtype=np.int64)
    cols = np.empty(ENTRIES_PER_INTERFACE, dtype=np.int64)
    vals = np.empty(ENTRIES_PER_INTERFACE, dtype=np.float64)
    for k in range(m):
        a = block_a[k]
        b = block_b[k]
        compatibility_triplets_one(
            0,
            a,
            b,
            iface_centroid[k],
            block_centroid[a],
            block_centroid[b],
            frame[k],
            (rows, cols, vals),
            0,
        )
        for p in range(ENTRIES_PER_INTERFACE):
            blk = cols[p] // 6
            local = cols[p] - 6 * blk
            if blk == b:
                local += 6
            out[k, rows[p], local] += vals[p]
    return out


@njit(cache=True)
def relative_motion(B, block_a, block_b, U, out_q):
    """Interface motions ``q = H U``.

    Parameters
    ----------
    B : (m, 6, 12) float64
    block_a, block_b : (m,) int64
    U : (n_blocks, 6) float64
        Block dofs ``(ux, uy, uz, rx, ry, rz)`` [m, rad].
    out_q : (m, 6) float64
        Output ``(dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad].
    """
    for k in range(B.shape[0]):
        a = block_a[k]
        b = block_b[k]
        for i in range(6):
            s = 0.0
            for j in range(6):
                s += B[k, i, j] * U[a, j] + B[k, i, 6 + j] * U[b, j]
            out_q[k, i] = s


@njit(cache=True)
def block_forces(B, block_a, block_b, f, out_F):
    """Wrenches ``H^T f`` that the interface actions exert on the blocks.

    Parameters
    ----------
    B : (m, 6, 12) float64
    block_a, block_b : (m,) int64
    f : (m, 6) float64
        ``(N, V1, V2, M1, M2, M3)`` [N, N m].
    out_F : (n_blocks, 6) float64
        Output, overwritten [N, N m].
    """
    out_F[:, :] = 0.0
    for k in range(B.shape[0]):
        a = block_a[k]
        b = block_b[k]
        for j in range(6):
            sa = 0.0
            sb = 0.0
            for i in range(6):
                sa += B[k, i, j] * f[k, i]
                sb += B[k, i, 6 + j] * f[k, i]
            out_F[a, j] += sa
            out_F[b, j] += sb


@njit(cache=True)
def interface_block(Bk, Dk, DB, out):
    """The 12 x 12 block ``B^T D B`` of one interface into ``out`` (``DB``: (6, 12) scratch)."""
    for i in range(6):
        for j in range(12):
            s = 0.0
            for p in range(6):
                s += Dk[i, p] * Bk[p, j]
            DB[i, j] = s
    for r in range(12):
        for c in range(12):
            s = 0.0
            for i in range(6):
                s += Bk[i, r] * DB[i, c]
            out[r, c] = s


@njit(cache=True)
def interface_dofs(dof_index, a, b, out):
    """The unknown of each of the 12 local dofs of an interface between blocks ``a`` and
    ``b`` into ``out``, -1 where eliminated (fixed block, restrained dof)."""
    for j in range(6):
        out[j] = dof_index[a, j]
        out[6 + j] = dof_index[b, j]


@njit(cache=True)
def stiffness_triplets(B, D, block_a, block_b, dof_index):
    """Triplets of the reduced stiffness ``K = H^T D H`` over the unknown dofs.

    Parameters
    ----------
    B : (m, 6, 12) float64
    D : (m, 6, 6) float64
        Interface tangents ``d f / d q`` (need not be symmetric).
    block_a, block_b : (m,) int64
    dof_index : (n_blocks, 6) int64
        Unknown number of each block dof, -1 where eliminated.

    Returns
    -------
    rows, cols : (nnz,) int64
    vals : (nnz,) float64
        Duplicates are summed by the sparse constructor.
    """
    m = B.shape[0]
    rows = np.empty(144 * m, dtype=np.int64)
    cols = np.empty(144 * m, dtype=np.int64)
    vals = np.empty(144 * m, dtype=np.float64)
    dofs = np.empty(12, dtype=np.int64)
    DB, Kk = np.empty((6, 12)), np.empty((12, 12))
    pos = 0
    for k in range(m):
        interface_dofs(dof_index, block_a[k], block_b[k], dofs)
        interface_block(B[k], D[k], DB, Kk)
        for r in range(12):
            for c in range(12):
                if dofs[r] >= 0 and dofs[c] >= 0:
                    rows[pos] = dofs[r]
                    cols[pos] = dofs[c]
                    vals[pos] = Kk[r, c]
                    pos += 1
    return rows[:pos], cols[:pos], vals[:pos]


@njit(cache=True)
def stiffness_values(B, D, block_a, block_b, dof_index, slots, out):
    """Add ``K = H^T D H`` into the values ``out`` of a fixed sparse structure: triplet ``p``
    of :func:`stiffness_triplets` (same order) goes to ``out[slots[p]]``, so ``out`` equals
    the structure's ``bincount`` of the triplets without forming them."""
    dofs = np.empty(12, dtype=np.int64)
    DB, Kk = np.empty((6, 12)), np.empty((12, 12))
    pos = 0
    for k in range(B.shape[0]):
        interface_dofs(dof_index, block_a[k], block_b[k], dofs)
        interface_block(B[k], D[k], DB, Kk)
        for r in range(12):
            for c in range(12):
                if dofs[r] >= 0 and dofs[c] >= 0:
                    out[slots[pos]] += Kk[r, c]
                    pos += 1
