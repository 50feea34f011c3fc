"""The contacts that carry the load at a state, named for a report."""

import numpy as np

from dem.explicit import ExplicitModel, RelaxationSettings, masonry_settings
from dem.explicit.diagnosis import pair_forces
from dem.scene import G, Scene, proportional_to_weight

SIDE = 0.2  # [m]


def box(lo, hi):
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def scene_of(blocks):
    scene = Scene.from_convex_blocks(blocks, density=2000.0, fixed=[0], mu=0.6)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def test_stack_at_rest_carries_its_weight_through_its_interfaces():
    """Two cubes stacked on a slab, relaxed: the slab carries both weights, the lower cube
    the upper one's (statics); both pairs share a face interface, with no gap; a third cube
    2 mm beside the stack, within the margin, touches only the slab."""
    blocks = [
        box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0)),
        box((0.0, 0.0, 0.0), (SIDE, SIDE, SIDE)),
        box((0.0, 0.0, SIDE), (SIDE, SIDE, 2 * SIDE)),
        box((SIDE + 2e-3, 0.0, 0.0), (2 * SIDE + 2e-3, SIDE, SIDE)),
    ]
    scene = scene_of(blocks)
    model = ExplicitModel(scene, masonry_settings(scene))
    model.set_external_wrench(scene.dead_wrench)
    model.relax(RelaxationSettings(max_steps=400000))
    forces = pair_forces(model)
    pairs = [tuple(p) for p in forces.pairs]
    assert sorted(pairs) == [(0, 1), (0, 3), (1, 2)]
    weight = 2000.0 * SIDE**3 * G
    by_pair = dict(zip(pairs, forces.force, strict=True))
    # force on the lower-numbered block from the other
    np.testing.assert_allclose(by_pair[(0, 1)], [0.0, 0.0, -2 * weight], atol=1e-3 * weight)
    np.testing.assert_allclose(by_pair[(1, 2)], [0.0, 0.0, -weight], atol=1e-3 * weight)
    assert forces.interface.all() and np.all(forces.gap == 0.0)
