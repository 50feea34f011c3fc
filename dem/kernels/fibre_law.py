"""Fibre interface law: each interface a grid of no-tension / Mohr-Coulomb springs (numba).

The spring model of seed 001 Sec. 2.1 used inside the wall model: interface ``k`` owns the
springs ``spring_ptr[k]:spring_ptr[k+1]`` at positions ``(y1, y2)`` about its centroid. A
relative motion ``q = (dn, dt1, dt2, phi1, phi2, phi3)`` moves spring ``i`` by

    u_n = dn + phi1 y2 - phi2 y1,   u_t1 = dt1 - phi3 y2,   u_t2 = dt2 + phi3 y1,

each spring follows the elastic-perfectly-plastic Coulomb law of
:func:`dem.kernels.spring_grid.spring_return_map_one`, and the interface actions are the
resultants ``N = sum f_n``, ``V = sum f_t``, ``M1 = sum y2 f_n``, ``M2 = -sum y1 f_n``,
``M3 = sum (y1 f_t2 - y2 f_t1)``. Rocking, torsion and their interaction follow from the
springs; no fitted exponent is needed. An optional compressive strength ``f_c`` caps each
spring's normal force at ``-f_c a`` (crushing, with a plastic closure kept per spring).

A spring whose tangential force lies on its Coulomb limit to within the relative
``KINK_BAND`` counts as sliding in the tangent (not only one beyond it), as in
:mod:`dem.kernels.interface_law`: after a return the committed spring lies on the limit up to
rounding, and a stick tangent there made the first iterate of the next step overshoot and the
step shrink (a dry wall with a fixed column crept in steps of 0.05 first increments, ten
iterations each). The forces are those of the return map; only the tangent changes.

Ties at zero gaps are decided the same way whatever the round-off, with ``touch`` =
``TOUCH`` (1e-12, :mod:`dem.kernels.interface_law`) times the model's extent (a parameter
column): a spring is open only beyond a gap of ``touch`` (a touching spring at a positive gap
keeps its tiny elastic tension, at most ``k_n touch`` per unit area), takes no friction from
a normal force within ``k_n touch``, and sticks while its trial slip exceeds its friction
limit by at most ``touch`` (:func:`dem.kernels.spring_grid.spring_return_map_one`); a sliding
spring takes the direction of its friction force from its trial slip, so that its tangent
couples the limit to the normal motion (``-mu k_n``) also where the limit is zero. After the
dead load of seed 001 S13 (return walls of blocks) 21 joints carried nothing, their relative
motions of round-off size (1e-20 m): their springs opened or closed and slid in round-off
directions, differently under each OpenBLAS kernel, and so did their tangents, the elastic
stiffness that sizes the first live step (0.16 % apart) and the frictional equilibrium the
path then found (lambda 0.1780 / 0.1834 / 0.1829 under Haswell / SkylakeX / Sandybridge).
"""

import numpy as np
from numba import njit, prange

from dem.kernels.interface_law import KINK_BAND
from dem.kernels.spring_grid import (
    STATUS_OPEN,
    STATUS_SLIP,
    STATUS_STICK,
    friction_limit,
    spring_return_map_one,
)

STATE_ELASTIC = 0
STATE_SHEAR = 1
STATE_FLEXURE = 2
STATE_DETACHED = 4
STATE_CRUSHED = 8

# columns of the per-interface parameter rows of the fibre law
F_KN = 0  # normal stiffness per unit area [Pa/m]
F_KS = 1  # tangential stiffness per unit area [Pa/m]
F_MU = 2  # friction coefficient [-]
F_COHESION = 3  # [Pa]
F_TENSILE = 4  # tensile strength [Pa]
F_FC = 5  # compressive strength [Pa]; inf for none
F_TOUCH = 6  # gap up to which a spring counts as touching [m] (module notes)
N_FIBRE_PARAMS = 7


@njit(cache=True)
def on_limit(f_n, f_1, f_2, mu, cohesion_force, touch_force):
    """Whether a sticking spring's tangential force is on its Coulomb limit (``KINK_BAND``).

    ``f_n`` [N] (< 0 in compression), ``f_1, f_2`` [N] the spring's forces, ``mu`` [-],
    ``cohesion_force`` its cohesion times its area [N] (0 once broken), ``touch_force`` the
    normal force of the touching gap [N] (:func:`dem.kernels.spring_grid.friction_limit`).
    """
    limit = friction_limit(f_n, mu, cohesion_force, touch_force)
    if limit <= 0.0:
        return False
    return np.hypot(f_1, f_2) >= limit * (1.0 - KINK_BAND)


@njit(cache=True)
def fibre_law_one(q, span, springs, params, plastic, floor, trial, out_f, out_D):
    """Return mapping of the springs of one interface, resultants and tangent.

    Parameters
    ----------
    q : (6,) float64
        Relative motion ``(dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad].
    span : (int, int)
        The interface's springs are ``span[0]:span[1]``.
    springs : (n_springs, 3) float64
        ``(y1, y2)`` about the interface centroid [m] and tributary area [m^2].
    params : (N_FIBRE_PARAMS,) float64
        The interface's law, columns ``F_*``: stiffnesses per unit area [Pa/m], friction
        coefficient [-], cohesion, tensile and compressive strength [Pa] (inf for none),
        touching gap [m].
    plastic : (slip, is_broken)
        Plastic slips and crushing closure (n_springs, 3) [m] at the last converged state,
        and the springs (n_springs,) bool that lost their tensile strength.
    floor : float
        Fraction of the elastic stiffness kept by open, sliding or crushed springs in the
        tangent.
    trial : (out_slip, out_broken)
        Output slips and closures, and flags, as ``plastic`` (only the span is written).
    out_f : (6,) float64
        Output ``(N, V1, V2, M1, M2, M3)`` [N, N m].
    out_D : (6, 6) float64
        Output tangent ``df/dq`` (summed spring tangents).

    Returns
    -------
    state : int
        ``STATE_DETACHED`` if every spring is open; else ``STATE_FLEXURE`` if open springs
        cover at least half the area, plus ``STATE_SHEAR`` if sliding springs cover at least
        half the closed area, plus ``STATE_CRUSHED`` if any spring is crushed.
    """
    for i in range(6):
        out_f[i] = 0.0
        for j in range(6):
            out_D[i, j] = 0.0
    area_open = 0.0
    area_slip = 0.0
    area_total = 0.0
    crushed = False
    for s in range(span[0], span[1]):
        code = spring_into(q, s, springs, params, plastic, floor, trial, out_f, out_D)
        a = springs[s, 2]
        area_total += a
        status = code & 3
        if status == STATUS_OPEN:
            area_open += a
        elif status == STATUS_SLIP:
            area_slip += a
        crushed = crushed or code >= 4
    if area_open >= area_total * (1.0 - 1e-12):
        return STATE_DETACHED
    state = STATE_ELASTIC
    if area_open >= 0.5 * area_total:
        state |= STATE_FLEXURE
    if area_slip >= 0.5 * (area_total - area_open):
        state |= STATE_SHEAR
    if crushed:
        state |= STATE_CRUSHED
    return state


@njit(cache=True)
def spring_into(q, s, springs, params, plastic, floor, trial, out_f, out_D):
    """Return map of spring ``s``, its forces and tangent added to the interface's.

    Arguments as :func:`fibre_law_one`. Returns the spring's status (``STATUS_STICK``,
    ``STATUS_SLIP`` also for a sticking spring on its limit, ``STATUS_OPEN``) plus 4 if it
    is crushed.
    """
    slip, is_broken = plastic
    out_slip, out_broken = trial
    y1, y2, a = springs[s, 0], springs[s, 1], springs[s, 2]
    kn = params[F_KN] * a
    ks = params[F_KS] * a
    mu = params[F_MU]
    f_c = params[F_FC]
    # normal motion net of the crushing closure; beyond the strength the spring crushes
    u_n = q[0] + q[3] * y2 - q[4] * y1 - slip[s, 2]
    closure = slip[s, 2]
    is_crushed = kn * u_n < -f_c * a * (1.0 - KINK_BAND)
    if is_crushed:
        closure += u_n + f_c * a / kn
        u_n = -f_c * a / kn
    u_1 = q[1] - q[5] * y2
    u_2 = q[2] + q[5] * y1
    cohesion = params[F_COHESION] * a
    f_n, f_1, f_2, s1, s2, brk, st = spring_return_map_one(
        (u_n, u_1, u_2),
        (slip[s, 0], slip[s, 1]),
        is_broken[s],
        (kn, ks, mu, cohesion, params[F_TENSILE] * a),
        params[F_TOUCH],
    )
    out_slip[s, 0] = s1
    out_slip[s, 1] = s2
    out_slip[s, 2] = closure
    out_broken[s] = brk
    out_f[0] += f_n
    out_f[1] += f_1
    out_f[2] += f_2
    out_f[3] += y2 * f_n
    out_f[4] -= y1 * f_n
    out_f[5] += y1 * f_2 - y2 * f_1
    # spring tangent d(f_n, f_1, f_2)/d(u_n, u_1, u_2)
    dnn, d11, d22, d12, d1n, d2n = kn, ks, ks, 0.0, 0.0, 0.0
    if st == STATUS_OPEN:
        dnn, d11, d22 = floor * kn, floor * ks, floor * ks
    elif st == STATUS_SLIP or (
        st == STATUS_STICK
        and on_limit(f_n, f_1, f_2, mu, 0.0 if brk else cohesion, kn * params[F_TOUCH])
    ):
        st = STATUS_SLIP
        norm = np.hypot(f_1, f_2)
        # the direction of the trial slip: that of the force, also where the limit is zero
        w_1, w_2 = u_1 - slip[s, 0], u_2 - slip[s, 1]
        trial = ks * np.hypot(w_1, w_2)
        t1 = ks * w_1 / trial if trial > 0.0 else 0.0
        t2 = ks * w_2 / trial if trial > 0.0 else 0.0
        ratio = min(norm / trial, 1.0) if trial > 0.0 else 0.0
        d11 = ks * (ratio * (1.0 - t1 * t1) + floor)
        d22 = ks * (ratio * (1.0 - t2 * t2) + floor)
        d12 = -ks * ratio * t1 * t2
        # the Coulomb limit grows with compression: f_t = (c - mu f_n) t
        d1n = -mu * kn * t1
        d2n = -mu * kn * t2
    if is_crushed:
        # the normal force stays at the strength, and with it the friction limit
        dnn, d1n, d2n = floor * kn, 0.0, 0.0
    add_spring_tangent(y1, y2, dnn, d11, d22, d12, d1n, d2n, out_D)
    return st + (4 if is_crushed else 0)


@njit(cache=True)
def add_spring_tangent(y1, y2, dnn, d11, d22, d12, d1n, d2n, out_D):
    """Add ``B^T T B`` of a spring at ``(y1, y2)`` to the interface tangent ``out_D`` (6, 6).

    ``B`` maps ``q`` to ``(u_n, u_1, u_2)``: ``u_n = dn + phi1 y2 - phi2 y1``,
    ``u_1 = dt1 - phi3 y2``, ``u_2 = dt2 + phi3 y1``; ``T`` the spring tangent
    ``[[dnn, 0, 0], [d1n, d11, d12], [d2n, d12, d22]]`` (rows ``f_n, f_1, f_2``).
    """
    # columns of B that are nonzero: u_n at (0, 3, 4), u_1 at (1, 5), u_2 at (2, 5)
    bn_idx = (0, 3, 4)
    bn_val = (1.0, y2, -y1)
    b1_idx = (1, 5)
    b1_val = (1.0, -y2)
    b2_idx = (2, 5)
    b2_val = (1.0, y1)
    for i in range(3):
        for j in range(3):
            out_D[bn_idx[i], bn_idx[j]] += bn_val[i] * dnn * bn_val[j]
    for i in range(2):
        r1, v1 = b1_idx[i], b1_val[i]
        r2, v2 = b2_idx[i], b2_val[i]
        for j in range(2):
            out_D[r1, b1_idx[j]] += v1 * d11 * b1_val[j]
            out_D[r1, b2_idx[j]] += v1 * d12 * b2_val[j]
            out_D[r2, b1_idx[j]] += v2 * d12 * b1_val[j]
            out_D[r2, b2_idx[j]] += v2 * d22 * b2_val[j]
        for j in range(3):
            out_D[r1, bn_idx[j]] += v1 * d1n * bn_val[j]
            out_D[r2, bn_idx[j]] += v2 * d2n * bn_val[j]


@njit(cache=True, parallel=True)
def fibre_law(q, spring_ptr, springs, params, plastic, floor, trial, out_f, out_D):
    """Batch of :func:`fibre_law_one` over ``m`` interfaces (a ``prange`` loop).

    Parameters
    ----------
    q : (m, 6) float64
    spring_ptr : (m + 1,) int64
    springs : (n_springs, 3) float64
    params : (m, N_FIBRE_PARAMS) float64
    plastic : (slip (n_springs, 3) float64, is_broken (n_springs,) bool)
    floor : float
    trial : (out_slip (n_springs, 3) float64, out_broken (n_springs,) bool)
    out_f : (m, 6) float64
    out_D : (m, 6, 6) float64

    Returns
    -------
    state : (m,) int64
    """
    m = q.shape[0]
    state = np.empty(m, dtype=np.int64)
    for j in prange(m):
        state[j] = fibre_law_one(
            q[j],
            (spring_ptr[j], spring_ptr[j + 1]),
            springs,
            params[j],
            plastic,
            floor,
            trial,
            out_f[j],
            out_D[j],
        )
    return state
