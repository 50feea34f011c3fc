"""Fibre interface law: each interface a grid of no-tension / Mohr-Coulomb springs (numba).

The spring model of seed 001 Sec. 2.1 used inside the wall model: interface ``k`` owns the
springs ``spring_ptr[k]:spring_ptr[k+1]`` at positions ``(y1, y2)`` about its centroid. A
relative motion ``q = (dn, dt1, dt2, phi1, phi2, phi3)`` moves spring ``i`` by

    u_n = dn + phi1 y2 - phi2 y1,   u_t1 = dt1 - phi3 y2,   u_t2 = dt2 + phi3 y1,

each spring follows the elastic-perfectly-plastic Coulomb law of
:func:`dem.kernels.spring_grid.spring_return_map_one`, and the interface actions are the
resultants ``N = sum f_n``, ``V = sum f_t``, ``M1 = sum y2 f_n``, ``M2 = -sum y1 f_n``,
``M3 = sum (y1 f_t2 - y2 f_t1)``. Rocking, torsion and their interaction follow from the
springs; no fitted exponent is needed.

A spring whose tangential force lies on its Coulomb limit to within the relative
``KINK_BAND`` counts as sliding in the tangent (not only one beyond it), as in
:mod:`dem.kernels.interface_law`: after a return the committed spring lies on the limit up to
rounding, and a stick tangent there made the first iterate of the next step overshoot and the
step shrink (a dry wall with a fixed column crept in steps of 0.05 first increments, ten
iterations each). The forces are those of the return map; only the tangent changes.
"""

import numpy as np
from numba import njit

from dem.kernels.interface_law import KINK_BAND
from dem.kernels.spring_grid import STATUS_OPEN, STATUS_SLIP, STATUS_STICK, spring_return_map_one

STATE_ELASTIC = 0
STATE_SHEAR = 1
STATE_FLEXURE = 2
STATE_DETACHED = 4


@njit(cache=True)
def on_limit(f_n, f_1, f_2, mu, cohesion_force):
    """Whether a sticking spring's tangential force is on its Coulomb limit (``KINK_BAND``).

    ``f_n`` [N] (< 0 in compression), ``f_1, f_2`` [N] the spring's forces, ``mu`` [-],
    ``cohesion_force`` its cohesion times its area [N] (0 once broken).
    """
    limit = cohesion_force - mu * f_n
    if limit <= 0.0:
        return False
    return np.hypot(f_1, f_2) >= limit * (1.0 - KINK_BAND)


@njit(cache=True)
def fibre_law_one(
    q,
    lo,
    hi,
    positions,
    areas,
    slip,
    is_broken,
    k_n,
    k_s,
    mu,
    cohesion,
    tensile,
    floor,
    out_f,
    out_slip,
    out_broken,
    out_D,
):
    """Return mapping of the springs of one interface, resultants and tangent.

    Parameters
    ----------
    q : (6,) float64
        Relative motion ``(dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad].
    lo, hi : int
        The interface's springs are ``lo:hi``.
    positions : (n_springs, 2) float64
        ``(y1, y2)`` about the interface centroid [m].
    areas : (n_springs,) float64
        Tributary areas [m^2].
    slip : (n_springs, 2) float64
        Plastic slips at the last converged state [m].
    is_broken : (n_springs,) bool
        Springs that lost their tensile strength.
    k_n, k_s : float
        Stiffness per unit area [Pa/m].
    mu : float
        Friction coefficient [-].
    cohesion, tensile : float
        Cohesion and tensile strength [Pa].
    floor : float
        Fraction of the elastic stiffness kept by open or sliding springs in the tangent.
    out_f : (6,) float64
        Output ``(N, V1, V2, M1, M2, M3)`` [N, N m].
    out_slip : (n_springs, 2) float64
        Output slips (only rows ``lo:hi`` are written).
    out_broken : (n_springs,) bool
        Output flags (rows ``lo:hi``).
    out_D : (6, 6) float64
        Output tangent ``df/dq`` (summed spring tangents).

    Returns
    -------
    state : int
        ``STATE_DETACHED`` if every spring is open; else ``STATE_FLEXURE`` if open springs
        cover at least half the area, plus ``STATE_SHEAR`` if sliding springs cover at least
        half the closed area.
    """
    for i in range(6):
        out_f[i] = 0.0
        for j in range(6):
            out_D[i, j] = 0.0
    area_open = 0.0
    area_slip = 0.0
    area_total = 0.0
    bn = np.zeros(6)
    b1 = np.zeros(6)
    b2 = np.zeros(6)
    for s in range(lo, hi):
        y1 = positions[s, 0]
        y2 = positions[s, 1]
        a = areas[s]
        kn = k_n * a
        ks = k_s * a
        u_n = q[0] + q[3] * y2 - q[4] * y1
        u_1 = q[1] - q[5] * y2
        u_2 = q[2] + q[5] * y1
        f_n, f_1, f_2, s1, s2, brk, st = spring_return_map_one(
            u_n,
            u_1,
            u_2,
            slip[s, 0],
            slip[s, 1],
            is_broken[s],
            kn,
            ks,
            mu,
            cohesion * a,
            tensile * a,
        )
        out_slip[s, 0] = s1
        out_slip[s, 1] = s2
        out_broken[s] = brk
        area_total += a
        # B rows: u_n, u_t1, u_t2 as linear functions of q
        bn[:] = 0.0
        b1[:] = 0.0
        b2[:] = 0.0
        bn[0] = 1.0
        bn[3] = y2
        bn[4] = -y1
        b1[1] = 1.0
        b1[5] = -y2
        b2[2] = 1.0
        b2[5] = y1
        out_f[0] += f_n
        out_f[1] += f_1
        out_f[2] += f_2
        out_f[3] += y2 * f_n
        out_f[4] -= y1 * f_n
        out_f[5] += y1 * f_2 - y2 * f_1
        # spring tangent d(f_n, f_1, f_2)/d(u_n, u_1, u_2)
        dnn = kn
        d11 = ks
        d22 = ks
        d12 = 0.0
        d1n = 0.0
        d2n = 0.0
        if st == STATUS_OPEN:
            area_open += a
            dnn = floor * kn
            d11 = floor * ks
            d22 = floor * ks
        elif st == STATUS_SLIP or (
            st == STATUS_STICK and on_limit(f_n, f_1, f_2, mu, 0.0 if brk else cohesion * a)
        ):
            area_slip += a
            t1 = 0.0
            t2 = 0.0
            norm = np.hypot(f_1, f_2)
            if norm > 0.0:
                t1 = f_1 / norm
                t2 = f_2 / norm
            trial = ks * np.hypot(u_1 - slip[s, 0], u_2 - slip[s, 1])
            ratio = min(norm / trial, 1.0) if trial > 0.0 else 0.0
            d11 = ks * (ratio * (1.0 - t1 * t1) + floor)
            d22 = ks * (ratio * (1.0 - t2 * t2) + floor)
            d12 = -ks * ratio * t1 * t2
            # the Coulomb limit grows with compression: f_t = (c - mu f_n) t
            if norm > 0.0:
                d1n = -mu * kn * t1
                d2n = -mu * kn * t2
        for r in range(6):
            for c in range(6):
                out_D[r, c] += (
                    bn[r] * dnn * bn[c]
                    + b1[r] * (d11 * b1[c] + d12 * b2[c] + d1n * bn[c])
                    + b2[r] * (d12 * b1[c] + d22 * b2[c] + d2n * bn[c])
                )
    if area_open >= area_total * (1.0 - 1e-12):
        return STATE_DETACHED
    state = STATE_ELASTIC
    if area_open >= 0.5 * area_total:
        state |= STATE_FLEXURE
    if area_slip >= 0.5 * (area_total - area_open):
        state |= STATE_SHEAR
    return state


@njit(cache=True)
def fibre_law(
    q,
    spring_ptr,
    positions,
    areas,
    slip,
    is_broken,
    k_n,
    k_s,
    mu,
    cohesion,
    tensile,
    floor,
    out_f,
    out_slip,
    out_broken,
    out_state,
    out_D,
):
    """Batch of :func:`fibre_law_one` over ``m`` interfaces.

    Parameters
    ----------
    q : (m, 6) float64
    spring_ptr : (m + 1,) int64
    positions : (n_springs, 2) float64
    areas : (n_springs,) float64
    slip : (n_springs, 2) float64
    is_broken : (n_springs,) bool
    k_n, k_s, mu, cohesion, tensile : (m,) float64
        Per-interface law ([Pa/m], [-], [Pa]).
    floor : float
    out_f : (m, 6) float64
    out_slip : (n_springs, 2) float64
    out_broken : (n_springs,) bool
    out_state : (m,) int64
    out_D : (m, 6, 6) float64
    """
    for j in range(q.shape[0]):
        out_state[j] = fibre_law_one(
            q[j],
            spring_ptr[j],
            spring_ptr[j + 1],
            positions,
            areas,
            slip,
            is_broken,
            k_n[j],
            k_s[j],
            mu[j],
            cohesion[j],
            tensile[j],
            floor,
            out_f[j],
            out_slip,
            out_broken,
            out_D[j],
        )
