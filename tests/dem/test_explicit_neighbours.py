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
from dem.kernels.contact_force import contact_entries, pair_frames
from dem.kernels.integrate import quat_to_rot
from dem.scene import Scene
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM

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


def test_entry_range_split_anywhere_counts_every_entry_once():
    """The entry loop walks runs of one block pair; a range that starts or ends inside a run
    (the chunks of the parallel loop) must evaluate each of its entries exactly once. Split
    at every entry, the two halves give the whole range's forces, depths and shear history bit
    for bit (an entry evaluated twice would increment its history twice, a missed one keeps
    NaN) and its pair sums up to rounding."""
    scene = tis_panel(3, 2.5)
    model = ExplicitModel(scene, ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=2 * MM))
    rng = np.random.default_rng(0)
    free = model.free_blocks
    model.vel[free] = rng.normal(scale=1e-3, size=(len(free), 3))
    model.omega[free] = rng.normal(scale=1e-2, size=(len(free), 3))
    sc, pairs, m = model.scratch, model.pairs, model.n_entries
    quat_to_rot(model.quat, sc.rot)
    pair_frames(model.state.motion, sc.rot, model.bodies, model.shapes, pairs)
    assert len(pairs.run_pair) > 10 and np.any(np.diff(pairs.run_ptr) > 1)

    def evaluate(ranges):
        contacts = model.state.contacts._replace(shear=model.state.contacts.shear.copy())
        for arr in (sc.out_force, sc.out_depth):
            arr.fill(np.nan)
        sc.skip_gap.fill(0.0)  # evaluate every entry
        sums = np.zeros((len(ranges), len(pairs.a), 6))
        for j, (begin, end) in enumerate(ranges):
            contact_entries(begin, end, model.constants, (contacts, model.state.motion), 1e-6,
                            sc, pairs, True, sums[j])  # fmt: skip
        return contacts.shear, sc.out_force.copy(), sc.out_depth.copy(), sums.sum(axis=0)

    shear, force, depth, sums = evaluate([(0, m)])
    assert np.count_nonzero(np.abs(shear).sum(axis=1)) > 10  # histories that change
    for k in range(m + 1):
        split = evaluate([(0, k), (k, m)])
        np.testing.assert_array_equal(split[0], shear)
        np.testing.assert_array_equal(split[1], force)
        np.testing.assert_array_equal(split[2], depth)
        np.testing.assert_allclose(split[3], sums, rtol=1e-12, atol=1e-12 * np.abs(sums).max())


def test_neighbour_list_equals_a_numpy_scan_of_every_node_and_every_block():
    """:func:`build_pairs` (each node tested only against the blocks whose bounding spheres
    come within the margin of its own, :func:`near_blocks`) against NumPy: every node against
    every other block of non-zero weight, kept where its face-plane distance is below the
    margin and it lies within the margin of the block's bounding sphere (the plane distance
    is a lower bound of the distance: beside an edge it can be below the margin far from the
    block); a 3 x 3 panel with the blocks moved up to 0.5 mm and turned up to 20 mrad."""
    from scipy.spatial.transform import Rotation

    from dem.kernels.broadphase import build_pairs

    margin = 0.3 * MM
    scene = tis_panel(3, 5.0)
    model = ExplicitModel(scene, ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1 * MM,
                                                  margin=margin))  # fmt: skip
    rng = np.random.default_rng(5)
    n = model.n_blocks
    pos = model.ref_centroid + rng.uniform(-0.5, 0.5, (n, 3)) * MM
    rot = Rotation.from_rotvec(rng.uniform(-0.02, 0.02, (n, 3))).as_matrix()
    node, block, _ = build_pairs(model.surface, pos, rot, model.bodies, model.shapes, margin)
    surface, shapes = model.surface, model.shapes
    world = pos[surface.block] + np.einsum("kij,kj->ki", rot[surface.block], surface.r0)
    expected = []
    for b in range(n):
        local = (world - pos[b]) @ rot[b] + model.ref_centroid[b]
        faces = slice(shapes.face_ptr[b], shapes.face_ptr[b + 1])
        phi = (local @ shapes.face_normal[faces].T - shapes.face_offset[faces]).max(axis=1)
        reach = np.linalg.norm(world - pos[b], axis=1) <= model.bodies.radius[b] + margin
        keep = (phi < margin) & reach & (surface.block != b)
        keep &= surface.weight[surface.block, b] != 0
        expected += [(i, b) for i in np.flatnonzero(keep)]
    assert len(expected) > 1000
    assert sorted(expected) == list(zip(node.tolist(), block.tolist(), strict=True))
