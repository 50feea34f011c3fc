"""Running-bond walls against hand counts; openings; supports; loads; bad input."""

import numpy as np
import pytest

from dem.scenes.running_bond_wall import running_bond_wall
from dem.units import MM

A, B, S = 100.0, 200.0, 50.0  # block height, length, thickness [mm]


def test_counts_and_areas_by_hand():
    # 4 blocks per course, 3 courses: 4 + 5 + 4 blocks (+ foundation); head joints 3 + 4 + 3;
    # each of the 2 bed joints between courses is cut by the offset head joints into 8 pieces
    # of b/2 x s; the foundation carries 4 full bed faces b x s
    scene = running_bond_wall(4, 3, A, B, S, 20.0)
    assert scene.n_blocks == 13 + 1
    iface = scene.assembly.interfaces()
    areas = np.sort(iface.area) / MM**2
    expected = np.sort([A * S] * 10 + [B / 2 * S] * 16 + [B * S] * 4)
    np.testing.assert_allclose(areas, expected, rtol=1e-12)
    np.testing.assert_allclose(
        scene.assembly.volume.sum(), (4 * 3 * A * B * S + 4 * B * S * A) * MM**3, rtol=1e-12
    )


def test_opening_leaves_no_block_inside_it():
    x0, z0, x1, z1 = 300.0, 200.0, 700.0, 500.0
    scene = running_bond_wall(6, 8, A, B, S, 20.0, openings_mm=[(x0, z0, x1, z1)])
    for blk in scene.assembly.blocks:
        lo, hi = blk.vertices.min(0) / MM, blk.vertices.max(0) / MM
        overlap_x = min(hi[0], x1) - max(lo[0], x0)
        overlap_z = min(hi[2], z1) - max(lo[2], z0)
        assert overlap_x <= 1e-9 or overlap_z <= 1e-9
    wall_volume = (6 * B * 8 * A - (x1 - x0) * (z1 - z0)) * S * MM**3
    np.testing.assert_allclose(scene.assembly.volume[:-1].sum(), wall_volume, rtol=1e-12)


def test_supports_and_live_loads():
    scene = running_bond_wall(
        4,
        3,
        A,
        B,
        S,
        20.0,
        fixed_columns=["left"],
        simply_supported=["top", "right"],
        live="pressure",
    )
    course = np.array(scene.meta["course"])
    fixed = np.flatnonzero(scene.supports.fixed)
    # foundation plus the first block of each of the 3 courses (left column)
    assert set(fixed) == {0, 4, 9, scene.n_blocks - 1}
    restrained = np.flatnonzero(scene.supports.restrained[:, 1])
    top = set(np.flatnonzero(course == 2)) - {9}
    assert set(restrained) == top | {3, 8}  # top course and right end blocks, minus fixed ones
    # unit pressure on the free blocks' faces: total force = their face area b x a [m^2]
    free_face_area = sum(
        (np.ptp(b.vertices[:, 0]) * np.ptp(b.vertices[:, 2]))
        for i, b in enumerate(scene.assembly.blocks)
        if i not in fixed
    )
    np.testing.assert_allclose(scene.loads.live_wrench[:, 1].sum(), free_face_area, rtol=1e-12)
    np.testing.assert_allclose(scene.loads.live_wrench[fixed], 0.0)


def test_in_plane_live_load_is_the_free_blocks_weight_along_x():
    # 4 x 3 wall of unit weight 20 kN/m^3 with a fixed left column: the live force is the
    # weight (volume x unit weight) of the 10 free blocks, along +x only, none on fixed blocks
    scene = running_bond_wall(4, 3, A, B, S, 20.0, fixed_columns=["left"], live="in_plane")
    fixed = scene.supports.fixed
    weight = 20.0e3 * scene.assembly.volume[~fixed].sum()
    live = scene.loads.live_wrench
    np.testing.assert_allclose(live[:, 0].sum(), weight, rtol=1e-12)
    np.testing.assert_allclose(live[:, 1:3], 0.0)
    np.testing.assert_allclose(live[fixed], 0.0)


def test_beam_load_is_a_dead_force_on_the_top_block():
    scene = running_bond_wall(4, 3, A, B, S, 20.0, beam_loads_kn=[(500.0, 2.0)])
    hit = np.flatnonzero(np.abs(scene.loads.dead_wrench[:, 2]) > 0)
    assert len(hit) == 1 and scene.meta["course"][hit[0]] == 2
    np.testing.assert_allclose(scene.loads.dead_wrench[hit[0], 2], -2000.0)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"n_per_course": 0}, "positive integers"),
        ({"a_mm": -1.0}, "a_mm"),
        ({"unit_weight_kn_m3": np.nan}, "unit_weight_kn_m3"),
        ({"fixed_columns": ["top"]}, "fixed_columns"),
        ({"simply_supported": ["front"]}, "simply_supported"),
        (
            {"fixed_columns": "left"},
            r"fixed_columns must be a collection of sides, e\.g\. \('left',\)",
        ),
        ({"simply_supported": "top"}, "simply_supported must be a collection"),
        ({"live": "wind"}, "live"),
        ({"openings_mm": [(100.0, 150.0, 300.0, 300.0)]}, "bed joint"),
        ({"openings_mm": [(100.0, 100.0, 9000.0, 300.0)]}, "not inside"),
        ({"beam_loads_kn": [(5000.0, 1.0)]}, "not above any top block"),
    ],
)
def test_bad_wall_input_raises(kwargs, message):
    args = {
        "n_per_course": 4,
        "n_courses": 3,
        "a_mm": A,
        "b_mm": B,
        "s_mm": S,
        "unit_weight_kn_m3": 20.0,
    }
    with pytest.raises(ValueError, match=message):
        running_bond_wall(**{**args, **kwargs})
