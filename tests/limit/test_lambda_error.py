"""The error bar of the limit-analysis multiplier (limit.lambda_error) against closed forms."""

import math

import numpy as np
import pytest

from limit import LimitSettings, bounds_and_estimates, limit_analysis
from limit.clarabel import solve_static, static_certificate
from limit.lambda_error import iteration_tail, outer_polygon_factor, solver_estimate
from limit.problems import build_static_problem
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
    assert set(est.sources) == {"duality gap", "feasibility"}


def test_bar_holds_the_pure_torsion_closed_form():
    """Vertex model, pure torsion: m_3 = mu N sqrt(0.15^2 + 0.1^2) (seed 001 Sec. 2.1)."""
    est = limit_analysis(torsion_pair()).lambda_estimate
    assert est.contains(0.7 * 240.0 * math.hypot(0.15, 0.1))


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
    the inscribed polygon gives less. Its bracket (cheap) and its measured error (full) both
    hold mu; the full bar is the true error to the solver's tolerance."""
    mu = 0.5
    scene = _sliding_block(np.radians(theta_deg), mu)
    settings = LimitSettings(friction_polygon=sides)
    cheap = limit_analysis(scene, settings, error="cheap").lambda_estimate
    full = limit_analysis(scene, settings, error="full").lambda_estimate
    true = mu - cheap.value
    for est in (cheap, full):
        assert est.contains(mu)
        assert est.cost_s > 0
    # the bracket's width is at most the outer polygon's excess over the inscribed one
    assert cheap.error <= cheap.value * (outer_polygon_factor(sides) - 1) + 1e-7
    assert full.error == pytest.approx(true, abs=1e-7)


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
    data = b.to_dict()
    assert data["upper_estimate"]["value"] == b.upper
