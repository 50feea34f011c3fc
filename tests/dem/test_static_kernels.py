"""Kernels of the static DEM against NumPy references and closed forms."""

import math

import numpy as np
import pytest
from scipy.integrate import dblquad

from dem.geometry.compatibility import compatibility_matrix
from dem.kernels import fibre_law as fk
from dem.kernels import interface_law as rk
from dem.kernels.fibre_law import fibre_law_one
from dem.kernels.interface_law import (
    STATE_DETACHED,
    STATE_ELASTIC,
    STATE_FLEXURE,
    STATE_SHEAR,
    resultant_law_one,
    torsion_coefficient,
)
from dem.kernels.spring_grid import spring_resultants
from dem.kernels.stiffness import (
    block_forces,
    local_compatibility,
    relative_motion,
    stiffness_triplets,
)
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import interface_alpha
from dem.static.laws import lobatto

RNG = np.random.default_rng(7)


@pytest.fixture(scope="module")
def wall():
    scene = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="weight")
    itf = scene.assembly.interfaces()
    c = scene.assembly.centroid
    B = local_compatibility(itf.block_a, itf.block_b, itf.centroid, c, itf.frame)
    return scene, itf, B


def test_local_blocks_reproduce_H(wall):
    scene, itf, B = wall
    H = compatibility_matrix(scene.assembly.centroid, itf).toarray()
    U = RNG.standard_normal((scene.n_blocks, 6))
    q = np.empty((itf.n_interfaces, 6))
    relative_motion(B, itf.block_a, itf.block_b, U, q)
    np.testing.assert_allclose(q.ravel(), H @ U.ravel(), atol=1e-12)
    f = RNG.standard_normal((itf.n_interfaces, 6))
    F = np.empty((scene.n_blocks, 6))
    block_forces(B, itf.block_a, itf.block_b, f, F)
    np.testing.assert_allclose(F.ravel(), H.T @ f.ravel(), atol=1e-12)


def test_stiffness_triplets_equal_HtDH_on_free_dofs(wall):
    scene, itf, B = wall
    m, n = itf.n_interfaces, scene.n_blocks
    H = compatibility_matrix(scene.assembly.centroid, itf).toarray()
    D = RNG.standard_normal((m, 6, 6))  # any, also non-symmetric
    free = scene.supports.free_dofs.copy()
    free[0, 2] = False  # also eliminate one single dof
    dof_index = np.full((n, 6), -1, dtype=np.int64)
    dof_index[free] = np.arange(free.sum())
    rows, cols, vals = stiffness_triplets(B, D, itf.block_a, itf.block_b, dof_index)
    K = np.zeros((free.sum(), free.sum()))
    np.add.at(K, (rows, cols), vals)
    Dfull = np.zeros((6 * m, 6 * m))
    for k in range(m):
        Dfull[6 * k : 6 * k + 6, 6 * k : 6 * k + 6] = D[k]
    ref = (H.T @ Dfull @ H)[np.ix_(free.ravel(), free.ravel())]
    np.testing.assert_allclose(K, ref, atol=1e-9 * np.abs(ref).max())


def test_general_kinematics_reduce_to_seed_eq_A1(wall):
    # seed 001 Eq. (A1): for a running-bond pair the relative translation at the joint is
    # u_j - u_i - (omega_i + omega_j)/2 x dy (dy = y_j - y_i), the rotation omega_j - omega_i
    scene, itf, B = wall
    c = scene.assembly.centroid
    U = RNG.standard_normal((scene.n_blocks, 6))
    q = np.empty((itf.n_interfaces, 6))
    relative_motion(B, itf.block_a, itf.block_b, U, q)
    checked = 0
    for k in range(itf.n_interfaces):
        i, j = itf.block_a[k], itf.block_b[k]
        if scene.supports.fixed[[i, j]].any():
            continue
        dy = c[j] - c[i]
        frame = itf.frame[k]
        rot = U[j, 3:] - U[i, 3:]
        np.testing.assert_allclose(q[k, 3:], frame[[1, 2, 0]] @ rot, atol=1e-12)
        if not np.allclose(itf.centroid[k], 0.5 * (c[i] + c[j]), atol=1e-12):
            # irregular pattern (a half block at the wall end): the general form uses the
            # actual interface centroid, the seed's regular form does not apply
            continue
        d = U[j, :3] - U[i, :3] - np.cross(0.5 * (U[i, 3:] + U[j, 3:]), dy)
        np.testing.assert_allclose(q[k, :3], frame @ d, atol=1e-12)
        checked += 1
    assert checked > 10


@pytest.mark.parametrize("l1, l2", [(0.3, 0.2), (0.105, 0.07), (0.05, 0.5)])
def test_torsion_coefficient_is_the_mean_distance(l1, l2):
    # c_T = (1/A) int sqrt(y1^2 + y2^2) dA, by quadrature
    val, _ = dblquad(lambda y, x: math.hypot(x, y), -l1 / 2, l1 / 2, -l2 / 2, l2 / 2)
    np.testing.assert_allclose(torsion_coefficient(l1, l2), val / (l1 * l2), rtol=1e-7)
    # a segment: l / 4
    np.testing.assert_allclose(torsion_coefficient(l1, 0.0), l1 / 4, rtol=1e-12)


def test_alpha_from_table_a1():
    # seed 001 Table A1, column f1 = f2: 1.43 at l1/l2 = 1, 1.70 at 0.5 and 2
    np.testing.assert_allclose(
        interface_alpha(np.array([1.0, 0.5, 2.0]), np.ones(3)), [1.43, 1.70, 1.70]
    )
    np.testing.assert_allclose(interface_alpha(np.ones(2), np.ones(2), 1.5), [1.5, 1.5])


def test_lobatto_rule_integrates_polynomials():
    x, w = lobatto(5)
    for p in range(8):  # exact to degree 2n - 3 = 7
        np.testing.assert_allclose(w @ x**p, (1 - (-1) ** (p + 1)) / (p + 1), atol=1e-13)


# --- the resultant law ----------------------------------------------------------------------
DIMS = np.array([0.21, 0.07])  # the joint: a 0.21 x 0.07 m rectangle about its centroid
AREA = DIMS[0] * DIMS[1]
KN, KT = 2.4e9, 1e9  # [Pa/m]
J11, J22 = DIMS[1] * DIMS[0] ** 3 / 12, DIMS[0] * DIMS[1] ** 3 / 12  # int y1^2, int y2^2
K6 = np.array([KN * AREA, KT * AREA, KT * AREA, KN * J22, KN * J11, KT * (J11 + J22)])
LEVER = DIMS[::-1] / 2  # rocking about t1 turns on the edge y2 = +-l2/2, about t2 on y1


def _params(ft=0.0, c=0.0, mu=0.7, alpha=1.5, f_c=np.inf):
    p = np.zeros(rk.N_PARAMS)
    p[rk.P_K : rk.P_K + 6] = K6
    p[rk.P_FT], p[rk.P_COHESION], p[rk.P_MU] = ft, c, mu
    p[rk.P_DIMS : rk.P_DIMS + 2] = DIMS
    p[rk.P_ALPHA], p[rk.P_FC], p[rk.P_AREA] = alpha, f_c, AREA
    p[rk.P_STIFF : rk.P_STIFF + 2] = KN, KN
    corners = 0.5 * DIMS * np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)])  # CCW
    p[rk.P_N_CORNERS] = 4
    p[rk.P_POLY : rk.P_POLY + 8] = corners.ravel()
    return p


def _law(q, qp=None, ft=0.0, c=0.0, mu=0.7, alpha=1.5, f_c=np.inf):
    f, qpo, D = np.zeros(6), np.zeros(6), np.zeros((6, 6))
    qp = np.zeros(6) if qp is None else qp
    brk, st = resultant_law_one(q, qp, False, _params(ft, c, mu, alpha, f_c), 0.0, f, qpo, D)
    return f, qpo, D, brk, st


def test_resultant_law_limits_match_seed_equations():
    n_force = -240.0  # seed 001 Sec. 2.1: 240 N compression
    dn = n_force / K6[0]
    # pure sliding: |V| = mu |N| = 168 N (Eq. 10)
    f, *_, st = _law(np.array([dn, 1e-3, 0, 0, 0, 0]))
    np.testing.assert_allclose(f[1], 168.0, rtol=1e-12)
    assert st == STATE_SHEAR
    # oblique sliding: on the circle
    f, *_ = _law(np.array([dn, 1e-3, 2e-3, 0, 0, 0]))
    np.testing.assert_allclose(math.hypot(f[1], f[2]), 168.0, rtol=1e-12)
    np.testing.assert_allclose(f[2] / f[1], 2.0, rtol=1e-12)
    # pure torsion: c_T mu |N| (Eq. 12)
    f, *_ = _law(np.array([dn, 0, 0, 0, 0, 1.0]))
    np.testing.assert_allclose(f[5], torsion_coefficient(*DIMS) * 168.0, rtol=1e-12)
    # detachment (Eq. 13): every corner open, no action at all
    f, *_, st = _law(np.array([0.04, 1e-3, 0, 1.0, 0, 1.0]))
    np.testing.assert_allclose(f, 0.0)
    assert st == STATE_DETACHED
    # tensile strength: N up to f_t, and the joint breaks beyond
    f, _, _, brk, st = _law(np.array([10.0 / K6[0], 0, 0, 0, 0, 0]), ft=20.0, c=14.0)
    assert st == STATE_ELASTIC and not brk
    f, _, _, brk, st = _law(np.array([30.0 / K6[0], 0, 0, 0, 0, 0]), ft=20.0, c=14.0)
    assert st == STATE_DETACHED and brk


@pytest.mark.parametrize("axis", [0, 1])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_resultant_rocking_hinges_on_the_edge_and_lifts(axis, sign):
    # Winkler no-tension joint rocking by theta about t1 (axis 0) or t2 (axis 1), closed form:
    # the stress is a triangle over the contact length c from the compressed edge, so
    # N = -k_n w theta c^2 / 2 and |M| = |N| (l - c / 3); the zero-stress line lies c from the
    # edge, so the centroid opens by dn = theta (l - c). As theta grows at fixed N, c -> 0:
    # M -> N l (seed 001 Eq. 9) and the centroid lifts by l per radian, as a rigid block
    # turning about its edge. Before the fix the law turned about the centroid: with the
    # centroid open it called the joint detached (here: N = M = 0).
    half, width = LEVER[axis], DIMS[axis]
    n_force = -240.0
    for theta in (0.02, 0.2, 2.0):
        c = math.sqrt(2 * abs(n_force) / (KN * width * theta))
        q = np.zeros(6)
        q[0] = theta * (half - c)
        q[3 + axis] = sign * theta
        f, *_, st = _law(q)
        # the gap dn + phi1 y2 - phi2 y1 closes on the edge whose moment has the rotation's sign
        m_expect = sign * abs(n_force) * (half - c / 3)
        np.testing.assert_allclose(f[0], n_force, rtol=1e-9)
        np.testing.assert_allclose(f[3 + axis], m_expect, rtol=1e-9)
        assert st & STATE_FLEXURE
    np.testing.assert_allclose(abs(f[3 + axis]) / abs(f[0]), half, rtol=1e-2)


def test_resultant_compressive_strength_closed_forms():
    # crushing: N capped at -f_c A, with no memory (the cap, not a plastic shortening)
    f_c = 1e5
    f, _, D, _, st = _law(np.array([-2 * f_c * AREA / K6[0], 0, 0, 0, 0, 0]), f_c=f_c)
    np.testing.assert_allclose(f[0], -f_c * AREA, rtol=1e-12)
    assert st & rk.STATE_CRUSHED
    assert D[0, 0] == 0.0  # floor 0: no normal stiffness while crushing
    f, *_ = _law(np.array([-0.5 * f_c * AREA / K6[0], 0, 0, 0, 0, 0]), f_c=f_c)
    np.testing.assert_allclose(f[0], -0.5 * f_c * AREA, rtol=1e-12)
    # rocking about t1 by theta: from the compressed edge, a block of stress f_c over p, then
    # a ramp to 0 over r = f_c / (k_n theta): N = -w f_c (p + r / 2),
    # M1 = -w f_c [p (l - p / 2) + (r / 2) (l - p - r / 3)]; as theta grows, r -> 0 and
    # M1 -> N (l - |N| / (2 f_c w)), the stress block of the limit analysis
    half, width = LEVER[0], DIMS[0]
    for theta, p in ((0.05, 0.004), (5.0, 0.01)):
        r = f_c / (KN * theta)
        q = np.array([theta * (half - p - r), 0, 0, -theta, 0, 0])
        f, *_, st = _law(q, f_c=f_c)
        n_expect = -width * f_c * (p + r / 2)
        m_expect = -width * f_c * (p * (half - p / 2) + r / 2 * (half - p - r / 3))
        np.testing.assert_allclose(f[0], n_expect, rtol=1e-9)
        np.testing.assert_allclose(f[3], m_expect, rtol=1e-9)
        assert st & rk.STATE_CRUSHED and st & STATE_FLEXURE
    block = f[0] * (half - abs(f[0]) / (2 * f_c * width))
    np.testing.assert_allclose(f[3], block, rtol=1e-3)


def test_resultant_interaction_surface_eq_A5():
    # the return lands on (|M3| / M_u)^alpha + |V|^2 / V_u^2 = 1, at the point nearest to the
    # trial in the elastic energy: the trial minus the returned point is normal to the surface
    n_force = -240.0
    q = np.array([n_force / K6[0], 5e-4, 0, 0, 0, 0.05])
    f, *_ = _law(q, alpha=1.5)
    v_u = 168.0
    m_u = torsion_coefficient(*DIMS) * v_u
    np.testing.assert_allclose((abs(f[5]) / m_u) ** 1.5 + (f[1] / v_u) ** 2, 1.0, rtol=1e-10)
    grad = np.array([2 * f[1] / v_u**2, 1.5 * abs(f[5]) ** 0.5 / m_u**1.5])
    step = np.array([(K6[1] * q[1] - f[1]) / K6[1], (K6[5] * q[5] - f[5]) / K6[5]])
    np.testing.assert_allclose(grad[0] * step[1], grad[1] * step[0], rtol=1e-8)


def test_resultant_torsion_is_taken_about_the_centre_of_compression():
    # a joint rocking about its edge y2 = +l2/2 (compressed strip there) slides along t1: the
    # friction acts at the strip, so the sliding shear V1 = mu |N| carries the moment
    # M3 = -l_c V1 about the centroid, l_c the distance of the centre of compression
    # (Orduna & Lourenco's reduced rectangle is centred there). Before, the law put M3 = 0
    # about the centroid while sliding: a friction force off the contact
    theta = 0.5
    n_force = -240.0
    c = math.sqrt(2 * abs(n_force) / (KN * DIMS[0] * theta))
    q = np.array([theta * (LEVER[0] - c), 1e-3, 0, -theta, 0, 0])
    f, *_, st = _law(q)
    y_c = f[3] / f[0]  # M1 = y2 N
    np.testing.assert_allclose(f[1], 0.7 * abs(f[0]), rtol=1e-9)
    np.testing.assert_allclose(f[5], -y_c * f[1], rtol=1e-9)
    assert st & STATE_SHEAR


@pytest.mark.parametrize(
    "q",
    [
        [-240.0 / K6[0], 1e-3, 0, 0, 0, 0],  # sliding
        [-240.0 / K6[0], 1e-3, 2e-3, 0, 0, 0],  # oblique sliding
        [-240.0 / K6[0], 0, 0, 0, 0, 1.0],  # pure torsion
        [-240.0 / K6[0], 5e-4, 0, 0, 0, 0.05],  # torsion-shear interaction (A5)
        [-240.0 / K6[0], 3e-6, 1e-6, 2e-4, -4e-5, 0.03],  # all at once, partly open
    ],
)
def test_resultant_return_is_a_fixed_point(q):
    # After a plastic return the committed state lies on the limit; evaluating the law again at
    # the same motion from that state must give the same actions, the same state (still
    # yielding) and the tangent of continued plastic flow: perfectly plastic, so no stiffness
    # along the plastic flow dq_p (closed form: dq_p . D dq_p = 0, against dq_p . K dq_p > 0
    # elastically). A strict "trial > limit" test took such joints as elastic at the start of
    # every load step (two thirds of the yielded joints of seed 001's S11), and the
    # path-following stalled.
    q = np.array(q, dtype=float)
    f, qp, _, _, st = _law(q)
    assert st & STATE_SHEAR
    f2, _, D2, _, st2 = _law(q, qp=qp)
    assert st2 == st
    np.testing.assert_allclose(f2, f, rtol=1e-12, atol=1e-10 * np.abs(f).max())
    flow = qp / np.linalg.norm(qp * np.sqrt(K6))  # elastic energy flow . K flow = 1
    assert abs(flow @ D2 @ flow) <= 1e-9


@pytest.mark.parametrize("f_c", [np.inf, 2e4])
@pytest.mark.parametrize("seed", range(4))
def test_resultant_tangent_matches_finite_differences(seed, f_c):
    # rigid-body motions of all sizes: closed joints, partly open ones (rocking), sliding and
    # twisting ones, and with a compressive strength crushed strips
    rng = np.random.default_rng(seed)
    checked, partly_open, crushed = 0, 0, 0
    for _ in range(400):
        q = rng.standard_normal(6) * np.array([1e-6, 4e-6, 4e-6, 2e-4, 2e-4, 2e-4])
        q[0] = -abs(q[0]) - 2e-6
        f, _, D, _, st = _law(q, f_c=f_c)
        Dfd = np.zeros((6, 6))
        same = True
        for j in range(6):
            h = 1e-5 * max(abs(q[j]), 1e-8)
            fp, *_, stp = _law(q + h * np.eye(6)[j], f_c=f_c)
            fm, *_, stm = _law(q - h * np.eye(6)[j], f_c=f_c)
            same &= stp == st and stm == st
            Dfd[:, j] = (fp - fm) / (2 * h)
        if not same:
            continue
        scale = np.maximum(np.abs(D).max(axis=1, keepdims=True), 1e-6 * np.abs(D).max())
        np.testing.assert_allclose(D / scale, Dfd / scale, atol=1e-4)
        checked += 1
        # beyond the middle third the joint is partly open
        partly_open += bool(np.any(np.abs(f[3:5]) > np.abs(f[0]) * LEVER / 3))
        crushed += bool(st & rk.STATE_CRUSHED)
    assert checked > 50 and partly_open > 10
    assert crushed > 5 or not np.isfinite(f_c)


# (v_t, m_t, V_u, M_u, k_t A, k_t J_p): near the corner, inside it by round-off (a joint of
# the Orduna 3 x 13 panel after its dead load), and well outside
RETURN_CASES = [
    (1.0 + 1e-12, 1e-12, 1.0, 0.3, 1.0, 0.1),
    (1.0, 1e-9, 1.0, 0.3, 1.0, 0.1),
    (14.820664024314073, 0.0, 14.820664024314077, 0.3179912454295486, 7.35e6, 9754.0625),
    (1.2, 0.05, 1.0, 0.3, 1.0, 0.1),
]


@pytest.mark.parametrize("alpha", [1.0, 1.43, 2.56])
@pytest.mark.parametrize("case", RETURN_CASES)
def test_torsion_shear_return_near_the_corner_is_finite(alpha, case):
    # a sliding joint without twist returns onto V_u (the corner of pure sliding): with
    # alpha = 1 the boundary's curvature there was 0 * inf = NaN, which made the whole
    # stiffness singular after the dead load (Orduna 3 x 13, resultant law, alpha = 1)
    from dem.kernels.shear_torsion_return import nearest_on_boundary

    v_t, m_t, v_u, m_u, a, b = case
    out = np.empty(10)
    nearest_on_boundary(v_t, m_t, v_u, m_u, alpha, a, b, out)
    assert np.all(np.isfinite(out)) and np.abs(out[2:]).max() < 1e3
    v, m = out[0], out[1]
    assert 0.0 < v <= v_u and m >= 0.0
    np.testing.assert_allclose((m / m_u) ** alpha + (v / v_u) ** 2, 1.0, atol=1e-9)
    if m_t < 1e-3:
        return  # at the kink of the corner: a difference quotient straddles it
    args = np.array([v_t, m_t, v_u, m_u])
    for i in range(4):
        h = 1e-7 * args[i]
        plus, minus = np.empty(10), np.empty(10)
        nearest_on_boundary(*(args + h * np.eye(4)[i]), alpha, a, b, plus)
        nearest_on_boundary(*(args - h * np.eye(4)[i]), alpha, a, b, minus)
        fd = (plus[:2] - minus[:2]) / (2 * h)
        np.testing.assert_allclose([out[2 + i], out[6 + i]], fd, rtol=1e-5, atol=1e-8)


# --- the fibre law --------------------------------------------------------------------------


def _grid(l1, l2, n):
    x, w = lobatto(n)
    g1, g2 = np.meshgrid(0.5 * l1 * x, 0.5 * l2 * x, indexing="ij")
    pos = np.ascontiguousarray(np.column_stack([g1.ravel(), g2.ravel()]))
    return pos, np.outer(w, w).ravel() * 0.25 * l1 * l2


def _fibre_params(mu=0.7, coh=0.0, ten=0.0, f_c=np.inf):
    p = np.empty(fk.N_FIBRE_PARAMS)
    p[fk.F_KN], p[fk.F_KS], p[fk.F_MU] = 2.4e9, 1e9, mu
    p[fk.F_COHESION], p[fk.F_TENSILE], p[fk.F_FC] = coh, ten, f_c
    p[fk.F_TOUCH] = 0.0
    return p


def _fibre(q, pos, areas, mu=0.7, coh=0.0, ten=0.0, f_c=np.inf, slip=None):
    ns = len(areas)
    f, D = np.zeros(6), np.zeros((6, 6))
    springs = np.ascontiguousarray(np.column_stack([pos, areas]))
    slip = np.zeros((ns, 3)) if slip is None else slip
    brk = np.zeros(ns, dtype=np.bool_)
    out_slip, out_brk = np.zeros((ns, 3)), brk.copy()
    params = _fibre_params(mu, coh, ten, f_c)
    st = fibre_law_one(q, (0, ns), springs, params, (slip, brk), 0.0, (out_slip, out_brk), f, D)
    return f, D, st


def test_fibre_law_closed_forms():
    l1, l2 = 0.3, 0.2
    pos, areas = _grid(l1, l2, 5)
    A = l1 * l2
    dn = -240.0 / (2.4e9 * A)
    # uniform compression: N = -240 N, no moments
    f, D, st = _fibre(np.array([dn, 0, 0, 0, 0, 0]), pos, areas)
    np.testing.assert_allclose(f[0], -240.0, rtol=1e-12)
    assert st == STATE_ELASTIC
    # elastic bending stiffness k_n J (Lobatto 5 integrates y^2 exactly)
    np.testing.assert_allclose(D[3, 3], 2.4e9 * l1 * l2**3 / 12, rtol=1e-12)
    np.testing.assert_allclose(D[5, 5], 1e9 * (l1 * l2**3 + l1**3 * l2) / 12, rtol=1e-12)
    # sliding: mu |N| = 168 N (seed 001 Sec. 2.1.2)
    f, _, st = _fibre(np.array([dn, 1e-3, 0, 0, 0, 0]), pos, areas)
    np.testing.assert_allclose(f[1], 168.0, rtol=1e-12)
    assert st & STATE_SHEAR
    # rocking on the edge (only the edge row in contact): M1 = |N| l2 / 2 exactly
    f, _, st = _fibre(np.array([0.09e-3, 0, 0, -1e-3, 0, 0]), pos, areas)
    np.testing.assert_allclose(f[3] / f[0], l2 / 2, rtol=1e-12)
    assert st & STATE_FLEXURE


def test_fibre_compressive_strength_caps_every_spring():
    # uniform closure beyond the strength: N = -f_c A (the spring areas sum to A), and a
    # tilt crushes the edge row first: the compressed resultant stays within -f_c A
    l1, l2, f_c = 0.3, 0.2, 1e5
    pos, areas = _grid(l1, l2, 5)
    f, D, st = _fibre(np.array([-1e-3, 0, 0, 0, 0, 0]), pos, areas, f_c=f_c)
    np.testing.assert_allclose(f[0], -f_c * l1 * l2, rtol=1e-12)
    assert st & fk.STATE_CRUSHED and D[0, 0] == 0.0
    f, _, st = _fibre(np.array([-1e-5, 0, 0, 1e-3, 0, 0]), pos, areas, f_c=f_c)
    assert st & fk.STATE_CRUSHED and -f_c * l1 * l2 <= f[0] < 0
    # the moment of a fully plastic (crushed) compressed zone cannot exceed the stress block's
    assert abs(f[3]) <= f_c * l1 * l2**2 / 4 * (1 + 1e-12)


def test_fibre_resultants_match_spring_grid_kernel():
    pos, areas = _grid(0.21, 0.07, 4)
    q = np.array([-2e-7, 3e-7, -1e-7, 1e-5, -2e-5, 3e-5])
    f, _, _ = _fibre(q, pos, areas)
    # the same springs through the other engineer's kernels (sign and order conventions)
    u_n = q[0] + q[3] * pos[:, 1] - q[4] * pos[:, 0]
    u_1 = q[1] - q[5] * pos[:, 1]
    u_2 = q[2] + q[5] * pos[:, 0]
    kn, ks = 2.4e9 * areas, 1e9 * areas
    fn = np.minimum(kn * u_n, 0.0)
    ft = np.column_stack([ks * u_1, ks * u_2])
    cap = -0.7 * fn
    norm = np.hypot(ft[:, 0], ft[:, 1])
    scale = np.where(norm > cap, cap / np.where(norm > 0, norm, 1), 1.0)
    ft = ft * scale[:, None]
    ft[fn == 0] = 0.0
    res = spring_resultants(pos, np.column_stack([ft, fn]))  # (f1, f2, f3, m1, m2, m3)
    np.testing.assert_allclose(f, res[[2, 0, 1, 3, 4, 5]], atol=1e-9 * np.abs(f).max())


@pytest.mark.parametrize("seed", range(3))
def test_fibre_tangent_matches_finite_differences(seed):
    rng = np.random.default_rng(seed)
    pos, areas = _grid(0.21, 0.07, 4)
    checked = 0
    for _ in range(200):
        q = rng.standard_normal(6) * np.array([1e-7, 3e-7, 3e-7, 5e-6, 5e-6, 5e-6])
        q[0] = -abs(q[0]) - 1e-7
        f, D, st = _fibre(q, pos, areas)
        Dfd = np.zeros((6, 6))
        for j in range(6):
            h = 1e-5 * max(abs(q[j]), 1e-9)
            fp, _, _ = _fibre(q + h * np.eye(6)[j], pos, areas)
            fm, _, _ = _fibre(q - h * np.eye(6)[j], pos, areas)
            Dfd[:, j] = (fp - fm) / (2 * h)
        scale = np.abs(D).max()
        err = np.abs(D - Dfd).max() / scale
        if err < 1e-3:
            checked += 1
    # a kink may lie inside a finite-difference stencil now and then; nearly all agree
    assert checked >= 180


@pytest.mark.parametrize("model", ["resultant", "fibre"])
def test_batched_laws_are_the_same_on_any_number_of_threads(model):
    """The batch loops over interfaces run in parallel: every interface must be computed on
    its own, so one thread, two threads and the single-interface kernel agree bit for bit."""
    import numba

    from dem.static import StaticSettings
    from dem.static.model import Model

    scene = running_bond_wall(4, 5, 81, 210, 70, 20, 0.7, live="weight")
    law = Model(scene, StaticSettings(interface_model=model, mu=0.7, tensile_strength=2e4)).law
    m = len(law.state)
    q = 1e-5 * RNG.standard_normal((m, 6))  # opens, closes, slips and rocks joints
    q[:, 0] -= 2e-6
    runs = []
    previous = numba.get_num_threads()
    try:
        for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
            numba.set_num_threads(threads)
            runs.append(law.evaluate(q, 1e-6))
    finally:
        numba.set_num_threads(previous)
    for a, b in zip(runs[0].plastic, runs[1].plastic, strict=True):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(runs[0].f, runs[1].f)
    np.testing.assert_array_equal(runs[0].D, runs[1].D)
    np.testing.assert_array_equal(runs[0].state, runs[1].state)
    assert len(np.unique(runs[0].state)) > 2  # several regimes are exercised
    f, qp, D = np.empty(6), np.empty(6), np.empty((6, 6))
    if model == "resultant":
        broken = np.empty(m, dtype=bool)
        for j in range(m):
            broken[j], _ = resultant_law_one(
                q[j], *(a[j] for a in law.plastic), law.params[j], 1e-6, f, qp, D
            )
            np.testing.assert_array_equal(f, runs[0].f[j])
            np.testing.assert_array_equal(D, runs[0].D[j])
            np.testing.assert_array_equal(qp, runs[0].plastic[0][j])
        np.testing.assert_array_equal(broken, runs[0].plastic[1])
        assert broken.any() and not broken.all()
    else:
        trial = tuple(np.empty_like(a) for a in law.plastic)
        for j in range(m):
            span = (law.spring_ptr[j], law.spring_ptr[j + 1])
            fibre_law_one(q[j], span, law.springs, law.params[j], law.plastic, 1e-6, trial, f, D)
            np.testing.assert_array_equal(f, runs[0].f[j])
            np.testing.assert_array_equal(D, runs[0].D[j])
        for a, b in zip(trial, runs[0].plastic, strict=True):
            np.testing.assert_array_equal(a, b)
        assert trial[1].any() and not trial[1].all()
