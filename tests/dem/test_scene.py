"""Scene: construction from user blocks, loads, JSON round trip, bad input."""

import warnings

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
    with pytest.raises(ValueError, match=r"dead must have shape \(1, 6\)"):
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


def test_a_thin_plate_sets_the_sliding_load():
    """Issue 13: a 1e-6 m plate of mu 0.1 between two 1 m blocks of mu 0.6: the top block
    slides on the plate at lambda = 0.1 (the smaller mu of each pair), not on the ground."""
    from limit.solve import limit_analysis

    ground = box_corners((-1, -1, -1), (2, 2, 0))
    plate = box_corners((0, 0, 0), (1, 1, 1e-6))
    top = box_corners((0.25, 0.25, 1e-6), (0.75, 0.75, 0.25))  # squat: slides before rocking
    scene = Scene.from_convex_blocks([ground, plate, top], 1000.0, fixed=[0], mu=[0.6, 0.1, 0.6])
    live = np.zeros((3, 6))
    live[2, 0] = scene.assembly.mass[2] * G
    assert limit_analysis(scene.with_loads(live=live)).lam == pytest.approx(0.1, rel=1e-6)


@pytest.mark.parametrize("fixed", [[1.5], ["0"], [True], [True, False, False, True], [[0]]])
def test_fixed_must_be_indices_or_a_mask(fixed):
    cube = box_corners((0, 0, 0), (1, 1, 1))
    blocks = [cube, cube + [0, 0, 1], cube + [0, 0, 2]]
    with pytest.raises(ValueError, match="fixed"):
        Scene.from_convex_blocks(blocks, 1.0, fixed=fixed)


def test_fixed_as_a_mask_or_indices():
    cube = box_corners((0, 0, 0), (1, 1, 1))
    blocks = [cube, cube + [0, 0, 1], cube + [0, 0, 2]]
    mask = Scene.from_convex_blocks(blocks, 1.0, fixed=[True, False, False])
    assert mask.supports.fixed.tolist() == [True, False, False]
    ids = Scene.from_convex_blocks(blocks, 1.0, fixed=np.array([2], dtype=np.int32))
    assert ids.supports.fixed.tolist() == [False, False, True]


def test_json_fixed_must_be_booleans(tmp_path, two_block_stack):
    data = two_block_stack.to_dict()
    data["fixed"] = ["yes", "no", "no"]
    with pytest.raises(ValueError, match="fixed"):
        Scene.from_dict(data)
    data["fixed"] = [0, 0, 1]  # integers in a mask position: ambiguous, refused
    with pytest.raises(ValueError, match="fixed"):
        Scene.from_dict(data)
    data = two_block_stack.to_dict()
    data["restrained"][0][0] = "no"
    with pytest.raises(ValueError, match="restrained"):
        Scene.from_dict(data)


@pytest.mark.parametrize("shape", [(6,), (3,), (6, 3), (2, 6)])
@pytest.mark.parametrize("which", ["live", "dead"])
def test_loads_of_the_wrong_shape_are_refused(two_block_stack, shape, which):
    with pytest.raises(ValueError, match=rf"{which} must have shape \(3, 6\)"):
        two_block_stack.with_loads(**{which: np.ones(shape)})


@pytest.mark.parametrize("name", ["density", "mu"])
def test_per_block_values_of_the_wrong_length_are_refused(name):
    cube = box_corners((0, 0, 0), (1, 1, 1))
    kw = {"density": 1.0, name: [0.5, 0.5]}
    with pytest.raises(ValueError, match=rf"{name} .*3 blocks.* got 2"):
        Assembly.from_convex_blocks([cube, cube + [0, 0, 1], cube + [0, 0, 2]], **kw)


WALL = dict(
    n_per_course=3,
    n_courses=2,
    a_mm=50.0,
    b_mm=200.0,
    s_mm=100.0,
    unit_weight_kn_m3=20.0,
    beam_loads_kn=[(100.0, 1.0)],
    openings_mm=[(200.0, 0.0, 400.0, 50.0)],
)
BUILDERS = {
    "running_bond_wall": ("dem.scenes.running_bond_wall", WALL),
    "wall_with_returns": (
        "dem.scenes.return_walls",
        {**WALL, "return_blocks": 2, "beam_loads_kn": [(300.0, 1.0)]},
    ),
    "tis_panel": (
        "dem.scenes.tis_panel",
        dict(n=3, theta_deg=10.0, size_mm=50.0, thickness_mm=3.18, density=2500.0),
    ),
}


def _bad_cases():
    for builder, (_, kw) in BUILDERS.items():
        for name, value in kw.items():
            if isinstance(value, list):
                yield builder, name, [(*value[0][:-1], np.nan)]
                yield builder, name, [(np.inf, *value[0][1:])]
            elif not isinstance(value, tuple):
                yield builder, name, np.nan
                yield builder, name, np.inf


@pytest.mark.parametrize(("builder", "name", "value"), list(_bad_cases()))
def test_builders_name_a_nan_or_infinite_parameter(builder, name, value):
    import importlib

    module, kw = BUILDERS[builder]
    build = getattr(importlib.import_module(module), builder)
    build(**kw)  # the base case builds
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        build(**{**kw, name: value})


def test_mixed_units_warn_naming_the_blocks():
    """A 0.2 x 0.2 x 1 m pillar typed in mm (200 x 200 x 1000) on a 3 m ground in m."""
    from dem.scene import MixedUnitsWarning

    ground = box_corners((-1.5, -1.5, -1.0), (1.5, 1.5, 0.0))
    pillar_mm = box_corners((0, 0, 0), (200.0, 200.0, 1000.0))
    with pytest.warns(MixedUnitsWarning, match=r"block 1 .* block 0"):
        Scene.from_convex_blocks([ground, pillar_mm], 2000.0, fixed=[0])
    pillar = box_corners((0, 0, 0), (0.2, 0.2, 1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Scene.from_convex_blocks([ground, pillar], 2000.0, fixed=[0])


def test_public_convex_block_is_exact_by_default():
    import dem

    cube = box_corners((0, 0, 0), (1, 1, 1))
    with_centre = np.vstack([cube, [[0.5, 0.5, 0.5]]])
    with pytest.raises(ValueError, match=r"not in convex position: points \[8\]"):
        dem.convex_block(with_centre)
    assert dem.convex_block(with_centre, exact=False).volume == pytest.approx(1.0)
    assert dem.convex_block(cube).volume == pytest.approx(1.0)


def test_a_density_in_tonnes_warns():
    from dem.scene import MixedUnitsWarning

    cube = box_corners((0, 0, 0), (1, 1, 1))
    with pytest.warns(MixedUnitsWarning, match=r"block 0 \(density 2e\+03.* block 1 \(density 2 "):
        Assembly.from_convex_blocks([cube, cube + [0, 0, 1]], [2000.0, 2.0])


def test_load_helpers_name_bad_blocks_and_values(cube_on_ground):
    from dem.scene import uniform_pressure

    a = cube_on_ground.assembly
    with pytest.raises(ValueError, match=r"blocks must be block indices 0..1, got \[5\]"):
        uniform_pressure(a, (0, 1, 0), blocks=[0, 5])
    with pytest.raises(ValueError, match=r"block index 1.5 out of range"):
        point_load(a, 1.5, (0, 0, 0), (1, 0, 0))
    with pytest.raises(ValueError, match=r"^force must be finite"):
        point_load(a, 0, (0, 0, 0), (np.nan, 0, 0))


def test_a_whole_scene_in_mm_or_a_density_in_tonnes_warns():
    """A 0.2 x 0.2 x 0.4 m block on a 1 x 1 x 0.1 m ground, all typed in mm: the blocks agree
    with each other, so only their size gives the units away (the median of the two bounding
    box diagonals, 954 "m"); likewise a density of 2.4 for every block (t/m^3)."""
    from dem.scene import MixedUnitsWarning

    ground_mm = box_corners((-500.0, -500.0, -100.0), (500.0, 500.0, 0.0))
    block_mm = box_corners((0, 0, 0), (200.0, 200.0, 400.0))
    with pytest.warns(MixedUnitsWarning, match=r"median block is 954 m across: .* not mm"):
        Scene.from_convex_blocks([ground_mm, block_mm], 2000.0, fixed=[0])
    ground, block = ground_mm / 1000.0, block_mm / 1000.0
    with pytest.warns(MixedUnitsWarning, match=r"median density is 2.4 kg/m\^3: .* t/m\^3"):
        Scene.from_convex_blocks([ground, block], 2.4, fixed=[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Scene.from_convex_blocks([ground, block], 2400.0, fixed=[0])
