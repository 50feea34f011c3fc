"""Sparse triplets of the interface compatibility matrix H (numba)."""

import numpy as np
from numba import njit

ENTRIES_PER_INTERFACE = 72  # 6 interface components x 12 dofs of the two blocks


@njit(cache=True)
def compatibility_triplets_one(k, a, b, c, xa, xb, frame, out, pos):
    """Write the 6 x 12 block of interface ``k`` into ``out = (rows, cols, vals)`` from
    ``pos``; returns the position after it.

    ``c`` (3,) interface centroid, ``xa, xb`` (3,) block centroids, ``frame`` (3, 3) rows
    ``n, t1, t2``. Relative motion of b with respect to a at ``c``:
    ``delta = (u_b - (c - x_b) x r_b) - (u_a - (c - x_a) x r_a)`` and ``phi = r_b - r_a``;
    rows are ``(n.delta, t1.delta, t2.delta, t1.phi, t2.phi, n.phi)``.
    """
    rows, cols, vals = out
    rot_rows = np.empty((3, 3))
    rot_rows[0] = frame[1]
    rot_rows[1] = frame[2]
    rot_rows[2] = frame[0]
    p = pos
    for side in range(2):
        blk = b if side == 0 else a
        sign = 1.0 if side == 0 else -1.0
        x = xb if side == 0 else xa
        d0, d1, d2 = c[0] - x[0], c[1] - x[1], c[2] - x[2]
        for i in range(3):
            e0, e1, e2 = frame[i, 0], frame[i, 1], frame[i, 2]
            # translation block: e . u
            for j in range(3):
                rows[p] = 6 * k + i
                cols[p] = 6 * blk + j
                vals[p] = sign * frame[i, j]
                p += 1
            # rotation block: e . (r x d) = r . (d x e)
            g0 = d1 * e2 - d2 * e1
            g1 = d2 * e0 - d0 * e2
            g2 = d0 * e1 - d1 * e0
            for j, g in enumerate((g0, g1, g2)):
                rows[p] = 6 * k + i
                cols[p] = 6 * blk + 3 + j
                vals[p] = sign * g
                p += 1
        for i in range(3):
            for j in range(3):
                rows[p] = 6 * k + 3 + i
                cols[p] = 6 * blk + 3 + j
                vals[p] = sign * rot_rows[i, j]
                p += 1
            for j in range(3):
                rows[p] = 6 * k + 3 + i
                cols[p] = 6 * blk + j
                vals[p] = 0.0
                p += 1
    return p


@njit(cache=True)
def compatibility_triplets(block_a, block_b, iface_centroid, block_centroid, frame):
    """Triplets of H for all interfaces.

    Parameters
    ----------
    block_a, block_b : (m,) int64
    iface_centroid : (m, 3) float64
    block_centroid : (n_blocks, 3) float64
    frame : (m, 3, 3) float64

    Returns
    -------
    rows, cols : (72 m,) int64
    vals : (72 m,) float64
    """
    m = block_a.shape[0]
    rows = np.empty(72 * m, dtype=np.int64)
    cols = np.empty(72 * m, dtype=np.int64)
    vals = np.empty(72 * m, dtype=np.float64)
    pos = 0
    for k in range(m):
        a = block_a[k]
        b = block_b[k]
        pos = compatibility_triplets_one(
            k,
            a,
            b,
            iface_centroid[k],
            block_centroid[a],
            block_centroid[b],
            frame[k],
            (rows, cols, vals),
            pos,
        )
    return rows, cols, vals
