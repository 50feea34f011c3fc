"""Signed distance of a point to a block in its body frame: face planes or a level-set grid.

Both functions work in the block's *reference* frame (the configuration in which the scene was
built, quaternion ``(1, 0, 0, 0)``): the caller maps a world point ``x`` to
``X = R^T (x - c) + C0`` with the block's current centroid ``c``, rotation ``R`` and reference
centroid ``C0``. Signed distances are negative inside the block, positive outside [m].

- Convex polyhedra: ``phi(X) = max_f (n_f . X - d_f)``. Exact inside and on the surface (the
  nearest face plane is the nearest surface point of a convex body), a lower bound outside.
  The gradient is the normal of the maximising face.
- Level set (LS-DEM, Kawamoto et al. 2016): ``phi`` sampled on a regular grid and
  interpolated trilinearly; the gradient is the derivative of the trilinear interpolant,
  normalised. Works for any shape whose signed distance the caller can sample.
"""

import math

from numba import njit


@njit(cache=True, inline="always")
def convex_sdf_one(x0, x1, x2, face_normal, face_offset, f_begin, f_end):
    """Signed distance of one point to one convex block from its face planes.

    Parameters
    ----------
    x0, x1, x2 : float
        Point in the block's reference frame [m].
    face_normal : (n_faces, 3) float64
        Outward unit normals of all faces (reference frame).
    face_offset : (n_faces,) float64
        Plane offsets ``n . X = d`` [m].
    f_begin, f_end : int
        The block's faces are ``f_begin:f_end``.

    Returns
    -------
    phi : float
        ``max_f (n_f . X - d_f)`` [m], negative inside.
    face : int
        Index of the maximising face (its normal is the contact normal).
    """
    best = -math.inf
    face = f_begin
    for f in range(f_begin, f_end):
        s = (
            face_normal[f, 0] * x0
            + face_normal[f, 1] * x1
            + face_normal[f, 2] * x2
            - face_offset[f]
        )
        if s > best:
            best = s
            face = f
    return best, face


@njit(cache=True)
def convex_sdf_many(points, face_normal, face_offset, f_begin, f_end, out_phi):
    """Batch version of :func:`convex_sdf_one` for ``points`` (k, 3) into ``out_phi`` (k,)."""
    for i in range(points.shape[0]):
        out_phi[i], _ = convex_sdf_one(
            points[i, 0], points[i, 1], points[i, 2], face_normal, face_offset, f_begin, f_end
        )


@njit(cache=True)
def level_set_sdf_one(x0, x1, x2, origin, spacing, dims, values, v_begin):
    """Trilinear level-set value and unit gradient of one block at one point.

    Parameters
    ----------
    x0, x1, x2 : float
        Point in the block's reference frame [m].
    origin : (3,) float64
        Grid corner ``(0, 0, 0)`` [m].
    spacing : float
        Grid spacing [m].
    dims : (3,) int64
        Grid points per axis ``(n0, n1, n2)``; values are stored with the last axis fastest.
    values : (n_values,) float64
        All blocks' grids, flat [m].
    v_begin : int
        Offset of this block's grid in ``values``.

    Returns
    -------
    phi : float
        Interpolated signed distance [m]; ``+inf`` outside the grid (no contact possible).
    g0, g1, g2 : float
        Unit gradient of the interpolant (outward normal), zeros if it vanishes.
    """
    u0 = (x0 - origin[0]) / spacing
    u1 = (x1 - origin[1]) / spacing
    u2 = (x2 - origin[2]) / spacing
    n0, n1, n2 = dims[0], dims[1], dims[2]
    if u0 < 0.0 or u1 < 0.0 or u2 < 0.0 or u0 > n0 - 1 or u1 > n1 - 1 or u2 > n2 - 1:
        return math.inf, 0.0, 0.0, 0.0
    i = min(int(u0), n0 - 2)
    j = min(int(u1), n1 - 2)
    k = min(int(u2), n2 - 2)
    a = u0 - i
    b = u1 - j
    c = u2 - k
    s1 = n2
    s0 = n1 * n2
    base = v_begin + i * s0 + j * s1 + k
    c000 = values[base]
    c001 = values[base + 1]
    c010 = values[base + s1]
    c011 = values[base + s1 + 1]
    c100 = values[base + s0]
    c101 = values[base + s0 + 1]
    c110 = values[base + s0 + s1]
    c111 = values[base + s0 + s1 + 1]
    # interpolate along the last axis, then the middle, then the first
    c00 = c000 + c * (c001 - c000)
    c01 = c010 + c * (c011 - c010)
    c10 = c100 + c * (c101 - c100)
    c11 = c110 + c * (c111 - c110)
    c0 = c00 + b * (c01 - c00)
    c1 = c10 + b * (c11 - c10)
    phi = c0 + a * (c1 - c0)
    g0 = (c1 - c0) / spacing
    g1 = ((1.0 - a) * (c01 - c00) + a * (c11 - c10)) / spacing
    d00 = c001 - c000
    d01 = c011 - c010
    d10 = c101 - c100
    d11 = c111 - c110
    g2 = ((1.0 - a) * ((1.0 - b) * d00 + b * d01) + a * ((1.0 - b) * d10 + b * d11)) / spacing
    norm = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    if norm > 0.0:
        return phi, g0 / norm, g1 / norm, g2 / norm
    return phi, 0.0, 0.0, 0.0
