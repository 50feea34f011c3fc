"""An in-plane running-bond wall (Restrepo-Velez blocks, mu 0.7, live load = weight along +x):
the associated programme of the resultant model, torsion interaction with alpha = 1.5."""

import cvxpy as cp
import pytest

from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import RESTREPO_BLOCK_MM, RESTREPO_MU, RESTREPO_UNIT_WEIGHT
from limit import cones
from limit.clarabel import solve_static
from limit.problems import LimitSettings, build_static_problem


def _in_plane_wall(n_per_course: int, n_courses: int):
    return running_bond_wall(
        n_per_course, n_courses, *RESTREPO_BLOCK_MM, RESTREPO_UNIT_WEIGHT, mu=RESTREPO_MU,
        live="in_plane",
    )  # fmt: skip


@pytest.fixture(scope="module")
def wall():
    return _in_plane_wall(8, 12)


def test_first_attempt_is_certified_and_the_power_cone_form_agrees(wall, monkeypatch):
    """The torsion bound written with rotated second-order cones is solved optimal and
    certified by the first Clarabel attempt; the same set written as one 3D power cone per
    joint (exponent not rewritten) has its optimum inside that result's bar and vice versa."""
    settings = LimitSettings(interface_model="resultant")
    soc_problem = build_static_problem(wall, settings)
    assert not any(isinstance(c, cp.constraints.PowCone3D) for c in soc_problem.problem.constraints)
    soc = solve_static(soc_problem)
    assert soc.attempts == [("refined", "optimal")]
    assert soc.certificate.worst() <= settings.cert_tol
    monkeypatch.setattr(cones, "rational_exponent", lambda p: None)
    pow_problem = build_static_problem(wall, settings)
    assert any(isinstance(c, cp.constraints.PowCone3D) for c in pow_problem.problem.constraints)
    powered = solve_static(pow_problem)
    assert soc.lambda_estimate.overlaps(powered.lambda_estimate)
    assert abs(soc.lam - powered.lam) <= soc.lambda_estimate.error + powered.lambda_estimate.error
