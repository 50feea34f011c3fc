"""Convex blocks: mass properties against closed forms, faces, clipping, bad input."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dem.geometry.polyhedron import clip_halfspace, convex_block, penetration_depth
from tests.conftest import box_corners


def test_box_mass_properties():
    a, b, c = 0.3, 0.7, 1.9
    block = convex_block(box_corners((1.0, -2.0, 0.5), (1.0 + a, -2.0 + b, 0.5 + c)), exact=True)
    vol = a * b * c  # closed form
    np.testing.assert_allclose(block.volume, vol, rtol=1e-12)
    np.testing.assert_allclose(block.centroid, [1 + a / 2, -2 + b / 2, 0.5 + c / 2], rtol=1e-12)
    expected = np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * vol / 12
    np.testing.assert_allclose(block.inertia, expected, rtol=1e-12, atol=1e-14 * expected.max())
    assert len(block.faces) == 6 and all(len(f) == 4 for f in block.faces)


def test_tetrahedron_mass_properties():
    # unit corner tetrahedron: V = 1/6, c = 1/4 (1,1,1), I_xx = 1/80, I_xy = 1/480 (closed form)
    block = convex_block(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float))
    np.testing.assert_allclose(block.volume, 1 / 6, rtol=1e-12)
    np.testing.assert_allclose(block.centroid, [0.25] * 3, rtol=1e-12)
    expected = np.full((3, 3), 1 / 480) + np.eye(3) * (1 / 80 - 1 / 480)
    np.testing.assert_allclose(block.inertia, expected, rtol=1e-12)


def test_rotated_translated_prism_mass_properties():
    # right triangle with legs p (x) and q (y), extruded by h along z, then moved rigidly
    p, q, h = 0.4, 0.25, 0.9
    local = np.array([[0, 0, 0], [p, 0, 0], [0, q, 0], [0, 0, h], [p, 0, h], [0, q, h]], float)
    area = p * q / 2
    cov_local = np.array(  # int (x - c)(x - c)^T dV of the prism, triangle moments p^3 q / 36 ...
        [
            [h * p**3 * q / 36, -h * p * p * q * q / 72, 0.0],
            [-h * p * p * q * q / 72, h * p * q**3 / 36, 0.0],
            [0.0, 0.0, area * h**3 / 12],
        ]
    )
    rot = Rotation.from_euler("zyx", [0.3, -1.1, 2.0]).as_matrix()
    shift = np.array([10.0, -4.0, 3.0])
    block = convex_block(local @ rot.T + shift, exact=True)
    cov = rot @ cov_local @ rot.T
    expected = np.trace(cov) * np.eye(3) - cov
    np.testing.assert_allclose(block.volume, area * h, rtol=1e-12)
    np.testing.assert_allclose(block.centroid, rot @ [p / 3, q / 3, h / 2] + shift, rtol=1e-12)
    np.testing.assert_allclose(
        block.inertia, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max()
    )
    assert sorted(len(f) for f in block.faces) == [3, 3, 4, 4, 4]


def test_faces_are_planar_ccw_and_outward():
    block = convex_block(
        Rotation.from_rotvec([0.2, 0.5, -0.1]).apply(box_corners((0, 0, 0), (1, 2, 3)))
    )
    for face, n, d in zip(block.faces, block.normals, block.offsets, strict=True):
        pts = block.vertices[face]
        np.testing.assert_allclose(pts @ n, d, atol=1e-12)
        # Newell normal of the ordered polygon points along the outward normal
        newell = np.cross(pts - pts.mean(0), np.roll(pts, -1, axis=0) - pts.mean(0)).sum(0)
        assert newell @ n > 0
        assert (block.centroid @ n) < d


def test_signed_distance_is_exact_inside():
    block = convex_block(box_corners((0, 0, 0), (1, 2, 3)))
    np.testing.assert_allclose(
        block.signed_distance([[0.5, 1.0, 1.5], [0.1, 1.0, 1.5]]), [-0.5, -0.1]
    )


@pytest.mark.parametrize(
    "points, message",
    [
        (np.zeros((3, 3)), "at least 4"),
        (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float), "coplanar"),
        (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.nan]]), "NaN"),
        (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, np.inf]]), "NaN or inf"),
        (np.ones((5, 3)), "zero volume"),
        (np.zeros((4, 2)), "shape"),
    ],
)
def test_bad_vertices_raise(points, message):
    with pytest.raises(ValueError, match=message):
        convex_block(points)


def test_zero_volume_sliver_raises():
    sliver = box_corners((0, 0, 0), (1, 1, 1e-14))
    with pytest.raises(ValueError, match="coplanar|zero"):
        convex_block(sliver)


def test_exact_rejects_points_not_in_convex_position():
    inside = np.vstack([box_corners((0, 0, 0), (1, 1, 1)), [[0.5, 0.5, 0.5]]])
    with pytest.raises(ValueError, match=r"not in convex position: points \[8\]"):
        convex_block(inside, exact=True)
    on_face = np.vstack([box_corners((0, 0, 0), (1, 1, 1)), [[0.5, 0.5, 1.0]]])
    with pytest.raises(ValueError, match="not in convex position"):
        convex_block(on_face, exact=True)
    assert convex_block(inside).volume == pytest.approx(1.0, rel=1e-12)  # hull without exact


def test_clip_halfspace_cuts_a_box_exactly():
    block = convex_block(box_corners((0, 0, 0), (2, 1, 1)))
    half = clip_halfspace(block, np.array([1.0, 0, 0]), 0.5)
    np.testing.assert_allclose(half.volume, 0.5, rtol=1e-12)
    corner = clip_halfspace(block, np.array([1.0, 1.0, 1.0]) / np.sqrt(3), 1 / np.sqrt(3))
    np.testing.assert_allclose(corner.volume, 1 / 6, rtol=1e-12)  # the corner tetrahedron
    assert clip_halfspace(block, np.array([1.0, 0, 0]), -1.0) is None
    assert clip_halfspace(block, np.array([1.0, 0, 0]), 5.0) is block


def test_penetration_depth_of_boxes():
    a = convex_block(box_corners((0, 0, 0), (1, 1, 1)))
    assert penetration_depth(a, convex_block(box_corners((1, 0, 0), (2, 1, 1)))) == pytest.approx(0)
    assert penetration_depth(
        a, convex_block(box_corners((0.8, 0.1, 0.0), (2, 1, 1)))
    ) == pytest.approx(0.2)
    assert penetration_depth(a, convex_block(box_corners((3, 0, 0), (4, 1, 1)))) < 0
