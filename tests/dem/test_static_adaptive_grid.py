"""The fibre law's adaptive grid (dem.static.adaptive_grid) against closed forms: the exact
collapse multiplier lies within the grid's error bound."""

import math

import numpy as np
import pytest

from dem.estimate import Estimate
from dem.interface_strength import torsion_coefficient_rectangle
from dem.scene import Scene
from dem.scenes.stack import stack
from dem.scenes.supported import on_supports
from dem.static import FibreLawSettings, StaticSettings, solve_collapse
from dem.static.adaptive_grid import SOURCE, GridRefinement, finer_points

G = 9.81


def hexagonal_prism(circumradius: float, height: float):
    """A hexagonal prism on a fixed ground slab, two edges of its base normal to x, pushed
    along +x by its weight times lambda. Rigid tipping about the leading edge (friction
    high enough not to slide): ``lambda = apothem / (height / 2)``."""
    angles = np.arange(6) * np.pi / 3 + np.pi / 6
    ring = np.column_stack([circumradius * np.cos(angles), circumradius * np.sin(angles)])
    prism = np.vstack(
        [np.column_stack([ring, np.zeros(6)]), np.column_stack([ring, np.full(6, height)])]
    )
    ground = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0.0)])
    scene = on_supports([prism], [ground], 2000.0, 2.0, (1.0, 0.0, 0.0), "hexagon", {})
    return scene, circumradius * math.cos(math.pi / 6) / (height / 2)


def test_rocking_hexagon_lies_within_the_grid_bound():
    # the midpoint grid of a hexagon has no springs on its edges: rocking comes out low by
    # about half a cell, a first-order error the refinement must bound
    scene, exact = hexagonal_prism(0.3, 1.0)
    law = FibreLawSettings(points=5, grid_tolerance=0.02, max_points=17)
    result = solve_collapse(scene, StaticSettings(law=law))
    grid = result.fibre_grid
    assert grid.points == (5, 9, 17) and grid.converged
    assert grid.change <= 0.02 * result.lambda_max
    estimate = Estimate(result.lambda_max, grid.error_sources())
    assert estimate.contains(exact), (estimate, exact)
    assert abs(result.lambda_max - exact) > 0  # the grid's error is real, not zero


def tipping_on_crushed_toe(compressive_strength: float):
    """A 0.4 x 0.4 x 1 m block on the ground pushed along x by lambda times its weight, with
    a joint compressive strength f_c: at collapse the weight W acts at the middle of the
    crushed toe, of width ``x_c = W / (f_c s)``, so ``lambda = (b - x_c) / h``."""
    b, s, h, rho = 0.4, 0.4, 1.0, 2000.0
    scene = stack(1, b, s, h, density=rho, mu=2.0)
    weight = rho * G * b * s * h
    return scene, (b - weight / (compressive_strength * s)) / h


@pytest.mark.parametrize(
    ("tolerance", "max_points", "converged"), [(0.01, 33, True), (0.005, 17, False)]
)
def test_tipping_on_a_crushed_toe_lies_within_the_grid_bound(tolerance, max_points, converged):
    # the crushed zone's edge falls between springs: the error changes sign with the grid
    f_c = 2e5
    scene, exact = tipping_on_crushed_toe(f_c)
    law = FibreLawSettings(points=5, grid_tolerance=tolerance, max_points=max_points)
    settings = StaticSettings(law=law, compressive_strength=f_c)
    result = solve_collapse(scene, settings)
    grid = result.fibre_grid
    assert grid.converged is converged
    assert grid.points[-1] <= max_points and len(grid.points) >= 3
    estimate = Estimate(result.lambda_max, grid.error_sources())
    assert estimate.contains(exact), (estimate, exact)
    assert result.settings["law"]["grid_tolerance"] == tolerance


def test_one_grid_without_a_tolerance_and_an_unbounded_error_with_one_run():
    scene, exact = hexagonal_prism(0.3, 1.0)
    fixed = solve_collapse(scene, StaticSettings(interface_model="fibre"))
    assert fixed.fibre_grid is None and fixed.settings["law"]["grid_tolerance"] is None
    # max_points below the first refinement: one grid, no change measured, the bound is inf
    law = FibreLawSettings(points=5, grid_tolerance=0.005, max_points=8)
    once = solve_collapse(scene, StaticSettings(law=law))
    assert once.fibre_grid.points == (5,) and not once.fibre_grid.converged
    assert math.isinf(once.fibre_grid.error_sources()[SOURCE])
    assert once.lambda_max == pytest.approx(fixed.lambda_max, rel=1e-12)


def test_cells_halve_between_grids():
    assert [finer_points(p) for p in (2, 5, 9)] == [3, 9, 17]


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.0, math.nan, True])
def test_bad_grid_tolerance_is_refused(bad):
    with pytest.raises(ValueError, match="grid_tolerance"):
        FibreLawSettings(grid_tolerance=bad)


def _box(lo, hi):
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def _block_on_ground(mu: float, live_row):
    """A 0.4 x 0.4 x 1 m block on a fixed slab; ``live_row(weight)`` the block's live load
    ``(F, M)`` (6,)."""
    blocks = [_box((-1, -1, -0.2), (1, 1, 0)), _box((-0.2, -0.2, 0), (0.2, 0.2, 1))]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=mu)
    live = np.zeros((2, 6))
    live[1] = live_row(scene.assembly.mass[1] * G)
    return scene.with_loads(live=live)


def test_a_twisted_block_where_the_grid_matters_lies_within_the_grid_bound():
    """A torque M = 0.1 m W about the vertical twists the block off its base at
    lambda = mu W c_T / M (c_T the mean distance of the square base's points to its centre):
    the 5-point grid is 2.9 % low, the 33-point grid within 0.02 %. The adaptive result at
    the default tolerance (0.5 %, up to 17 points) holds the 33-point value and the closed
    form in its bar."""
    mu = 0.6
    scene = _block_on_ground(mu, lambda w: (0, 0, 0, 0, 0, 0.1 * w))
    exact = mu * torsion_coefficient_rectangle(0.4, 0.4) / 0.1
    law = FibreLawSettings(points=5, grid_tolerance=0.005, max_points=17)
    result = solve_collapse(scene, StaticSettings(law=law))
    fine = solve_collapse(scene, StaticSettings(law=FibreLawSettings(points=33))).lambda_max
    coarse = result.fibre_grid.lambdas[0]
    assert abs(coarse / fine - 1) > 0.02  # the grid matters
    assert abs(fine / exact - 1) < 2e-4
    bar = result.lambda_estimate
    assert bar.contains(fine) and bar.contains(exact), (bar, fine, exact)
    assert result.fibre_grid.error_sources()[SOURCE] <= 0.02 * result.lambda_max


def test_a_corner_tipping_on_a_finer_grid_ends_at_its_limit():
    """Pushed along its diagonal the block tips about a corner at sqrt(2) b / h: every
    Lobatto grid has a spring at the corner, so its limit is the rigid one."""
    half = 1 / math.sqrt(2.0)  # lambda times the weight along the diagonal
    scene = _block_on_ground(0.9, lambda w: (half * w, half * w, 0, 0, 0, 0))
    expected = math.sqrt(2.0) * 0.4 / 1.0
    result = solve_collapse(scene, StaticSettings(law=FibreLawSettings(points=9)))
    # the path creeps at 1e-5 of its initial slope while the corner's neighbours open; only
    # the tangent's limit point, once the corner spring alone carries the weight, ends it
    assert result.termination == "plateau" and result.certificate == "limit point"
    assert result.lambda_estimate.contains(expected), result.lambda_estimate
    assert result.lambda_max == pytest.approx(expected, rel=1e-3)


def test_a_refinement_describes_its_grids():
    refinement = GridRefinement((5, 9, 17), (0.5657, 0.5433, math.nan), 0.005, False)
    assert (
        refinement.describe()
        == "fibre grids 5, 9, 17 points: lambda_max 0.5657, 0.5433, no collapse"
    )
    assert math.isinf(refinement.change)
