"""Small walls on which Clarabel failed: a finite compressive strength with the resultant model
(nonsymmetric power cones stalled) and a fixed-capacity iteration (a re-solve kept the
equilibration of the first data). Each now solves with a certificate and matches an
independent expectation. The cones that replace power cones, and the fixed-capacity cones per
unit capacity, against closed forms."""

import cvxpy as cp
import numpy as np
import pytest

from dem.scenes.return_walls import wall_with_returns
from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import RESTREPO_BLOCK_MM, RESTREPO_MU, RESTREPO_UNIT_WEIGHT
from limit import estimates
from limit.clarabel import solve_static
from limit.cones import power_mean, rational_exponent
from limit.estimates import iterative_estimate
from limit.problems import LimitSettings, build_static_problem
from limit.solve import limit_analysis


def _restrepo_wall(n_per_course: int, n_courses: int, **kw):
    """A wall of the Restrepo-Velez blocks (28 x 80 x 40 mm), mu = 0.7, on a foundation."""
    unit = (*RESTREPO_BLOCK_MM, RESTREPO_UNIT_WEIGHT)
    return running_bond_wall(n_per_course, n_courses, *unit, mu=RESTREPO_MU, **kw)


def _crushing(fc):
    return LimitSettings(interface_model="resultant", mu=RESTREPO_MU, compressive_strength=fc)


def test_compressive_strength_on_a_wall_with_a_fixed_column_is_certified():
    """4 x 13 wall held by a fixed column at its left end, f_c = 3 MPa, resultant model
    (Clarabel ended ``InsufficientProgress`` on it when the stress block was a power cone).
    Independent expectations: SCS (a first-order splitting solver) on the same programme, and
    the order of the admissible sets, f_c = 0.3 MPa inside 3 MPa inside unlimited."""
    scene = _restrepo_wall(4, 13, fixed_columns=("left",))
    res = limit_analysis(scene, _crushing(3.0e6))
    assert res.certificate.worst() <= res.settings["cert_tol"]
    sp_ = build_static_problem(scene, _crushing(3.0e6))
    sp_.problem.solve(solver=cp.SCS, eps_abs=1e-6, eps_rel=1e-6, max_iters=100_000)
    assert sp_.problem.status == "optimal"
    np.testing.assert_allclose(res.lam, float(sp_.lam.value) * sp_.lam_scale, rtol=1e-3)
    weaker = limit_analysis(scene, _crushing(0.3e6)).lam
    unlimited = limit_analysis(scene, _crushing(None)).lam
    tol = res.lambda_estimate.error
    assert weaker <= res.lam + tol and res.lam <= unlimited + tol
    assert weaker < unlimited  # crushing matters on this wall


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_a_resolve_is_a_fresh_solve(model):
    """Solving a programme again with new parameter values gives what a newly built programme
    with those values gives, to the last bit and in as many Clarabel iterations (a re-solve
    that reused the previous solver kept its equilibration: other iterates, other result)."""
    scene = _restrepo_wall(4, 5, fixed_columns=("left",))
    settings = LimitSettings(interface_model=model, mu=RESTREPO_MU)
    start = limit_analysis(scene, settings)
    reused = build_static_problem(scene, settings, friction="fixed_capacity")
    cap = estimates._normal_capacity(reused, start)
    estimates._set_capacity(reused, np.full_like(cap, cap.mean()), reused.mu_interface)
    solve_static(reused)
    estimates._set_capacity(reused, cap, reused.mu_interface)
    again = solve_static(reused)
    fresh = build_static_problem(scene, settings, friction="fixed_capacity")
    estimates._set_capacity(fresh, cap, fresh.mu_interface)
    first = solve_static(fresh)
    assert again.lam == first.lam
    assert reused.problem.solver_stats.num_iters == fresh.problem.solver_stats.num_iters


def test_fixed_capacity_iteration_on_a_wall_with_a_return_wall(monkeypatch):
    """Estimate (b) of a 4 x 7 wall with a 3-block return wall, resultant model (it stopped at
    its second update with Clarabel's ``solver_error``). Independent expectation: each
    update's multiplier equals that of a newly built programme with the same capacities."""
    scene = wall_with_returns(
        4, 7, *RESTREPO_BLOCK_MM, RESTREPO_UNIT_WEIGHT, mu=RESTREPO_MU, return_blocks=3
    )
    settings = LimitSettings(interface_model="resultant", mu=RESTREPO_MU)
    used = []
    set_capacity = estimates._set_capacity

    def recording(fixed, cap_n, mu):
        used.append(cap_n.copy())
        set_capacity(fixed, cap_n, mu)

    monkeypatch.setattr(estimates, "_set_capacity", recording)
    est = iterative_estimate(scene, settings, max_updates=3)
    assert est.failure == "" and est.n_iter == 3
    assert est.result.certificate.worst() <= settings.cert_tol
    for lam, cap_n in zip(est.history[1:], used, strict=True):
        fresh = build_static_problem(scene, settings, friction="fixed_capacity")
        set_capacity(fresh, cap_n, fresh.mu_interface)
        np.testing.assert_allclose(lam, solve_static(fresh).lam, rtol=1e-12)


@pytest.mark.parametrize("p", [2.0 / 3.0, 0.5, 3.0 / 5.0, 1.0 / 1.7])
def test_power_mean_is_the_power_cone(p):
    """max t s.t. |t| <= x^p y^(1-p) for fixed x, y, whether written as rotated second-order
    cones (p = r/s with s <= 8) or as one power cone (1/1.7 = 10/17): x^p y^(1-p)."""
    x, y = np.array([0.3, 2.0, 1e-3]), np.array([1.0, 0.05, 40.0])
    t = cp.Variable(3)
    cons = power_mean(t, x, y, p, 3)
    assert (rational_exponent(p) is None) == any(isinstance(c, cp.PowCone3D) for c in cons)
    cp.Problem(cp.Maximize(cp.sum(t)), cons).solve(solver=cp.CLARABEL)
    np.testing.assert_allclose(t.value, x**p * y ** (1 - p), rtol=1e-7)
    cp.Problem(cp.Minimize(cp.sum(t)), cons).solve(solver=cp.CLARABEL)
    np.testing.assert_allclose(t.value, -(x**p) * y ** (1 - p), rtol=1e-7)


@pytest.mark.parametrize("torsion", ["interaction", "independent"])
@pytest.mark.parametrize("capacity", [1e-2, 1e-6, 0.0])
def test_fixed_capacities_down_to_zero(torsion, capacity):
    """Fixed-capacity programme (resultant model), closed forms: a squat block (b/h = 3)
    pushed sideways slides at lambda W = C_s; a block under a unit torque twists at
    lambda = C_t [N m]; each within the result's own error bar. A vanishing capacity (an
    open joint of the previous iterate) gives lambda = 0."""
    from tests.limit._scenes import block_on_ground, torsion_pair

    settings = LimitSettings(interface_model="resultant", torsion=torsion, dead_load_check=False)
    for scene, kind in (
        (block_on_ground(0.6, 0.6, 0.2, mu=0.7), "shear"),
        (torsion_pair(), "torsion"),
    ):
        fixed = build_static_problem(scene, settings, friction="fixed_capacity")
        big = 1e3  # the other capacity never governs
        fixed.capacity["shear"].value = np.array([capacity if kind == "shear" else big])
        fixed.capacity["torsion"].value = np.array([capacity if kind == "torsion" else big])
        res = solve_static(fixed)
        # capacities are scaled by W (shear) and W L (torsion); the torque load is 1 N m
        unit = 1.0 if kind == "shear" else fixed.weight * fixed.length
        assert abs(res.lam - capacity * unit) <= res.lambda_estimate.error
