"""Scene: construction from user blocks, loads, JSON round trip, bad input."""

import numpy as np
import pytest

from dem.scene import Assembly, Scene, Supports, point_load, proportional_to_weight
from dem.units import G
from tests.conftest import box_corners


def test_from_convex_blocks_builds_a_scene_under_self_weight(cube_on_ground):
    scene = cube_on_ground
    np.testing.assert_allclose(scene.assembly.mass, [1000.0, 9000.0])
    np.testing.assert_allclose(scene.dead_wrench[0], [0, 0, -1000.0 * G, 0, 0, 0])
    assert scene.supports.fixed.tolist() == [False, True]
    assert scene.supports.free_dofs[0].all() and not scene.supports.free_dofs[1].any()
    assert scene.free_blocks.tolist() == [0]


def test_loads_proportional_to_weight_and_point_loads(cube_on_ground):
    a = cube_on_ground.assembly
    live = proportional_to_weight(a, (0, 2.0, 0))
    np.testing.assert_allclose(live[0], [0, 1000.0 * G, 0, 0, 0, 0])
    # 10 N along x at the top of the cube: moment (p - c) x F = (0, 0, 0.5) x (10, 0, 0)
    np.testing.assert_allclose(
        point_load(a, 0, (0.5, 0.5, 1.0), (10.0, 0, 0))[0], [10, 0, 0, 0, 5, 0]
    )


def test_json_round_trip(tmp_path, two_block_stack):
    scene = two_block_stack.with_loads(
        live=proportional_to_weight(two_block_stack.assembly, (1, 0, 0))
    )
    scene.to_json(tmp_path / "s.json")
    back = Scene.from_json(tmp_path / "s.json")
    np.testing.assert_allclose(back.assembly.volume, scene.assembly.volume, rtol=1e-15)
    np.testing.assert_array_equal(back.supports.fixed, scene.supports.fixed)
    np.testing.assert_allclose(back.loads.live_wrench, scene.loads.live_wrench)
    np.testing.assert_allclose(back.assembly.mu, scene.assembly.mu)


def test_struct_of_arrays_matches_blocks(two_block_stack):
    arr = two_block_stack.assembly.arrays
    assert arr.vert_ptr.tolist() == [0, 8, 16, 24] and arr.face_ptr.tolist() == [0, 6, 12, 18]
    f = 7  # a face of block 1, through the global vertex numbering
    corners = arr.vertices[arr.face_vert[arr.face_vert_ptr[f] : arr.face_vert_ptr[f + 1]]]
    np.testing.assert_allclose(corners @ arr.face_normal[f], arr.face_offset[f], atol=1e-15)


def test_bad_scene_input_raises():
    cube = box_corners((0, 0, 0), (1, 1, 1))
    with pytest.raises(ValueError, match="block 1: .*coplanar"):
        Assembly.from_convex_blocks(
            [cube, np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.0]])], 1.0
        )
    with pytest.raises(ValueError, match="density"):
        Assembly.from_convex_blocks([cube], -1.0)
    with pytest.raises(ValueError, match="mu"):
        Assembly.from_convex_blocks([cube], 1.0, mu=np.nan)
    with pytest.raises(ValueError, match="fixed block index"):
        Supports.fixed_blocks(1, [3])
    scene = Scene.from_convex_blocks([cube], 1.0)
    with pytest.raises(ValueError, match="live_wrench contains NaN"):
        scene.with_loads(live=np.full((1, 6), np.nan))
    with pytest.raises(ValueError, match=r"loads.dead_wrench must have shape \(1, 6\)"):
        scene.with_loads(dead=np.zeros((2, 6)))


def test_non_convex_user_block_raises_instead_of_taking_its_hull():
    # an L-shaped prism: its re-entrant corners lie inside the convex hull
    l_shape = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], dtype=float)
    corners = np.vstack(
        [np.column_stack([l_shape, np.zeros(6)]), np.column_stack([l_shape, np.ones(6)])]
    )
    with pytest.raises(ValueError, match=r"block 0: .*not in convex position: points \[3, 9\]"):
        Scene.from_convex_blocks([corners], density=1000.0)
    hull = Assembly.from_convex_blocks([corners], 1000.0, exact=False)
    assert hull.volume[0] == pytest.approx(3.5)  # the hull: 4 - 1/2, by hand
