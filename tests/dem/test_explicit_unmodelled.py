"""Contacts that appear after motion are modelled; blocks passing through each other stop."""

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


def sliding_pair(gap, speed=0.5):
    """Two cubes on a fixed base ``gap`` apart, frictionless and undamped, the first thrown at
    the second at ``speed`` [m/s]."""
    base = box(-0.01, -0.01, -SIDE, 0.05, 0.03, SIDE)
    scene = Scene.from_convex_blocks([base, box(0, 0, 0), box(SIDE + gap, 0, 0)], 2500.0,
                                     fixed=[0], mu=0.0)  # fmt: skip
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4, margin=MARGIN,
                                global_damping=0.0)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.vel[1] = [speed, 0.0, 0.0]
    return model


def test_blocks_meeting_on_faces_apart_at_the_start_collide_as_a_contact():
    """5 margins apart, the facing sides did not touch at the start; both cubes carry nodes on
    every face (halving), so they collide: the run goes on, the first cube stays behind the
    second and pushes it, and the base (frictionless) keeps their momentum along x."""
    model = sliding_pair(5 * MARGIN)
    momentum = model.vel[1:, 0].sum()
    model.advance(int(0.03 / 0.5 / model.dt))
    assert model.pos[1, 0] < model.pos[2, 0]
    assert model.vel[2, 0] > 0.1  # the second cube was pushed
    np.testing.assert_allclose(model.vel[1:, 0].sum(), momentum, rtol=1e-9)


def test_blocks_passing_through_each_other_still_stop_the_run_naming_them():
    """Thrown at 50 m/s, the penalty could stop the first cube only 1.8 mm inside the second
    (relative kinetic energy m v^2 / 4 = k_n A d^2 / 2), beyond OVERLAP_LIMIT (1 mm of the
    10 mm cubes): the run stops before they pass through each other."""
    model = sliding_pair(5 * MARGIN, speed=50.0)
    expected = r"blocks 1 and 2 overlap .*do not hold them apart.*passing"
    with pytest.raises(UnmodelledContactError, match=expected):
        model.advance(int(0.03 / 50.0 / model.dt))
    assert model.pos[1, 0] < model.pos[2, 0]


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
