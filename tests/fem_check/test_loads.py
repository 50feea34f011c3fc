"""DEM loads on a block: wrench to traction, interface signs, consistent point loads."""

import dataclasses
import re

import numpy as np
import pytest

from dem.geometry.interfaces import find_interfaces
from dem.geometry.polyhedron import convex_block
from fem_check import elastic, loads
from fem_check.admissible import admissible_resultants, nodal_forces
from fem_check.elastic import BlockSolver, ElasticMaterial, LoadTransferError
from fem_check.loads import (
    BlockLoad,
    BlockPointLoads,
    EquilibriumError,
    InterfaceResultants,
    TractionPatch,
    check_equilibrium,
    check_patch_on_face,
    interface_block_loads,
    loads_on_side,
    patch_face,
    wrench_patches,
)
from fem_check.mesh import MeshSettings


def box(lo, hi):
    return convex_block(
        np.array(
            [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        )
    )


def test_wrench_patch_is_the_section_formula():
    """Rectangle b x h in the plane x = 0 under N, M: sigma = N/A + M y / I (beam section)."""
    b, h = 2e-3, 4e-3
    poly = np.array(
        [[0, -b / 2, -h / 2], [0, b / 2, -h / 2], [0, b / 2, h / 2], [0, -b / 2, h / 2]]
    )
    n_force, moment_y = 50.0, 0.03
    (patch,) = wrench_patches(
        [poly], np.array([n_force, 0, 0]), np.array([0, moment_y, 0]), np.zeros(3)
    )
    z = np.linspace(-h / 2, h / 2, 5)
    pts = np.c_[np.zeros(5), np.zeros(5), z]
    inertia = b * h**3 / 12
    # moment about +y of a traction sigma e_x at height z is z * sigma
    np.testing.assert_allclose(
        patch.at(pts)[:, 0], n_force / (b * h) + moment_y * z / inertia, rtol=1e-12
    )
    np.testing.assert_allclose(patch.at(pts)[:, 1:], 0.0, atol=1e-6)


def test_torsion_patch_circulates_about_centroid():
    """M3 alone: in-plane traction tau = M r / J_p, perpendicular to the radius (closed form)."""
    a = 3e-3
    poly = np.array([[0, -a, -a], [0, a, -a], [0, a, a], [0, -a, a]]) / 2
    torque = 0.02
    (patch,) = wrench_patches([poly], np.zeros(3), np.array([torque, 0, 0]), np.zeros(3))
    polar = a**4 / 6  # square of side a: J_p = a^4 / 6
    r = np.array([[0.0, 1e-3, 0.0]])
    np.testing.assert_allclose(patch.at(r)[0], [0, 0, torque * 1e-3 / polar], rtol=1e-12)


def test_interface_sign_convention_compression_pushes_b_along_n():
    a_blk, b_blk = box([0, 0, 0], [1e-3, 1e-3, 1e-3]), box([1e-3, 0, 0], [2e-3, 1e-3, 1e-3])
    itf = find_interfaces([a_blk, b_blk])
    n = itf.frame[0, 0]
    np.testing.assert_allclose(n, [1, 0, 0])
    state = InterfaceResultants(itf, np.array([[7.0, 1.0, 0.0, 0.0, 0.0, 0.0]]))
    loads = interface_block_loads(state, 2, density=0.0, gravity=np.zeros(3))
    f_a, _ = loads[0].resultant(a_blk)
    f_b, _ = loads[1].resultant(b_blk)
    np.testing.assert_allclose(f_b, 7.0 * n + 1.0 * itf.frame[0, 1], atol=1e-12)
    np.testing.assert_allclose(f_a, -f_b, atol=1e-12)
    # compression: the traction on b points along +n with magnitude N / A
    np.testing.assert_allclose(loads[1].patches[0].traction @ n, 7.0 / 1e-6)


def test_point_load_vector_reproduces_force_and_moment():
    """R^T f of consistent nodal loads equals the sum of forces and their moments."""
    rng = np.random.default_rng(0)
    blk = box([0, 0, 0], [2e-3, 1e-3, 1.5e-3])
    pts = np.c_[rng.uniform(0, 2e-3, 30), rng.uniform(0, 1e-3, 30), np.full(30, 1.5e-3)]
    forces = rng.normal(size=(30, 3))
    c = blk.centroid
    f, m = forces.sum(axis=0), np.cross(pts - c, forces).sum(axis=0)
    base = blk.vertices[blk.faces[int(np.argmin(blk.normals[:, 2]))]]
    load = BlockLoad(pts, forces, tuple(wrench_patches([base], -f, -m, c)))
    for degree in (1, 2):
        solver = BlockSolver(ElasticMaterial(1e9, 0.3), MeshSettings(size=0.6e-3), degree=degree)
        sol = solver.solve(blk, load)
        np.testing.assert_allclose(sol.discrete_resultant, 0.0, atol=1e-12 * np.abs(forces).sum())
        # the point forces alone, through the same mapping
        only = BlockLoad(pts, forces)
        fv, _ = sol.operator.point_load_vector(pts, forces)
        np.testing.assert_allclose(sol.operator.modes.T @ fv, np.r_[f, m], rtol=1e-10, atol=1e-14)
        del only


def test_nodal_forces_keep_the_resultant():
    poly = np.array([[0, 0, 0], [3e-3, 0, 0], [2e-3, 2e-3, 0], [0.5e-3, 2e-3, 0]])
    patch = TractionPatch(poly, [1e5, -2e5, 3e5], [1e7, 2e7, -3e7], [1e-3, 1e-3, 0])
    pts_load = nodal_forces(BlockLoad(patches=(patch,)), 0.3e-3)
    about = np.array([0.3e-3, -1e-3, 0.2e-3])
    f0, m0 = patch.resultant(about)
    f1 = pts_load.forces.sum(axis=0)
    m1 = np.cross(pts_load.points - about, pts_load.forces).sum(axis=0)
    np.testing.assert_allclose(f1, f0, rtol=1e-12)
    np.testing.assert_allclose(m1, m0, rtol=1e-12)


def test_loads_on_side_of_a_box_under_gravity():
    """Half of a box's weight is below its mid plane (closed form)."""
    blk = box([0, 0, 0], [1e-3, 1e-3, 2e-3])
    rho, g = 2000.0, np.array([0, 0, -9.81])
    load = BlockLoad(density=rho, gravity=g)
    f, _ = loads_on_side(blk, load, np.array([0, 0, 1.0]), 1e-3, blk.centroid)
    np.testing.assert_allclose(f, 0.5 * rho * blk.volume * g, rtol=1e-12)


def test_admissible_state_balances_every_free_block():
    blocks = [box([i * 1e-3, 0, 0], [(i + 1) * 1e-3, 1e-3, 1e-3]) for i in range(3)]
    itf = find_interfaces(blocks)
    ext = np.zeros((3, 6))
    ext[1, :3] = [0, 0, -2.0]
    state = admissible_resultants(itf, np.array([b.centroid for b in blocks]), np.array([1]), ext)
    loads = interface_block_loads(state, 3, 0.0, np.zeros(3))
    f, m = loads[1].resultant(blocks[1])
    np.testing.assert_allclose(f + ext[1, :3], 0.0, atol=1e-12)
    np.testing.assert_allclose(m, 0.0, atol=1e-15)


def test_point_state_rejects_bad_shapes():
    with pytest.raises(ValueError, match="acceleration"):
        BlockPointLoads(
            np.array([0]),
            np.zeros((1, 3)),
            np.zeros((1, 3)),
            np.zeros(3),
            np.zeros((2, 5)),
            np.ones(2),
        )


def test_torque_free_spinning_block_is_balanced():
    """Euler's equations: a torque-free block has I alpha = -omega x I omega. With that alpha
    and the centripetal field, the d'Alembert load of a free block balances exactly."""
    rng = np.random.default_rng(11)
    blk = convex_block(rng.normal(size=(12, 3)) * 1e-3)
    rho = 2500.0
    omega = np.array([30.0, -12.0, 7.0])
    inertia = rho * blk.inertia
    alpha = -np.linalg.solve(inertia, np.cross(omega, inertia @ omega))
    load = BlockLoad(density=rho, acceleration=np.r_[0, 0, 0, alpha], angular_velocity=omega)
    scale = rho * blk.volume * np.dot(omega, omega) * blk.size  # centripetal force scale
    f, m = load.resultant(blk)
    np.testing.assert_allclose(f, 0.0, atol=1e-12 * scale)
    np.testing.assert_allclose(m, 0.0, atol=1e-12 * scale * blk.size)
    # without the angular velocity the gyroscopic moment is missing: an imbalance
    _, m_bad = BlockLoad(density=rho, acceleration=np.r_[0, 0, 0, alpha]).resultant(blk)
    np.testing.assert_allclose(m_bad, -inertia @ alpha, rtol=1e-10)
    # the FE load vector of the same field has the same (zero) resultant
    solver = BlockSolver(ElasticMaterial(1e9, 0.3), MeshSettings(size=1e-3), degree=2)
    sol = solver.solve(blk, load)
    np.testing.assert_allclose(sol.discrete_resultant[:3], 0.0, atol=1e-10 * scale)
    np.testing.assert_allclose(sol.discrete_resultant[3:], 0.0, atol=1e-10 * scale * blk.size)


def test_masonry_state_pipeline(tmp_path):
    """A wall state in equilibrium by construction (least-squares admissible resultants under
    weight and lambda x lateral weight) goes through the fem-masonry-stress pipeline with a
    load imbalance at round-off level, and a perturbed state is refused."""
    from dem.scenes.running_bond_wall import running_bond_wall
    from validation.cases.fem import run_masonry_stress

    scene = running_bond_wall(3, 3, 81, 210, 70, 20.0, fixed_columns=("left",))
    a = scene.assembly
    lam = 0.2
    ext = scene.dead_wrench + lam * scene.loads.live_wrench
    state = admissible_resultants(a.interfaces(), a.centroid, scene.free_blocks, ext)
    scene_json = tmp_path / "wall.json"
    scene.to_json(scene_json)
    arrays = {
        "interface_block_a": state.interfaces.block_a,
        "interface_block_b": state.interfaces.block_b,
        "resultants": -state.resultants,  # dem.static signs: tension positive
        "load_multiplier": np.array(lam),
        "scene_json": np.array(str(scene_json)),
    }
    np.savez(tmp_path / "state.npz", **arrays)
    rows, _ = run_masonry_stress(True, tmp_path / "state.npz", tmp_path)
    assert rows[0].ours < 1e-10
    assert (tmp_path / "fem-masonry-stress.vtu").exists()
    arrays["resultants"] = -state.resultants * 1.1  # no longer balances the weight
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(EquilibriumError):
        run_masonry_stress(True, tmp_path / "bad.npz", tmp_path)


def test_point_state_in_reference_points_and_world_vectors():
    """Points in the block's reference configuration, forces and accelerations in the world
    frame of the rotated block: with the rotation given, the load balances again."""
    from fem_check.loads import check_equilibrium, rotation_from_quaternion

    phi = 0.3  # rotation about z by phi: the textbook matrix
    rz = rotation_from_quaternion(np.array([[np.cos(phi / 2), 0, 0, np.sin(phi / 2)]]))[0]
    np.testing.assert_allclose(
        rz, [[np.cos(phi), -np.sin(phi), 0], [np.sin(phi), np.cos(phi), 0], [0, 0, 1]], atol=1e-15
    )
    blk = box([0, 0, 0], [2e-3, 1e-3, 1.5e-3])
    rng = np.random.default_rng(5)
    rho, g_ref = 2500.0, np.array([0.3, -0.2, -9.81])
    acc_ref = np.r_[0.5, 0.1, -0.4, 0, 0, 0]
    pts = np.c_[rng.uniform(0, 2e-3, 20), rng.uniform(0, 1e-3, 20), np.full(20, 1.5e-3)]
    frc = rng.normal(size=(20, 3))
    partial = BlockLoad(pts, frc, (), rho, g_ref, acc_ref)
    f, m = partial.resultant(blk)
    base = blk.vertices[blk.faces[int(np.argmin(blk.normals[:, 2]))]]
    balanced = nodal_forces(
        partial.with_patches(wrench_patches([base], -f, -m, blk.centroid)), 2e-4
    )
    check_equilibrium(blk, balanced, 1e-12)
    rot = rotation_from_quaternion(np.array([[0.9, 0.1, -0.3, 0.2]]))[0]
    state = BlockPointLoads(
        np.zeros(len(balanced.points), dtype=np.int64),
        balanced.points,
        balanced.forces @ rot.T,
        rot @ g_ref,
        np.r_[rot @ acc_ref[:3], rot @ acc_ref[3:]][None],
        np.array([rho]),
        rotation=rot[None],
    )
    check_equilibrium(blk, state.for_block(0), 1e-12)
    mixed = dataclasses.replace(state, rotation=None)
    with pytest.raises(EquilibriumError):
        check_equilibrium(blk, mixed.for_block(0), 1e-3)


def cube_top_and_bottom(a, overhang, p):
    """A cube of side a, a square patch overhanging its top face by ``overhang`` on every side
    at -p [Pa] and its bottom face at the pressure that balances it."""
    blk = box((0, 0, 0), (a, a, a))
    lo, hi = -overhang, a + overhang
    top = np.array([[lo, lo, a], [hi, lo, a], [hi, hi, a], [lo, hi, a]])
    bottom = np.array([[0, 0, 0], [a, 0, 0], [a, a, 0], [0, a, 0]], float)
    zero, c = np.zeros(3), np.full(3, a / 2)
    scale_up = ((a + 2 * overhang) / a) ** 2
    load = BlockLoad(
        patches=(
            TractionPatch(top, [0, 0, -p], zero, c),
            TractionPatch(bottom, [0, 0, p * scale_up], zero, c),
        )
    )
    return blk, load


@pytest.mark.parametrize("reverse", [False, True])
def test_patch_area_outside_its_face_is_patch_minus_face(reverse):
    """A square patch of side 3a over a cube face of side a: 8 a^2 lies outside."""
    a = 0.2
    blk, load = cube_top_and_bottom(a, a, 1e5)
    patch = load.patches[0]
    if reverse:  # clockwise about the face normal: same areas
        patch = TractionPatch(patch.polygon[::-1], patch.traction, patch.spin, patch.centre)
    face, off_plane, area, outside = patch_face(blk, patch)
    np.testing.assert_allclose(blk.normals[face], [0, 0, 1], atol=1e-12)
    assert off_plane == pytest.approx(0.0, abs=1e-15)
    np.testing.assert_allclose(area, 9 * a**2, rtol=1e-12)
    np.testing.assert_allclose(outside, 9 * a**2 - a**2, rtol=1e-12)


def test_patch_past_its_face_is_refused_before_the_equilibrium_check():
    """The balanced-looking load of a 3a x 3a patch on a cube of side a is not accepted."""
    a = 0.2
    blk, load = cube_top_and_bottom(a, a, 1e5)
    force, _ = load.resultant(blk)
    np.testing.assert_allclose(force, 0.0, atol=1e-9)  # the whole polygon balances
    with pytest.raises(ValueError, match="traction patch 0 extends past block face") as err:
        check_equilibrium(blk, load, name="cube")
    assert not isinstance(err.value, EquilibriumError)
    assert f"{8 * a**2:.3e} m^2 of its {9 * a**2:.3e} m^2" in str(err.value)


def test_interface_overhang_within_the_dem_tolerance_is_accepted():
    """A patch sticking out by the DEM contact tolerance (1e-6 of the size) passes; its area
    outside is the frame ``(a + 2 e)^2 - a^2``."""
    a = 0.2
    eps = 1e-6 * a
    blk, load = cube_top_and_bottom(a, eps, 1e5)
    _, _, _, outside = patch_face(blk, load.patches[0])
    np.testing.assert_allclose(outside, (a + 2 * eps) ** 2 - a**2, rtol=1e-6)
    assert check_patch_on_face(blk, load.patches[0]) == int(np.argmax(blk.normals[:, 2]))
    assert check_equilibrium(blk, load, 1e-12, "cube").rel < 1e-12


def test_solver_refuses_a_patch_past_its_face_before_meshing():
    a = 0.2
    blk, load = cube_top_and_bottom(a, a, 1e5)
    solver = BlockSolver(ElasticMaterial(10e9, 0.2), MeshSettings(size=a / 4), degree=1)
    with pytest.raises(ValueError, match="cube: traction patch 0 extends past block face"):
        solver.solve(blk, load, "cube")
    assert solver.timings["mesh"] == 0.0


def test_load_lost_in_assembly_is_not_hidden(monkeypatch):
    """With the face check switched off, the FE load clips the 3a x 3a patch to the face and
    loses p (9 a^2 - a^2) [N]: the solver compares resultants and raises instead of solving."""
    a, p = 0.2, 1e5

    def face_only(block, patch, label=""):
        return patch_face(block, patch)[0]

    monkeypatch.setattr(loads, "check_patch_on_face", face_only)
    monkeypatch.setattr(elastic, "check_patch_on_face", face_only)
    blk, load = cube_top_and_bottom(a, a, p)
    solver = BlockSolver(ElasticMaterial(10e9, 0.2), MeshSettings(size=a / 4), degree=1)
    with pytest.raises(LoadTransferError, match=re.escape(f"by {p * 8 * a**2:.3e} N")):
        solver.solve(blk, load, "cube")
