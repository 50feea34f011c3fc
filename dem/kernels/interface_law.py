r"""Resultant interface law of seed 001 (Eqs. (8)-(14), (A5)): return mapping and tangent.

One interface carries the actions ``f = (N, V1, V2, M1, M2, M3)`` [N, N m] (``N > 0`` in
tension) conjugate to the relative motion ``q = (dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad]
of block b with respect to block a (see :mod:`dem.geometry.compatibility`).

- normal force and bending (Eqs. 8-9): the resultants of the joint's normal stress
  ``k_n dn + k_r (phi1 y2 - phi2 y1)`` capped by the tensile strength (0: the joint opens)
  and the compressive strength ``f_c``, integrated exactly over the joint polygon
  (:mod:`dem.kernels.contact_stress`). The limits are the seed's,
  ``|M_i| <= (f_t - N) l_i`` with ``l_i`` the distance to the hinge edge, reached as the
  compressed part shrinks to that edge; on the way the joint opens progressively and, rocking
  about an edge, lifts at its centroid, as rigid blocks do (where that lift is confined the
  assembly arches). Seed 001's Eq. (13) (elastic up to the limit, then ``k_r = 0``) let the
  joint turn about its centroid with no lift: a restrained 3 x 13 dry panel collapsed at a
  fifth of the fibre law's and the explicit DEM's load. A joint open over its whole area is
  detached (Eq. 13): no action. No memory: a dry joint recloses elastically.
- bond: a mortared joint (``f_t > 0`` or ``c > 0``) cracks when its tensile cap covers half
  its area (``STATE_FLEXURE``: it rocks; at ``N = 0`` that is 2/3 of Eq. 9's limit, twice
  the elastic cracking moment) or the whole of it. Its tensile strength and cohesion are then
  lost for good, in the trial that cracks it already (the dry joint's response at the same
  motion, like the fibre law's brittle springs), and it behaves as a dry no-tension Coulomb
  joint from then on. Held at the cap for ever (the seed's perfectly plastic Eq. 9), a
  rocking mortared joint hardened towards the uniform tensile block without end: 4 of seed
  001's 6 Chee Liang walls rose at 0.04-0.26 % of their initial slope after 400 steps.
- shear and torsion (Eqs. 10, 12, 14, A5): elastic ``V = k_t A w``, ``M3' = k_t J_p theta``
  with ``w`` the elastic slip at the centre of compression ``y_c`` (where ``N`` acts) and
  ``theta`` the elastic twist, within
  ``(|M3'| / M_{3u})^\alpha + (V_1^2 + V_2^2) / V_u^2 <= 1``, ``V_u = c + \mu (-N)``
  (``c = \mu f_t`` in the seed), ``M_{3u} = c_T V_u``, ``c_T`` the mean distance to ``y_c`` of
  the compressed rectangle reduced by the eccentricities (Orduna & Lourenco's uniform-stress
  hypothesis, seed Fig. 10); ``alpha`` from Table A1 at the interface's aspect ratio (column
  ``f1 = f2``). The torsion is taken about ``y_c``, where the reduced rectangle is centred:
  about the centroid, a joint hinged on an edge and sliding had its friction off the contact
  (``M3 = 0`` instead of ``y_c x V``). A trial outside returns to the nearest point
  (:mod:`dem.kernels.shear_torsion_return`); the slip and twist are kept in ``q_p`` (at the
  centroid), and ``M3 = M3' + y_c x V``.

The tangent ``D = df/dq`` is consistent (non-symmetric: the friction limits and the centre of
compression move with ``N, M1, M2``); yielded components keep ``floor`` times their elastic
stiffness, a fully open joint ``floor`` times all of them, so that a stiffness matrix stays
invertible away from true mechanisms.

A shear-torsion state counts as yielding when its trial reaches the limit to within a relative
``KINK_BAND``, not only when it exceeds it. After a plastic return the committed state lies
exactly on the limit, so at the start of the next load step the trial equals the limit up to
rounding; with a strict test about two thirds of the yielded joints of a wall were then taken
as elastic (seed 001 S11), the first Newton iterate of every step used their elastic stiffness,
overshot, and the iteration cycled between states until the path-following stalled. In the
band the action is the limit itself, so only the tangent changes: the one of continued plastic
flow, which the next iterate corrects if the joint unloads.

Ties at zero gaps are decided the same way whatever the round-off, with the touching gap
``touch`` = ``TOUCH`` (1e-12) times the model's extent (a parameter column), as in the fibre
law (:mod:`dem.kernels.fibre_law`): a point of the joint opens only beyond it (its trial
stress above the cap by ``k_n touch``), a normal force within ``k_n touch A`` gives no
friction and no centre of compression, and a dry joint whose elastic slip and twist stay
below it is unloaded (elastic tangent). After the dead load of seed 001 S13 and S5 (return
walls of blocks) 75 joints carried nothing, their relative motions of round-off size
(1e-20 m): their states and tangents differed between OpenBLAS kernels (up to half the
largest entry), and with them the first live step (0.4 % on S13).
"""

import math

import numpy as np
from numba import njit, prange

from dem.kernels import friction_domain
from dem.kernels.contact_stress import MAX_VERTICES, stress_resultants
from dem.kernels.shear_torsion_return import nearest_on_boundary

STATE_ELASTIC = 0
STATE_SHEAR = 1  # bit: sliding / torsion on the yield surface
STATE_FLEXURE = 2  # bit: at least half of the joint open (rocking)
STATE_DETACHED = 4  # the whole interface is open (exclusive)
STATE_CRUSHED = 8  # bit: the compressive strength is reached
KINK_BAND = 1e-9  # relative band below a limit that already counts as yielding (module notes)
OPEN_BAND = 1e-12  # relative open area above which a joint counts as detached
TOUCH = 1e-12  # gaps below this fraction of the model's extent count as touching (notes)

# columns of the per-interface parameter rows of the resultant law
P_K = 0  # 0:6  elastic stiffnesses (k_n A, k_t A, k_t A, k_r J22, k_r J11, k_t Jp)
P_FT = 6  # tensile strength force f_t A [N]
P_COHESION = 7  # cohesion force c A [N]
P_MU = 8  # friction coefficient [-]
P_DIMS = 9  # 9:11 extents (l1, l2) [m]
P_ALPHA = 11  # exponent of Eq. (A5) [-]
P_FC = 12  # compressive strength f_c [Pa]; inf for none
P_AREA = 13  # area A [m^2]
P_STIFF = 14  # 14:16 (k_n, k_r) per unit area [Pa/m]
P_TOUCH = 16  # gap up to which a joint counts as touching [m] (module notes)
P_DOMAIN = 17  # shear-torsion domain: DOMAIN_EQ_A5 or DOMAIN_EXACT
P_N_CORNERS = 18  # corners of the joint polygon
P_POLY = 19  # 19:19 + 2 MAX_VERTICES corners (y1, y2) about the centroid, CCW [m]
N_PARAMS = P_POLY + 2 * MAX_VERTICES
NORMAL_ROWS = (0, 3, 4)  # the components (dn, phi1, phi2) the normal force depends on
DOMAIN_EQ_A5 = 0  # seed 001's Eq. (A5) on the reduced rectangle
DOMAIN_EXACT = 1  # the joint's own domain (dem.kernels.friction_domain)


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
def resultant_law_one(q, qp, is_broken, params, floor, out_f, out_qp, out_D):
    """Return mapping of one interface (seed 001, Eqs. (8)-(14), (A5)).

    Parameters
    ----------
    q : (6,) float64
        Total relative motion ``(dn, dt1, dt2, phi1, phi2, phi3)`` [m, rad].
    qp : (6,) float64
        Plastic part at the last converged state: slips ``qp[1:3]`` and twist ``qp[5]`` at the
        centroid (``qp[0], qp[3], qp[4]`` unused, 0) [m, rad].
    is_broken : bool
        Tensile strength and cohesion already lost (the joint cracked earlier).
    params : (N_PARAMS,) float64
        The interface's parameters, columns ``P_*``: elastic stiffnesses
        ``(k_n A, k_t A, k_t A, k_r J22, k_r J11, k_t Jp)`` [N/m, N m/rad]; tensile strength
        and cohesion forces ``sigma_t A``, ``c A`` [N]; friction coefficient [-]; extents
        ``(l1, l2)`` along ``t1, t2`` [m]; exponent of Eq. (A5) [-]; compressive strength [Pa]
        (inf for none); area [m^2]; ``(k_n, k_r)`` per unit area [Pa/m]; the touching gap
        [m]; the number of corners and the corners ``(y1, y2)`` of the joint polygon about its
        centroid, CCW [m].
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
        Whether the bond is lost: before, or cracked by this motion (module notes).
    state : int
        Bit set of ``STATE_SHEAR``, ``STATE_FLEXURE``, ``STATE_CRUSHED``, or
        ``STATE_DETACHED``.
    """
    k = params[P_K : P_K + 6]
    bonded = not is_broken and (params[P_FT] > 0.0 or params[P_COHESION] > 0.0)
    ft = params[P_FT] if bonded else 0.0
    c = params[P_COHESION] if bonded else 0.0
    out_D[:, :] = 0.0
    state = normal_and_rocking(q, qp, params, ft, floor, out_f, out_qp, out_D)
    if bonded and state & (STATE_FLEXURE | STATE_DETACHED):
        # cracked (module notes): the bond is lost for good, the dry joint answers already
        is_broken = True
        ft = c = 0.0
        out_D[:, :] = 0.0
        state = normal_and_rocking(q, qp, params, ft, floor, out_f, out_qp, out_D)
    if state == STATE_DETACHED:
        # detachment (Eq. 13): no action; the slips follow the motion so that re-contact
        # starts unloaded
        for i in (1, 2, 5):
            out_f[i] = 0.0
            out_qp[i] = q[i]
            out_D[i, i] = floor * k[i]
        return is_broken, STATE_DETACHED
    state |= shear_and_torsion(q, qp, params, c, ft - out_f[0], floor, out_f, out_qp, out_D)
    return is_broken, state


@njit(cache=True)
def normal_and_rocking(q, qp, params, ft, floor, out_f, out_qp, out_D):
    """Normal force and bending moments, Eq. (9), from the capped stress field of the joint
    (:mod:`dem.kernels.contact_stress`).

    Arguments as :func:`resultant_law_one`, ``ft`` the tensile strength force in effect [N].
    Writes rows 0, 3 and 4 of ``out_f``, ``out_qp`` (0: no memory), ``out_D``; returns the
    state bits: ``STATE_DETACHED`` alone when the whole joint is at its tensile cap,
    ``STATE_FLEXURE`` when at least half of it is, ``STATE_CRUSHED`` when a part is at
    ``f_c``.
    """
    k = params[P_K : P_K + 6]
    area = params[P_AREA]
    n = int(params[P_N_CORNERS])
    poly = params[P_POLY : P_POLY + 2 * n].reshape((n, 2))
    f3 = np.empty(3)
    D3 = np.empty((3, 3))
    strength = np.array((ft / area, params[P_FC], params[P_STIFF] * params[P_TOUCH]))
    area_t, area_c = stress_resultants(
        np.array((q[0], q[3], q[4])), poly, n, params[P_STIFF : P_STIFF + 2], strength, f3, D3
    )
    for i in range(3):
        out_qp[NORMAL_ROWS[i]] = 0.0
        out_f[NORMAL_ROWS[i]] = f3[i]
        for j in range(3):
            out_D[NORMAL_ROWS[i], NORMAL_ROWS[j]] = D3[i, j]
    if area_t >= area * (1.0 - OPEN_BAND):
        for i in NORMAL_ROWS:
            out_f[i] = 0.0
            out_D[i, i] = floor * k[i]
        return STATE_DETACHED
    state = STATE_ELASTIC
    if area_t >= 0.5 * area:
        state |= STATE_FLEXURE
    if area_c > 0.0:
        state |= STATE_CRUSHED
    # the exact tangent is regular while a part of the joint is in contact; the floor only
    # keeps a sliver of contact (or a crushed joint) from making it singular
    for i in NORMAL_ROWS:
        out_D[i, i] = max(out_D[i, i], floor * k[i])
    return state


@njit(cache=True)
def shear_and_torsion(q, qp, params, c, cap, floor, out_f, out_qp, out_D):
    """Shear and torsion of a closed joint, Eqs. (10), (12), (14), (A5), about the centre of
    compression (module notes).

    Arguments as :func:`resultant_law_one`; ``c`` the cohesion force in effect and
    ``cap = f_t - N`` [N]. Needs rows 0, 3, 4 of ``out_f`` and ``out_D``
    (:func:`normal_and_rocking`); writes rows 1, 2, 5; returns the state bits.
    """
    k = params[P_K : P_K + 6]
    touch = params[P_TOUCH]
    touch_force = params[P_STIFF] * touch * params[P_AREA]  # N of the touching gap
    centre, d_centre = np.zeros(2), np.zeros((2, 6))
    compression_centre(out_f, out_D, cap, touch_force, centre, d_centre)
    # elastic slip at the centre and twist: V = k_t A w, M3' = k_t J_p theta
    theta = q[5] - qp[5]
    dv = np.zeros((2, 6))  # d V_trial / d q
    v1 = k[1] * (q[1] - qp[1] - theta * centre[1])
    v2 = k[2] * (q[2] - qp[2] + theta * centre[0])
    dv[0, 1], dv[0, 5] = k[1], -k[1] * centre[1]
    dv[1, 2], dv[1, 5] = k[2], k[2] * centre[0]
    for j in range(6):
        dv[0, j] -= k[1] * theta * d_centre[1, j]
        dv[1, j] += k[2] * theta * d_centre[0, j]
    m_t = k[5] * theta
    # a touching joint (|N| within the touching gap's force) takes no friction from N
    v_u = c - params[P_MU] * out_f[0] if abs(out_f[0]) > touch_force else c
    dims = params[P_DIMS : P_DIMS + 2]
    if v_u <= 0.0:
        # no friction capacity; an unloaded joint (a dry joint at N = 0, its elastic slip and
        # twist below the touching gap) keeps its elastic tangent, so that the first
        # iteration from the unloaded state sees it
        unloaded = (
            math.hypot(v1, v2) <= k[1] * touch and abs(theta) * max(dims[0], dims[1]) <= touch
        )
        for i in (1, 2, 5):
            out_f[i] = 0.0
            out_qp[i] = qp[i] if unloaded else q[i]
            out_D[i, i] = k[i] if unloaded else floor * k[i]
        return STATE_ELASTIC if unloaded else STATE_SHEAR
    out_f[1], out_f[2], out_f[5] = v1, v2, m_t
    if params[P_DOMAIN] == DOMAIN_EXACT:
        mu = params[P_MU] if abs(out_f[0]) > touch_force else 0.0
        plastic = exact_flow(q, params, (c, mu), cap, centre, d_centre, dv, floor, out_f, out_D)
    else:
        plastic = eq_a5_flow(params, v_u, cap, centre, dv, floor, out_f, out_D)
    if plastic:
        state = STATE_SHEAR
    else:
        for i in (1, 2, 5):
            out_qp[i] = qp[i]
        out_D[1, :], out_D[2, :] = dv[0], dv[1]
        out_D[5, 5] = k[5]
        state = STATE_ELASTIC
    # back to the centroid: M3 = M3' + y_c x V; the elastic slip at the centroid
    out_f[5] += centre[0] * out_f[2] - centre[1] * out_f[1]
    for j in range(6):
        out_D[5, j] += d_centre[0, j] * out_f[2] + centre[0] * out_D[2, j]
        out_D[5, j] -= d_centre[1, j] * out_f[1] + centre[1] * out_D[1, j]
    if state == STATE_SHEAR:
        twist = (out_f[5] - centre[0] * out_f[2] + centre[1] * out_f[1]) / k[5]
        out_qp[1] = q[1] - out_f[1] / k[1] - twist * centre[1]
        out_qp[2] = q[2] - out_f[2] / k[2] + twist * centre[0]
        out_qp[5] = q[5] - twist
    return state


@njit(cache=True)
def eq_a5_flow(params, v_u, cap, centre, dv, floor, out_f, out_D):
    """Yield test and return on seed 001's domain, Eq. (A5) with ``c_T`` of the reduced
    rectangle (module notes). Rows 1, 2, 5 of ``out_f`` hold the trial ``(V1, V2, M3')``
    about the centre of compression ``centre``; a yielded trial is returned in place with its
    tangent (:func:`shear_torsion_flow`). Returns whether it yielded."""
    dims = params[P_DIMS : P_DIMS + 2]
    reduced = (max(dims[0] - 2.0 * abs(centre[0]), 0.0), max(dims[1] - 2.0 * abs(centre[1]), 0.0))
    m_u = torsion_coefficient(reduced[0], reduced[1]) * v_u
    v1, v2, m_t = out_f[1], out_f[2], out_f[5]
    g = (v1 * v1 + v2 * v2) / (v_u * v_u)
    if m_u > 0.0:
        g += (abs(m_t) / m_u) ** params[P_ALPHA]
    elif m_t != 0.0:
        g = math.inf
    if g < 1.0 - KINK_BAND:
        return False
    shear_torsion_flow(params, v_u, cap, reduced, dv, floor, out_f, out_D)
    return True


@njit(cache=True)
def exact_flow(q, params, friction, cap, centre, d_centre, dv, floor, out_f, out_D):
    """Yield test and return on the joint's exact domain (:mod:`dem.kernels.friction_domain`)
    under its capped stress field, with the same contract as :func:`eq_a5_flow`;
    ``friction`` the cohesion force in effect [N] and the friction coefficient in effect.

    The tangent adds to the trial's the change of the domain with the normal motion (its
    capacity ``c - mu sigma`` on the linear part) and with the centre of compression.
    """
    k = params[P_K : P_K + 6]
    area = params[P_AREA]
    kn, kr = params[P_STIFF], params[P_STIFF + 1]
    mu = friction[1]
    n = int(params[P_N_CORNERS])
    poly = params[P_POLY : P_POLY + 2 * n].reshape((n, 2))
    # sigma(y) = a + b1 y1 + b2 y2 (dem.kernels.contact_stress)
    sigma = np.array((kn * q[0], -kr * q[4], kr * q[3]))
    strength = np.array(((cap + out_f[0]) / area, params[P_FC]))
    regions = np.zeros((3, friction_domain.MAX_REGION, 2))
    beta = np.zeros((3, 3))
    counts = friction_domain.capacity_regions(
        poly, n, sigma, strength, np.array((friction[0] / area, mu)), centre, regions, beta
    )
    s, A, B, G = np.empty(3), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 5))
    trial = np.array((out_f[1], out_f[2], out_f[5]))
    C = np.array((k[1], k[2], k[5]))
    if not friction_domain.project(trial, C, regions, counts, beta, KINK_BAND, s, A, B, G):
        return False
    # d (trial) / d q and d g / d q at the fixed slip: capacity beta (about the centre), centre
    dtrial = np.zeros((3, 6))
    dtrial[0], dtrial[1] = dv[0], dv[1]
    dtrial[2, 5] = k[5]
    dbeta = np.zeros((5, 6))
    dbeta[0, 0] = -mu * kn
    dbeta[0, 4] = mu * kr * centre[0]
    dbeta[0, 3] = -mu * kr * centre[1]
    dbeta[1, 4] = mu * kr
    dbeta[2, 3] = -mu * kr
    dbeta[3], dbeta[4] = d_centre[0], d_centre[1]
    rows = A @ dtrial + B @ (G @ dbeta)
    out_D[1, :], out_D[2, :], out_D[5, :] = rows[0], rows[1], rows[2]
    out_f[1], out_f[2], out_f[5] = s[0], s[1], s[2]
    for i in (1, 2, 5):
        out_D[i, i] += floor * k[i]
    return True


@njit(cache=True)
def compression_centre(f, D, cap, touch_force, out, out_d):
    """Centre of compression ``y_c = (M2, -M1) / cap`` [m] (where the compressive resultant
    ``cap = f_t - N`` acts; 0 for ``cap <= touch_force``, a joint barely touching) into ``out``
    (2,), and ``d y_c / d q`` from rows 0, 3, 4 of ``D`` into ``out_d`` (2, 6)."""
    if cap <= touch_force:
        return
    out[0], out[1] = f[4] / cap, -f[3] / cap
    for j in range(6):
        # cap = f_t - N, so d cap = -D[0, j]
        out_d[0, j] = D[4, j] / cap + f[4] * D[0, j] / (cap * cap)
        out_d[1, j] = -D[3, j] / cap - f[3] * D[0, j] / (cap * cap)


@njit(cache=True)
def shear_torsion_flow(params, v_u, cap, reduced, dv, floor, out_f, out_D):
    """Return of a trial ``(V, M3')`` outside the domain of Eq. (A5)
    (:mod:`dem.kernels.shear_torsion_return`) and its tangent, on rows 1, 2, 5.

    ``reduced`` the sides of the compressed rectangle [m]; ``dv`` (2, 6) the derivative of
    the trial shear; rows 1, 2, 5 of ``out_f`` hold the trial ``(V1, V2, M3')``.
    """
    k = params[P_K : P_K + 6]
    c_t = torsion_coefficient(reduced[0], reduced[1])
    v_t = math.hypot(out_f[1], out_f[2])
    n1, n2 = (out_f[1] / v_t, out_f[2] / v_t) if v_t > 0.0 else (0.0, 0.0)
    s = 1.0 if out_f[5] >= 0.0 else -1.0
    # d (v_t, |M3'_t|, V_u, M_u) / d q
    dp = np.zeros((4, 6))
    for j in range(6):
        dp[0, j] = n1 * dv[0, j] + n2 * dv[1, j]
        dp[2, j] = -params[P_MU] * out_D[0, j]
    dp[1, 5] = s * k[5]
    torsion_capacity_gradient(params[P_DIMS : P_DIMS + 2], cap, reduced, v_u, out_f, out_D, dp[3])
    for j in range(6):
        dp[3, j] += c_t * dp[2, j]
    sol = np.empty(10)
    nearest_on_boundary(v_t, abs(out_f[5]), v_u, c_t * v_u, params[P_ALPHA], k[1], k[5], sol)
    ratio = sol[0] / v_t if v_t > 0.0 else sol[2]
    for j in range(6):
        d_len = sol[2] * dp[0, j] + sol[3] * dp[1, j] + sol[4] * dp[2, j] + sol[5] * dp[3, j]
        d_m = sol[6] * dp[0, j] + sol[7] * dp[1, j] + sol[8] * dp[2, j] + sol[9] * dp[3, j]
        # V = v n: the direction turns with the trial, the length follows v
        along = n1 * dv[0, j] + n2 * dv[1, j]
        out_D[1, j] = ratio * (dv[0, j] - n1 * along) + n1 * d_len
        out_D[2, j] = ratio * (dv[1, j] - n2 * along) + n2 * d_len
        out_D[5, j] = s * d_m
    if v_t == 0.0:
        for j in range(6):
            out_D[1, j], out_D[2, j] = ratio * dv[0, j], ratio * dv[1, j]
    out_f[1], out_f[2], out_f[5] = sol[0] * n1, sol[0] * n2, s * sol[1]
    for i in (1, 2, 5):
        out_D[i, i] += floor * k[i]


@njit(cache=True)
def torsion_capacity_gradient(dims, cap, reduced, v_u, f, D, out):
    """``V_u d c_T / d q`` through the eccentricities ``e1 = |M2| / cap``, ``e2 = |M1| / cap``
    of the reduced rectangle ``(r1, r2) = dims - 2 e`` (central differences of
    :func:`torsion_coefficient`); adds into ``out`` (6,)."""
    if cap <= 0.0:
        return
    r1, r2 = reduced[0], reduced[1]
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
        # e = |M| / cap with cap = f_t - N
        de1 = sg4 * D[4, j] / cap + abs(f[4]) * D[0, j] / (cap * cap)
        de2 = sg3 * D[3, j] / cap + abs(f[3]) * D[0, j] / (cap * cap)
        out[j] -= v_u * 2.0 * (dc1 * de1 + dc2 * de2)


@njit(cache=True, parallel=True)
def resultant_law(q, plastic, params, floor, trial, out_state, out_f, out_D):
    """Batch of :func:`resultant_law_one` over ``m`` interfaces (a ``prange`` loop).

    Parameters
    ----------
    q : (m, 6) float64
    plastic : (qp (m, 6) float64, is_broken (m,) bool)
        The committed state.
    params : (m, N_PARAMS) float64
        One row per interface (see :func:`resultant_law_one`).
    floor : float
    trial : (out_qp (m, 6) float64, out_broken (m,) bool)
        Output plastic state of the trial.
    out_state : (m,) int64
    out_f : (m, 6) float64
    out_D : (m, 6, 6) float64
    """
    # the tuples are indexed inside the loop: unpacked before it, the writes into the
    # boolean array were lost on two threads (numba 0.68.1; caught by the thread test)
    for j in prange(q.shape[0]):
        brk, st = resultant_law_one(
            q[j], plastic[0][j], plastic[1][j], params[j], floor, out_f[j], trial[0][j], out_D[j]
        )
        trial[1][j] = brk
        out_state[j] = st
