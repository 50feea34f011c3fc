"""Small walls on which Clarabel failed: a finite compressive strength with the resultant model
(nonsymmetric power cones stalled) and a fixed-capacity iteration (a re-solve kept the
equilibration of the first data). Each now solves with a certificate and matches an
independent expectation."""

import cvxpy as cp
import numpy as np
import pytest

from dem.scenes.return_walls import wall_with_returns
from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import RESTREPO_BLOCK_MM, RESTREPO_MU, RESTREPO_UNIT_WEIGHT
from limit import estimates
from limit.clarabel import solve_static
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
