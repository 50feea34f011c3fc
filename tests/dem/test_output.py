"""VTU files read back with their data; off-screen pictures are written."""

import meshio
import numpy as np

from dem.output import render_scene, write_interfaces_vtu, write_scene_vtu


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
