"""TIS panels of seed 000 against the closed forms stated in dem/scenes/tis_panel.py."""

import math

import numpy as np
import pytest

from dem.geometry.interfaces import bounding_boxes, candidate_pairs
from dem.geometry.polyhedron import penetration_depth
from dem.scenes.tis_panel import tis_panel
from dem.units import MM

PANELS = [(n, theta) for n in (3, 5, 7) for theta in (2.5, 5.0, 7.5)]
SIZE, THICK = 50 * MM, 3.18 * MM


@pytest.fixture(scope="module", params=PANELS, ids=lambda p: f"{p[0]}x{p[0]}-{p[1]}deg")
def panel(request):
    n, theta = request.param
    return n, math.radians(theta), tis_panel(n, theta)


def test_block_count_and_volume_with_voids_fill_the_box(panel):
    n, theta, scene = panel
    assert scene.n_blocks == (n + 2) ** 2
    voids = (n + 1) ** 2 * 4 / 3 * math.tan(theta) ** 2 * THICK**3  # pinwheel void per vertex
    np.testing.assert_allclose(scene.assembly.volume.sum() + voids, SIZE * SIZE * THICK, rtol=1e-12)
    internal = np.flatnonzero(~scene.supports.fixed)
    side = SIZE / (n + 1)
    one_block = side**2 * THICK - 4 / 3 * math.tan(theta) ** 2 * THICK**3
    np.testing.assert_allclose(scene.assembly.volume[internal], one_block, rtol=1e-12)
    assert len(internal) == n * n


def test_no_two_blocks_overlap(panel):
    _, _, scene = panel
    blocks = scene.assembly.blocks
    lo, hi = bounding_boxes(blocks)
    pairs = candidate_pairs(lo, hi, 1e-9)
    depths = [penetration_depth(blocks[i], blocks[j]) for i, j in pairs]
    assert len(pairs) > scene.n_blocks and max(depths) < 1e-12


def test_each_internal_block_has_four_lateral_interfaces_with_its_grid_neighbours(panel):
    n, _, scene = panel
    iface = scene.assembly.interfaces()
    assert iface.n_interfaces == 2 * (n + 1) * (n + 2)
    grid = np.array(scene.meta["grid"])
    for blk in np.flatnonzero(~scene.supports.fixed):
        mine = (iface.block_a == blk) | (iface.block_b == blk)
        others = np.where(iface.block_a[mine] == blk, iface.block_b[mine], iface.block_a[mine])
        steps = {tuple(d) for d in (grid[others] - grid[blk]).tolist()}
        assert steps == {(1, 0), (-1, 0), (0, 1), (0, -1)}


def test_lateral_interfaces_are_the_closed_form_trapezoids(panel):
    n, theta, scene = panel
    side, lean = SIZE / (n + 1), THICK * math.tan(theta)
    iface = scene.assembly.interfaces()
    grid = np.array(scene.meta["grid"])
    on_edge = _same_boundary_line(grid, iface, n)
    for k in range(iface.n_interfaces):
        scale = 0.5 if on_edge[k] else 1.0
        poly = iface.local_polygon(k)  # y1 runs up the slope for these near-vertical planes
        assert len(poly) == 4
        bottom = poly[np.isclose(poly[:, 0], poly[:, 0].min())]
        top = poly[np.isclose(poly[:, 0], poly[:, 0].max())]
        np.testing.assert_allclose(np.ptp(bottom[:, 1]), scale * side, rtol=1e-10)
        np.testing.assert_allclose(np.ptp(top[:, 1]), scale * (side - 2 * lean), rtol=1e-10)
        np.testing.assert_allclose(np.ptp(poly[:, 0]), THICK / math.cos(theta), rtol=1e-10)
        np.testing.assert_allclose(
            iface.area[k], scale * (side - lean) * THICK / math.cos(theta), rtol=1e-12
        )
        np.testing.assert_allclose(abs(iface.frame[k, 0, 2]), math.sin(theta), atol=1e-12)


def _same_boundary_line(grid, iface, n):
    """Interfaces between two boundary blocks on the same panel edge (cut in half)."""
    ga, gb = grid[iface.block_a], grid[iface.block_b]
    same_col = (ga[:, 0] == gb[:, 0]) & np.isin(ga[:, 0], [0, n + 1])
    same_row = (ga[:, 1] == gb[:, 1]) & np.isin(ga[:, 1], [0, n + 1])
    return same_col | same_row


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"n": 0, "theta_deg": 5}, "positive integer"),
        ({"n": 2.5, "theta_deg": 5}, "positive integer"),
        ({"n": 3, "theta_deg": -1}, "theta_deg"),
        ({"n": 3, "theta_deg": 5, "thickness_mm": 0}, "thickness_mm"),
        ({"n": 7, "theta_deg": 60}, "too steep"),
    ],
)
def test_bad_panel_input_raises(kwargs, message):
    with pytest.raises(ValueError, match=message):
        tis_panel(**kwargs)


def test_theta_zero_gives_a_grid_of_boxes():
    scene = tis_panel(3, 0.0)
    np.testing.assert_allclose(scene.assembly.volume.sum(), SIZE * SIZE * THICK, rtol=1e-12)
    assert scene.meta["central_block"] == 2 * 5 + 2
