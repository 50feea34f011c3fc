"""Interfaces from geometry: exact polygons, frames, moments, broad phase, overlaps."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dem.geometry.interfaces import OverlapError, candidate_pairs, find_interfaces
from dem.geometry.polyhedron import convex_block
from tests.conftest import box_corners


def test_offset_boxes_share_the_overlap_rectangle():
    # top face [0,2]x[0,1] against bottom face [0.5,3]x[0.25,2]: overlap 1.5 x 0.75 at z = 1
    low = convex_block(box_corners((0, 0, 0), (2, 1, 1)))
    high = convex_block(box_corners((0.5, 0.25, 1), (3, 2, 2)))
    iface = find_interfaces([low, high])
    assert iface.n_interfaces == 1
    w, h = 1.5, 0.75
    np.testing.assert_allclose(iface.area, [w * h], rtol=1e-12)
    np.testing.assert_allclose(iface.centroid[0], [1.25, 0.625, 1.0], rtol=1e-12)
    np.testing.assert_allclose(iface.frame[0, 0], [0, 0, 1], atol=1e-15)  # from block 0 to 1
    np.testing.assert_allclose(np.linalg.det(iface.frame[0]), 1.0, rtol=1e-12)
    # frame of a horizontal plane: t1 along x, t2 along y; J11 = int y1^2 = h w^3 / 12
    np.testing.assert_allclose(
        iface.second_moments[0], [h * w**3 / 12, w * h**3 / 12, 0], atol=1e-15
    )
    np.testing.assert_allclose(iface.polar_moment, [w * h * (w * w + h * h) / 12], rtol=1e-12)


def test_interfaces_move_with_a_rigid_motion():
    rot = Rotation.from_rotvec([0.4, -0.2, 0.9]).as_matrix()
    shift = np.array([3.0, -1.0, 7.0])
    blocks = [
        convex_block(box_corners((0, 0, 0), (1, 1, 1))),
        convex_block(box_corners((0, 0, 1), (1, 1, 2))),
    ]
    ref = find_interfaces(blocks)
    moved = find_interfaces([b.transformed(rot, shift) for b in blocks])
    np.testing.assert_allclose(moved.area, ref.area, rtol=1e-12)
    np.testing.assert_allclose(moved.centroid, ref.centroid @ rot.T + shift, atol=1e-12)
    np.testing.assert_allclose(moved.frame[:, 0], ref.frame[:, 0] @ rot.T, atol=1e-12)
    np.testing.assert_allclose(moved.polar_moment, ref.polar_moment, rtol=1e-10)


def test_touching_edges_or_corners_are_no_interface_but_are_listed(caplog):
    a = convex_block(box_corners((0, 0, 0), (1, 1, 1)))
    edge = convex_block(box_corners((1, 1, 0), (2, 2, 1)))  # shares only an edge
    far = convex_block(box_corners((0, 0, 1.5), (1, 1, 2)))  # parallel, 0.5 apart
    corner = convex_block(box_corners((2, 2, 1), (3, 3, 2)))  # a corner of `edge`
    apart = convex_block(box_corners((1.01, -1, 0), (2, -0.01, 1)))  # 0.01 off a's edge
    iface = find_interfaces([a, edge, far, corner, apart])
    assert iface.n_interfaces == 0
    assert iface.edge_contacts.tolist() == [[0, 1], [1, 3]]
    with caplog.at_level("WARNING", logger="dem.geometry.interfaces"):
        iface.warn_edge_contacts()
        iface.warn_edge_contacts()  # once per object
    assert caplog.text.count("touch only along an edge") == 1
    assert "2 pair(s) of blocks touch only along an edge or at a corner (blocks 0-1, 1-3)" in (
        caplog.text
    )


def test_a_block_resting_on_an_edge_is_listed_not_skipped():
    # a cube turned 45 deg about x stands on the top of a slab along one edge only
    slab = convex_block(box_corners((-1, -1, -1), (2, 2, 0)))
    rot = Rotation.from_rotvec([np.pi / 4, 0, 0]).as_matrix()
    cube = convex_block(box_corners((0, -0.5, -0.5), (1, 0.5, 0.5)) @ rot.T + [0, 0, 0.5**0.5])
    iface = find_interfaces([slab, cube])
    assert iface.n_interfaces == 0
    assert iface.edge_contacts.tolist() == [[0, 1]]
    # lifted by more than the tolerance it touches nothing
    lifted = find_interfaces([slab, cube.transformed(np.eye(3), [0, 0, 1e-3])])
    assert lifted.edge_contacts.shape == (0, 2)


def test_overlapping_blocks_are_reported_with_pair_and_depth():
    blocks = [
        convex_block(box_corners((0, 0, 0), (1, 1, 1))),
        convex_block(box_corners((5, 0, 0), (6, 1, 1))),
        convex_block(box_corners((0.7, 0, 0), (1.7, 1, 1))),
    ]
    with pytest.raises(OverlapError, match=r"blocks 0 and 2 by 3\.000e-01 m") as info:
        find_interfaces(blocks)
    ((i, j, depth),) = info.value.overlaps
    assert (i, j) == (0, 2) and depth == pytest.approx(0.3)


def test_sort_and_sweep_matches_brute_force():
    rng = np.random.default_rng(7)
    lo = rng.uniform(0, 10, size=(300, 3))
    hi = lo + rng.uniform(0.1, 1.5, size=(300, 3))
    fast = {tuple(p) for p in candidate_pairs(lo, hi, 0.0)}
    overlap = np.all((lo[:, None] <= hi[None]) & (hi[:, None] >= lo[None]), axis=2)
    brute = {(i, j) for i, j in zip(*np.nonzero(np.triu(overlap, 1)), strict=True)}
    assert fast == brute and len(brute) > 0


def _plate_sandwich(thickness: float):
    """A 1 m ground, a ``thickness`` plate and a 1 m block stacked along z."""
    ground = convex_block(box_corners((-1, -1, -1), (2, 2, 0)))
    plate = convex_block(box_corners((0, 0, 0), (1, 1, thickness)))
    top = convex_block(box_corners((0, 0, thickness), (1, 1, 1 + thickness)))
    return [ground, plate, top]


@pytest.mark.parametrize("thickness", [1e-6, 1e-8])
def test_a_thin_plate_is_a_real_block(thickness):
    """The contact tolerance never exceeds a fraction of the thinner block: the top block
    rests on the plate, never on the ground through it."""
    iface = find_interfaces(_plate_sandwich(thickness))
    pairs = list(zip(iface.block_a.tolist(), iface.block_b.tolist(), strict=True))
    assert pairs == [(0, 1), (1, 2)]
    np.testing.assert_allclose(iface.area, [1.0, 1.0], rtol=1e-9)


def test_block_thickness_is_its_smallest_width():
    plate = convex_block(box_corners((0, 0, 0), (1, 2, 1e-6)))
    assert plate.thickness == pytest.approx(1e-6, rel=1e-9)
    # a regular tetrahedron of edge 1: width between opposite edges 1/sqrt(2), and the
    # height over a face sqrt(2/3) is the smallest face width
    tet = convex_block(np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]) / 8**0.5)
    assert tet.thickness == pytest.approx((2 / 3) ** 0.5, rel=1e-12)
