"""The error bar of the limit-analysis multiplier (limit.lambda_error) against closed forms."""

import math

import numpy as np
import pytest

from limit import LimitSettings, bounds_and_estimates, limit_analysis
from limit.clarabel import solve_static, static_certificate
from limit.lambda_error import iteration_tail, outer_polygon_factor, solver_estimate
from limit.problems import build_static_problem
from limit.solve import polygon_bracket
from tests.limit._scenes import block_on_ground, torsion_pair
from tests.limit.test_closed_forms import _sliding_block

MODELS = ("vertex", "resultant")


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize(("width", "height", "mu"), [(0.2, 0.5, 0.7), (0.4, 0.5, 0.3)])
def test_bar_holds_the_closed_form_and_is_the_solvers_size(model, width, height, mu):
    """A block pushed by lambda times its weight collapses at min(mu, b/h); the bar holds it
    and is of the order of Clarabel's tolerance (1e-9), not a decorative percent."""
    res = limit_analysis(block_on_ground(width, 0.3, height, mu), LimitSettings(model))
    est = res.lambda_estimate
    assert est.value == res.lam
    assert est.contains(min(mu, width / height))
    assert 0 < est.error < 1e-7
    assert set(est.sources) == {"duality gap", "feasibility", "dual stationarity", "dual cone"}


def test_bar_holds_the_pure_torsion_closed_form():
    """Vertex model, pure torsion: m_3 = mu N sqrt(0.15^2 + 0.1^2) (seed 001 Sec. 2.1)."""
    est = limit_analysis(torsion_pair()).lambda_estimate
    assert est.contains(0.7 * 240.0 * math.hypot(0.15, 0.1))


@pytest.mark.parametrize(("alpha", "power_cone"), [(1.5, False), (1.7, True)])
def test_bar_holds_pure_torsion_in_either_form_of_the_interaction(alpha, power_cone):
    """Resultant model, pure torsion: m_3 = c_T mu N whatever alpha (seed 001 Eq. 11-12),
    with the torsion written as rotated second-order cones (1/1.5 = 2/3) or as a power cone
    (1/1.7 = 10/17)."""
    import cvxpy as cp

    settings = LimitSettings(interface_model="resultant", torsion_alpha=alpha)
    sp_ = build_static_problem(torsion_pair(), settings)
    assert any(isinstance(c, cp.PowCone3D) for c in sp_.problem.constraints) == power_cone
    l1, l2 = 0.3, 0.2
    d = math.hypot(l1, l2)
    c_t = (
        d + l1**2 / (2 * l2) * math.log((l2 + d) / l1) + l2**2 / (2 * l1) * math.log((l1 + d) / l2)
    ) / 6
    est = limit_analysis(torsion_pair(), settings).lambda_estimate
    assert est.contains(c_t * 0.7 * 240.0)
    assert est.error < 1e-7 * est.value


@pytest.mark.parametrize("offset", [1e-3, -1e-3, 1e-6])
def test_a_point_off_the_optimum_gets_a_bar_that_reaches_the_optimum(offset):
    """Feed the certificate a wrong multiplier (the solved forces with lambda moved by
    ``offset`` of its value): the equilibrium is then violated, and the feasibility shift must
    widen the bar to reach the exact b/h = 0.4 again."""
    scene = block_on_ground(0.2, 0.3, 0.5, 0.7)
    sp_ = build_static_problem(scene, LimitSettings())
    res = solve_static(sp_)
    wrong = res.lam * (1 + offset)
    sp_.lam.value = np.array(wrong / sp_.lam_scale)
    f = sp_.interface_forces()
    est = solver_estimate(wrong, static_certificate(sp_, f, res.vertex_forces, wrong))
    assert est.contains(0.4)
    assert est.error < 10 * abs(wrong - 0.4)


def test_no_certificate_is_an_unknown_error_not_zero():
    assert math.isinf(solver_estimate(0.3, None).error)
    res = limit_analysis(block_on_ground(0.2, 0.3, 0.5, 0.7), error="none")
    assert math.isinf(res.lambda_estimate.error)
    with pytest.raises(ValueError, match="error budget"):
        limit_analysis(block_on_ground(0.2, 0.3, 0.5, 0.7), error="some")


@pytest.mark.parametrize("theta_deg", [0.0, 10.0, 22.5, 40.0])
@pytest.mark.parametrize("sides", [4, 8])
def test_friction_polygon_bar_holds_the_exact_cone(theta_deg, sides):
    """A flat block sliding under its weight at ``theta`` carries exactly mu with the cone;
    the inscribed polygon gives less. Both budgets measure the polygon's error against the
    exact cones: the bar is the true error to the solver's tolerance. The outer polygon's
    bracket (the fallback) holds mu too, within the outer polygon's excess."""
    mu = 0.5
    scene = _sliding_block(np.radians(theta_deg), mu)
    settings = LimitSettings(friction_polygon=sides)
    cheap = limit_analysis(scene, settings, error="cheap").lambda_estimate
    full = limit_analysis(scene, settings, error="full").lambda_estimate
    true = mu - cheap.value
    for est in (cheap, full):
        assert est.contains(mu)
        assert est.cost_s > 0
        assert est.error == pytest.approx(true, abs=1e-7)
    sp_ = build_static_problem(scene, settings)
    bracket = polygon_bracket(sp_, solve_static(sp_))
    assert bracket.contains(mu)
    assert bracket.error <= bracket.value * (outer_polygon_factor(sides) - 1) + 1e-7


def test_iteration_tail_of_a_geometric_sequence_is_its_distance_to_the_limit():
    """lambda_k = 1 - 0.5^k: the tail rho/(1 - rho) |last step| is exactly 1 - lambda_k."""
    history = [1 - 0.5**k for k in range(6)]
    assert iteration_tail(history) == pytest.approx(1 - history[-1], rel=1e-12)
    assert math.isinf(iteration_tail([0.0, 1.0, 0.0, 1.0]))  # cycling: no fixed point
    assert math.isinf(iteration_tail([0.0, 1.0]))  # one step: no rate
    assert iteration_tail([0.0, 1.0], resolution=2.0) == 1.0


def test_bounds_carry_their_estimates():
    """Upper bound and estimates (a), (b) each carry a bar; the upper one holds b/h."""
    b = bounds_and_estimates(block_on_ground(0.4, 0.3, 0.5, 0.3))
    assert b.upper_estimate.contains(0.3)
    assert b.reduced_mu_estimate.value == b.reduced_mu
    assert b.reduced_mu_estimate.contains(0.3 / math.sqrt(1 + 0.3**2))
    assert math.isfinite(b.iterative.estimate.error)
    # frictionless, the block slides at once: Radenkovic's lower bound is exactly 0
    assert b.lower_estimate.value == b.lower == 0.0
    assert b.lower_estimate.contains(0.0) and b.lower_estimate.error < 1e-7
    data = b.to_dict()
    assert data["upper_estimate"]["value"] == b.upper
    assert data["lower_estimate"]["value"] == 0.0


@pytest.mark.parametrize("solver", ["HIGHS", "CLARABEL"])
@pytest.mark.parametrize(("p", "s", "tau"), [(1e5, 3e3, 1e4), (1.0, 0.03, 0.1)])
def test_tresca_multiplier_bar_holds_the_closed_form(solver, p, s, tau):
    """2 x 2 unit cells under -p I + alpha tau (e1 e2 + e2 e1): alpha* = s / tau exactly
    (seed 003; the top row slides on the bottom one). The bar holds it and is the solver's
    size (a simplex vertex of HiGHS is exact to round-off)."""
    from limit.tresca import TrescaSettings, max_load_multiplier
    from limit.voronoi_packing import uniform_stress_traction, voronoi_packing_from_seeds

    packing = voronoi_packing_from_seeds(
        np.array([[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [1.5, 1.5]]), 2.0, 2.0
    )
    res = max_load_multiplier(
        packing,
        uniform_stress_traction(packing, -p * np.eye(2)),
        uniform_stress_traction(packing, [[0.0, tau], [tau, 0.0]]),
        s,
        TrescaSettings(solver=solver),
    )
    est = res.load_multiplier_estimate
    assert est.contains(s / tau)
    assert est.error < 1e-6 * (s / tau)
    assert set(est.sources) == {"duality gap", "feasibility", "round-off"}


def test_tresca_bar_widens_for_forces_that_violate_their_rows():
    """An estimate from a result whose forces violate their rows carries that as its
    feasibility source; a result without the shift computed has an unknown error."""
    from dataclasses import replace

    from limit.tresca import TrescaSettings, max_load_multiplier
    from limit.voronoi_packing import brick_wall_packing, uniform_stress_traction

    wall = brick_wall_packing(n_courses=5, bricks_per_course=3, brick_length=0.2, brick_height=0.1)
    res = max_load_multiplier(
        wall,
        uniform_stress_traction(wall, -np.eye(2)),
        uniform_stress_traction(wall, [[0.0, 1.0], [1.0, 0.0]]),
        0.7,
        TrescaSettings(),
    )
    assert res.load_multiplier_estimate.contains(0.7)  # closed form s / 1 Pa
    assert math.isinf(replace(res, feasibility_shift=math.nan).load_multiplier_estimate.error)


def test_the_iterative_estimate_is_built_on_its_own_lam():
    """Estimate (b)'s Estimate carries ``lam`` itself (a caller that changes ``lam`` changes
    the estimate), with the last solve's sources and the iteration tail."""
    b = bounds_and_estimates(block_on_ground(0.4, 0.3, 0.5, 0.3))
    it = b.iterative
    it.lam = 3.0 * it.lam
    assert it.estimate.value == it.lam
    assert "iteration" in it.estimate.sources


@pytest.mark.parametrize("dual", [0.9, 1.0, 1.3])
def test_duals_that_are_not_stationary_widen_the_bound_by_the_stationarity_shift(dual):
    """max x s.t. x <= 2 (optimum 2), its dual replaced by ``dual``: the dual objective
    2 dual misses the optimum for dual < 1, and the stationarity shift |1 - dual| x at the
    returned point restores the bound; exact duals shift nothing."""
    import cvxpy as cp

    from limit.certificates import conic_certificate

    x = cp.Variable()
    problem = cp.Problem(cp.Maximize(x), [x <= 2.0])
    problem.solve(solver=cp.CLARABEL)
    problem.constraints[0].save_dual_value(np.array(dual))
    cert = conic_certificate(problem)
    assert cert["dual_objective"] == pytest.approx(2.0 * dual, rel=1e-7)
    assert cert["stationarity_shift"] == pytest.approx(abs(1.0 - dual) * 2.0, abs=1e-7)
    assert cert["dual_objective"] + cert["stationarity_shift"] >= 2.0 - 1e-7
