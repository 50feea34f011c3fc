"""Tresca packings of seed 003: closed-form checks of the LP forces and their certificates."""

from __future__ import annotations

import numpy as np
import pytest

from limit.errors import DeadLoadInfeasibleError, NoMechanismError, NumericalFailureError
from limit.tresca import (
    TrescaSettings,
    _accept,
    admissibility_residuals,
    forces_from_uniform_stress,
    solve_tresca,
)
from limit.voronoi_packing import (
    brick_wall_packing,
    uniform_stress_traction,
    verification_packing,
    voronoi_packing,
    voronoi_packing_from_seeds,
)

S_TRESCA = 10.0  # Tresca threshold [Pa], 10x the imposed pressure: friction never binds


@pytest.mark.parametrize("name", ["four-cells", "five-cells"])
def test_uniform_compression_recovers_imposed_normal_stress(name):
    # closed form: sigma = -p I on the boundary -> sigma_nn = -p, shear 0 on every internal edge
    p = 1.0
    packing = verification_packing(name)
    traction = uniform_stress_traction(packing, -p * np.eye(2))
    res = solve_tresca(packing, traction, S_TRESCA, TrescaSettings(selection="min_energy"))
    np.testing.assert_allclose(res.normal_stress, -p, rtol=1e-9)
    np.testing.assert_allclose(res.shear_stress, 0.0, atol=1e-9 * p)
    assert res.equilibrium_residual < 1e-9
    assert abs(res.duality_gap) < 1e-8
    assert res.primal_residual < 1e-8


def test_four_cells_raw_interior_point_duals_are_uniform():
    # the 4-cell problem is symmetric under both mirror lines, so the interior-point (central
    # path) duals are the symmetric force set: sigma_nn = -1 on all four edges (seed 003 Fig. 6)
    packing = verification_packing("four-cells")
    traction = uniform_stress_traction(packing, -np.eye(2))
    res = solve_tresca(packing, traction, S_TRESCA, TrescaSettings(solver="CLARABEL"))
    np.testing.assert_allclose(res.normal_stress, -1.0, rtol=1e-6)


def test_general_uniform_stress_on_random_voronoi():
    # closed form: edge tractions of a uniform stress sigma0 are n.sigma0.n and -t.sigma0.n
    sigma0 = np.array([[-2.0, 0.3], [0.3, -1.0]])
    packing = voronoi_packing(12, 1.0, 0.5, seed=7)
    traction = uniform_stress_traction(packing, sigma0)
    res = solve_tresca(packing, traction, S_TRESCA, TrescaSettings(selection="min_energy"))
    n, t = packing.edge_normal, packing.edge_tangent
    expected_nn = np.einsum("ei,ij,ej->e", n, sigma0, n)
    expected_t = -np.einsum("ei,ij,ej->e", t, sigma0, n)
    np.testing.assert_allclose(res.normal_stress, expected_nn, rtol=1e-7, atol=1e-7)
    np.testing.assert_allclose(res.shear_stress, expected_t, atol=1e-7)


def test_uniform_stress_forces_are_admissible_on_60_cells():
    # seed 003 Sec. 4.5: the constant stress -I is an admissible maximiser of the dual
    packing = voronoi_packing(60, 1.0, 1.0, seed=0)
    traction = uniform_stress_traction(packing, -np.eye(2))
    lam, f_t = forces_from_uniform_stress(packing, -np.eye(2))
    eq, fr = admissibility_residuals(packing, traction, S_TRESCA, lam, f_t)
    assert eq < 1e-12 and fr <= 0.0
    res = solve_tresca(packing, traction, S_TRESCA)
    assert res.equilibrium_residual < 1e-6 and res.friction_residual < 1e-6


def test_brick_wall_shear_capacity_is_the_tresca_threshold():
    # closed form: a horizontal bed joint spans the wall, so shear tau is carried iff tau <= s
    s = 1.0
    wall = brick_wall_packing(n_courses=4, bricks_per_course=3, brick_length=0.2, brick_height=0.1)
    ok = solve_tresca(wall, uniform_stress_traction(wall, [[-1.0, 0.9], [0.9, -1.0]]), s)
    assert np.all(np.abs(ok.shear_stress) <= s * (1 + 1e-6))
    with pytest.raises(DeadLoadInfeasibleError, match="unbounded"):
        solve_tresca(wall, uniform_stress_traction(wall, [[-1.0, 1.1], [1.1, -1.0]]), s)


@pytest.mark.parametrize("solver", ["HIGHS", "CLARABEL"])
def test_tensile_load_raises(solver):
    packing = verification_packing("four-cells")
    traction = uniform_stress_traction(packing, np.eye(2))
    with pytest.raises(DeadLoadInfeasibleError, match="unbounded"):
        solve_tresca(packing, traction, S_TRESCA, TrescaSettings(solver=solver))


def test_status_map():
    class _Fake:
        status = "optimal_inaccurate"

    with pytest.warns(RuntimeWarning, match="optimal_inaccurate"):
        assert _accept(_Fake(), "x", "") is True
    _Fake.status = "infeasible"
    with pytest.raises(DeadLoadInfeasibleError, match="infeasible"):
        _accept(_Fake(), "x", "")
    _Fake.status = "unbounded"
    with pytest.raises(NoMechanismError, match="unbounded"):
        _accept(_Fake(), "x", "", unbounded=NoMechanismError)
    _Fake.status = "solver_error"
    with pytest.raises(NumericalFailureError, match="solver_error"):
        _accept(_Fake(), "x", "")


def test_voronoi_geometry_closed_form():
    width, height = 2.0, 1.0
    packing = voronoi_packing(20, width, height, seed=3)
    np.testing.assert_allclose(packing.cell_area.sum(), width * height, rtol=1e-12)
    np.testing.assert_allclose(packing.bnd_length.sum(), 2 * (width + height), rtol=1e-12)
    # Voronoi: the edge normal is parallel to the seed-to-seed vector
    d = packing.centres[packing.edge_cells[:, 1]] - packing.centres[packing.edge_cells[:, 0]]
    cos = np.sum(d * packing.edge_normal, axis=1) / np.linalg.norm(d, axis=1)
    np.testing.assert_allclose(cos, 1.0, atol=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n_cells": 10, "width": 0.0, "height": 1.0}, "width"),
        ({"n_cells": 10, "width": 1.0, "height": -1.0}, "height"),
        ({"n_cells": 10, "width": np.nan, "height": 1.0}, "width"),
        ({"n_cells": 1, "width": 1.0, "height": 1.0}, "n_cells"),
    ],
)
def test_bad_packing_inputs(kwargs, match):
    with pytest.raises(ValueError, match=match):
        voronoi_packing(seed=0, **kwargs)


def test_bad_seeds_and_loads():
    with pytest.raises(ValueError, match="n_cells"):
        voronoi_packing_from_seeds(np.array([[0.5, 0.5]]), 1.0, 1.0)
    with pytest.raises(ValueError, match="inside the rectangle"):
        voronoi_packing_from_seeds(np.array([[0.5, 0.5], [1.5, 0.5]]), 1.0, 1.0)
    packing = verification_packing("four-cells")
    with pytest.raises(ValueError, match="traction"):
        solve_tresca(packing, np.zeros((3, 2)), S_TRESCA)
    unbalanced = uniform_stress_traction(packing, -np.eye(2))
    unbalanced[0] += 1.0
    with pytest.raises(ValueError, match="resultant"):
        solve_tresca(packing, unbalanced, S_TRESCA)
    with pytest.raises(ValueError, match="threshold"):
        solve_tresca(packing, uniform_stress_traction(packing, -np.eye(2)), -1.0)
    with pytest.raises(ValueError, match="solver"):
        TrescaSettings(solver="GLPK")


@pytest.mark.parametrize("solver", ["HIGHS", "CLARABEL"])
def test_brick_wall_shear_multiplier_closed_form(solver):
    # closed form: alpha* = s / 1 Pa (a full-width bed joint carries at most s per unit length)
    from limit.tresca import max_load_multiplier

    s = 0.7
    wall = brick_wall_packing(n_courses=5, bricks_per_course=3, brick_length=0.2, brick_height=0.1)
    res = max_load_multiplier(
        wall,
        uniform_stress_traction(wall, -np.eye(2)),
        uniform_stress_traction(wall, [[0.0, 1.0], [1.0, 0.0]]),
        s,
        TrescaSettings(solver=solver),
    )
    np.testing.assert_allclose(res.load_multiplier, s, rtol=1e-7)


@pytest.mark.parametrize("solver", ["HIGHS", "CLARABEL"])
def test_multiplier_outcomes_by_type(solver):
    # a pure pressure as live load never fails a jammed packing (no mechanism), and a shear above
    # the Tresca threshold as dead load is not carried at all (falls by itself), whether the live
    # load cannot help (infeasible) or only its reverse could (alpha* = 0.7 - 1 < 0): told apart
    # by type, never a negative multiplier
    from limit.tresca import max_load_multiplier

    s = 0.7
    wall = brick_wall_packing(n_courses=5, bricks_per_course=3, brick_length=0.2, brick_height=0.1)
    pressure = uniform_stress_traction(wall, -np.eye(2))
    shear = uniform_stress_traction(wall, [[0.0, 1.0], [1.0, 0.0]])
    with pytest.raises(NoMechanismError):
        max_load_multiplier(wall, pressure, pressure, s, TrescaSettings(solver=solver))
    with pytest.raises(DeadLoadInfeasibleError):
        max_load_multiplier(wall, pressure + shear, pressure, s, TrescaSettings(solver=solver))
    with pytest.raises(DeadLoadInfeasibleError, match="reversed"):
        max_load_multiplier(wall, pressure + shear, shear, s, TrescaSettings(solver=solver))


def _two_by_two_unit_squares():
    return voronoi_packing_from_seeds(
        np.array([[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [1.5, 1.5]]), 2.0, 2.0
    )


@pytest.mark.parametrize("solver", ["HIGHS", "CLARABEL"])
@pytest.mark.parametrize(
    "p, s, tau",
    [(1e5, 3e3, 1e4), (1.0, 0.03, 0.1)],
    ids=["SI", "scaled"],
)
def test_multiplier_2x2_pure_shear_closed_form(solver, p, s, tau):
    # closed form alpha* = s / tau, in any units: the uniform stress -p I + alpha tau (e1 e2 +
    # e2 e1) puts shear alpha tau on every edge, all normals compressive (lower bound), and the
    # top row sliding on the bottom one dissipates 2 s against live power 2 tau (upper bound).
    # Unscaled, Clarabel stopped at alpha = 0.0028 in SI units
    from limit.tresca import max_load_multiplier

    packing = _two_by_two_unit_squares()
    res = max_load_multiplier(
        packing,
        uniform_stress_traction(packing, -p * np.eye(2)),
        uniform_stress_traction(packing, [[0.0, tau], [tau, 0.0]]),
        s,
        TrescaSettings(solver=solver),
    )
    np.testing.assert_allclose(res.load_multiplier, s / tau, rtol=1e-7)
    np.testing.assert_allclose(res.upper_bound, s / tau, rtol=1e-7)
    assert res.duality_gap <= 1e-6
    assert res.dual_residual <= 1e-6
    assert res.equilibrium_residual <= 1e-9
    assert res.friction_residual <= 1e-6


def test_multiplier_voronoi_clarabel_agrees_with_highs():
    # another solver: HiGHS (simplex, exact vertex) on the same LP; Clarabel was 0.2 % low
    # before the programme was scaled
    from limit.tresca import max_load_multiplier

    packing = voronoi_packing(30, 1.0, 1.0, seed=3)
    dead = uniform_stress_traction(packing, -1e5 * np.eye(2))
    live = uniform_stress_traction(packing, [[1e4, 0.0], [0.0, 0.0]])
    alphas = {
        solver: max_load_multiplier(packing, dead, live, 3e3, TrescaSettings(solver=solver))
        for solver in ("HIGHS", "CLARABEL")
    }
    np.testing.assert_allclose(
        alphas["CLARABEL"].load_multiplier, alphas["HIGHS"].load_multiplier, rtol=1e-6
    )
    for res in alphas.values():
        assert res.duality_gap <= 1e-6


def test_multiplier_gap_not_closed_is_a_numerical_failure():
    # a gap tolerance below what Clarabel reaches even with tightened tolerances: an error
    # that names both solves, never an uncertified multiplier
    from limit.tresca import max_load_multiplier

    packing = voronoi_packing(30, 1.0, 1.0, seed=3)
    dead = uniform_stress_traction(packing, -np.eye(2))
    live = uniform_stress_traction(packing, [[0.1, 0.0], [0.0, 0.0]])
    with pytest.raises(NumericalFailureError, match="after 2 solves.*duality gap"):
        max_load_multiplier(packing, dead, live, 0.03, TrescaSettings(feas_tol=1e-14))
