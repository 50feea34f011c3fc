"""The mechanism check before the path (dem.static.mechanism): the rigid-part stage and the
full linear program, against motions worked out by hand."""

import numpy as np

from dem.scene import Scene
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import StaticSettings
from dem.static.mechanism import (
    _max_work,
    gap_matrix,
    no_mechanism_reason,
    rigid_components,
    rigid_motions,
)
from dem.static.model import Model


def box(x0, x1, y0, y1, z0, z1):
    return np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])


def pulled_apart() -> Scene:
    """Two 1 m cubes side by side on a fixed slab, the left pulled along -x and the right
    along +x by equal forces: no rigid motion of the pair does work (no net force or
    moment), but the two sliding apart (their joint opening) does."""
    blocks = [box(-1, 0, 0, 1, 0, 1), box(0, 1, 0, 1, 0, 1), box(-3, 3, -1, 2, -1, 0)]
    scene = Scene.from_convex_blocks(blocks, 1000.0, fixed=[2], mu=0.5)
    live = np.zeros((3, 6))
    live[0, 0], live[1, 0] = -1.0, 1.0
    return scene.with_loads(live=live)


def test_rigid_motion_of_a_part_maps_to_every_block():
    # a rotation omega about z of the part {0, 1} moves block i's centroid by omega x r_i
    model = Model(pulled_apart(), StaticSettings())
    n_parts, label = rigid_components(model)
    assert n_parts == 1 and label.tolist() == [0, 0, -1]
    P, E = rigid_motions(model, n_parts, label)
    assert E.shape[0] == 0
    u = P @ np.array([0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
    # centroids (-0.5, 0.5, 0.5) and (0.5, 0.5, 0.5) about their mean (0, 0.5, 0.5)
    np.testing.assert_allclose(u.reshape(2, 6)[:, :3], [[0, -0.5, 0], [0, 0.5, 0]], atol=1e-15)
    np.testing.assert_allclose(u.reshape(2, 6)[:, 5], 1.0)


def test_a_mechanism_no_rigid_part_shows_is_found_by_the_full_program():
    model = Model(pulled_apart(), StaticSettings())
    n_parts, label = rigid_components(model)
    P, _ = rigid_motions(model, n_parts, label)
    between = np.flatnonzero(label[model.a] != label[model.b])
    work, _ = _max_work(model, gap_matrix(model, between), P, None)
    assert abs(work) < 1e-9  # no net force or moment: no rigid motion of the pair works
    assert no_mechanism_reason(model) == ""  # sliding apart does: the full program finds it


def test_restrained_dofs_are_the_equalities_of_the_rigid_parts():
    # the top course held out of plane: E x is the uy of each top block under the part's
    # rigid motion x, t_y + omega_z r_x - omega_x r_z about the part's mean centroid
    scene = running_bond_wall(4, 4, 81, 210, 70, 20, 0.7, simply_supported=("top",))
    model = Model(scene, StaticSettings())
    n_parts, label = rigid_components(model)
    P, E = rigid_motions(model, n_parts, label)
    top = np.flatnonzero(scene.supports.restrained[:, 1])
    assert n_parts == 1 and E.shape == (len(top), 6)
    x = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    movable = label >= 0
    r = scene.assembly.centroid[top] - scene.assembly.centroid[movable].mean(axis=0)
    np.testing.assert_allclose(E @ x, x[1] + x[5] * r[:, 0] - x[3] * r[:, 2], atol=1e-15)
    assert no_mechanism_reason(model) == ""
