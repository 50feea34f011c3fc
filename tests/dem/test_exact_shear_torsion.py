"""The exact shear-torsion domain of the resultant law (dem.kernels.friction_domain) against
closed forms, finite differences and the fibre law on refined grids."""

import math

import numpy as np
import pytest

from dem.interface_strength import torsion_coefficient_rectangle
from dem.kernels import friction_domain as fd
from dem.kernels import interface_law as rk
from dem.kernels.fibre_law import fibre_law_one
from dem.kernels.interface_law import STATE_ELASTIC, STATE_SHEAR, resultant_law_one
from dem.static.laws import _polygon_springs, lobatto
from dem.static.settings import ResultantLawSettings

KN, KT = 2.4e9, 1e9  # [Pa/m]
MU = 0.7
RECTANGLE = 0.5 * np.array([(-0.21, -0.07), (0.21, -0.07), (0.21, 0.07), (-0.21, 0.07)])
HEXAGON = 0.1 * np.array([(math.cos(a), math.sin(a)) for a in np.arange(6) * math.pi / 3])
TRIANGLE = np.array([(-0.1, -0.05), (0.15, -0.05), (-0.1, 0.1)])


def _moments(poly):
    """Area and ``(J11, J22) = (int y1^2, int y2^2)`` about the centroid, and the polygon
    about its centroid (shoelace)."""
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    area = cr.sum() / 2
    c = np.array([((x + xn) * cr).sum(), ((y + yn) * cr).sum()]) / (6 * area)
    p = poly - c
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    j11 = ((x * x + x * xn + xn * xn) * cr).sum() / 12
    j22 = ((y * y + y * yn + yn * yn) * cr).sum() / 12
    return area, j11, j22, p


def _params(poly, ft=0.0, c=0.0, f_c=np.inf):
    area, j11, j22, p = _moments(poly)
    row = np.zeros(rk.N_PARAMS)
    row[rk.P_K : rk.P_K + 6] = [KN * area, KT * area, KT * area, KN * j22, KN * j11] + [
        KT * (j11 + j22)
    ]
    row[rk.P_FT], row[rk.P_COHESION], row[rk.P_MU] = ft * area, c * area, MU
    row[rk.P_DIMS : rk.P_DIMS + 2] = np.ptp(p, axis=0)
    row[rk.P_ALPHA], row[rk.P_FC], row[rk.P_AREA] = 1.43, f_c, area
    row[rk.P_STIFF : rk.P_STIFF + 2] = KN, KN
    row[rk.P_DOMAIN] = rk.DOMAIN_EXACT
    row[rk.P_N_CORNERS] = len(p)
    row[rk.P_POLY : rk.P_POLY + 2 * len(p)] = p.ravel()
    return row


def _exact(q, poly, qp=None, **strength):
    f, qpo, D = np.zeros(6), np.zeros(6), np.zeros((6, 6))
    qp = np.zeros(6) if qp is None else qp
    _, st = resultant_law_one(q, qp, False, _params(poly, **strength), 0.0, f, qpo, D)
    return f, qpo, D, st


def _fibre(q, poly, n, ft=0.0, c=0.0, f_c=np.inf):
    area, _, _, p = _moments(poly)
    if len(poly) == 4:  # the rectangle: Lobatto points, the outer ones on the edges
        x, w = lobatto(n)
        half = 0.5 * np.ptp(p, axis=0)
        g1, g2 = np.meshgrid(half[0] * x, half[1] * x, indexing="ij")
        springs = np.column_stack([g1.ravel(), g2.ravel(), np.outer(w, w).ravel() * area / 4])
    else:  # the law's own grid of other polygons
        springs = _polygon_springs(p, area, n)
    springs = np.ascontiguousarray(springs)
    ns = len(springs)
    params = np.array([KN, KT, MU, c, ft, f_c, 0.0])
    f, D = np.zeros(6), np.zeros((6, 6))
    plastic = (np.zeros((ns, 3)), np.zeros(ns, dtype=np.bool_))
    trial = (np.zeros((ns, 3)), np.zeros(ns, dtype=np.bool_))
    fibre_law_one(q, (0, ns), springs, params, plastic, 0.0, trial, f, D)
    return f


def _uniform_regions(poly, pressure):
    area, _, _, p = _moments(poly)
    regions, beta = np.zeros((3, fd.MAX_REGION, 2)), np.zeros((3, 3))
    counts = fd.capacity_regions(
        p, len(p), np.array([-pressure, 0.0, 0.0]), np.array([0.0, np.inf]),
        np.array([0.0, MU]), np.zeros(2), regions, beta,
    )  # fmt: skip
    return regions, counts, beta, area


@pytest.mark.parametrize("sides", [(0.42, 0.14), (0.3, 0.2), (0.2, 0.2)])
def test_pure_torsion_of_a_rectangle_is_mu_N_times_its_mean_distance(sides):
    """Uniform pressure p on an l1 x l2 rectangle, twist about its centre: every point slides
    across its radius with mu p, so M3 = mu N c_T (c_T the mean distance to the centre, the
    closed form of dem.interface_strength) and no shear."""
    l1, l2 = sides
    poly = 0.5 * np.array([(-l1, -l2), (l1, -l2), (l1, l2), (-l1, l2)])
    regions, counts, beta, area = _uniform_regions(poly, 1e5)
    acc = np.zeros(fd.N_ACC)
    fd.support(np.array([0.0, 0.0, 1.0]), regions, counts, beta, acc)
    expected = MU * 1e5 * area * torsion_coefficient_rectangle(l1, l2)
    np.testing.assert_allclose(acc[3], expected, rtol=1e-10)
    np.testing.assert_allclose(acc[1:3], 0.0, atol=1e-10 * expected / l1)
    # the capacity's polar moment about its centroid: mu p A (l1^2 + l2^2) / 12
    v_u, c1, c2 = fd.capacity_centroid(regions, counts, beta)
    polar, reach = fd.polar_capacity(regions, counts, beta, c1, c2)
    np.testing.assert_allclose(v_u, MU * 1e5 * area, rtol=1e-12)
    np.testing.assert_allclose([c1, c2], 0.0, atol=1e-14)
    np.testing.assert_allclose(polar, MU * 1e5 * area * (l1**2 + l2**2) / 12, rtol=1e-12)
    np.testing.assert_allclose(reach, math.hypot(l1, l2) / 2, rtol=1e-12)
    # pure sliding: mu N along the slip, no torsion about the centre
    fd.support(np.array([0.6, 0.8, 0.0]), regions, counts, beta, acc)
    np.testing.assert_allclose(acc[1:4], MU * 1e5 * area * np.array([0.6, 0.8, 0.0]), atol=1e-9)


@pytest.mark.parametrize("poly", [RECTANGLE, HEXAGON, TRIANGLE], ids=["rect", "hex", "tri"])
def test_support_gradient_and_hessian_match_finite_differences(poly):
    """g = grad h and H = grad g for rotation centres inside, on an edge, outside and far off
    (slip w = (w1, w2, 1) turns about (-w2, w1))."""
    regions, counts, beta, _ = _uniform_regions(poly, 1e5)
    acc, plus, minus = np.zeros(fd.N_ACC), np.zeros(fd.N_ACC), np.zeros(fd.N_ACC)
    for w in ([0.01, -0.02, 1.0], [0.035, 0.0, 1.0], [0.3, 0.1, 1.0], [1.0, 0.5, 1e-3]):
        w = np.array(w)
        fd.support(w, regions, counts, beta, acc)
        for j in range(3):
            h = 1e-6 * np.abs(w).max()
            fd.support(w + h * np.eye(3)[j], regions, counts, beta, plus)
            fd.support(w - h * np.eye(3)[j], regions, counts, beta, minus)
            np.testing.assert_allclose(
                acc[1 + j],
                (plus[0] - minus[0]) / (2 * h),
                rtol=1e-6,
                atol=1e-7 * np.abs(acc[1:4]).max(),
            )
            np.testing.assert_allclose(
                acc[4:13].reshape(3, 3)[:, j],
                (plus[1:4] - minus[1:4]) / (2 * h),
                rtol=1e-5, atol=1e-6 * np.abs(acc[4:13]).max(),
            )  # fmt: skip
        # h is homogeneous of degree 1: w . g = h, H w = 0
        np.testing.assert_allclose(w @ acc[1:4], acc[0], rtol=1e-10)
        np.testing.assert_allclose(acc[4:13].reshape(3, 3) @ w, 0.0, atol=1e-8 * acc[0])


DN = -240.0 / (KN * 0.21 * 0.07)  # the rectangle under 240 N
MOTIONS = [
    [DN, 0.0, 0.0, 0.0, 0.0, 1.0],  # pure torsion
    [DN, 1.0, 0.5, 0.0, 0.0, 10.0],  # shear and torsion
    [-2e-6, 0.3, 0.1, 2e-4, -4e-5, 10.0],  # partly open, twisting about an off-centre point
    [-2e-6, 0.1, 0.3, 1e-3, 0.0, 3.0],  # rocking about an edge
]


@pytest.mark.parametrize("q", MOTIONS)
@pytest.mark.parametrize("poly", [RECTANGLE, HEXAGON, TRIANGLE], ids=["rect", "hex", "tri"])
def test_exact_domain_is_the_limit_of_the_fibre_law(q, poly):
    """Far beyond the elastic range every spring slides along its own slip: the fibre law's
    shear and torsion are the support point of its grid's domain, and the exact domain is its
    limit. Against grids of halving cells the resultant law with the exact domain agrees to the
    fibre grid's stated error, twice the last change (dem.static.adaptive_grid), and the
    finest grid to 1 % of the joint's friction capacity."""
    q = np.array(q)
    q[[1, 2, 5]] *= 1e3  # the elastic slips (1e-5 m) change the flow direction by 1e-8
    f, _, _, st = _exact(q, poly)
    assert st & STATE_SHEAR
    rows = [1, 2, 5]
    grids = (5, 9, 17, 33) if len(poly) == 4 else (4, 8, 16, 32)
    fibres = [_fibre(q, poly, n) for n in grids]
    scale = np.array([1.0, 1.0, 1.0 / math.sqrt(_moments(poly)[0])]) * MU * abs(fibres[-1][0])
    for coarse, fine in zip(fibres[1:-1], fibres[2:], strict=True):
        bound = 2 * np.abs(fine[rows] - coarse[rows]) + 1e-9 * scale
        assert np.all(np.abs(fine[rows] - f[rows]) <= bound), (fine[rows], f[rows], bound)
    # and the grids approach it: first order on the triangle (cells cut by its hypotenuse)
    errors = [np.abs((fibre[rows] - f[rows]) / scale).max() for fibre in fibres]
    assert errors[-1] <= 0.6 * errors[1] and errors[-1] <= 1e-2


def test_exact_domain_torsion_matches_closed_form_in_the_law():
    """The law's pure torsion under uniform pressure: mu |N| c_T about the centroid."""
    f, *_ = _exact(np.array(MOTIONS[0]), RECTANGLE)
    np.testing.assert_allclose(f[5], MU * 240.0 * torsion_coefficient_rectangle(0.21, 0.07))


def test_a_trial_inside_stays_elastic():
    """Small shear and twist under compression: elastic, V = k_t A dt, M3 = k_t J_p phi3."""
    area, j11, j22, _ = _moments(RECTANGLE)
    q = np.array([DN, 1e-7, -2e-7, 0.0, 0.0, 1e-6])
    f, qp, D, st = _exact(q, RECTANGLE)
    assert st == STATE_ELASTIC
    np.testing.assert_allclose(f[[1, 2, 5]], KT * np.array([area, area, j11 + j22]) * q[[1, 2, 5]])
    np.testing.assert_allclose(qp, 0.0)
    # no shear and no twist at all (a joint under its dead load): elastic, finite tangent
    f, qp, D, st = _exact(np.array([DN, 0.0, 0.0, 0.0, 0.0, 0.0]), RECTANGLE)
    assert st == STATE_ELASTIC and np.all(np.isfinite(D))
    np.testing.assert_allclose(f[[1, 2, 5]], 0.0)


@pytest.mark.parametrize("poly", [RECTANGLE, TRIANGLE], ids=["rect", "tri"])
def test_exact_return_is_a_fixed_point_with_no_stiffness_along_the_flow(poly):
    """Perfect plasticity: from the returned state the same motion gives the same actions,
    still yielding, and the tangent has no stiffness along the plastic flow."""
    area, j11, j22, _ = _moments(poly)
    k6 = np.array([KN * area, KT * area, KT * area, KN * j22, KN * j11, KT * (j11 + j22)])
    for q in ([DN, 3e-5, 1e-5, 0, 0, 2e-4], [-2e-6, 3e-6, 1e-6, 2e-4, -4e-5, 0.03]):
        q = np.array(q)
        f, qp, _, st = _exact(q, poly)
        assert st & STATE_SHEAR
        f2, _, D2, st2 = _exact(q, poly, qp=qp)
        assert st2 == st
        np.testing.assert_allclose(f2, f, rtol=1e-9, atol=1e-9 * np.abs(f).max())
        flow = qp / np.linalg.norm(qp * np.sqrt(k6))
        assert abs(flow @ D2 @ flow) <= 1e-6


@pytest.mark.parametrize("seed", range(2))
def test_exact_tangent_matches_finite_differences(seed):
    """Closed, partly open and crushed joints sliding and twisting: the consistent tangent,
    including the change of the domain with the normal motion and the centre of compression."""
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(60):
        q = rng.standard_normal(6) * np.array([1e-6, 4e-6, 4e-6, 2e-4, 2e-4, 2e-4])
        q[0] = -abs(q[0]) - 2e-6
        f, _, D, st = _exact(q, RECTANGLE, f_c=2e4 if checked % 2 else np.inf)
        if not st & STATE_SHEAR:
            continue
        f_c = 2e4 if checked % 2 else np.inf
        Dfd = np.zeros((6, 6))
        for j in range(6):
            h = 1e-6 * max(abs(q[j]), 1e-8)
            fp, *_ = _exact(q + h * np.eye(6)[j], RECTANGLE, f_c=f_c)
            fm, *_ = _exact(q - h * np.eye(6)[j], RECTANGLE, f_c=f_c)
            Dfd[:, j] = (fp - fm) / (2 * h)
        scale = np.maximum(np.abs(D).max(axis=1, keepdims=True), 1e-6 * np.abs(D).max())
        np.testing.assert_allclose(D / scale, Dfd / scale, atol=1e-4)
        checked += 1
    assert checked > 10


def test_shear_torsion_setting_is_checked():
    assert ResultantLawSettings().shear_torsion == "eq_a5"
    with pytest.raises(ValueError, match="shear_torsion"):
        ResultantLawSettings(shear_torsion="exactly")
    with pytest.raises(ValueError, match="alpha"):
        ResultantLawSettings(shear_torsion="exact", alpha=1.5)


def test_a_block_pushed_and_twisted_slides_where_the_refined_fibre_law_does():
    """A 0.4 x 0.4 x 1 m block on the ground (mu 0.3) under lambda times (its weight W along
    x, a torque 0.2 m W about z) slides and twists before it tips (0.4). The fibre law's
    adaptive grid (0.5 %) brackets the resultant law with the exact domain, which agrees with
    the 33-point grid to 1e-4; Eq. (A5) lies outside that bar (seed 001's fitted domain, a
    modelling choice, is 2 % low here)."""
    from dem.scene import Scene
    from dem.static import FibreLawSettings, StaticSettings, solve_collapse

    def box(lo, hi):
        return np.array(
            [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        )

    blocks = [box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0)), box((-0.2, -0.2, 0.0), (0.2, 0.2, 1.0))]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.3)
    weight = scene.assembly.mass[1] * 9.81
    live = np.zeros((2, 6))
    live[1, 0], live[1, 5] = weight, 0.2 * weight
    scene = scene.with_loads(live=live)

    def lam(law):
        return solve_collapse(scene, StaticSettings(law=law))

    exact = lam(ResultantLawSettings(shear_torsion="exact")).lambda_max
    eq_a5 = lam(ResultantLawSettings()).lambda_max
    fine = lam(FibreLawSettings(points=33)).lambda_max
    adaptive = lam(FibreLawSettings(grid_tolerance=0.005, max_points=17))
    bar = adaptive.lambda_estimate
    assert adaptive.fibre_grid.converged
    assert bar.contains(exact) and bar.contains(fine), (bar, exact, fine)
    assert exact == pytest.approx(fine, rel=1e-4)
    assert not bar.contains(eq_a5)


@pytest.mark.parametrize("poly", [RECTANGLE, TRIANGLE], ids=["rect", "tri"])
def test_the_quick_inner_set_lies_inside_the_domain(poly):
    """Trials the inner set (sliding disc and twist apexes) calls inside have no direction
    w with s . w > h(w): checked by the direction search, and on 64 fixed directions."""
    _, _, _, p = _moments(poly)
    regions, beta = np.zeros((3, fd.MAX_REGION, 2)), np.zeros((3, 3))
    sigma = np.array([-1e5, -4e5, 2e5])  # partly open: tau linear, off-centre capacity
    counts = fd.capacity_regions(
        p, len(p), sigma, np.array([0.0, np.inf]), np.array([0.0, MU]), np.zeros(2), regions, beta
    )
    v_u, c1, c2 = fd.capacity_centroid(regions, counts, beta)
    acc = np.zeros(fd.N_ACC)
    rng = np.random.default_rng(3)
    directions = rng.standard_normal((64, 3)) * np.array([1.0, 1.0, 10.0])
    C = np.array([1e8, 1e8, 3e6])
    inside = 0
    for _ in range(300):
        trial = rng.uniform(-1, 1, 3) * v_u * np.array([1.0, 1.0, 0.1])
        if not fd.inside_bicone(trial, regions, counts, beta, 1e-9, acc):
            continue
        inside += 1
        _, psi = fd._max_direction(trial, C, regions, counts, beta, 1e-9, acc)
        assert psi < 0
        for w in directions:
            fd.support(w, regions, counts, beta, acc)
            assert trial @ w < acc[0]
    assert inside > 20
    assert v_u == pytest.approx(MU * abs(_law_normal_force(poly, sigma)), rel=1e-12)


def _law_normal_force(poly, sigma):
    """The normal force of the capped stress field, through the resultant law's kernel."""
    from dem.kernels.contact_stress import stress_resultants

    _, _, _, p = _moments(poly)
    f, D = np.zeros(3), np.zeros((3, 3))
    motion = np.array([sigma[0] / KN, sigma[2] / KN, -sigma[1] / KN])
    stress_resultants(motion, p, len(p), np.array([KN, KN]), np.array([0.0, np.inf, 0.0]), f, D)
    return f[0]


def test_the_stiffness_solve_of_the_projection_never_raises():
    """diag(C) + H made exactly singular by round-off: the least-norm least-squares solution
    (numpy's lstsq), not LAPACK's exception, which numba cannot carry out of a parallel loop;
    a regular matrix is solved as it is."""
    from dem.kernels.friction_domain import solve_stiffness

    singular = np.array([[2.0, 1.0, 0.0], [1.0, 0.5, 0.0], [0.0, 0.0, 3.0]])
    b = np.array([1.0, 2.0, 3.0])
    expected = np.linalg.lstsq(singular, b, rcond=None)[0]
    np.testing.assert_allclose(solve_stiffness(singular, b), expected, rtol=1e-12)
    rhs = np.diag([1.0, 2.0, 3.0])
    np.testing.assert_allclose(
        solve_stiffness(singular, rhs), np.linalg.lstsq(singular, rhs, rcond=None)[0], rtol=1e-12
    )
    regular = singular + np.eye(3)
    np.testing.assert_allclose(solve_stiffness(regular, b), np.linalg.solve(regular, b), rtol=1e-14)
