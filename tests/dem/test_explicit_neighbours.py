"""The explicit solver's shortcuts in the node loop give exactly the full scan's results.

Two shortcuts (:func:`dem.kernels.contact_force.contact_entries`): a separated entry is not
evaluated while the drift of its two blocks cannot have closed its gap, and an entry whose
neighbour has one or two faces that can be its nearest plane until the next list rebuild
(:func:`dem.kernels.broadphase.near_faces`) tests those planes only. The reference evaluates
every entry against every face of its neighbour at every step: the trajectories must agree bit
for bit, so a contact missed for one step, or a wrong plane, fails the tests.
"""

import numpy as np

from dem.explicit import ExplicitModel, ExplicitSettings
from dem.scene import Scene

SIDE = 0.01  # [m]
MARGIN = 1e-4  # [m]


def box(x, y, z, sx=SIDE, sy=SIDE, sz=SIDE):
    return np.array(
        [[x + i * sx, y + j * sy, z + k * sz] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    )


def model_of(blocks, velocity):
    scene = Scene.from_convex_blocks(blocks, 2500.0, fixed=[0], mu=0.3)
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4, margin=MARGIN,
                                global_damping=0.0)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.vel[1] = velocity
    return model


def full_scan(model, n_steps):
    """Advance step by step with both shortcuts off: every entry, every face."""
    for _ in range(n_steps):
        model.pairs.near_faces[:] = -1
        model.scratch.skip_gap[:] = 0.0
        model.advance(1)


def shortcut_counts(model, n_steps, chunk=50):
    """Advance with the shortcuts; entries with one face, with two faces and entries skipped,
    summed over chunks."""
    single = double = skipped = 0
    for _ in range(n_steps // chunk):
        model.advance(chunk)
        near = model.pairs.near_faces
        single += int(np.count_nonzero((near[:, 0] >= 0) & (near[:, 1] < 0)))
        double += int(np.count_nonzero(near[:, 1] >= 0))
        skipped += int(np.count_nonzero(model.scratch.skip_gap > 0))
    return single, double, skipped


def assert_same_run(blocks, velocity, n_steps):
    fast, slow = model_of(blocks, velocity), model_of(blocks, velocity)
    single, double, skipped = shortcut_counts(fast, n_steps)
    full_scan(slow, n_steps)
    assert single > 0 and skipped > 0  # both shortcuts were used
    np.testing.assert_array_equal(fast.pos, slow.pos)
    np.testing.assert_array_equal(fast.quat, slow.quat)
    np.testing.assert_array_equal(fast.state.contacts.shear, slow.state.contacts.shear)
    return fast, double


def test_block_sliding_off_an_edge_matches_full_scan():
    """A block pushed along its support slides over the support's edge: the nodes that pass the
    edge change their nearest plane (top face -> end face) and lose contact; it then tips."""
    ground = box(-0.02, -0.01, -SIDE, sx=0.03, sy=0.03)
    top = box(0.0, 0.0, 0.0)
    model, double = assert_same_run([ground, top], [0.8, 0.0, 0.0], 6000)
    assert double > 0  # nodes near the edge tested two planes
    assert model.pos[1, 0] - SIDE / 2 > 0.5 * SIDE  # its centroid is past the edge
    assert model.quat[1, 2] != 0.0  # it tips over the edge


def test_block_coming_back_from_beyond_the_margin_matches_full_scan():
    """A block starts half a margin above its support and is thrown up by 5 margins: its nodes
    leave the list (nothing within the margin), then fall back, re-enter it and land; the
    skipped entries must come back in time."""
    ground = box(-0.01, -0.01, -SIDE, sx=0.03, sy=0.03)
    top = box(0.0, 0.0, 0.5 * MARGIN)
    model = model_of([ground, top], [0.05, 0.0, 0.1])
    model.advance(300)
    assert model.n_entries == 0 and model.pos[1, 2] - SIDE / 2 > 3 * MARGIN  # far
    model, _ = assert_same_run([ground, top], [0.05, 0.0, 0.1], 3000)
    assert model.n_entries > 0
    assert abs(model.pos[1, 2] - SIDE / 2) < MARGIN  # landed, did not pass through
