"""Surface files of walls whose blocks share corners, edges and faces (dem.surface_io).

Expectations are the blocks written: their count, volumes and the interfaces the builder's own
scene has (a wall built by :func:`running_bond_wall`, written out and read back).
"""

import itertools

import numpy as np
import pytest

from dem.scene_io import SceneSpec, blocks_from_surfaces, read_scene
from dem.scenes.running_bond_wall import running_bond_wall
from dem.surface_io import read_surface_bodies


def _box(lo, hi):
    """Corners and outward quads (right-hand rule) of an axis-aligned box."""
    corners = np.array(list(itertools.product(*zip(lo, hi, strict=True))), dtype=float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return corners, quads


def _grid_boxes(nx=3, nz=3, size=(0.4, 0.2, 0.3)):
    """A stack-bond wall: nx x nz boxes, every inner corner shared by four of them."""
    dx, dy, dz = size
    return [
        _box((i * dx, 0, k * dz), ((i + 1) * dx, dy, (k + 1) * dz))
        for k in range(nz)
        for i in range(nx)
    ]


def _write_obj(path, boxes, objects=True, drop_face=None):
    lines, offset = [], 0
    for k, (corners, faces) in enumerate(boxes):
        if objects:
            lines.append(f"o block_{k}")
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in corners]
        for j, face in enumerate(faces):
            if (k, j) != drop_face:
                lines.append("f " + " ".join(str(offset + i + 1) for i in face))
        offset += len(corners)
    path.write_text("\n".join(lines) + "\n")
    return path


def _write_stl(path, boxes):
    """An ASCII STL with one ``solid`` per box (triangles, every corner repeated)."""
    lines = []
    for k, (corners, faces) in enumerate(boxes):
        lines.append(f"solid block_{k}")
        for face in faces:
            for tri in ((face[0], face[1], face[2]), (face[0], face[2], face[3])):
                lines += ["facet normal 0 0 0", "outer loop"]
                lines += [f"vertex {x:.17g} {y:.17g} {z:.17g}" for x, y, z in corners[list(tri)]]
                lines += ["endloop", "endfacet"]
        lines.append(f"endsolid block_{k}")
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("objects", [True, False], ids=["o-objects", "no-objects"])
def test_stack_bond_wall_in_one_obj_file(tmp_path, objects):
    """Nine boxes in one OBJ, inner corners shared by four boxes and edges by four faces:
    nine blocks of the written volume, in file order, whether or not the file names objects
    (without objects they are found by faces joined across edges)."""
    boxes = _grid_boxes()
    blocks = blocks_from_surfaces(_write_obj(tmp_path / "wall.obj", boxes, objects))
    assert len(blocks) == 9
    np.testing.assert_allclose([b.volume for b in blocks], 0.4 * 0.2 * 0.3, rtol=1e-12)
    expected = [c.mean(axis=0) for c, _ in boxes]
    np.testing.assert_allclose([b.centroid for b in blocks], expected, atol=1e-12)


def test_ascii_stl_solids_are_blocks(tmp_path):
    blocks = blocks_from_surfaces(_write_stl(tmp_path / "wall.stl", _grid_boxes(2, 2)))
    assert len(blocks) == 4
    np.testing.assert_allclose([b.volume for b in blocks], 0.4 * 0.2 * 0.3, rtol=1e-12)


def test_running_bond_wall_read_back_has_the_builders_interfaces(tmp_path):
    """A builder's wall (bricks sharing head-joint faces, a base under the first course)
    written as OBJ objects reads back as the same blocks with the same interfaces."""
    built = running_bond_wall(3, 4, 100.0, 300.0, 120.0, 18.0, mu=0.6)
    boxes = [(b.vertices, [list(f) for f in b.faces]) for b in built.assembly.blocks]
    for objects in (True, False):
        path = _write_obj(tmp_path / f"wall_{objects}.obj", boxes, objects)
        scene = read_scene(path, SceneSpec(density=float(built.assembly.density[0]), mu=0.6))
        assert scene.n_blocks == built.n_blocks
        np.testing.assert_allclose(scene.assembly.volume, built.assembly.volume, rtol=1e-12)
        ours, theirs = scene.assembly.interfaces(), built.assembly.interfaces()
        assert ours.n_interfaces == theirs.n_interfaces
        np.testing.assert_allclose(sorted(ours.area), sorted(theirs.area), rtol=1e-9)


def test_an_open_body_is_refused_with_its_edges(tmp_path):
    """Box 4 (the middle one) without its top face: named, with the four open edges."""
    path = _write_obj(tmp_path / "wall.obj", _grid_boxes(), drop_face=(4, 1))
    message = r"body 4 of wall.obj \(object 'block_4'\) is open: 4 edges"
    with pytest.raises(ValueError, match=message):
        read_surface_bodies(path)


def test_a_body_open_in_a_file_without_objects_is_refused(tmp_path):
    path = _write_obj(tmp_path / "one.obj", [_box((0, 0, 0), (1, 1, 1))], False, (0, 0))
    with pytest.raises(ValueError, match="body 0 of one.obj is open: 4 edges belong to one face"):
        blocks_from_surfaces(path)
