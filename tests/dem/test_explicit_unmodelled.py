"""Blocks that meet where no contact node was seeded stop the run, naming the pair."""

from types import SimpleNamespace

import numpy as np
import pytest

from dem.explicit import ExplicitModel, ExplicitSettings, UnmodelledContactError
from dem.explicit.unmodelled import block_hulls, worst_overlap
from dem.kernels.integrate import quat_to_rot
from dem.scene import Assembly, Scene

SIDE, MARGIN = 0.01, 1e-4  # [m]


def box(x, y, z, sx=SIDE, sy=SIDE, sz=SIDE):
    return np.array(
        [[x + i * sx, y + j * sy, z + k * sz] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    )


def sliding_pair(gap, margin=MARGIN):
    """Two cubes on a fixed base ``gap`` apart, frictionless, the first thrown at the second."""
    base = box(-0.01, -0.01, -SIDE, 0.05, 0.03, SIDE)
    scene = Scene.from_convex_blocks([base, box(0, 0, 0), box(SIDE + gap, 0, 0)], 2500.0,
                                     fixed=[0], mu=0.0)  # fmt: skip
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4, margin=margin,
                                global_damping=0.0)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.vel[1] = [0.5, 0.0, 0.0]
    return model


def test_blocks_meeting_without_nodes_stop_the_run_naming_them():
    # 5 margins apart: no node between the facing sides; without the check the first cube
    # passed through the second (centroid at x = 35 mm, beyond the second's 15.5 mm)
    model = sliding_pair(5 * MARGIN)
    expected = r"blocks 1 and 2 overlap .*no contact .*larger margin"
    with pytest.raises(UnmodelledContactError, match=expected):
        model.advance(int(0.03 / 0.5 / model.dt))
    assert model.pos[1, 0] < model.pos[2, 0]  # stopped before passing through


def test_a_margin_wider_than_the_gap_seeds_the_facing_sides():
    """What the error advises (a user's 4 x 4 TIS panel at 12.5 degrees stopped at 1.88 mm
    with the default 0.1 mm and reached its peak, 743 N, with 0.3 mm): the same pair 5
    margins apart, with a margin of 10, collides as a modelled contact."""
    model = sliding_pair(5 * MARGIN, margin=10 * MARGIN)
    model.advance(int(0.03 / 0.5 / model.dt))
    assert model.pos[1, 0] < model.pos[2, 0]
    assert model.vel[2, 0] > 0.1  # the second cube was pushed


def test_blocks_touching_at_the_start_collide_without_error():
    model = sliding_pair(0.0)  # facing sides seeded: a modelled collision
    model.advance(int(0.01 / 0.5 / model.dt))
    assert model.pos[2, 0] > SIDE * 1.5 + 1e-3  # the second cube was pushed


@pytest.mark.parametrize(
    ("shift", "angle", "depth"),
    [(0.003, 0.0, 0.007), (0.0, 0.0, 0.01), (0.0105, 0.0, 0.0), (0.0, 45.0, 0.01)],
)
def test_penetration_depth_of_two_cubes(shift, angle, depth):
    # closed form: two aligned cubes shifted along x overlap by SIDE - shift; a cube turned
    # about z on the same centre still needs SIDE along z to get out
    asm = Assembly.from_convex_blocks([box(0, 0, 0), box(0, 0, 0)], 2500.0)
    centre = asm.centroid
    pos = centre + [[0.0, 0.0, 0.0], [shift, 0.0, 0.0]]
    rot = np.empty((2, 3, 3))
    half = np.radians(angle) / 2
    quat_to_rot(np.array([[1.0, 0, 0, 0], [np.cos(half), 0, 0, np.sin(half)]]), rot)
    blocks = asm.blocks
    bodies = SimpleNamespace(radius=np.full(2, SIDE), free_blocks=np.array([1]))
    shapes = SimpleNamespace(face_ptr=np.array([0, 6, 12]),
                             face_normal=np.concatenate([b.normals for b in blocks]))  # fmt: skip
    got = worst_overlap(block_hulls(blocks, centre), bodies, shapes, pos, rot,
                        np.zeros((0, 2), dtype=int), MARGIN)  # fmt: skip
    assert got[2] == pytest.approx(depth, abs=1e-12)


def test_kernel_depth_equals_the_geometry_sat_on_posed_blocks():
    # independent expectation: dem.geometry.polyhedron.penetration_depth on the posed blocks
    from scipy.spatial.transform import Rotation

    from dem.geometry.polyhedron import convex_block, penetration_depth
    from dem.kernels.overlap import penetration_depths

    rng = np.random.default_rng(3)
    base = rng.normal(size=(12, 3)) * [0.02, 0.015, 0.01]
    for _ in range(20):
        posed = [convex_block(Rotation.random(random_state=rng).apply(base) + shift)
                 for shift in (np.zeros(3), rng.normal(scale=0.012, size=3))]  # fmt: skip
        arrays = []
        for get in (lambda b: b.vertices, lambda b: b.normals,
                    lambda b: b.vertices[b.edges[:, 1]] - b.vertices[b.edges[:, 0]]):  # fmt: skip
            rows = [get(b) for b in posed]
            ptr = np.array([0, len(rows[0]), len(rows[0]) + len(rows[1])])
            arrays += [np.concatenate(rows), ptr]
        edges = arrays[4] / np.linalg.norm(arrays[4], axis=1)[:, None]
        out = np.empty(1)
        penetration_depths(arrays[0], arrays[1], arrays[2], arrays[3], edges, arrays[5],
                           np.array([[0, 1]]), out)  # fmt: skip
        expected = max(0.0, penetration_depth(*posed))
        assert out[0] == pytest.approx(expected, abs=1e-12)
