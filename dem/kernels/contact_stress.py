r"""Normal force and bending moments of a joint from its normal stress field (numba).

The part ``(N, M1, M2)`` of the resultant law (:mod:`dem.kernels.interface_law`). A relative
motion ``(dn, phi1, phi2)`` gives the trial normal stress at ``(y1, y2)`` of the joint polygon
``P`` (about its centroid)

.. math:: \sigma(y) = k_n\,dn + k_r\,(\phi_1 y_2 - \phi_2 y_1)

(seed 001 Eq. (4): ``k_r = k_n`` makes it the stress of a Winkler layer whose gap is
``dn + phi1 y2 - phi2 y1``), capped pointwise by the strengths,
``-f_c <= sigma <= sigma_t`` (``sigma_t = f_t / A``; 0 for a dry joint, where the cap is the
opening). The actions are its resultants about the centroid,

.. math:: N = \int_P \sigma\,dA,\ M_1 = \int_P y_2 \sigma\,dA,\ M_2 = -\int_P y_1 \sigma\,dA,

exact integrals over the parts of ``P`` cut by the lines ``sigma = sigma_t`` and
``sigma = -f_c`` (polygon clipping and shoelace moments). Their limits are seed 001 Eq. (9),
``|M_j| <= (f_t - N) l_j``, as the compressed part shrinks to the edge, and, with ``f_c``,
the uniform stress block. Both are approached as the rotation grows: the compressed strip of a
rocking joint narrows as ``theta^(-1/2)``, so a path ends on its plateau about 1 % below the
rigid-block limit (0.988 b / h for a single block). On the way the compressed part shrinks
progressively from the middle third on, and a joint rocking about its edge opens at its
centroid (a rigid block turning about an edge lifts). Seed 001's own rule (Eq. 13: elastic
until the limit, then ``k_r = 0``) lets the joint turn about its centroid without opening, half
of it passing through its neighbour: where that lift is confined (a wall held along an edge,
interlocked units) the assembly then finds mechanisms that rigid blocks do not have (a 3 x 13
dry panel with a restrained column collapsed at a fifth of the fibre law's and the explicit
DEM's load), and a panel of interlocked units with inclined faces found no equilibrium under
its own weight (a face rotating about an edge had its centroid open and counted as
detached).

The response has no memory (like the fibre law's springs, a dry joint reopens and recloses
elastically; a crushed zone is capped, not plastically shortened). The tangent is
``D = int_E b (d sigma / d q) dA`` over the uncapped part ``E`` (the capped parts and the
moving cut lines add nothing: the stress is continuous across them), with ``b = (1, y2, -y1)``.
"""

import numpy as np
from numba import njit

from dem.kernels.polygon import polygon_moments

MAX_VERTICES = 16  # corners of a joint polygon the parameter rows hold


@njit(cache=True)
def clip_half_plane(poly, n, c, out):
    """Corners of the part of the CCW polygon ``poly[:n]`` where ``c0 + c1 y1 + c2 y2 > 0``.

    ``out`` (>= n + 1, 2) receives them, CCW; returns their number (0 if the part is empty).
    Strict: an unloaded joint (``c = 0``) has no part at a cap, and keeps its elastic tangent.
    """
    count = 0
    for j in range(n):
        k = (j + 1) % n
        sj = c[0] + c[1] * poly[j, 0] + c[2] * poly[j, 1]
        sk = c[0] + c[1] * poly[k, 0] + c[2] * poly[k, 1]
        if sj > 0.0:
            out[count, 0] = poly[j, 0]
            out[count, 1] = poly[j, 1]
            count += 1
        if (sj > 0.0) != (sk > 0.0):
            w = sj / (sj - sk)
            out[count, 0] = poly[j, 0] + w * (poly[k, 0] - poly[j, 0])
            out[count, 1] = poly[j, 1] + w * (poly[k, 1] - poly[j, 1])
            count += 1
    return count


@njit(cache=True)
def origin_moments(poly, n, sign, out):
    """Add ``sign`` times ``(A, int y1, int y2, int y1^2, int y1 y2, int y2^2)`` of the CCW
    polygon ``poly[:n]`` about the origin to ``out`` (6,) [m^2, m^3, m^4]."""
    if n < 3:
        return
    area, cx, cy, ixx, iyy, ixy = polygon_moments(poly[:n])
    ox, oy = poly[0, 0], poly[0, 1]
    out[0] += sign * area
    out[1] += sign * area * (ox + cx)
    out[2] += sign * area * (oy + cy)
    out[3] += sign * (ixx + 2.0 * ox * area * cx + ox * ox * area)
    out[4] += sign * (ixy + ox * area * cy + oy * area * cx + ox * oy * area)
    out[5] += sign * (iyy + 2.0 * oy * area * cy + oy * oy * area)


@njit(cache=True)
def stress_resultants(motion, poly, n, stiffness, strength, out_f, out_D):
    """``(N, M1, M2)`` and their tangent from the capped stress field (module notes).

    Parameters
    ----------
    motion : (3,) float64
        ``(dn, phi1, phi2)`` [m, rad].
    poly : (>= n, 2) float64
        Joint corners ``(y1, y2)`` about its centroid, CCW [m].
    n : int
        Corners.
    stiffness : (2,) float64
        ``(k_n, k_r)`` per unit area [Pa/m].
    strength : (3,) float64
        ``(sigma_t, f_c, sigma_touch)``: tensile and compressive strength [Pa] (``f_c = inf``
        for none), and the stress ``k_n touch`` of the touching gap [Pa]: a point is capped
        only where its trial stress exceeds ``sigma_t`` by more (a gap of round-off size does
        not open it, whatever its sign; :mod:`dem.kernels.interface_law`).
    out_f : (3,) float64
        Output ``(N, M1, M2)`` [N, N m].
    out_D : (3, 3) float64
        Output ``d (N, M1, M2) / d (dn, phi1, phi2)``.

    Returns
    -------
    area_capped_t, area_capped_c : float
        Areas where the tensile (for a dry joint: open) and the compressive cap hold [m^2].
    """
    kn, kr = stiffness[0], stiffness[1]
    sigma_t, f_c = strength[0], strength[1]
    # sigma(y) = a + b1 y1 + b2 y2
    a, b1, b2 = kn * motion[0], -kr * motion[2], kr * motion[1]
    part = np.empty((n + 1, 2))
    m_e = np.zeros(6)  # moments of the uncapped part
    m_t = np.zeros(6)
    m_c = np.zeros(6)
    origin_moments(poly, n, 1.0, m_e)
    count = clip_half_plane(poly, n, (a - sigma_t - strength[2], b1, b2), part)
    origin_moments(part, count, 1.0, m_t)
    if np.isfinite(f_c):
        count = clip_half_plane(poly, n, (-f_c - a, -b1, -b2), part)
        origin_moments(part, count, 1.0, m_c)
    for i in range(6):
        m_e[i] -= m_t[i] + m_c[i]
    # int sigma b dA with b = (1, y2, -y1): uncapped part plus the two caps
    s0 = a * m_e[0] + b1 * m_e[1] + b2 * m_e[2] + sigma_t * m_t[0]
    s1 = a * m_e[1] + b1 * m_e[3] + b2 * m_e[4] + sigma_t * m_t[1]
    s2 = a * m_e[2] + b1 * m_e[4] + b2 * m_e[5] + sigma_t * m_t[2]
    if m_c[0] > 0.0:
        s0 -= f_c * m_c[0]
        s1 -= f_c * m_c[1]
        s2 -= f_c * m_c[2]
    out_f[0], out_f[1], out_f[2] = s0, s2, -s1
    # d sigma / d (dn, phi1, phi2) = (k_n, k_r y2, -k_r y1) on the uncapped part
    out_D[0, 0], out_D[0, 1], out_D[0, 2] = kn * m_e[0], kr * m_e[2], -kr * m_e[1]
    out_D[1, 0], out_D[1, 1], out_D[1, 2] = kn * m_e[2], kr * m_e[5], -kr * m_e[4]
    out_D[2, 0], out_D[2, 1], out_D[2, 2] = -kn * m_e[1], -kr * m_e[4], kr * m_e[3]
    return m_t[0], m_c[0]
