"""Fibre (spring grid) interface strength: seed 001 Sec. 2.1 and appendix."""

import math

import numpy as np
import pytest

from dem.interface_strength import (
    CoulombSpringLaw,
    SpringInterface,
    fit_alpha,
    incremental_analysis,
    interaction_domain,
    interaction_law_torsion,
    max_torsion_socp,
    shear_capacities,
    shear_strength,
    torsion_coefficient_rectangle,
    torsion_section,
    torsion_strength,
    torsion_strength_with_bending,
    torsion_strength_with_bending_closed_form,
    twist_centre_resultants,
)
from dem.kernels.spring_grid import STATUS_OPEN, STATUS_SLIP, STATUS_STICK, spring_return_map_one

# seed 001 Sec. 2.1: interface b x s = 0.3 x 0.2 m, N = -240 N, mu = 0.7, 32 x 32 springs
L1, L2, N, MU = 0.3, 0.2, -240.0, 0.7
DRY = CoulombSpringLaw(mu=MU)


@pytest.fixture(scope="module")
def seed_interface():
    return SpringInterface.rectangle(L1, L2, 32)


def test_shear_strength_is_mu_times_normal_force(seed_interface):
    # closed form f_su = -mu N = 168 N for every direction (seed 001 Eq. (10), Sec. 2.1.2)
    for angle in np.linspace(0.0, 2 * np.pi, 7):
        f_s = shear_strength(seed_interface, DRY, N, angle)
        np.testing.assert_allclose(f_s, 168.0, rtol=1e-12)


def test_square_torsion_coefficient_independent_form():
    # c_T of a square of side a: a (sqrt 2 + ln(1 + sqrt 2)) / 6 (mean distance to the centre)
    a = 0.37
    expected = a * (math.sqrt(2.0) + math.log(1.0 + math.sqrt(2.0))) / 6.0
    np.testing.assert_allclose(torsion_coefficient_rectangle(a, a), expected, rtol=1e-14)


def test_torsion_coefficient_matches_quadrature():
    # independent: scipy dblquad of the distance to the centroid over the rectangle
    from scipy.integrate import dblquad

    for l1, l2 in [(0.3, 0.2), (1.0, 0.1), (0.05, 0.4)]:
        val, _ = dblquad(
            lambda y, x: math.hypot(x, y), -l1 / 2, l1 / 2, -l2 / 2, l2 / 2, epsabs=1e-13
        )
        np.testing.assert_allclose(
            torsion_coefficient_rectangle(l1, l2), val / (l1 * l2), rtol=1e-8
        )


def test_torsion_strength_seed_value(seed_interface):
    # seed 001 Sec. 2.1.3 prints m3u = 16.2 N m; the grid gives 16.258 (closed form 16.264),
    # which would round to 16.3: the seed's value reads as truncated (or taken before every
    # spring slides). Tolerance 0.07 N m = 0.4 %.
    m3u = torsion_strength(seed_interface, DRY, N)
    assert abs(m3u - 16.2) <= 0.07
    np.testing.assert_allclose(m3u, torsion_coefficient_rectangle(L1, L2) * MU * 240.0, rtol=1e-3)


def test_torsion_converges_to_closed_form_at_second_order():
    c_t = torsion_coefficient_rectangle(L1, L2)
    ns = [8, 16, 32, 64]
    errs = [
        abs(torsion_strength(SpringInterface.rectangle(L1, L2, n), DRY, N) / (MU * 240.0) - c_t)
        for n in ns
    ]
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    # midpoint rule on a function with a cone point at the centroid: O(h^2)
    np.testing.assert_allclose(rates, 2.0, atol=0.1)
    assert errs[-1] / c_t < 1e-4


def test_pure_torsion_equals_sum_of_distances(seed_interface):
    # a grid symmetric about its centroid twists about the centroid: m3u = sum r_i |y_i|
    caps = shear_capacities(seed_interface, DRY, N)
    expected = caps @ np.hypot(seed_interface.positions[:, 0], seed_interface.positions[:, 1])
    np.testing.assert_allclose(torsion_strength(seed_interface, DRY, N), expected, rtol=1e-12)


def test_thin_strip_domain_is_alpha_one():
    # a strip across the shear (l1 << l2): twist centre on the strip axis at y2 = c,
    # m3/m3u = 1 - (c/a)^2 and f/fu = c/a exactly -> alpha = 1 (Table A1: 1.00 at l1/l2 = 0.1)
    strip = SpringInterface.rectangle(1e-4, 1.0, 1, 400)
    dom = interaction_domain(strip, DRY, N, n_points=65)
    np.testing.assert_allclose(dom.torsion_normalised, 1.0 - dom.shear_normalised**2, atol=2e-3)


# seed 001 Table A1, 2nd-4th columns; the seed gives no fitting rule. Tolerance: |d alpha| <= 0.15,
# which moves the law by <= 0.03 in m3/m3u at f/fsu ~ 0.7, and the seed's law must stay within
# 0.06 of our exact domain (the best law of the family is itself up to 0.04 off).
TABLE_A1 = {
    0.1: (1.00, 2.56, 2.00),
    0.2: (1.05, 2.44, 1.90),
    0.5: (1.25, 1.92, 1.70),
    1.0: (1.43, 1.43, 1.43),
    2.0: (1.92, 1.25, 1.70),
    5.0: (2.44, 1.05, 1.90),
    10.0: (2.56, 1.00, 2.00),
}


@pytest.mark.parametrize("ratio", sorted(TABLE_A1))
def test_alpha_against_table_a1(ratio):
    interface = SpringInterface.rectangle(ratio * L2, L2, 32)
    for column, angle in enumerate([0.0, 0.5 * np.pi, 0.25 * np.pi]):
        dom = interaction_domain(interface, DRY, N, shear_angle=angle)
        alpha = fit_alpha(dom, "equal_ratio", interface=interface, law=DRY, normal_force=N)
        seed_alpha = TABLE_A1[ratio][column]
        assert abs(alpha - seed_alpha) <= 0.15, (ratio, column, alpha, seed_alpha)
        law_misfit = np.max(
            np.abs(
                interaction_law_torsion(dom.shear_normalised, seed_alpha) - dom.torsion_normalised
            )
        )
        assert law_misfit <= 0.06


def test_alpha_symmetry_between_columns():
    # Table A1: alpha(f2 only, l1/l2) = alpha(f1 only, l2/l1)
    a = SpringInterface.rectangle(0.1, 0.2, 32)
    b = SpringInterface.rectangle(0.2, 0.1, 32)
    alpha_a = fit_alpha(interaction_domain(a, DRY, N, shear_angle=0.0))
    alpha_b = fit_alpha(interaction_domain(b, DRY, N, shear_angle=0.5 * np.pi))
    np.testing.assert_allclose(alpha_a, alpha_b, rtol=1e-9)


def test_three_routes_agree(seed_interface):
    # kinematic (twist centre) vs Newton section vs SOCP vs elastic-plastic increments
    caps = shear_capacities(seed_interface, DRY, N)
    centre = np.array([[0.0, 0.05]])
    f1, f2, m3 = twist_centre_resultants(seed_interface, caps, centre)[0]
    m3_newton, centres, _ = torsion_section(seed_interface, caps, np.array([[f1, f2]]))
    np.testing.assert_allclose(m3_newton[0], m3, rtol=1e-10)
    np.testing.assert_allclose(centres[0], centre[0], atol=1e-9)
    socp = max_torsion_socp(seed_interface, DRY, N, (f1, f2))
    np.testing.assert_allclose(socp.torsion, m3, rtol=1e-6)
    assert socp.max_cone_violation < 1e-8 and socp.equality_residual < 1e-8
    # rotation delta3 with sliding d1 = 0.05 delta3 at the centre: twist about (0, 0.05)
    epp = incremental_analysis(seed_interface, DRY, N, (0.05, 0.0, 1.0), 0.05, 20)
    np.testing.assert_allclose(epp.resultants[-1, [0, 1, 5]], [f1, f2, m3], rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(epp.resultants[:, 2], N, rtol=1e-12)
    assert epp.n_slip[-1] == seed_interface.n_springs


def test_force_and_displacement_modes_agree_on_axes(seed_interface):
    # on a symmetry axis the twist centre of a fixed-force section lies on the normal axis:
    # the Newton section at the shear of each displacement-driven point gives the same torsion
    d_disp = interaction_domain(seed_interface, DRY, N, shear_angle=0.0, n_points=33)
    caps = shear_capacities(seed_interface, DRY, N)
    m3, _, _ = torsion_section(seed_interface, caps, d_disp.shear_vectors[:-1])
    np.testing.assert_allclose(m3, d_disp.torsion[:-1], rtol=1e-7, atol=1e-9)
    d_force = interaction_domain(seed_interface, DRY, N, shear_angle=0.0, mode="force")
    np.testing.assert_allclose(d_force.torsion_ultimate, d_disp.torsion_ultimate, rtol=1e-12)


def test_bending_reduces_torsion_like_reduced_rectangle(seed_interface):
    # no bending: the reduced rectangle is the whole interface
    np.testing.assert_allclose(
        torsion_strength_with_bending(seed_interface, DRY, N, 0.0, 0.0, L1, L2),
        torsion_strength(seed_interface, DRY, N),
        rtol=1e-12,
    )
    # m1 = 12 N m -> e2 = 0.05 m, compressed rectangle 0.3 x 0.1 m (16 of 32 rows exactly)
    spring = torsion_strength_with_bending(seed_interface, DRY, N, -12.0, 0.0, L1, L2)
    closed = torsion_strength_with_bending_closed_form(L1, L2, MU, N, -12.0, 0.0)
    np.testing.assert_allclose(closed, MU * 240.0 * torsion_coefficient_rectangle(0.3, 0.1))
    np.testing.assert_allclose(spring, closed, rtol=2e-3)


def test_torsion_with_tensile_strength_follows_eq12(seed_interface):
    # seed 001 Eq. (12): m3u = c_T mu (f_t - N) with c = mu sigma_t
    sigma_t = 2000.0  # [Pa]
    law = CoulombSpringLaw.from_tensile_strength(MU, sigma_t)
    f_t = sigma_t * L1 * L2
    expected = torsion_coefficient_rectangle(L1, L2) * MU * (f_t - N)
    np.testing.assert_allclose(torsion_strength(seed_interface, law, N), expected, rtol=1e-3)
    np.testing.assert_allclose(shear_strength(seed_interface, law, N), MU * (f_t - N), rtol=1e-12)


def test_spring_return_map_one_closed_forms():
    # stick: elastic forces
    out = spring_return_map_one((-1e-4, 1e-6, 0.0), (0.0, 0.0), False, (1e5, 2e4, 0.5, 0.0, 0.0))
    np.testing.assert_allclose(out[:3], [-10.0, 0.02, 0.0])
    assert out[6] == STATUS_STICK
    # slip: radial return onto |t| = mu |n| = 5 N, slip so that k_s (u - s) = t
    out = spring_return_map_one((-1e-4, 3e-3, 4e-3), (0.0, 0.0), False, (1e5, 2e4, 0.5, 0.0, 0.0))
    np.testing.assert_allclose(out[1:3], [3.0, 4.0])
    np.testing.assert_allclose(out[3:5], [3e-3 - 3.0 / 2e4, 4e-3 - 4.0 / 2e4])
    assert out[6] == STATUS_SLIP
    # opening beyond the tensile force: no force, the spring breaks
    out = spring_return_map_one((1e-3, 0.0, 0.0), (0.0, 0.0), False, (1e5, 2e4, 0.5, 1.0, 2.0))
    assert out[:3] == (0.0, 0.0, 0.0) and out[5] and out[6] == STATUS_OPEN


@pytest.mark.parametrize(
    ("call", "word"),
    [
        (lambda: SpringInterface.rectangle(-0.3, 0.2, 32), "l1"),
        (lambda: SpringInterface.rectangle(0.3, 0.0, 32), "l2"),
        (lambda: SpringInterface.rectangle(0.3, 0.2, 0), "n1"),
        (lambda: SpringInterface.rectangle(0.3, 0.2, 4, 0), "n2"),
        (lambda: shear_strength(SpringInterface.rectangle(0.3, 0.2, 4), DRY, 0.0), "normal_force"),
        (
            lambda: torsion_strength(SpringInterface.rectangle(0.3, 0.2, 4), DRY, 10.0),
            "normal_force",
        ),
        (lambda: CoulombSpringLaw(mu=-0.1), "mu"),
        (lambda: SpringInterface(np.zeros((0, 2)), np.zeros(0)), "n_springs"),
        (lambda: torsion_coefficient_rectangle(0.3, -1.0), "l2"),
    ],
)
def test_bad_inputs_raise_value_error(call, word):
    with pytest.raises(ValueError, match=word):
        call()


def test_no_tension_pressure_is_navier_inside_the_core(seed_interface):
    # small eccentricity: the whole interface stays compressed and the pressure is
    # sigma = N/A + m1 y2 / I1 - m2 y1 / I2 with the grid's second moments (Navier)
    from dem.interface_strength import no_tension_normal_forces

    m1, m2 = 3.0, -2.0
    n = no_tension_normal_forces(seed_interface, DRY, N, m1, m2)
    y1, y2 = seed_interface.positions.T
    a = seed_interface.areas
    i1, i2 = a @ y2**2, a @ y1**2
    expected = a * (N / a.sum() + m1 * y2 / i1 - m2 * y1 / i2)
    np.testing.assert_allclose(n, expected, rtol=1e-10, atol=1e-12)
    # partialised: resultants still equal (N, m1, m2)
    n = no_tension_normal_forces(seed_interface, DRY, N, 15.0, 0.0)
    assert np.any(n == 0.0)
    np.testing.assert_allclose([n.sum(), y2 @ n, -(y1 @ n)], [N, 15.0, 0.0], atol=1e-9)
