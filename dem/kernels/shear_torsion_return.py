r"""Closest-point return of shear and torsion onto seed 001's interaction domain (numba).

For the resultant law (:mod:`dem.kernels.interface_law`): with ``v = |V|`` the shear and ``m``
the torsion about the centre of compression, the domain of seed 001 Eq. (14) / (A5) is

.. math:: g(v, m) = (|m| / M_u)^\alpha + (v / V_u)^2 \le 1 .

A trial outside it returns to the point of the boundary nearest in the elastic energy
``(v - v_t)^2 / a + (m - m_t)^2 / b`` (``a = k_t A``, ``b = k_t J_p``): the flow is normal to
the domain, as the slip and twist of a rigid contact under Coulomb friction at a fixed pressure
are normal to its limit surface, and the direction of ``V`` is kept (the domain is round in
``V``). The boundary is ``m(v) = M_u (1 - (v / V_u)^2)^{1/alpha}``, ``0 <= v <= V_u``; the
nearest point is the root of ``phi'(v) = (v - v_t) / a + (m(v) - m_t) m'(v) / b`` (a sign change
from ``v = 0``), or the corner ``(V_u, 0)`` of pure sliding. As ``M_u -> 0`` (a joint hinged on
an edge) it tends continuously to sliding on the Coulomb circle with no torsion, unlike a
radial return, which would take the friction away with the torsion.

Near that corner ``v(m)`` loses the digits of the torsion: ``m = M_u w^{1/alpha}`` with
``w = 1 - (v / V_u)^2`` computed from a ``v`` known to ``1e-16 V_u`` is noise below about
``(1e-16)^{1/alpha} M_u``. A root on the sliding half of the boundary (``w < 1/2``) is
therefore refined on the boundary written as ``v(m) = V_u (1 - (m / M_u)^alpha)^{1/2}``,
the root of ``psi'(m) = (v(m) - v_t) v'(m) / a + (m - m_t) / b``, and its derivatives are
taken there; each half of the boundary is then written in the coordinate in which it is a
well-conditioned graph.
"""

import math

from numba import njit

ITERATIONS = 100


@njit(cache=True)
def boundary(v, v_u, m_u, alpha):
    """``(m, dm/dv, d2m/dv2, dm/dV_u, d(dm/dv)/dV_u)`` of the boundary at ``v`` (< ``v_u``)."""
    x = v / v_u
    w = 1.0 - x * x
    e = 1.0 / alpha
    h = w**e
    dh = -2.0 * x * e * w ** (e - 1.0)
    d2h = -2.0 * e * w ** (e - 1.0)
    if alpha != 1.0:  # (alpha = 1: the term is 0, and 0 * inf at the corner w = 0)
        d2h += 4.0 * x * x * e * (e - 1.0) * w ** (e - 2.0)
    m = m_u * h
    dm = m_u * dh / v_u
    d2m = m_u * d2h / (v_u * v_u)
    dm_dvu = -m_u * dh * x / v_u
    ddm_dvu = -m_u * (d2h * x + dh) / (v_u * v_u)
    return m, dm, d2m, dm_dvu, ddm_dvu


@njit(cache=True)
def slope(v, v_t, m_t, v_u, m_u, alpha, a, b):
    """``phi'(v)`` (module notes)."""
    m, dm, _, _, _ = boundary(v, v_u, m_u, alpha)
    return (v - v_t) / a + (m - m_t) * dm / b


@njit(cache=True)
def sliding_side(m, v_u, m_u, alpha):
    """``(v, dv/dm, d2v/dm2, dv/dV_u, d(dv/dm)/dV_u, dv/dM_u, d(dv/dm)/dM_u)`` of the
    boundary written as ``v(m)`` (module notes), at ``0 <= m < M_u``."""
    r = m / m_u
    ra = r**alpha
    s = math.sqrt(1.0 - ra)
    h = s
    dh = -0.5 * alpha * r ** (alpha - 1.0) / s
    d2h = -0.25 * alpha * alpha * r ** (2.0 * alpha - 2.0) / (s * s * s)
    if alpha != 1.0:  # (alpha = 1: the term is 0; at r = 0 its limit: 0, finite or inf)
        if r > 0.0 or alpha > 2.0:
            d2h -= 0.5 * alpha * (alpha - 1.0) * r ** (alpha - 2.0) / s
        else:
            d2h -= math.inf if alpha < 2.0 else 0.5 * alpha * (alpha - 1.0)
    v = v_u * h
    dv = v_u * dh / m_u
    d2v = v_u * d2h / (m_u * m_u)
    return v, dv, d2v, h, dv / v_u, -r * dv, -v_u * (r * d2h + dh) / (m_u * m_u)


@njit(cache=True)
def refine_on_sliding_side(v_t, m_t, v_u, m_u, alpha, a, b, m, out):
    """Root of ``psi'(m)`` (module notes) from ``m`` and its derivatives into ``out`` (10,)
    as :func:`nearest_on_boundary`; False if it lies off the sliding half (``w > 1/2``)."""
    lo, hi = 0.0, m_u
    for _ in range(ITERATIONS):
        v, dv, d2v, _, _, _, _ = sliding_side(m, v_u, m_u, alpha)
        s = (v - v_t) * dv / a + (m - m_t) / b
        if s == 0.0:
            break
        if s > 0.0:
            hi = m
        else:
            lo = m
        curvature = (dv * dv + (v - v_t) * d2v) / a + 1.0 / b
        new = m - s / curvature if curvature > 0.0 and math.isfinite(curvature) else 0.5 * (lo + hi)
        if not lo <= new <= hi:
            new = 0.5 * (lo + hi)
        if abs(new - m) <= 1e-15 * m_u:
            m = new
            break
        m = new
    if (m / m_u) ** alpha > 0.5:
        return False
    v, dv, d2v, dv_dvu, ddv_dvu, dv_dmu, ddv_dmu = sliding_side(m, v_u, m_u, alpha)
    curvature = (dv * dv + (v - v_t) * d2v) / a + 1.0 / b
    # implicit derivatives of psi'(m; v_t, m_t, V_u, M_u) = 0
    dpsi = (
        -dv / a,
        -1.0 / b,
        (dv_dvu * dv + (v - v_t) * ddv_dvu) / a,
        (dv_dmu * dv + (v - v_t) * ddv_dmu) / a,
    )
    explicit_v = (0.0, 0.0, dv_dvu, dv_dmu)
    out[0], out[1] = v, m
    for i in range(4):
        dm = -dpsi[i] / curvature if math.isfinite(curvature) else 0.0
        out[6 + i] = dm
        out[2 + i] = dv * dm + explicit_v[i]
    return True


@njit(cache=True)
def nearest_on_boundary(v_t, m_t, v_u, m_u, alpha, a, b, out):
    """Nearest boundary point ``(v, m)`` to the trial ``(v_t, m_t >= 0)`` and its derivatives.

    ``out`` (10,) receives ``v, m``, then ``dv/d(v_t, m_t, V_u, M_u)`` and
    ``dm/d(v_t, m_t, V_u, M_u)``. Needs ``V_u > 0``, ``M_u >= 0``, ``alpha >= 1``.
    """
    for i in range(10):
        out[i] = 0.0
    # the corner of pure sliding: phi' <= 0 up to v = V_u
    if m_u <= 0.0 or m_t <= 0.0:
        end = (v_u - v_t) / a
    elif alpha > 1.0:
        end = math.inf
    else:  # alpha = 1: m'(V_u) = -2 M_u / V_u
        end = (v_u - v_t) / a + 2.0 * m_t * m_u / (v_u * b)
    if end <= 0.0:
        # m_t = 0 on a smooth corner (alpha > 1): the root m = 0 of psi' and its derivatives
        if m_t == 0.0 and m_u > 0.0 and alpha > 1.0:
            refine_on_sliding_side(v_t, m_t, v_u, m_u, alpha, a, b, 0.0, out)
            return
        out[0] = v_u
        out[4] = 1.0
        return
    lo, hi = 0.0, v_u
    v = min(v_t, v_u) * 0.5
    for _ in range(ITERATIONS):
        s = slope(v, v_t, m_t, v_u, m_u, alpha, a, b)
        if s > 0.0:
            hi = v
        else:
            lo = v
        m, dm, d2m, _, _ = boundary(v, v_u, m_u, alpha)
        curvature = 1.0 / a + (dm * dm + (m - m_t) * d2m) / b
        new = v - s / curvature if curvature > 0.0 else 0.5 * (lo + hi)
        if not lo < new < hi:
            new = 0.5 * (lo + hi)
        if abs(new - v) <= 1e-15 * v_u:
            v = new
            break
        v = new
    if v >= v_u:  # converged onto the corner (a trial inside the domain by round-off)
        out[0] = v_u
        out[4] = 1.0
        return
    if v * v >= 0.5 * v_u * v_u and m_u > 0.0:
        m0 = m_u * (1.0 - (v / v_u) ** 2) ** (1.0 / alpha)
        if refine_on_sliding_side(v_t, m_t, v_u, m_u, alpha, a, b, m0, out):
            return
    m, dm, d2m, dm_dvu, ddm_dvu = boundary(v, v_u, m_u, alpha)
    h = m / m_u if m_u > 0.0 else (1.0 - (v / v_u) ** 2) ** (1.0 / alpha)
    dh = dm * v_u / m_u if m_u > 0.0 else 0.0
    curvature = 1.0 / a + (dm * dm + (m - m_t) * d2m) / b
    # implicit derivatives of phi'(v; v_t, m_t, V_u, M_u) = 0
    dphi = (
        -1.0 / a,
        -dm / b,
        (dm_dvu * dm + (m - m_t) * ddm_dvu) / b,
        (h * dm + (m - m_t) * dh / v_u) / b,
    )
    explicit_m = (0.0, 0.0, dm_dvu, h)
    out[0], out[1] = v, m
    for i in range(4):
        dv = -dphi[i] / curvature
        out[2 + i] = dv
        out[6 + i] = dm * dv + explicit_m[i]
