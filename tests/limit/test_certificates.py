"""Certificates reject wrong answers: a perturbed force, a violated cone, a wrong lambda, a
suboptimal point, wrong duals. Each check is fed a solution known to be wrong.

The expectation is independent of the solver: the correct point of the reference problem
(a block overturning at lambda = b / h) passes every check to ``cert_tol``; each deliberate
error is large (5-20 %), so the residual that measures it must exceed ``cert_tol`` by orders
of magnitude.
"""

import cvxpy as cp
import numpy as np
import pytest

from limit.certificates import conic_certificate
from limit.clarabel import solve_static, static_certificate
from limit.problems import LimitSettings, build_static_problem
from tests.limit._scenes import block_on_ground

TOL = LimitSettings().cert_tol


@pytest.fixture(params=["vertex", "resultant"])
def solved(request):
    """A solved programme (b / h = 0.5, overturning) and its certified result."""
    sp_ = build_static_problem(
        block_on_ground(0.4, 0.3, 0.8, mu=0.7), LimitSettings(interface_model=request.param)
    )
    res = solve_static(sp_)
    assert res.lam == pytest.approx(0.5, rel=1e-6)
    assert res.certificate.worst() <= TOL
    return sp_, res


def _certificate(sp_, lam=None):
    f = sp_.interface_forces()
    vf = None
    if sp_.model == "vertex":
        vf = np.stack([np.ravel(v.value) for v in sp_.x_vars[:3]], axis=1) * sp_.weight
    return static_certificate(sp_, f, vf, sp_.lam_scale * sp_.lam.value if lam is None else lam)


def test_a_perturbed_force_is_rejected(solved):
    sp_, _ = solved
    x = sp_.x_vars[1]  # s1 (vertex) or V1 (resultant): a tangential force
    x.save_value(x.value + 0.1 * np.max(np.abs(sp_.x_vars[0].value)))
    cert = _certificate(sp_)
    assert cert.equilibrium_residual > 1e3 * TOL
    assert cert.primal_residual > 1e3 * TOL


def test_a_violated_cone_is_rejected(solved):
    """Normal forces scaled by 0.8 with the shear kept: |V| > mu c at the corner or joint
    that carries the push (and equilibrium fails too)."""
    sp_, _ = solved
    normal = sp_.x_vars[0]
    normal.save_value(0.8 * normal.value)
    cert = _certificate(sp_)
    assert cert.yield_residual > 1e3 * TOL or cert.primal_residual > 1e3 * TOL
    assert cert.worst() > 1e3 * TOL


def test_a_wrong_lambda_is_rejected(solved):
    sp_, _ = solved
    sp_.lam.save_value(1.05 * sp_.lam.value)
    cert = _certificate(sp_)
    assert cert.equilibrium_residual > 1e3 * TOL
    assert abs(cert.duality_gap) > 1e3 * TOL


def test_a_feasible_but_suboptimal_point_is_caught_by_the_gap_alone(solved):
    """An equilibrium at 0.8 lambda* inside every cone passes every primal check; only the
    duality gap (with the optimal duals) shows that it is not the optimum."""
    sp_, _ = solved
    optimal_duals = [[d.value for d in c.dual_variables] for c in sp_.problem.constraints]
    capped = cp.Problem(
        sp_.problem.objective, [*sp_.problem.constraints, sp_.lam <= 0.8 * sp_.lam.value]
    )
    capped.solve(solver=cp.CLARABEL)
    for c, zs in zip(sp_.problem.constraints, optimal_duals, strict=True):
        for d, z in zip(c.dual_variables, zs, strict=True):
            d.save_value(z)
    cert = _certificate(sp_)
    assert cert.equilibrium_residual <= TOL and cert.primal_residual <= TOL
    assert cert.yield_residual <= TOL
    assert cert.duality_gap > 0.1


def test_wrong_duals_are_rejected(solved):
    """The equilibrium duals (the mechanism) scaled by 1.2: stationarity fails."""
    sp_, _ = solved
    eq = sp_.equilibrium
    eq.save_dual_value(1.2 * eq.dual_value)
    cert = conic_certificate(sp_.problem)
    assert cert["stationarity"] > 1e3 * TOL


def test_a_dual_outside_its_cone_is_rejected(solved):
    """A second-order-cone dual pushed outside the dual cone (|x| > t)."""
    sp_, _ = solved
    soc = next(c for c in sp_.problem.constraints if isinstance(c, cp.constraints.SOC))
    t = soc.dual_variables[0]
    t.save_value(-(np.abs(t.value) + 1.0))
    cert = conic_certificate(sp_.problem)
    assert cert["dual_cone_residual"] > 1e3 * TOL


@pytest.mark.parametrize(
    ("duals", "expected_shift"),
    [((0.9, 0.0), 0.1 * 0.95), ((1.07, -0.07), 0.07 * 1.05)],
    ids=["off stationarity", "off its cone"],
)
def test_the_dual_shifts_lift_an_inexact_dual_bound_to_the_optimum(duals, expected_shift):
    """max x s.t. x <= 1, x <= 2 (optimum 1) at the feasible x = 0.95 with hand-set duals
    whose bound z^T h lies below the optimum: (0.9, 0) misses stationarity by r = 0.1,
    (1.07, -0.07) has a negative inequality dual (distance 0.07, |g_2(x)| = 1.05). The bar of
    x from the gap alone does not reach 1; with the shifts |r| |x| + dist(z, K*) |g(x)|
    it does (the stationarity shift in the first case, the dual-cone shift in the second)."""
    x = cp.Variable(name="x")
    problem = cp.Problem(cp.Maximize(x), [x <= 1, x <= 2])
    x.save_value(np.array(0.95))
    for c, y in zip(problem.constraints, duals, strict=True):
        c.save_dual_value(np.array(y))
    cert = conic_certificate(problem)
    gap = abs(cert["dual_objective"] - 0.95)
    assert 0.95 + gap < 1.0
    shift = cert["stationarity_shift"] + cert["dual_cone_shift"]
    assert shift == pytest.approx(expected_shift, rel=1e-12)
    assert 0.95 + gap + shift >= 1.0
