"""Scenes from mesh files, surface files and TOML (dem.scene_io) against exact geometry."""

import itertools

import meshio
import numpy as np
import pytest

from dem.scene_io import SceneSpec, blocks_from_mesh, blocks_from_surfaces, read_scene

BOX = (1.2, 0.6, 0.9)  # [m]
DIVS = (3, 2, 2)  # cells per side


def _gmsh_box(path):
    """A box meshed by gmsh into DIVS hexahedra (transfinite + recombine)."""
    import gmsh

    gmsh.initialize(["-v", "0"])
    try:
        gmsh.model.add("box")
        gmsh.model.occ.addBox(0, 0, 0, *BOX)
        gmsh.model.occ.synchronize()

        def cells_along(tag):
            lo = np.array(gmsh.model.getBoundingBox(1, tag)[:3])
            hi = np.array(gmsh.model.getBoundingBox(1, tag)[3:])
            return DIVS[int(np.argmax(hi - lo))]

        _write_hexahedra(path, cells_along)
    finally:
        gmsh.finalize()


def _write_hexahedra(path, cells_along):
    """Mesh the current gmsh model into transfinite hexahedra, ``cells_along(curve tag)``
    cells per curve, and write it to ``path``."""
    import gmsh

    for _, tag in gmsh.model.getEntities(1):
        gmsh.model.mesh.setTransfiniteCurve(tag, cells_along(tag) + 1)
    for _, tag in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(tag)
        gmsh.model.mesh.setRecombine(2, tag)
    for _, tag in gmsh.model.getEntities(3):
        gmsh.model.mesh.setTransfiniteVolume(tag)
    gmsh.model.mesh.generate(3)
    gmsh.write(str(path))


def _grid_interfaces(divs, size):
    """Count and total area of the internal faces of a box cut into a regular grid."""
    n = np.array(divs)
    h = np.array(size) / n
    count, area = 0, 0.0
    for axis in range(3):
        k = (n[axis] - 1) * np.prod(np.delete(n, axis))
        count += k
        area += k * np.prod(np.delete(h, axis))
    return int(count), float(area)


def test_gmsh_box_of_hexahedra(tmp_path):
    path = tmp_path / "box.msh"
    _gmsh_box(path)
    (tmp_path / "box.toml").write_text(
        "[material]\ndensity = 2000.0\nmu = 0.7\n[supports]\nfixed_below = 0.3\n"
        '[loads]\nlive = "x"\n'
    )
    scene = read_scene(path)
    n_cells = int(np.prod(DIVS))
    assert scene.n_blocks == n_cells
    cell = np.prod(np.array(BOX) / DIVS)
    np.testing.assert_allclose(scene.assembly.volume, cell, rtol=1e-9)
    itf = scene.assembly.interfaces()
    count, area = _grid_interfaces(DIVS, BOX)
    assert itf.n_interfaces == count == 20
    np.testing.assert_allclose(itf.area.sum(), area, rtol=1e-9)
    # the bottom layer (centroids at z = 0.225) is fixed and carries no live load
    bottom = scene.assembly.centroid[:, 2] < 0.3
    assert bottom.sum() == DIVS[0] * DIVS[1]
    assert np.array_equal(scene.supports.fixed, bottom)
    live = scene.loads.live_wrench
    np.testing.assert_allclose(live[~bottom, 0], 2000.0 * cell * 9.81, rtol=1e-3)
    assert np.all(live[bottom] == 0) and np.all(scene.assembly.mu == 0.7)


def _wedge_vtu(path, nx=2, ny=2, nz=2, dx=0.5, dy=0.4, dz=0.3):
    """A box of nx x ny x nz squares, each split along its diagonal into two wedges."""
    grid = np.array(list(itertools.product(range(nx + 1), range(ny + 1), range(nz + 1))))
    index = {tuple(p): i for i, p in enumerate(grid)}
    points = grid * np.array([dx, dy, dz], dtype=float)
    wedges = []
    for i, j, k in itertools.product(range(nx), range(ny), range(nz)):
        a, b, c, d = (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)
        for tri in ((a, b, c), (a, c, d)):
            wedges.append([index[(*p, k)] for p in tri] + [index[(*p, k + 1)] for p in tri])
    meshio.Mesh(points, [("wedge", np.array(wedges))]).write(path)
    return dx, dy, dz


def test_vtu_of_wedges(tmp_path):
    path = tmp_path / "wedges.vtu"
    dx, dy, dz = _wedge_vtu(path)
    scene = read_scene(path, SceneSpec(density=1500.0, mu=0.5, fixed_below=dz))
    assert scene.n_blocks == 16
    np.testing.assert_allclose(scene.assembly.volume, dx * dy * dz / 2, rtol=1e-12)
    itf = scene.assembly.interfaces()
    # per layer: 4 diagonals, 4 shared square sides; 8 triangles between the layers
    diag = np.hypot(dx, dy) * dz
    expected = sorted([diag] * 8 + [dx * dz] * 4 + [dy * dz] * 4 + [dx * dy / 2] * 8)
    assert itf.n_interfaces == 24
    np.testing.assert_allclose(np.sort(itf.area), expected, rtol=1e-12)
    assert scene.supports.fixed.sum() == 8


def test_polyhedron_cells_and_a_non_convex_cell_is_named(tmp_path):
    cube = np.array(list(itertools.product((0, 1), (0, 1), (0, 1))), dtype=float)
    faces = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]]
    good = tmp_path / "poly.vtu"
    meshio.Mesh(cube, [("polyhedron8", [faces])]).write(good)
    (block,) = blocks_from_mesh(good)
    assert block.volume == pytest.approx(1.0)
    # a hexahedron with a corner pushed into the cell: re-entrant, refused by name
    hexes = np.array([[0, 1, 2, 3, 4, 5, 6, 7], [8, 9, 10, 11, 12, 13, 14, 15]])
    unit = np.array(
        [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],
        dtype=float,
    )
    dented = unit + [2.0, 0.0, 0.0]
    dented[6] = (2.7, 0.7, 0.7)
    bad = tmp_path / "bad.vtu"
    meshio.Mesh(np.vstack([unit, dented]), [("hexahedron", hexes)]).write(bad)
    with pytest.raises(ValueError, match=r"cell 1 \(hexahedron"):
        blocks_from_mesh(bad)
    # a warped face whose corners are all on the hull: still refused, naming the cell
    warped = unit.copy()
    warped[6] = (1.0, 1.0, 1.3)
    path = tmp_path / "warped.vtu"
    meshio.Mesh(warped, [("hexahedron", hexes[:1])]).write(path)
    with pytest.raises(ValueError, match=r"cell 0 .*warped or re-entrant"):
        blocks_from_mesh(path)


def test_mesh_needs_a_density(tmp_path):
    path = tmp_path / "wedges.vtu"
    _wedge_vtu(path)
    with pytest.raises(ValueError, match="density"):
        read_scene(path)


def _box_triangles(lo, hi):
    from scipy.spatial import ConvexHull

    corners = np.array(list(itertools.product(*zip(lo, hi, strict=True))), dtype=float)
    return corners, ConvexHull(corners).simplices


@pytest.mark.parametrize("suffix", [".stl", ".obj"])
def test_multi_body_surface_file(tmp_path, suffix):
    ground, g_tri = _box_triangles((-1, -1, -0.2), (1, 1, 0))
    pillar, p_tri = _box_triangles((-0.2, -0.1, 0), (0.2, 0.1, 0.6))
    path = tmp_path / f"bodies{suffix}"
    meshio.Mesh(np.vstack([ground, pillar]), [("triangle", np.vstack([g_tri, p_tri + 8]))]).write(
        path
    )
    scene = read_scene(path, SceneSpec(density=2000.0, fixed=(0,), mu=0.6, live=(1.0, 0, 0)))
    np.testing.assert_allclose(sorted(scene.assembly.volume), [0.4 * 0.2 * 0.6, 2 * 2 * 0.2])
    itf = scene.assembly.interfaces()
    assert itf.n_interfaces == 1
    np.testing.assert_allclose(itf.area, [0.4 * 0.2])


def test_folder_of_bodies_and_a_non_convex_body(tmp_path):
    for k, (lo, hi) in enumerate([((0, 0, 0), (1, 1, 1)), ((0, 0, 1), (1, 1, 2))]):
        pts, tri = _box_triangles(lo, hi)
        meshio.Mesh(pts, [("triangle", tri)]).write(tmp_path / f"b{k}.stl")
    blocks = blocks_from_surfaces(tmp_path)
    assert [b.volume for b in blocks] == pytest.approx([1.0, 1.0])
    # an L-shaped body (its inner corner is not a corner of the hull)
    l_pts = np.array([(0, 0, 0), (2, 0, 0), (2, 1, 0), (1, 1, 0), (1, 2, 0), (0, 2, 0)], float)
    pts = np.vstack([l_pts, l_pts + [0, 0, 1]])
    tri = [(0, 1, 2), (0, 2, 3), (0, 3, 5), (3, 4, 5)]
    tri += [tuple(i + 6 for i in t) for t in tri]
    for i in range(6):
        j = (i + 1) % 6
        tri += [(i, j, j + 6), (i, j + 6, i + 6)]
    bad = tmp_path / "l_shape.obj"
    meshio.Mesh(pts, [("triangle", np.array(tri))]).write(bad)
    with pytest.raises(ValueError, match="body 0 of l_shape.obj is not a convex block"):
        blocks_from_surfaces(bad)


def test_toml_point_loads_and_json_overrides(tmp_path, two_block_stack):
    path = tmp_path / "stack.json"
    two_block_stack.to_json(path)
    (tmp_path / "stack.toml").write_text(
        '[loads]\nlive = "-y"\n[[loads.point]]\nblock = 1\npoint = [0.5, 0.5, 1.0]\n'
        'force = [0.0, 0.0, -100.0]\nkind = "dead"\n'
    )
    scene = read_scene(path)
    np.testing.assert_allclose(scene.loads.dead_wrench[1], [0, 0, -100.0, 0, 0, 0], atol=1e-12)
    weight = scene.assembly.mass * 9.81
    np.testing.assert_allclose(scene.loads.live_wrench[:2, 1], -weight[:2], rtol=1e-3)
    assert np.all(scene.loads.live_wrench[2] == 0)  # the fixed ground
    # the command line wins over the TOML
    scene = read_scene(path, SceneSpec(live=(1.0, 0.0, 0.0)))
    assert np.all(scene.loads.live_wrench[:2, 0] > 0)
    with pytest.raises(ValueError, match="load direction"):
        SceneSpec.direction("w")
    (tmp_path / "bad.toml").write_text("[suports]\nfixed = [0]\n")
    with pytest.raises(ValueError, match=r"unknown key .suports. in the top level"):
        read_scene(path, toml=tmp_path / "bad.toml")


def test_gmsh_physical_groups_as_supports(tmp_path):
    """Two boxes meshed as one hexahedron each, tagged 'foundation' and 'wall' in gmsh."""
    import gmsh

    path = tmp_path / "groups.msh"
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.model.add("groups")
        low = gmsh.model.occ.addBox(0, 0, 0, 1.0, 0.5, 0.4)
        high = gmsh.model.occ.addBox(0, 0, 0.4, 1.0, 0.5, 0.6)
        gmsh.model.occ.fragment([(3, low)], [(3, high)])
        gmsh.model.occ.synchronize()
        (_, v_low), (_, v_high) = sorted(gmsh.model.getEntities(3))
        gmsh.model.addPhysicalGroup(3, [v_low], name="foundation")
        gmsh.model.addPhysicalGroup(3, [v_high], name="wall")
        _write_hexahedra(path, lambda tag: 1)
    finally:
        gmsh.finalize()
    spec = SceneSpec(density=2000.0, mu=0.5, fixed_groups=("foundation",), live=(1.0, 0, 0))
    scene = read_scene(path, spec)
    assert scene.n_blocks == 2
    (base,) = np.flatnonzero(scene.supports.fixed)
    np.testing.assert_allclose(scene.assembly.volume[base], 1.0 * 0.5 * 0.4)
    np.testing.assert_allclose(scene.assembly.interfaces().area, [0.5])
    assert sorted(scene.meta["groups"]) == ["foundation", "wall"]
    with pytest.raises(ValueError, match=r"fixed group 'base' .*\['foundation', 'wall'\]"):
        read_scene(path, SceneSpec(density=2000.0, fixed_groups=("base",)))
