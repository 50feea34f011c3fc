"""The compatibility matrix H: rigid motions, and H^T as the equilibrium operator."""

import numpy as np

from dem.geometry.compatibility import compatibility_matrix
from dem.scenes.running_bond_wall import running_bond_wall


def test_rigid_motion_of_the_whole_wall_gives_no_interface_motion():
    scene = running_bond_wall(3, 3, 100, 200, 50, 20)
    x = scene.assembly.centroid
    H = compatibility_matrix(x, scene.assembly.interfaces())
    u, r = np.array([0.1, -0.3, 0.2]), np.array([0.02, 0.05, -0.01])
    U = np.hstack([u + np.cross(r, x), np.tile(r, (len(x), 1))]).ravel()
    assert np.abs(H @ U).max() < 1e-14


def test_transpose_of_H_sums_interface_forces_onto_blocks():
    # independent statics: a force F and moment M (in the global frame) at the interface
    # centroid act on block b as (F, (c - x_b) x F + M) and on block a with opposite sign
    scene = running_bond_wall(3, 2, 100, 200, 50, 20)
    x = scene.assembly.centroid
    iface = scene.assembly.interfaces()
    H = compatibility_matrix(x, iface)
    rng = np.random.default_rng(1)
    f = rng.normal(size=(iface.n_interfaces, 6))
    expected = np.zeros((scene.n_blocks, 6))
    for k in range(iface.n_interfaces):
        n, t1, t2 = iface.frame[k]
        force = f[k, 0] * n + f[k, 1] * t1 + f[k, 2] * t2
        moment = f[k, 3] * t1 + f[k, 4] * t2 + f[k, 5] * n
        for blk, sign in ((iface.block_b[k], 1.0), (iface.block_a[k], -1.0)):
            expected[blk, :3] += sign * force
            expected[blk, 3:] += sign * (np.cross(iface.centroid[k] - x[blk], force) + moment)
    np.testing.assert_allclose((H.T @ f.ravel()).reshape(-1, 6), expected, atol=1e-12)
