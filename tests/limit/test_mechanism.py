"""Collapse mechanisms from the duals: rocking about the toe, sliding with dilatancy mu."""

import numpy as np
import pytest

from limit.mechanism import rotation_matrices, thrust_points, write_mechanism
from limit.problems import LimitSettings
from limit.solve import limit_analysis
from tests.limit._scenes import block_on_ground


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_overturning_block_rotates_about_its_toe(model):
    """A slender block (b/h < mu) overturns: its velocity field is a rotation about the
    toe edge x = b/2, z = 0 (instantaneous axis along y), so the toe does not move."""
    b, h = 0.2, 0.6
    scene = block_on_ground(b, 0.3, h, mu=0.8)
    res = limit_analysis(scene, LimitSettings(interface_model=model))
    u, w = res.velocities[1, :3], res.velocities[1, 3:]
    toe = np.array([b / 2, 0.0, 0.0]) - scene.assembly.centroid[1]
    np.testing.assert_allclose(u + np.cross(w, toe), 0.0, atol=1e-7 * np.abs(u).max())
    assert w[1] > 0 and abs(w[0]) < 1e-8 * w[1] and abs(w[2]) < 1e-8 * w[1]
    # the ground does not move; live-load power is 1 by normalisation
    np.testing.assert_allclose(res.velocities[0], 0.0)


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_sliding_block_dilates_with_mu(model):
    """A squat block slides (mu < b/h); associated flow (normality) makes it lift off at
    the dilatancy angle: u_z / u_x = mu and no rotation."""
    mu = 0.4
    scene = block_on_ground(1.0, 1.0, 0.2, mu=mu)
    res = limit_analysis(scene, LimitSettings(interface_model=model))
    u, w = res.velocities[1, :3], res.velocities[1, 3:]
    np.testing.assert_allclose(u[2] / u[0], mu, rtol=1e-6)
    np.testing.assert_allclose(w, 0.0, atol=1e-7 * abs(u[0]))


def test_rotation_matrices_are_rotations():
    rng = np.random.default_rng(0)
    r = rotation_matrices(rng.standard_normal((5, 3)))
    np.testing.assert_allclose(
        r @ np.transpose(r, (0, 2, 1)), np.tile(np.eye(3), (5, 1, 1)), atol=1e-14
    )
    np.testing.assert_allclose(np.linalg.det(r), 1.0, rtol=1e-14)


def test_thrust_point_of_overturning_block_at_toe(tmp_path):
    """At overturning the whole weight passes through the toe: the centre of pressure of the
    bed joint is the edge x = b/2; the VTU and the npz are written."""
    b, h = 0.2, 0.6
    scene = block_on_ground(b, 0.3, h, mu=0.8)
    res = limit_analysis(scene, LimitSettings(interface_model="resultant"))
    tp = thrust_points(scene, res.interface_forces)
    np.testing.assert_allclose(tp["point"][0, 0], b / 2, atol=1e-7)
    weight = scene.assembly.mass[1] * 9.81
    np.testing.assert_allclose(tp["compression"][0], weight, rtol=1e-7)
    paths = write_mechanism(scene, res, tmp_path / "block")
    import pyvista as pv

    grid = pv.read(paths["vtu"])
    assert grid.n_cells == sum(len(blk.faces) for blk in scene.assembly.blocks)
