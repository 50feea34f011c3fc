"""Contacts between faces that did not touch at the start carry the penalty force.

A knife edge (a fixed block turned 45 degrees about y, its lowest edge along y, longer than the
cube) pressed ``d`` into the top face of a cube of side ``L``. A point of the cube's surface
inside the edge lies ``(d - |x| - s) / sqrt(2)`` below the edge's nearest face (``x`` from the
edge line, ``s`` below the top face), whose normal is 45 degrees from the vertical: the
penalty pushes the cube down with ``k_n (d - |x| - s) / 2`` per unit area. Over the top face
(``s = 0``) and the two end faces (the triangles ``|x| + s < d``):

    F_z = -k_n [ L int (d - |x|) dx / 2 + 2 int int (d - |x| - s) ds dx / 2 ]
        = -k_n (L d^2 / 2 + d^3 / 3),    F_x = 0.

The nodes (vertex layout, pulled ``delta = 2 margin = h / 2`` inside the face's edges) sum these
integrals by the trapezoidal rule on cells of side ``h``; the edge line lies ``0.3 h`` off a
grid line, so that no node is on the ridge, where the two faces are equally near. On the top
face (1D): a kink of the slope by ``J`` inside a cell costs at most ``J h^2 / 8`` (the
trapezoidal error of ``|x|`` on a cell is ``t (h - t) <= h^2 / 4``, ``t`` the kink's offset
from the cell's end), and the tent has kinks of 1, 2 and 1: at most ``k_n L h^2 / 4``. On an
end face a cell that a kink line crosses errs by at most ``J h^2 / 2`` times the line's length
in it (the integrand departs from its linear part by at most ``J h / 2`` there): gradient jump
1 along the ridge (length ``d``) and ``1 / sqrt(2)`` along the two sides (``sqrt(2) d``), at
most ``3 d h^2 / 2`` per face; its top row, ``delta`` below the edge, carries ``k_n delta / 2``
less per unit area on ``2 d / h`` nodes of ``h^2 / 2``: ``k_n delta h d / 2`` per face. In all
``|F_z + k_n (L d^2 / 2 + d^3 / 3)| <= k_n (L h^2 / 4 + 7 d h^2 / 2)``. Horizontally each
side of the ridge pushes ``k_n L d^2 / 4`` one way, to within ``k_n L (d h / 2 + h^2 / 8) / 2``
(the jump of the side's integrand at the ridge costs at most ``d h / 2``), and the end faces'
share is at most theirs vertically: ``|F_x| <= k_n (L (d h + h^2 / 4) / 2 + d^3 / 3)``.
"""

import numpy as np
import pytest

from dem.contact_nodes import seed_contact_nodes
from dem.explicit import ExplicitModel, ExplicitSettings
from dem.scene import Scene
from dem.scenes.tis_panel import tis_panel
from dem.units import MM

SIDE, K_N, H = 0.01, 1e10, 0.1 * MM  # [m], [Pa/m], [m]


def cube(lo, side=SIDE):
    return np.array([[lo[0] + i * side, lo[1] + j * side, lo[2] + k * side]
                     for i in (0, 1) for j in (0, 1) for k in (0, 1)])  # fmt: skip


def knife_edge_scene() -> Scene:
    """A free cube [0, L]^3 (block 0) under a fixed knife edge (block 1) along y at
    x = L / 2 + 0.3 h, touching its top face; no gravity."""
    a, x = SIDE, 0.5 * SIDE + 0.3 * H
    section = [(x, SIDE), (x + a, SIDE + a), (x, SIDE + 2 * a), (x - a, SIDE + a)]
    edge = np.array([(x, y, z) for x, z in section for y in (-0.5 * SIDE, 1.5 * SIDE)])
    return Scene.from_convex_blocks([cube((0, 0, 0)), edge], 2500.0, fixed=[1], mu=0.0, g=0.0)


@pytest.mark.parametrize("depth", [0.35 * MM, 0.8 * MM])
def test_an_edge_pressed_into_a_face_that_never_touched_carries_the_penalty(depth):
    """The cube's top face and the knife edge's faces are 45 degrees apart: no interface, so
    no face of either block had nodes (the model found no contact stiffness at all, and the
    edge went into the cube unopposed); the free cube now counts the contact on all its
    faces (module docstring)."""
    settings = ExplicitSettings(k_n=K_N, node_spacing=H, margin=H / 4, mu=0.0)
    model = ExplicitModel(knife_edge_scene(), settings)
    model.pos[0, 2] += depth  # the edge goes `depth` into the cube's top face
    model.rebuild()
    force, *_ = model.contact_wrenches()
    expected = K_N * (SIDE * depth**2 / 2 + depth**3 / 3)
    assert abs(force[0, 2] + expected) <= K_N * (SIDE * H**2 / 4 + 7 * depth * H**2 / 2)
    assert abs(force[0, 0]) <= K_N * (SIDE * (depth * H + H**2 / 4) / 2 + depth**3 / 3)
    assert abs(force[0, 1]) <= 1e-9 * expected  # the edge is uniform along y


def test_a_block_dropped_onto_a_support_it_did_not_touch_rests_on_it():
    """A cube released 3 margins above a fixed slab (no interface at the start: neither face
    had nodes, and the cube fell into the slab until the run stopped) comes to rest on it,
    sunk by the penalty's deflection ``m g / (k_n A)`` (uniform depth over its base)."""
    slab = np.array([[x, y, z] for x in (-0.01, 0.02) for y in (-0.01, 0.02)
                     for z in (-0.005, 0.0)])  # fmt: skip
    margin = 0.1 * MM
    scene = Scene.from_convex_blocks([cube((0, 0, 3 * margin)), slab], 2500.0, fixed=[1],
                                     mu=0.5)  # fmt: skip
    # no contact at the start sets the step: dt well below 2 / omega of the cube on its base
    # (vertical sqrt(k_n A / m) = 2e4 rad/s, rocking sqrt(3) times that); it falls for 8 ms,
    # then local damping brings it to rest
    settings = ExplicitSettings(k_n=K_N, node_spacing=SIDE / 5, margin=margin, dt=5e-6,
                                local_damping=0.7)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.advance(8000)
    assert np.linalg.norm(model.vel[0]) < 1e-5
    weight = 2500.0 * SIDE**3 * 9.80665
    sink = -(model.pos[0, 2] - 0.5 * SIDE)
    np.testing.assert_allclose(sink, weight / (K_N * SIDE**2), rtol=1e-3)
    force, *_ = model.contact_wrenches()
    np.testing.assert_allclose(force[0], [0.0, 0.0, weight], rtol=1e-3, atol=1e-6 * weight)


def test_every_pair_is_counted_once_by_a_block_with_nodes_on_all_faces():
    """TIS panel: the weights of each pair add up to 1 (0 for two fixed blocks), and a block
    that counts against another carries nodes on each of its faces whose areas add up to the
    face's area (shoelace, via the block's own polygon)."""
    scene = tis_panel(3, 5.0)
    fixed = scene.supports.fixed
    nodes = seed_contact_nodes(scene.assembly, fixed, 0.5 * MM, 0.1 * MM)
    total = nodes.weight + nodes.weight.T
    both_fixed = fixed[:, None] & fixed[None, :]
    np.fill_diagonal(both_fixed, True)
    np.testing.assert_array_equal(total[~both_fixed], 1.0)
    np.testing.assert_array_equal(total[both_fixed], 0.0)
    face_ptr = scene.assembly.arrays.face_ptr
    for i in np.flatnonzero(nodes.weight.max(axis=1) > 0):
        blk = scene.assembly.blocks[i]
        for f, ids in enumerate(blk.faces):
            poly = blk.vertices[ids]
            area = 0.5 * np.linalg.norm(np.cross(poly[1:-1] - poly[0], poly[2:] - poly[0],
                                                 axis=1).sum(axis=0))  # fmt: skip
            on = nodes.face == face_ptr[i] + f
            np.testing.assert_allclose(nodes.area[on].sum(), area, rtol=1e-9)
