"""Error bars of the FEM check (fem_check.error) against closed forms."""

import math

import numpy as np
import pytest

from dem.geometry.polyhedron import convex_block
from fem_check.elastic import BlockSolver, ElasticMaterial
from fem_check.error import (
    FULL_RATIO,
    cut_check,
    level_estimate,
    reference_solvers,
    solve_with_error,
)
from fem_check.loads import BlockLoad, TractionPatch
from fem_check.mesh import MeshSettings

L, C, D = 6e-3, 1e-3, 1e-3  # bar [0, L] x [-C, C] x [-D, D] [m]
A = 1e9  # bending gradient: sigma_xx = A y [Pa/m]
MATERIAL = ElasticMaterial(20e9, 0.25)


def _bar():
    return convex_block(np.array([(x, y, z) for x in (0, L) for y in (-C, C) for z in (-D, D)]))


def _cap(x):
    return np.array([(x, -C, -D), (x, C, -D), (x, C, D), (x, -C, D)], float)


def _pure_bending():
    """End tractions t = +-A y e_x (spin -+A e_z about each cap centre): Saint-Venant's pure
    bending, sigma_xx = A y and nothing else, exactly (linear: P2 reproduces it)."""
    return BlockLoad(
        patches=(
            TractionPatch(_cap(L), np.zeros(3), np.array([0, 0, -A]), np.array([L, 0, 0])),
            TractionPatch(_cap(0.0), np.zeros(3), np.array([0, 0, A]), np.zeros(3)),
        )
    )


@pytest.mark.parametrize("order", [1.0, 2.0, 3.0])
def test_full_bar_of_a_converging_sequence_holds_the_limit(order):
    """s_h = 1 + 0.3 h^p on h, r h, r^2 h (r = sqrt 2): the grid convergence index with the
    observed order p (capped at the formal order 2) is 1.25 times the true error for p <= 2
    and 1.25 (r^p - 1) / (r^2 - 1) = 2.3 times it for p = 3: it holds the limit 1, within
    10x. The cheap bar |s_h - s_2h| holds it too."""
    h = 0.1
    r = FULL_RATIO
    values = [1 + 0.3 * (h * r**k) ** order for k in range(3)]
    est = level_estimate(values, "full", formal_order=2.0)
    true = values[0] - 1.0
    used = min(order, 2.0)
    assert est.contains(1.0)
    expected = 1.25 * (r**order - 1) / (r**used - 1) * true + 1e-9 * values[0]
    np.testing.assert_allclose(est.error, expected, rtol=1e-9)
    assert est.error <= 10 * true
    cheap = level_estimate([values[0], 1 + 0.3 * (2 * h) ** order], "cheap")
    assert cheap.contains(1.0) and cheap.error <= 10 * true


def test_a_diverging_sequence_gets_an_infinite_bar():
    """A peak under a point force grows like h^-1/2 under refinement: no converged value."""
    values = [(0.1 * FULL_RATIO**k) ** -0.5 for k in range(3)]
    est = level_estimate(values, "full")
    assert math.isinf(est.error) and "mesh (diverging)" in est.sources
    assert math.isinf(level_estimate(values, "none").error)
    with pytest.raises(ValueError, match="needs 3 mesh levels"):
        level_estimate(values[:2], "full")


@pytest.mark.parametrize(("degree", "budget"), [(2, "cheap"), (2, "full"), (1, "cheap")])
def test_pure_bending_bar_holds_the_exact_stress(degree, budget):
    """Pure bending: max principal A C, min principal -A C, von Mises A C. P2 is exact (its
    bars at the round-off floor); P1 is 10-25 % off and its P1/P2 bar says so."""
    solver = BlockSolver(MATERIAL, MeshSettings(size=0.7e-3), degree=degree)
    refs = reference_solvers(solver, budget)
    _, est = solve_with_error(solver, _bar(), _pure_bending(), refs, budget)
    exact = {"max_principal": A * C, "min_principal": -A * C, "max_von_mises": A * C}
    for name, value in exact.items():
        e = getattr(est, name)
        assert e.contains(value), (name, e)
        assert e.cost_s > 0
        if degree == 2:
            assert e.error <= 1e-8 * A * C
        else:
            assert e.error >= 0.05 * A * C  # P1 is visibly off, and its bar shows it


def test_cut_check_residual_is_the_distance_to_the_loads_on_one_side():
    """Cauchy cut x = L/3 of the bent bar: force 0 and moment -A I e_z... exactly; the
    residual source is the distance of each FE component to the loads on one side."""
    solver = BlockSolver(MATERIAL, MeshSettings(size=0.7e-3), degree=2)
    sol = solver.solve(_bar(), _pure_bending())
    normal, offset = np.array([1.0, 0.0, 0.0]), L / 3
    about = np.array([offset, 0.0, 0.0])
    check = cut_check(sol, _bar(), _pure_bending(), normal, offset, about)
    for est, exact in zip(
        (*check.force, *check.moment), (*check.force_exact, *check.moment_exact), strict=True
    ):
        assert est.contains(exact)
        assert est.sources["equilibrium residual"] == pytest.approx(abs(est.value - exact))
    inertia = (2 * D) * (2 * C) ** 3 / 12
    assert abs(check.moment_exact[2]) == pytest.approx(A * inertia, rel=1e-9)


def test_oscillating_levels_get_the_larger_step():
    """Levels that go up then down (no order can be read): the bar is the larger of the two
    steps, which holds a limit lying anywhere between the two finest levels and beyond."""
    est = level_estimate([1.00, 1.10, 1.04], "full")
    assert est.error == pytest.approx(0.10 + 1e-9, rel=1e-9)
    assert est.contains(1.10) and est.contains(0.95)
