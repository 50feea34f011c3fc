"""Row-wise RT0 stress reconstruction (seed 003, Sec. 3): closed-form checks."""

from __future__ import annotations

import numpy as np
import pytest

from fem_check.rt_reconstruction import reconstruct_stress


def _outward_normals(cell_ptr, cell_xy):
    n = np.empty_like(cell_xy)
    for c in range(len(cell_ptr) - 1):
        p = cell_xy[cell_ptr[c] : cell_ptr[c + 1]]
        d = np.roll(p, -1, axis=0) - p
        n[cell_ptr[c] : cell_ptr[c + 1]] = (
            np.stack([d[:, 1], -d[:, 0]], 1) / np.linalg.norm(d, axis=1)[:, None]
        )
    return n


def _hexagon_and_square():
    """Two hand-made cells: a regular hexagon (centre off the middle) and a unit square."""
    ang = np.arange(6) * np.pi / 3
    hexagon = np.stack([np.cos(ang), np.sin(ang)], 1) + [3.0, 0.0]
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    cell_xy = np.vstack([hexagon, square])
    return np.array([0, 6, 10]), cell_xy, np.array([[3.2, -0.1], [0.3, 0.6]])


def _brick_wall():
    """2 courses of running bond: T-junctions give cells with collinear facets."""
    from limit.voronoi_packing import brick_wall_packing

    w = brick_wall_packing(n_courses=2, bricks_per_course=2, brick_length=0.2, brick_height=0.1)
    return w.cell_ptr, w.cell_xy, w.centres


@pytest.mark.parametrize("mesh", [_hexagon_and_square, _brick_wall])
def test_uniform_stress_is_recovered(mesh):
    # closed form: a constant symmetric stress is row-wise RT0, divergence free and symmetric,
    # so it is the unique solution of seed 003 Eq. (15) for its own tractions
    cell_ptr, cell_xy, centres = mesh()
    sigma0 = np.array([[-2.0, 0.5], [0.5, -1.0]])
    traction = _outward_normals(cell_ptr, cell_xy) @ sigma0.T
    rec = reconstruct_stress(cell_ptr, cell_xy, centres, traction)
    np.testing.assert_allclose(
        rec.sigma_vertex, np.broadcast_to(sigma0, rec.sigma_vertex.shape), atol=1e-12 * 2.0
    )
    np.testing.assert_allclose(
        rec.cell_stress, np.broadcast_to(sigma0, rec.cell_stress.shape), atol=1e-12 * 2.0
    )
    assert rec.div_norm.max() < 1e-10 and rec.skew_norm.max() < 1e-10


def test_moment_of_tractions_equals_first_moment_of_divergence():
    # Green's identity for weakly symmetric sigma: int_{dc} (x-C) x sigma n ds
    # = int_c (x-C) x div(sigma) dx, and div is constant per triangle
    cell_ptr, cell_xy, centres = _hexagon_and_square()
    rng = np.random.default_rng(0)
    traction = rng.normal(size=cell_xy.shape)
    rec = reconstruct_stress(cell_ptr, cell_xy, centres, traction)
    d = rec.tri_xy.mean(axis=1) - rec.tri_xy[:, 0]
    first = rec.tri_area * (d[:, 0] * rec.div[:, 1] - d[:, 1] * rec.div[:, 0])
    # moment of the data, computed directly from the facets
    nxt = np.concatenate([np.roll(cell_xy[0:6], -1, 0), np.roll(cell_xy[6:10], -1, 0)])
    mid = 0.5 * (cell_xy + nxt) - np.repeat(centres, [6, 4], axis=0)
    length = np.linalg.norm(nxt - cell_xy, axis=1)
    moment = length * (mid[:, 0] * traction[:, 1] - mid[:, 1] * traction[:, 0])
    expected = np.array([moment[:6].sum(), moment[6:].sum()])
    np.testing.assert_allclose(np.bincount(rec.tri_cell, weights=first), expected, atol=1e-12)
    np.testing.assert_allclose(rec.traction_moment, expected, atol=1e-12)
    assert rec.weak_symmetry_residual.max() < 1e-12


def test_bad_inputs():
    cell_ptr, cell_xy, centres = _hexagon_and_square()
    traction = np.zeros_like(cell_xy)
    with pytest.raises(ValueError, match="facet_traction"):
        reconstruct_stress(cell_ptr, cell_xy, centres, traction[:-1])
    with pytest.raises(ValueError, match="centres"):
        reconstruct_stress(cell_ptr, cell_xy, centres[:1], traction)
    with pytest.raises(ValueError, match="cell_ptr"):
        reconstruct_stress(np.array([0, 2, 10]), cell_xy, centres, traction)
    outside = centres.copy()
    outside[1] = [5.0, 5.0]
    with pytest.raises(ValueError, match="centre"):
        reconstruct_stress(cell_ptr, cell_xy, outside, traction)


def test_lp_forces_to_rt_recover_uniform_stress():
    # closed form: on a Voronoi packing the min-energy forces of a uniform load are those of the
    # uniform stress (Voronoi edges are normal to the seed-seed vector), so RT0 recovers sigma0
    from limit.tresca import TrescaSettings, facet_tractions, solve_tresca
    from limit.voronoi_packing import uniform_stress_traction, voronoi_packing

    sigma0 = np.array([[-1.5, 0.2], [0.2, -1.0]])
    packing = voronoi_packing(15, 1.0, 1.0, seed=11)
    traction = uniform_stress_traction(packing, sigma0)
    res = solve_tresca(packing, traction, 10.0, TrescaSettings(selection="min_energy"))
    rec = reconstruct_stress(
        packing.cell_ptr, packing.cell_xy, packing.centres, facet_tractions(packing, res, traction)
    )
    np.testing.assert_allclose(
        rec.cell_stress, np.broadcast_to(sigma0, rec.cell_stress.shape), atol=1e-7
    )
