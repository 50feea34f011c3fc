"""Blocks near other blocks they do not bear on: no strength from the neighbours.

A node stands for a patch of its face (:func:`dem.contact_nodes.node_patches`); against the
plane of the neighbour's face that faces it, only the part of the patch over the neighbour
counts. A node on the edge of its face that lies beside a neighbour (two columns side by side,
whose joints meet edge to edge, or stand a gap apart) therefore carries nothing against it,
however deep below the neighbour's face plane it lies. The closed forms: a column of ``n``
cubes of side ``b`` under a live load equal to its weight tips at ``lambda = b / (n b)``; a
neighbour that it does not touch changes nothing.

Columns that touch tip together, each about its own toe, and overlap by ``b (1 - cos theta)``
after a finite rotation ``theta``: they then bear on each other and friction between them
holds the one in front down, so the mechanism that formed at ``1 / n`` stops after a few mm
(at the material's joint stiffness, 10 mm for 0.2 m cubes; the structure carries about 0.41
in that deformed state). The driver reports the onset (a step that moves the blocks ten times
more than the stiffest response so far) as the collapse, as the rigid-block methods do in
small displacements, and says the mechanism was arrested.
"""

import numpy as np
import pytest

from dem.contact_nodes import node_patches, seed_face
from dem.explicit import ExplicitModel, ExplicitSettings, simulate_lateral
from dem.explicit.lateral import LiveLoadRamp
from dem.scene import Scene, proportional_to_weight

SIDE = 0.2  # [m]
DRIVER = LiveLoadRamp(step=0.05, max_lambda=0.8, refinements=4)


def box(lo, hi):
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def columns(x_starts, n_high, fixed_columns=()):
    """Columns of ``n_high`` cubes starting at ``x_starts`` on a fixed slab (block 0); the
    live load is each free block's weight along +x."""
    blocks = [box((-1.0, -1.0, -0.2), (2.0, 1.0, 0.0))]
    fixed = [0]
    for c, x0 in enumerate(x_starts):
        for k in range(n_high[c]):
            if c in fixed_columns:
                fixed.append(len(blocks))
            blocks.append(box((x0, 0.0, k * SIDE), (x0 + SIDE, SIDE, (k + 1) * SIDE)))
    scene = Scene.from_convex_blocks(blocks, density=2000.0, fixed=fixed, mu=0.6)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def assert_tips_at(result, expected):
    """The bracket holds ``expected`` (the driver's detection threshold below it)."""
    assert result.collapsed and result.mechanism_confirmed
    width = DRIVER.step / 2**DRIVER.refinements
    assert result.lambda_moving - result.lambda_stable <= width + 1e-12
    assert result.lambda_stable - result.detection_lambda <= expected <= result.lambda_moving


@pytest.mark.parametrize("gap", [0.0, 1e-3, 10e-3, 30e-3])
def test_two_columns_a_gap_apart_each_tip_at_b_over_h(gap):
    """Two columns of three cubes, ``gap`` apart along the load: each tips at 1/3 (within
    the margin of 25 mm the top-face nodes of one column's blocks lie beside the other
    column's blocks, below their bottom planes once the columns rock); touching columns stop
    once they bear on each other (module docstring), columns a gap apart do not."""
    scene = columns([0.0, SIDE + gap], [3, 3])
    result = simulate_lateral(scene, driver=DRIVER)
    assert_tips_at(result, 1.0 / 3.0)
    np.testing.assert_array_equal(result.moving_blocks, np.arange(1, 7))
    assert result.arrested == (gap == 0.0)


def test_stack_bonded_wall_tips_column_by_column():
    """Three touching columns of two cubes (a wall in stack bond, no bond between the
    columns): each tips at 1/2, arrested once they bear on each other."""
    result = simulate_lateral(columns([0.0, SIDE, 2 * SIDE], [2, 2, 2]), driver=DRIVER)
    assert_tips_at(result, 0.5)
    assert result.arrested


@pytest.mark.slow
def test_grid_of_columns_tips_at_b_over_h():
    """A 2 x 2 grid in plan of touching columns of three cubes (touching along and across
    the load): 1/3, and three touching columns along the load: 1/3."""
    blocks = [box((-1.0, -1.0, -0.2), (2.0, 2.0, 0.0))]
    for i, j, k in np.ndindex(2, 2, 3):
        blocks.append(box((i * SIDE, j * SIDE, k * SIDE),
                          ((i + 1) * SIDE, (j + 1) * SIDE, (k + 1) * SIDE)))  # fmt: skip
    scene = Scene.from_convex_blocks(blocks, density=2000.0, fixed=[0], mu=0.6)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    assert_tips_at(simulate_lateral(scene, driver=DRIVER), 1.0 / 3.0)
    three = simulate_lateral(columns([0.0, SIDE, 2 * SIDE], [3, 3, 3]), driver=DRIVER)
    assert_tips_at(three, 1.0 / 3.0)


def test_column_beside_a_wall_it_does_not_touch_is_unaffected():
    """A column of two cubes 1 mm from a fixed column of three on its heel side: it tips at
    b / h = 1/2 as it does alone (its heel rises along the wall's joint)."""
    alone = simulate_lateral(columns([0.0], [2]), driver=DRIVER)
    beside = simulate_lateral(columns([-SIDE - 1e-3, 0.0], [3, 2], fixed_columns=(0,)),
                              driver=DRIVER)  # fmt: skip
    for result in (alone, beside):
        assert_tips_at(result, 0.5)
    assert beside.lambda_moving == alone.lambda_moving


@pytest.mark.parametrize("layout", ["vertex", "centroid"])
@pytest.mark.parametrize("edge", [0.1, 0.11, 0.137])
def test_overhanging_block_counts_only_the_part_over_its_support(layout, edge):
    """A cube pressed uniformly by ``d`` into a support whose edge runs under it at
    ``x = edge``: the contact force is ``k_n d`` times the area over the support,
    ``edge * SIDE``, exactly (the patches are boxes cut by a line along their sides)."""
    blocks = [box((-0.5, -0.5, -0.2), (edge, 0.5, 0.0)), box((0.0, 0.0, 0.0), (SIDE,) * 3)]
    scene = Scene.from_convex_blocks(blocks, density=2000.0, fixed=[0], mu=0.6)
    k_n, depth = 1e9, 1e-6
    settings = ExplicitSettings(k_n=k_n, node_spacing=0.05, node_layout=layout,
                                contact_plane="compatible", margin=0.025)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.pos[1, 2] -= depth
    force = model.contact_wrenches()[0][1]
    np.testing.assert_allclose(force, [0.0, 0.0, k_n * depth * edge * SIDE], rtol=1e-9,
                               atol=1e-9 * k_n * depth * SIDE**2)  # fmt: skip


@pytest.mark.parametrize("layout", ["vertex", "centroid"])
def test_patches_of_a_rectangle_tile_it(layout):
    """On a rectangle the nodes' patches are disjoint boxes that cover it: their areas sum to
    the face's and each node lies in its own box."""
    poly = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.3, 0.0], [0.0, 0.3, 0.0]])
    normal = np.array([0.0, 0.0, 1.0])
    points, _ = seed_face(poly, normal, 0.07, layout)
    centre, half_u, half_v = node_patches(poly, normal, 0.07, points, layout)
    ru, rv = np.linalg.norm(half_u, axis=1), np.linalg.norm(half_v, axis=1)
    np.testing.assert_allclose((4 * ru * rv).sum(), 0.5 * 0.3, rtol=1e-12)
    rel = points - centre
    assert np.all(np.abs(np.einsum("ij,ij->i", rel, half_u)) <= ru**2 * (1 + 1e-9))
    assert np.all(np.abs(np.einsum("ij,ij->i", rel, half_v)) <= rv**2 * (1 + 1e-9))
