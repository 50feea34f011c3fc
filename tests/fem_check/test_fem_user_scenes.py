"""FEM check on blocks built by hand: slivers and tiny blocks."""

import numpy as np
import pytest

from dem import convex_block
from fem_check.mesh import MeshingError, MeshSettings, mesh_polyhedra


def _plate(thickness: float, side: float = 0.2) -> np.ndarray:
    """(8, 3) corners of a ``side x side x thickness`` plate [m]."""
    return np.array([(x, y, z) for x in (0.0, side) for y in (0.0, side) for z in (0.0, thickness)])


def test_a_sliver_below_the_cad_tolerance_is_refused_by_name():
    """A 0.2 m plate 50 nm thick is a valid block (volume 2e-9 m^3), but OpenCASCADE merges
    points closer than about 1e-7 m and gmsh raised a bare ``Exception('Could not create
    line')``. The error must name the block, its shortest edge and the cause."""
    blocks = [convex_block(_plate(0.01)), convex_block(_plate(5e-8) + (0.0, 0.0, 0.01))]
    with pytest.raises(MeshingError, match=r"block 1 .*shortest edge 5e-08 m"):
        mesh_polyhedra(blocks, MeshSettings(size=0.05))


def test_a_thin_plate_above_the_cad_tolerance_meshes_with_its_exact_volume():
    """A 0.2 m plate 0.5 um thick meshes, every tetrahedron positive, total volume exact."""
    block = convex_block(_plate(5e-7))
    tm = mesh_polyhedra([block], MeshSettings(size=0.05, order=2))
    p, t = tm.points, tm.tets
    a, b, c, d = (p[t[:, k]] for k in range(4))
    vol = np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0
    assert np.all(vol > 0)
    assert vol.sum() == pytest.approx(block.volume, rel=1e-12)


def test_the_crosscheck_solves_the_other_blocks_and_fails_on_the_sliver(tmp_path):
    """Three 0.2 m cubes stacked with a 50 nm sliver between the upper two, pushed along +x:
    the FEM step failed as a whole with gmsh's bare 'Could not create line'. Now the sliver
    is listed as not meshed (with the reason), the two cubes are solved, and the verdict
    fails on it."""
    from dem import Scene
    from dem.scene import proportional_to_weight
    from validation.crosscheck import CrosscheckSettings, crosscheck

    cube = 0.2 * np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    ground = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0.0)])
    blocks = [ground, cube, _plate(5e-8) + (0.0, 0.0, 0.2), cube + (0.0, 0.0, 0.2 + 5e-8)]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=[0.6, 0.6, 0.5, 0.6])
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    result = crosscheck(scene, CrosscheckSettings.quick(methods=("dem", "fem")), tmp_path)
    fem = result.step("fem")
    assert fem.values["not_meshed"] == [2]
    assert fem.values["n_solved"] == 2 and fem.values["not_in_equilibrium"] == []
    failed = [c for c in result.checks if c.status == "fail"]
    assert [c.name for c in failed] == ["FEM meshed every free block"]
    assert "shortest edge 5e-08 m" in failed[0].detail
