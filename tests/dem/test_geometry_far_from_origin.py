"""Blocks and interfaces far from the origin (national-grid coordinates) match those at it.

A float64 coordinate of 4e6 m resolves ~5e-10 m, so a block moved there is its copy at the
origin up to that rounding: its faces, volume and joints must be the same (translation
invariance), not merely close when the face planes happen to round well.
"""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dem.geometry.interfaces import find_interfaces
from dem.geometry.polyhedron import DegenerateFaceError, _merge_coplanar_facets, convex_block
from dem.scenes import voussoir_arch
from tests.conftest import box_corners

OFFSETS = [
    (500_000.0, 4_600_000.0, 120.0),  # UTM
    (2_600_000.0, 1_200_000.0, 120.0),  # Swiss LV95
    (4_000_000.0, 0.0, 0.0),  # Gauss-Krueger zone 4
    (-4_000_000.0, 4_000_000.0, 4_000_000.0),
]
TURN = Rotation.from_rotvec([0.3, -0.5, 0.7]).as_matrix()


def voussoir_corners(r_in, r_out, alpha_0, alpha_1, depth) -> np.ndarray:
    """(8, 3) corners of a voussoir: the radial joints at ``alpha_0, alpha_1`` [rad] in xz."""
    return np.array(
        [
            (r * np.cos(alpha), y, r * np.sin(alpha))
            for r in (r_in, r_out)
            for alpha in (alpha_0, alpha_1)
            for y in (-depth / 2, depth / 2)
        ]
    )


@pytest.mark.parametrize("offset", OFFSETS)
def test_a_voussoir_far_from_the_origin_keeps_its_faces_and_volume(offset):
    r_in, r_out, depth = 0.9, 1.1, 0.2
    alpha_0, alpha_1 = 5 * np.pi / 12, np.pi / 2  # the crown voussoir of a 12-voussoir arch
    corners = voussoir_corners(r_in, r_out, alpha_0, alpha_1, depth)
    # closed form: the section between two chords, (r_out^2 - r_in^2) sin(dalpha) / 2, extruded
    volume = (r_out**2 - r_in**2) * np.sin(alpha_1 - alpha_0) / 2 * depth
    at_origin = convex_block(corners, exact=True)
    shift = np.array(offset)
    moved = convex_block(corners + shift, exact=True)
    # the same rounded corners moved back to the origin (an exact subtraction): translation
    # invariance to round-off
    back = convex_block((corners + shift) - shift, exact=True)

    assert [len(f) for f in moved.faces] == [4] * 6
    np.testing.assert_allclose(moved.volume, back.volume, rtol=1e-12)
    np.testing.assert_allclose(moved.centroid - shift, back.centroid, atol=1e-12)
    # rounding the corners to ~5e-10 m changes a 0.2 m block by ~1e-8 relative at most
    np.testing.assert_allclose(moved.volume, volume, rtol=1e-8)
    np.testing.assert_allclose(moved.centroid - shift, at_origin.centroid, atol=1e-8)
    np.testing.assert_allclose(moved.normals, at_origin.normals, atol=1e-8)
    np.testing.assert_allclose(moved.offsets - moved.normals @ shift, at_origin.offsets, atol=1e-8)


@pytest.mark.parametrize("turned", [False, True])
@pytest.mark.parametrize("offset", OFFSETS)
def test_an_arch_far_from_the_origin_keeps_every_joint(offset, turned):
    span, t, n = 2.0, 0.2, 12
    # turned: no face along an axis, so rounding moves each corner off its face's plane
    rot = TURN if turned else np.eye(3)
    blocks = [
        convex_block(b.vertices @ rot.T, exact=True)
        for b in voussoir_arch(span, t, n).assembly.blocks  # depth = t
    ]
    shift = np.array(offset)
    ref = find_interfaces(blocks)
    moved = find_interfaces([convex_block(b.vertices + shift, exact=True) for b in blocks])

    # n + 1 radial joints (two at the springings), each a t x depth rectangle
    assert ref.n_interfaces == moved.n_interfaces == n + 1
    assert moved.edge_contacts.shape == (0, 2)
    np.testing.assert_array_equal(moved.block_a, ref.block_a)
    np.testing.assert_array_equal(moved.block_b, ref.block_b)
    np.testing.assert_allclose(moved.area, t * t, rtol=1e-6)
    np.testing.assert_allclose(moved.area, ref.area, rtol=1e-7)
    np.testing.assert_allclose(moved.centroid - shift, ref.centroid, atol=1e-8)
    np.testing.assert_allclose(moved.frame, ref.frame, atol=1e-7)
    np.testing.assert_allclose(moved.polar_moment, ref.polar_moment, rtol=1e-6)


def test_a_small_turned_block_far_from_the_origin_keeps_its_faces():
    # a 1 mm cube at 4e6 m: its corners are rounded by ~1e-6 of its size
    corners = box_corners((0, 0, 0), (1e-3, 1e-3, 1e-3)) @ TURN.T + 4e6
    block = convex_block(corners, exact=True)
    assert [len(f) for f in block.faces] == [4] * 6
    np.testing.assert_allclose(block.volume, 1e-9, rtol=1e-5)  # closed form a^3


def test_a_face_with_fewer_than_three_corners_is_an_error():
    # a facet plane (z = 5) that no corner of the unit cube lies on
    cube = box_corners((0, 0, 0), (1, 1, 1))
    plane = np.array([[0.0, 0.0, 1.0, -5.0]])
    facet = np.array([[[0.0, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 1.0, 5.0]]])
    with pytest.raises(DegenerateFaceError, match="0 corners"):
        _merge_coplanar_facets(plane, facet, cube, 1e-9)
