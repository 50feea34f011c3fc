r"""Resultant interface law of seed 001 (Eqs. (8)-(14), (A5)): return mapping and tangent.

One interface carries the actions ``f = (N, V1, V2, M1, M2, M3)`` [N, N m] (``N > 0`` in
tension) conjugate to the relative motion ``q = (dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad]
of block b with respect to block a (see :mod:`dem.geometry.compatibility`). Elastically
``f = diag(k) (q - q_p)`` with ``k = (k_n A, k_t A, k_t A, k_r J_22, k_r J_11, k_t J_p)``.

The law, elastic-perfectly plastic with the seed's interactions:

- detachment (Eq. 8-9, 13): if ``N = k_0 dn > f_t`` all actions vanish; a mortared joint
  (``f_t > 0``) is then broken for good and behaves as a dry joint (``f_t = c = 0``);
- rocking (Eq. 9): ``-(f_t - N) l^-_i <= M_i <= (f_t - N) l^+_i`` for ``i = 1, 2``, where
  ``l^\pm`` are the distances from the interface centroid to the polygon's edges on the side
  of the hinge (``l_c1 = s/2``, ``l_c2 = b/4`` for a bed joint of seed 001);
- shear and torsion (Eq. 10, 12, 14, A5):
  ``(|M3| / M_{3u})^\alpha + (V_1^2 + V_2^2) / V_u^2 <= 1`` with ``V_u = c + \mu (-N)``
  (``c = \mu f_t`` in the seed) and ``M_{3u} = c_T V_u``, ``c_T`` the mean distance to the
  centroid of the compressed rectangle reduced by the eccentricities ``M/(f_t - N)``
  (Orduna & Lourenco's uniform-stress hypothesis, seed Fig. 10). The return puts the shear on
  the Coulomb circle first and then caps the torsion at what the shear leaves,
  ``M_{3u} (1 - V^2/V_u^2)^{1/\alpha}``: unlike a radial return it stays continuous when
  ``M_{3u} -> 0`` (a hinge on an edge keeps its friction); ``alpha`` is taken from Table A1
  at the interface's aspect ratio (seed Table A1, column ``f1 = f2``, the intermediate value the
  seed recommends for a single exponent).

An optional compressive strength ``f_c`` caps the normal force at ``-f_c A`` (crushing, with a
plastic closure kept in ``q_p[0]``) and takes the rectangular stress block of depth
``(f_t - N) / (f_c w)`` out of each rocking limit (``w`` the joint's width along the hinge):
``M <= (f_t - N) (l - (f_t - N) / (2 f_c w))``, the uniaxial form of the limit analysis' block.
Without it (``f_c = inf``) the normal response has no plastic part (a gap); plastic rotations
and slips are kept in ``q_p``. The tangent ``D = df/dq`` keeps the dependence of the rocking
and friction limits on the normal force (non-symmetric); yielded components keep ``floor``
times their elastic stiffness so that a stiffness matrix stays invertible away from true
mechanisms.

A component counts as yielding when its trial action reaches the limit to within a relative
``KINK_BAND``, not only when it exceeds it. After a plastic return the committed state lies
exactly on the limit, so at the start of the next load step the trial equals the limit up to
rounding; with a strict test about two thirds of the yielded joints of a wall were then taken
as elastic (seed 001 S11), the first Newton iterate of every step used their elastic stiffness,
overshot, and the iteration cycled between states until the path-following stalled. In the
band the action is the limit itself, so only the tangent changes: the one of continued plastic
flow, which the next iterate corrects if the joint unloads.
"""

import math

import numpy as np
from numba import njit

STATE_ELASTIC = 0
STATE_SHEAR = 1  # bit: sliding / torsion on the yield surface
STATE_FLEXURE = 2  # bit: rocking limit reached about t1 or t2
STATE_DETACHED = 4  # the whole interface is open (exclusive)
STATE_CRUSHED = 8  # bit: the compressive strength is reached
KINK_BAND = 1e-9  # relative band below a limit that already counts as yielding (module notes)

# columns of the per-interface parameter rows of the resultant law
P_K = 0  # 0:6  elastic stiffnesses (k_n A, k_t A, k_t A, k_r J22, k_r J11, k_t Jp)
P_LEVER = 6  # 6:10 rocking lever arms (l1+, l1-, l2+, l2-) [m]
P_FT = 10  # tensile strength force f_t A [N]
P_COHESION = 11  # cohesion force c A [N]
P_MU = 12  # friction coefficient [-]
P_DIMS = 13  # 13:15 extents (l1, l2) [m]
P_ALPHA = 15  # exponent of Eq. (A5) [-]
P_FC = 16  # compressive strength f_c [Pa]; inf for none
P_AREA = 17  # area A [m^2]
N_PARAMS = 18


@njit(cache=True)
def torsion_coefficient(l1, l2):
    """Mean distance ``c_T`` [m] of a ``l1 x l2`` rectangle's points to its centre.

    Closed form of ``(1/A) int sqrt(y1^2 + y2^2) dA``; a segment (one side 0) gives ``l / 4``,
    a point 0.
    """
    # a rectangle shrunk to a segment keeps the segment's mean distance l / 4
    if l1 <= 0.0 and l2 <= 0.0:
        return 0.0
    if l2 <= 1e-12 * l1:
        return 0.25 * l1
    if l1 <= 1e-12 * l2:
        return 0.25 * l2
    d = math.sqrt(l1 * l1 + l2 * l2)
    t1 = l1 * l1 / (2.0 * l2) * math.log((l2 + d) / l1)
    t2 = l2 * l2 / (2.0 * l1) * math.log((l1 + d) / l2)
    return (d + t1 + t2) / 6.0


@njit(cache=True)
def rocking_limit(cap, lever, f_c, width):
    """Rocking capacity ``cap (l - cap / (2 f_c w))`` [N m] and its derivative in ``cap`` [m].

    ``cap = f_t - N`` [N], ``lever`` the distance from the centroid to the hinge edge [m],
    ``f_c`` the compressive strength [Pa] (inf: a hinge on the edge), ``width`` [m] the joint
    along the hinge. The stress block is never deeper than twice the lever (the limit stays
    >= 0 and stops falling there).
    """
    if math.isinf(f_c) or width <= 0.0:
        return cap * lever, lever
    depth = cap / (f_c * width)
    if depth >= 2.0 * lever:
        return 0.0, 0.0
    return cap * (lever - 0.5 * depth), lever - depth


@njit(cache=True)
def resultant_law_one(q, qp, is_broken, params, floor, out_f, out_qp, out_D):
    """Return mapping of one interface (seed 001, Eqs. (8)-(14), (A5)).

    Parameters
    ----------
    q : (6,) float64
        Total relative motion ``(dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad].
    qp : (6,) float64
        Plastic part at the last converged state (``qp[0]`` the crushing closure) [m, rad].
    is_broken : bool
        Tensile strength and cohesion already lost.
    params : (N_PARAMS,) float64
        The interface's parameters, columns ``P_*``: elastic stiffnesses
        ``(k_n A, k_t A, k_t A, k_r J22, k_r J11, k_t Jp)`` [N/m, N m/rad]; rocking lever arms
        ``(l1+, l1-, l2+, l2-)`` for ``M1 > 0``, ``M1 < 0``, ``M2 > 0``, ``M2 < 0`` [m];
        tensile strength and cohesion forces ``sigma_t A``, ``c A`` [N]; friction coefficient
        [-]; extents ``(l1, l2)`` along ``t1, t2`` [m]; exponent of Eq. (A5) [-];
        compressive strength [Pa] (inf for none); area [m^2].
    floor : float
        Fraction of the elastic stiffness kept by yielded components of the tangent [-].
    out_f : (6,) float64
        Output actions ``(N, V1, V2, M1, M2, M3)`` [N, N m].
    out_qp : (6,) float64
        Output plastic motion.
    out_D : (6, 6) float64
        Output tangent ``df/dq``.

    Returns
    -------
    is_broken : bool
    state : int
        Bit set of ``STATE_SHEAR``, ``STATE_FLEXURE``, ``STATE_CRUSHED``, or
        ``STATE_DETACHED``.
    """
    k = params[P_K : P_K + 6]
    ft = params[P_FT]
    c = params[P_COHESION]
    if is_broken:
        ft = 0.0
        c = 0.0
    out_D[:, :] = 0.0
    if k[0] * (q[0] - qp[0]) > ft:
        # detachment (Eq. 13): no action; the slips follow the motion so that re-contact
        # starts unloaded
        for i in range(6):
            out_f[i] = 0.0
            out_qp[i] = q[i]
            out_D[i, i] = floor * k[i]
        out_qp[0] = qp[0]
        return is_broken or params[P_FT] > 0.0, STATE_DETACHED
    state = normal_and_rocking(q, qp, params, ft, floor, out_f, out_qp, out_D)
    state |= shear_and_torsion(q, qp, params, c, ft - out_f[0], floor, out_f, out_qp, out_D)
    return is_broken, state


@njit(cache=True)
def normal_and_rocking(q, qp, params, ft, floor, out_f, out_qp, out_D):
    """Normal force (with crushing) and rocking moments of a closed joint, Eq. (9).

    Arguments as :func:`resultant_law_one`, ``ft`` the tensile strength force in effect [N].
    Writes rows 0, 3 and 4 of ``out_f``, ``out_qp``, ``out_D``; returns the state bits.
    """
    k = params[P_K : P_K + 6]
    lever = params[P_LEVER : P_LEVER + 4]
    dims = params[P_DIMS : P_DIMS + 2]
    f_c = params[P_FC]
    state = STATE_ELASTIC
    n_force = k[0] * (q[0] - qp[0])
    dn_dq0 = k[0]  # d N / d dn
    out_qp[0] = qp[0]
    n_crush = -f_c * params[P_AREA]
    if n_force < n_crush * (1.0 - KINK_BAND):
        # crushing: the normal force stays at the strength, the closure is plastic
        n_force = n_crush
        out_qp[0] = q[0] - n_crush / k[0]
        dn_dq0 = floor * k[0]
        state |= STATE_CRUSHED
    out_f[0] = n_force
    out_D[0, 0] = dn_dq0
    cap = ft - n_force  # >= 0
    # rocking about t1 (M1, lever along y2, hinge along y1) and t2 (M2)
    for j in range(2):
        i = 3 + j
        m_trial = k[i] * (q[i] - qp[i])
        width = dims[0] if j == 0 else dims[1]
        hi, dhi = rocking_limit(cap, lever[2 * j], f_c, width)
        lo, dlo = rocking_limit(cap, lever[2 * j + 1], f_c, width)
        lo = -lo
        if m_trial > hi - KINK_BAND * abs(hi):
            out_f[i] = hi
            out_qp[i] = q[i] - hi / k[i]
            out_D[i, i] = floor * k[i]
            out_D[i, 0] = -dn_dq0 * dhi
            state |= STATE_FLEXURE
        elif m_trial < lo + KINK_BAND * abs(lo):
            out_f[i] = lo
            out_qp[i] = q[i] - lo / k[i]
            out_D[i, i] = floor * k[i]
            out_D[i, 0] = dn_dq0 * dlo
            state |= STATE_FLEXURE
        else:
            out_f[i] = m_trial
            out_qp[i] = qp[i]
            out_D[i, i] = k[i]
    return state


@njit(cache=True)
def shear_and_torsion(q, qp, params, c, cap, floor, out_f, out_qp, out_D):
    """Shear and torsion of a closed joint, Eqs. (10), (12), (14), (A5).

    Arguments as :func:`resultant_law_one`; ``c`` the cohesion force in effect and
    ``cap = f_t - N`` [N]. Needs rows 0, 3, 4 of ``out_f`` and ``out_D``
    (:func:`normal_and_rocking`); writes rows 1, 2, 5; returns the state bits.
    """
    k = params[P_K : P_K + 6]
    v1 = k[1] * (q[1] - qp[1])
    v2 = k[2] * (q[2] - qp[2])
    m3 = k[5] * (q[5] - qp[5])
    v_u = c - params[P_MU] * out_f[0]
    if v_u <= 0.0:
        # no friction capacity; an unloaded joint (a dry joint at N = 0) keeps its elastic
        # tangent, so that the first iteration from the unloaded state sees it
        unloaded = v1 == 0.0 and v2 == 0.0 and m3 == 0.0
        for i in (1, 2, 5):
            out_f[i] = 0.0
            out_qp[i] = qp[i] if unloaded else q[i]
            out_D[i, i] = k[i] if unloaded else floor * k[i]
        return STATE_ELASTIC if unloaded else STATE_SHEAR
    # shear first, then torsion (Eq. 14 / A5 read as the torsion left by the shear):
    # V on the Coulomb circle if the trial exceeds it, then |M3| <= M_u (1 - |V|^2/V_u^2)^(1/a).
    # Continuous as M_u -> 0 (a hinge on an edge keeps its friction, loses its torsion).
    vt = math.sqrt(v1 * v1 + v2 * v2)
    dvu0 = -params[P_MU] * out_D[0, 0]  # d V_u / d dn
    if vt > v_u * (1.0 - KINK_BAND):
        n1 = v1 / vt
        n2 = v2 / vt
        ratio = v_u / vt
        out_f[1] = v_u * n1
        out_f[2] = v_u * n2
        # d V / d q: (V_u/|v|)(I - n n^T) k_t on the tangential motions, n dV_u/d dn
        out_D[1, 1] = ratio * (1.0 - n1 * n1) * k[1] + floor * k[1]
        out_D[1, 2] = -ratio * n1 * n2 * k[2]
        out_D[2, 1] = -ratio * n1 * n2 * k[1]
        out_D[2, 2] = ratio * (1.0 - n2 * n2) * k[2] + floor * k[2]
        out_D[1, 0] = n1 * dvu0
        out_D[2, 0] = n2 * dvu0
        out_qp[1] = q[1] - out_f[1] / k[1]
        out_qp[2] = q[2] - out_f[2] / k[2]
        out_f[5] = 0.0
        out_qp[5] = q[5]
        out_D[5, 5] = floor * k[5]
        return STATE_SHEAR
    out_f[1] = v1
    out_f[2] = v2
    out_qp[1] = qp[1]
    out_qp[2] = qp[2]
    out_D[1, 1] = k[1]
    out_D[2, 2] = k[2]
    return torsion(q, qp, params, v_u, cap, floor, out_f, out_qp, out_D)


@njit(cache=True)
def torsion(q, qp, params, v_u, cap, floor, out_f, out_qp, out_D):
    """Torsion left by an elastic shear: ``|M3| <= M_u (1 - |V|^2 / V_u^2)^(1/alpha)`` with
    ``M_u = c_T V_u`` on the compressed rectangle reduced by the eccentricities (uniform
    stress, seed Fig. 10). Writes row 5; returns the state bits."""
    k = params[P_K : P_K + 6]
    dims = params[P_DIMS : P_DIMS + 2]
    alpha = params[P_ALPHA]
    m3 = k[5] * (q[5] - qp[5])
    r1 = max(dims[0] - 2.0 * (abs(out_f[4]) / cap if cap > 0.0 else 0.0), 0.0)
    r2 = max(dims[1] - 2.0 * (abs(out_f[3]) / cap if cap > 0.0 else 0.0), 0.0)
    c_t = torsion_coefficient(r1, r2)
    m_u = c_t * v_u
    b = (out_f[1] ** 2 + out_f[2] ** 2) / (v_u * v_u)
    left = (1.0 - b) ** (1.0 / alpha) if b < 1.0 else 0.0
    m_max = m_u * left
    if abs(m3) < m_max * (1.0 - KINK_BAND):
        out_f[5] = m3
        out_qp[5] = qp[5]
        out_D[5, 5] = k[5]
        return STATE_ELASTIC
    sg = 1.0 if m3 >= 0.0 else -1.0
    out_f[5] = sg * m_max
    out_qp[5] = q[5] - out_f[5] / k[5]
    out_D[5, 5] = floor * k[5]
    if m_max <= 0.0:
        return STATE_SHEAR
    # tangent of M3 = sg M_u(q) (1 - b(q))^(1/alpha), b = |V|^2 / V_u^2 with V elastic
    dvu0 = -params[P_MU] * out_D[0, 0]
    dleft_db = -(1.0 / alpha) * (1.0 - b) ** (1.0 / alpha - 1.0)
    db = np.zeros(6)
    db[1] = 2.0 * out_f[1] * k[1] / (v_u * v_u)
    db[2] = 2.0 * out_f[2] * k[2] / (v_u * v_u)
    db[0] = -2.0 * b / v_u * dvu0
    dmu = np.zeros(6)
    torsion_capacity_gradient(dims, cap, r1, r2, v_u, out_f, out_D, dmu)
    dmu[0] += c_t * dvu0
    for j in range(6):
        out_D[5, j] += sg * (left * dmu[j] + m_u * dleft_db * db[j])
    return STATE_SHEAR


@njit(cache=True)
def torsion_capacity_gradient(dims, cap, r1, r2, v_u, f, D, out):
    """``V_u d c_T / d q`` through the eccentricities ``e1 = |M2| / cap``, ``e2 = |M1| / cap``
    of the reduced rectangle ``(r1, r2) = dims - 2 e`` (central differences of
    :func:`torsion_coefficient`); adds into ``out`` (6,)."""
    if cap <= 0.0:
        return
    h = 1e-6 * (dims[0] + dims[1])
    dc1 = 0.0
    dc2 = 0.0
    if r1 > 0.0:
        lo1 = max(r1 - h, 0.0)
        dc1 = (torsion_coefficient(r1 + h, r2) - torsion_coefficient(lo1, r2)) / (r1 + h - lo1)
    if r2 > 0.0:
        lo2 = max(r2 - h, 0.0)
        dc2 = (torsion_coefficient(r1, r2 + h) - torsion_coefficient(r1, lo2)) / (r2 + h - lo2)
    sg4 = 1.0 if f[4] >= 0.0 else -1.0
    sg3 = 1.0 if f[3] >= 0.0 else -1.0
    for j in range(6):
        de1 = sg4 * D[4, j] / cap
        de2 = sg3 * D[3, j] / cap
        if j == 0:  # cap = f_t - N
            de1 += abs(f[4]) * D[0, 0] / (cap * cap)
            de2 += abs(f[3]) * D[0, 0] / (cap * cap)
        out[j] -= v_u * 2.0 * (dc1 * de1 + dc2 * de2)


@njit(cache=True)
def resultant_law(q, qp, is_broken, params, floor, out_f, out_qp, out_broken, out_state, out_D):
    """Batch of :func:`resultant_law_one` over ``m`` interfaces.

    Parameters
    ----------
    q, qp : (m, 6) float64
    is_broken : (m,) bool
    params : (m, N_PARAMS) float64
        One row per interface (see :func:`resultant_law_one`).
    floor : float
    out_f, out_qp : (m, 6) float64
    out_broken : (m,) bool
    out_state : (m,) int64
    out_D : (m, 6, 6) float64
    """
    for j in range(q.shape[0]):
        brk, st = resultant_law_one(
            q[j], qp[j], is_broken[j], params[j], floor, out_f[j], out_qp[j], out_D[j]
        )
        out_broken[j] = brk
        out_state[j] = st
