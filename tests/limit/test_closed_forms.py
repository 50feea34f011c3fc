"""Closed-form collapse multipliers, both interface models, with their certificates."""

import numpy as np
import pytest

from dem.scene import Scene, proportional_to_weight
from dem.scenes.running_bond_wall import running_bond_wall
from limit.errors import LimitAnalysisError
from limit.matrices import mean_distance_polygon
from limit.problems import LimitSettings
from limit.solve import limit_analysis
from tests.limit._scenes import GROUND, block_on_ground, box, harmonic_stack, torsion_pair

MODELS = ("vertex", "resultant")
RTOL = 1e-6


def _certified(result):
    cert = result.certificate
    assert cert.equilibrium_residual < 1e-8
    assert cert.primal_residual < 1e-7
    assert abs(cert.duality_gap) < 1e-7
    assert cert.stationarity < 1e-7
    assert cert.dual_cone_residual < 1e-7


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize(("width", "height", "mu"), [(0.2, 0.5, 0.7), (0.4, 0.5, 0.3)])
def test_single_block_min_mu_b_over_h(model, width, height, mu):
    """A block on the ground pushed by a fraction lambda of its weight: sliding at
    lambda = mu, overturning about its edge at lambda = b/h; collapse at the smaller."""
    scene = block_on_ground(width, 0.3, height, mu)
    res = limit_analysis(scene, LimitSettings(interface_model=model))
    np.testing.assert_allclose(res.lam, min(mu, width / height), rtol=RTOL)
    _certified(res)
    # associated flow: kinematic multiplier from the dual velocities equals lambda
    np.testing.assert_allclose(-res.dead_power, res.lam, rtol=1e-6)


@pytest.mark.parametrize("model", MODELS)
def test_free_standing_wall_s_over_h(model):
    """A free-standing running-bond wall (thickness s, height H) under out-of-plane load
    proportional to its weight overturns as a whole about the base edge at lambda = s/H
    (any rocking joint higher up gives s / (H - z) > s/H)."""
    s_mm, a_mm, nc = 100.0, 50.0, 6
    scene = running_bond_wall(4, nc, a_mm, 200.0, s_mm, 20.0, mu=0.7)
    res = limit_analysis(scene, LimitSettings(interface_model=model))
    np.testing.assert_allclose(res.lam, s_mm / (nc * a_mm), rtol=RTOL)
    _certified(res)


def test_pure_torsion_vertex_model():
    """Vertex model, pure torsion of the seed's 0.3 x 0.2 m interface under N = 240 N:
    every corner slides perpendicular to its radius, m_3 = mu N sqrt(0.15^2 + 0.1^2)
    = 30.29 N m."""
    res = limit_analysis(torsion_pair(), LimitSettings(interface_model="vertex"))
    expected = 0.7 * 240.0 * np.hypot(0.15, 0.1)
    np.testing.assert_allclose(res.lam, expected, rtol=RTOL)
    assert abs(expected - 30.29) < 5e-3
    _certified(res)


@pytest.mark.parametrize("torsion", ["interaction", "independent"])
def test_pure_torsion_uniform_pressure(torsion):
    """Uniform-pressure model: m_3u = c_T mu N with c_T the mean distance to the centroid
    (seed 001 Eq. 11-12): 16.26 N m for the seed's interface."""
    res = limit_analysis(
        torsion_pair(), LimitSettings(interface_model="resultant", torsion=torsion)
    )
    l1, l2 = 0.3, 0.2
    d = np.hypot(l1, l2)
    c_t = (
        d + l1**2 / (2 * l2) * np.log((l2 + d) / l1) + l2**2 / (2 * l1) * np.log((l1 + d) / l2)
    ) / 6
    np.testing.assert_allclose(res.lam, c_t * 0.7 * 240.0, rtol=RTOL)
    assert abs(res.lam - 16.26) < 5e-3
    _certified(res)


@pytest.mark.parametrize("model", MODELS)
def test_harmonic_overhang(model):
    """Classical harmonic stack (n blocks of length L, overhangs L/(2k)): it stands at
    (1 - eps) of the classical overhang and falls at (1 + eps)."""
    eps = 1e-3
    stands = limit_analysis(harmonic_stack(4, factor=1 - eps), LimitSettings(interface_model=model))
    assert stands.lam >= 0
    with pytest.raises(LimitAnalysisError, match="falls down by itself"):
        limit_analysis(harmonic_stack(4, factor=1 + eps), LimitSettings(interface_model=model))


def _sliding_block(theta: float, mu: float = 0.5):
    """A flat block (it cannot overturn) on the ground, live load = its weight at ``theta``
    from x in the horizontal plane."""
    blk = box((-0.5, -0.5, 0.0), (0.5, 0.5, 0.2))
    scene = Scene.from_convex_blocks([GROUND, blk], 2000.0, fixed=[0], mu=mu)
    direction = (np.cos(theta), np.sin(theta), 0.0)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, direction))


@pytest.mark.parametrize("theta_deg", [0.0, 22.5, 30.0])
def test_inscribed_polygons_are_safe_and_nested(theta_deg):
    """A sliding block carries lambda = the radius of the friction set along the load: mu for
    the exact cone; for the inscribed k-gon with corners at 2 pi j / k from x,
    mu cos(pi/k) / cos(theta - phi) with phi the nearest facet normal (2 pi (j + 1/2) / k).
    k = 4, 8, 16 are nested, so lambda rises monotonically towards mu."""
    mu, theta = 0.5, np.radians(theta_deg)
    scene = _sliding_block(theta, mu)
    exact = limit_analysis(scene, LimitSettings()).lam
    np.testing.assert_allclose(exact, mu, rtol=RTOL)
    previous = 0.0
    for k in (4, 8, 16):
        lam = limit_analysis(scene, LimitSettings(friction_polygon=k)).lam
        phi = 2 * np.pi * (np.round(theta * k / (2 * np.pi) - 0.5) + 0.5) / k
        np.testing.assert_allclose(lam, mu * np.cos(np.pi / k) / np.cos(theta - phi), rtol=RTOL)
        assert previous <= lam * (1 + 1e-8) and lam <= exact * (1 + 1e-8)
        previous = lam


def test_mean_distance_independent_of_vertex_order():
    poly = np.array([[0, 0], [0.3, 0], [0.3, 0.2], [0, 0.2]])
    assert mean_distance_polygon(poly) == pytest.approx(mean_distance_polygon(poly[::-1]))


@pytest.mark.parametrize("model", MODELS)
def test_tensile_strength_closed_forms(model):
    """Mortar joint with tensile strength sigma_t (Coulomb apex at sigma_t, seed 001
    Eq. 8-10): a squat block slides at lambda W = mu (W + sigma_t A); a block hanging under a
    fixed block, pulled down by lambda W, detaches at (1 + lambda) W = sigma_t A."""
    from dem.scene import Scene, proportional_to_weight
    from tests.limit._scenes import GROUND, box

    sigma_t, mu = 2.0e3, 0.5
    scene = block_on_ground(1.0, 1.0, 0.2, mu)
    weight = scene.assembly.mass[1] * 9.81
    settings = LimitSettings(interface_model=model, tensile_strength=sigma_t)
    res = limit_analysis(scene, settings)
    np.testing.assert_allclose(res.lam, mu * (1 + sigma_t * 1.0 / weight), rtol=RTOL)
    _certified(res)
    # hang a 0.4 x 0.3 x 0.5 m block under the fixed block (its bottom face is z = -1)
    sigma_t = 2.0e4
    settings = LimitSettings(interface_model=model, tensile_strength=sigma_t)
    blocks = [GROUND, box((-0.2, -0.15, -1.5), (0.2, 0.15, -1.0))]
    sc = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=mu)
    sc = sc.with_loads(live=proportional_to_weight(sc.assembly, (0.0, 0.0, -1.0)))
    w2 = sc.assembly.mass[1] * 9.81
    res = limit_analysis(sc, settings)
    np.testing.assert_allclose(res.lam, sigma_t * 0.4 * 0.3 / w2 - 1.0, rtol=RTOL)
    _certified(res)


def test_validation_case_closed_forms_quick():
    """Smoke test of ``python -m validation run limit-closed-forms --quick``: every row meets
    its closed form to 1e-6."""
    from validation.cases.limit import CASES

    rows, notes = CASES["limit-closed-forms"](quick=True)
    assert len(rows) >= 20 and notes
    for row in rows:
        assert row.rel_error is not None and row.rel_error < 1e-6, row.quantity


def test_torsion_bending_is_below_the_reduced_rectangle():
    """Resultant model with ``torsion_bending``: under an eccentric normal force (e along
    t1) the torsion capacity stays below the uniform-stress capacity of the reduced rectangle
    mu c c_T(l1 - 2|e|, l2) (seed 001 Fig. 10, Orduna & Lourenco 2005a) and equals it at
    e = 0 (the tangent plane touches there)."""
    from tests.limit._scenes import torsion_pair

    def c_t(l1, l2):
        d = np.hypot(l1, l2)
        return (
            d + l1**2 / (2 * l2) * np.log((l2 + d) / l1) + l2**2 / (2 * l1) * np.log((l1 + d) / l2)
        ) / 6

    scene = torsion_pair()
    c = 240.0
    for ecc in (0.0, 0.05):
        dead = np.zeros((2, 6))
        dead[1, 4] = c * ecc  # a couple about y moves the centre of pressure along x
        sc = scene.with_loads(dead=dead)
        s = LimitSettings(interface_model="resultant", torsion="independent", torsion_bending=True)
        lam = limit_analysis(sc, s).lam
        reduced = 0.7 * c * c_t(0.3 - 2 * ecc, 0.2)
        if ecc == 0.0:
            np.testing.assert_allclose(lam, reduced, rtol=1e-6)
        else:
            assert 0.7 * reduced < lam < reduced
