"""Block meshes: volume, determinism, shape cache and rigid matching."""

import math

import numpy as np
import pytest

from dem.geometry.polyhedron import convex_block
from fem_check.mesh import MeshCache, MeshSettings, mesh_polyhedra, rigid_match

L_SIDE, T, THETA = 8.33e-3, 3.18e-3, math.radians(5.0)


def tis_block(turned=False, centre=(0.0, 0.0)):
    """One full TIS block (seed 000 Fig. 4a): bottom l x l, lateral faces leaning by theta."""
    lean = T * math.tan(THETA)
    h = L_SIDE / 2
    top = (h - lean, h + lean) if turned else (h + lean, h - lean)
    pts = [
        (centre[0] + sx * hx, centre[1] + sy * hy, z)
        for z, hx, hy in ((0.0, h, h), (T, *top))
        for sx in (-1, 1)
        for sy in (-1, 1)
    ]
    return convex_block(np.array(pts))


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def tet_volumes(tm):
    p, t = tm.points, tm.tets
    a, b, c, d = (p[t[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


@pytest.mark.parametrize("order", [1, 2])
def test_mesh_volume_matches_closed_form(order):
    # closed form of the TIS block volume: l^2 t - (4/3) tan^2(theta) t^3 (prismatoid)
    expected = L_SIDE**2 * T - 4.0 / 3.0 * math.tan(THETA) ** 2 * T**3
    tm = mesh_polyhedra([tis_block()], MeshSettings(size=1.5e-3, order=order))
    assert np.all(tet_volumes(tm) > 0)
    np.testing.assert_allclose(np.abs(tet_volumes(tm)).sum(), expected, rtol=1e-12)
    if order == 2:
        # 10-node tetrahedra: one node per corner and per edge
        n_corners = len(np.unique(tm.mesh.t))
        assert tm.mesh.doflocs.shape[1] == n_corners + tm.mesh.edges.shape[1]


def test_meshing_is_deterministic():
    a = mesh_polyhedra([tis_block()], MeshSettings(size=1.2e-3))
    b = mesh_polyhedra([tis_block()], MeshSettings(size=1.2e-3))
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.tets, b.tets)


def test_bonded_blocks_share_interface_nodes():
    # two blocks side by side (types A and B meet on an inclined plane): one conforming mesh
    a, b = tis_block(False, (0.0, 0.0)), tis_block(True, (L_SIDE, 0.0))
    tm = mesh_polyhedra([a, b], MeshSettings(size=1.5e-3))
    assert set(np.unique(tm.region)) == {0, 1}
    np.testing.assert_allclose(np.abs(tet_volumes(tm)).sum(), a.volume + b.volume, rtol=1e-12)
    # conforming: every interior facet is shared by exactly two tetrahedra (no hanging faces)
    boundary_area = 0.0
    m = tm.mesh
    for f in m.boundary_facets():
        p = m.p[:, m.facets[:, f]].T
        boundary_area += 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
    surface = sum(
        0.5
        * np.linalg.norm(
            np.cross(
                blk.vertices[f[1:-1]] - blk.vertices[f[0]], blk.vertices[f[2:]] - blk.vertices[f[0]]
            ),
            axis=1,
        ).sum()
        for blk in (a, b)
        for f in blk.faces
    )
    interface = (L_SIDE - T * math.tan(THETA)) * T / math.cos(THETA)  # seed 000 geometry
    np.testing.assert_allclose(boundary_area, surface - 2 * interface, rtol=1e-10)


def test_rigid_match_recovers_rotation_and_rejects_mirror():
    rng = np.random.default_rng(3)
    a = tis_block()
    rot, t = random_rotation(rng), rng.normal(size=3) * 1e-2
    b = convex_block(a.vertices @ rot.T + t)
    found = rigid_match(a, b)
    assert found is not None
    np.testing.assert_allclose(found[0], rot, atol=1e-9)
    np.testing.assert_allclose(found[1], t, atol=1e-12)
    # a mirror image of a chiral block is not a rigid motion of it
    chiral = convex_block(
        np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0], [0, 0, 3], [1, 1, 1.2]]) * 1e-3
    )
    mirror = convex_block(chiral.vertices * np.array([-1.0, 1.0, 1.0]))
    assert rigid_match(chiral, mirror) is None


def test_cache_meshes_congruent_blocks_once():
    cache = MeshCache(MeshSettings(size=2e-3))
    blocks = [
        tis_block(turned=(i + j) % 2 == 1, centre=(i * L_SIDE, j * L_SIDE))
        for i in range(3)
        for j in range(3)
    ]
    meshes = [cache.get(b) for b in blocks]
    # type A and type B are one shape turned by 90 degrees (seed 000, Fig. 4b)
    assert len(cache.shapes) == 1
    for bm in meshes:
        lo, hi = bm.world_points().min(axis=0), bm.world_points().max(axis=0)
        np.testing.assert_allclose(lo, bm.block.vertices.min(axis=0), atol=1e-12)
        np.testing.assert_allclose(hi, bm.block.vertices.max(axis=0), atol=1e-12)


def test_mesh_settings_reject_bad_input():
    with pytest.raises(ValueError, match="mesh size"):
        MeshSettings(size=0.0)
    with pytest.raises(ValueError, match="order"):
        MeshSettings(size=1.0, order=3)
