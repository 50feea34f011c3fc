"""A_eq from statics equals -H^T of the DEM; vertex map and torsion coefficient."""

import numpy as np
import pytest

from dem.geometry.compatibility import compatibility_matrix
from dem.scenes.running_bond_wall import running_bond_wall
from limit.matrices import (
    equilibrium_matrix,
    mean_distance_polygon,
    torsion_coefficient,
    vertex_force_matrix,
)


@pytest.fixture(scope="module")
def wall():
    return running_bond_wall(3, 4, 50.0, 200.0, 100.0, 20.0, mu=0.6, fixed_columns=("left",))


def test_equilibrium_matrix_is_minus_h_transpose(wall):
    """Virtual work: the statics of the interface resultants is the adjoint of the DEM's
    kinematics (dem.geometry.compatibility), A_eq = -H^T, entry by entry."""
    interfaces = wall.assembly.interfaces()
    a_eq = equilibrium_matrix(wall.assembly.centroid, interfaces).toarray()
    h = compatibility_matrix(wall.assembly.centroid, interfaces).toarray()
    np.testing.assert_allclose(a_eq, -h.T, rtol=0, atol=1e-14)


def test_equilibrium_matrix_rotated_blocks():
    """Same identity on a randomly rotated assembly (frames not aligned with the axes)."""
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    scene = running_bond_wall(2, 3, 50.0, 200.0, 100.0, 20.0, mu=0.6)
    from dem.scene import Assembly

    blocks = [b.vertices @ q.T + 0.3 for b in scene.assembly.blocks]
    asm = Assembly.from_convex_blocks(blocks, 1000.0)
    interfaces = asm.interfaces()
    a_eq = equilibrium_matrix(asm.centroid, interfaces).toarray()
    h = compatibility_matrix(asm.centroid, interfaces).toarray()
    np.testing.assert_allclose(a_eq, -h.T, rtol=0, atol=1e-13)


def test_vertex_forces_resultants(wall):
    """Uniform pressure p on the corners gives N = -4p and no moment (centroid); a corner
    force gives the moments y x F of the definition."""
    interfaces = wall.assembly.interfaces()
    b = vertex_force_matrix(interfaces)
    k = 0
    lo, hi = interfaces.poly_ptr[k], interfaces.poly_ptr[k + 1]
    x = np.zeros(b.shape[1])
    x[3 * lo : 3 * hi : 3] = 10.0
    f = (b @ x).reshape(-1, 6)[k]
    np.testing.assert_allclose(f, [-10.0 * (hi - lo), 0, 0, 0, 0, 0], atol=1e-12)
    y = interfaces.local_polygon(k)[0]
    x[:] = 0.0
    x[3 * lo : 3 * lo + 3] = (2.0, 0.5, -0.25)  # p, s1, s2
    f = (b @ x).reshape(-1, 6)[k]
    # traction sigma = -p n + s1 t1 + s2 t2 at (y1, y2): M = y x sigma in (t1, t2, n)
    expected = [-2.0, 0.5, -0.25, y[1] * -2.0, -y[0] * -2.0, y[0] * -0.25 - y[1] * 0.5]
    np.testing.assert_allclose(f, expected, atol=1e-12)


def test_mean_distance_closed_forms():
    """Square of side a: a (sqrt 2 + ln(1 + sqrt 2)) / 6; disc-like regular 200-gon of radius
    R: 2R/3 (to the polygon's own accuracy)."""
    a = 0.37
    sq = np.array([[0, 0], [a, 0], [a, a], [0, a]])
    np.testing.assert_allclose(
        mean_distance_polygon(sq), a * (np.sqrt(2) + np.log(1 + np.sqrt(2))) / 6, rtol=1e-13
    )
    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    disc = np.stack([np.cos(t), np.sin(t)], axis=1)
    np.testing.assert_allclose(mean_distance_polygon(disc), 2 / 3, rtol=1e-5)


def test_torsion_coefficient_seed_interface():
    """Seed 001 Eq. (11) (with its typo corrected): c_T = 0.096812 m for 0.3 x 0.2 m, so
    m_3u = c_T mu N = 16.26 N m for mu N = 168 N; checked against a Monte Carlo mean."""
    from tests.limit._scenes import torsion_pair

    scene = torsion_pair()
    ct = torsion_coefficient(scene.assembly.interfaces())
    rng = np.random.default_rng(0)
    pts = rng.uniform((-0.15, -0.1), (0.15, 0.1), size=(400_000, 2))
    np.testing.assert_allclose(ct, np.hypot(*pts.T).mean(), rtol=2e-3)
    l1, l2 = 0.3, 0.2
    d = np.hypot(l1, l2)
    closed = (
        d + l1**2 / (2 * l2) * np.log((l2 + d) / l1) + l2**2 / (2 * l1) * np.log((l1 + d) / l2)
    ) / 6
    np.testing.assert_allclose(ct, closed, rtol=1e-12)


def test_mean_distance_of_a_degenerate_polygon_raises():
    with pytest.raises(ValueError, match="zero area"):
        mean_distance_polygon(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))
