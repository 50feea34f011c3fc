"""VTU files read back with their data; off-screen pictures are written."""

import meshio
import numpy as np
import pytest

from dem.output import render_scene, write_interfaces_vtu, write_scene_vtu
from dem.scene import Scene
from tests.conftest import box_corners


def test_scene_and_interface_vtu_round_trip(tmp_path, two_block_stack):
    scene = two_block_stack
    speed = np.array([1.0, 2.0, 3.0])
    mesh = meshio.read(write_scene_vtu(tmp_path / "s.vtu", scene, {"speed": speed}))
    # each box face gives 2 triangles: 3 blocks x 12 triangles, data repeated per triangle
    assert mesh.cells[0].data.shape == (36, 3)
    np.testing.assert_allclose(np.unique(mesh.cell_data["speed"][0]), speed)
    iface = scene.assembly.interfaces()
    back = meshio.read(write_interfaces_vtu(tmp_path / "i.vtu", iface, {"force": iface.area * 2}))
    np.testing.assert_allclose(np.unique(back.cell_data["area"][0]), np.unique(iface.area))


def test_render_scene_writes_a_png(tmp_path, two_block_stack):
    path = render_scene(tmp_path / "s.png", two_block_stack)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_posed_vertices_match_rigidly_transformed_blocks(two_block_stack):
    from scipy.spatial.transform import Rotation

    from dem.output import posed_vertices

    a = two_block_stack.assembly
    rot = Rotation.from_rotvec([[0.1, 0.2, 0.3], [0.0, -0.4, 0.1], [0.0, 0.0, 0.0]]).as_matrix()
    centroid = a.centroid + np.array([[1.0, 0, 0], [0, 2.0, 0], [0, 0, 0]])
    # rotating about the centroid, then moving it: x -> R x + (c' - R c)
    expected = np.concatenate(
        [
            b.transformed(r, c - r @ b.centroid).vertices
            for b, r, c in zip(a.blocks, rot, centroid, strict=True)
        ]
    )
    np.testing.assert_allclose(posed_vertices(a, rot, centroid), expected, atol=1e-14)


def _vtk_cells_and_arrays(path):
    """Cell count and cell-array names as VTK reads the file (meshio cannot read an empty VTU)."""
    import pyvista as pv

    grid = pv.read(path)
    return grid.n_cells, set(grid.cell_data.keys())


def test_interface_vtu_without_interfaces_is_an_empty_valid_file(tmp_path):
    cube = box_corners((0, 0, 0), (1, 1, 1))
    one = Scene.from_convex_blocks([cube], 1000.0, fixed=[0])
    apart = Scene.from_convex_blocks([cube, cube + [2.0, 0, 0]], 1000.0, fixed=[0])
    for k, scene in enumerate((one, apart)):
        iface = scene.assembly.interfaces()
        assert iface.n_interfaces == 0
        path = write_interfaces_vtu(tmp_path / f"i{k}.vtu", iface, {"force": np.zeros((0, 3))})
        n_cells, names = _vtk_cells_and_arrays(path)
        assert n_cells == 0
        assert names == {"interface", "block_a", "block_b", "area", "normal", "force"}


def test_pose_of_the_wrong_shape_is_refused(tmp_path, two_block_stack):
    quaternions = np.tile([1.0, 0.0, 0.0, 0.0], (3, 1))
    with pytest.raises(ValueError, match=r"rotation must have shape \(3, 3, 3\) .*got \(3, 4\)"):
        write_scene_vtu(tmp_path / "q.vtu", two_block_stack, rotation=quaternions)
    with pytest.raises(ValueError, match=r"centroid must have shape \(3, 3\) \[m\], got \(2, 3\)"):
        write_scene_vtu(tmp_path / "c.vtu", two_block_stack, centroid=np.zeros((2, 3)))
