"""Penetration depth of pairs of convex polyhedra by the separating-axis test.

The array form of :func:`dem.geometry.polyhedron.penetration_depth`, for many pairs of posed
blocks at once: the least distance that separates the two blocks' projections over the face
normals of both and the normalised cross products of their edge directions (zero when one of
these axes separates them).
"""

import math

from numba import njit


@njit(cache=True)
def _overlap_along(ax, ay, az, verts, a0, a1, b0, b1):
    """Distance [m] that separates the projections of vertices ``a0:a1`` and ``b0:b1`` on the
    axis (negative when they are apart)."""
    lo_a, hi_a, lo_b, hi_b = math.inf, -math.inf, math.inf, -math.inf
    for v in range(a0, a1):
        p = ax * verts[v, 0] + ay * verts[v, 1] + az * verts[v, 2]
        lo_a, hi_a = min(lo_a, p), max(hi_a, p)
    for v in range(b0, b1):
        p = ax * verts[v, 0] + ay * verts[v, 1] + az * verts[v, 2]
        lo_b, hi_b = min(lo_b, p), max(hi_b, p)
    return min(hi_a - lo_b, hi_b - lo_a)


@njit(cache=True)
def penetration_depths(verts, vert_ptr, normals, face_ptr, edges, edge_ptr, pairs, out):
    """Penetration depth of each pair of blocks (module notes).

    Parameters
    ----------
    verts : (n_vertices, 3) float64
        World vertices; block ``b``'s are ``vert_ptr[b]:vert_ptr[b + 1]`` [m].
    normals : (n_faces, 3) float64
        World unit face normals, by ``face_ptr``.
    edges : (n_edges, 3) float64
        World unit edge directions, by ``edge_ptr``.
    pairs : (p, 2) int64
    out : (p,) float64
        Depths [m] (0 for separated pairs).
    """
    for k in range(pairs.shape[0]):
        a, b = pairs[k, 0], pairs[k, 1]
        a0, a1, b0, b1 = vert_ptr[a], vert_ptr[a + 1], vert_ptr[b], vert_ptr[b + 1]
        depth = math.inf
        for blk in (a, b):
            for f in range(face_ptr[blk], face_ptr[blk + 1]):
                n = normals[f]
                depth = min(depth, _overlap_along(n[0], n[1], n[2], verts, a0, a1, b0, b1))
        for i in range(edge_ptr[a], edge_ptr[a + 1]):
            for j in range(edge_ptr[b], edge_ptr[b + 1]):
                cx = edges[i, 1] * edges[j, 2] - edges[i, 2] * edges[j, 1]
                cy = edges[i, 2] * edges[j, 0] - edges[i, 0] * edges[j, 2]
                cz = edges[i, 0] * edges[j, 1] - edges[i, 1] * edges[j, 0]
                norm = math.sqrt(cx * cx + cy * cy + cz * cz)
                if norm > 1e-6:
                    ov = _overlap_along(cx / norm, cy / norm, cz / norm, verts, a0, a1, b0, b1)
                    depth = min(depth, ov)
        out[k] = max(0.0, depth)
