"""Free-floating elastic blocks: patch test, rigid-body modes, beam, unbalanced loads."""

import math

import numpy as np
import pytest

from dem.geometry.polyhedron import convex_block
from fem_check.elastic import BlockSolver, ElasticMaterial
from fem_check.loads import BlockLoad, EquilibriumError, TractionPatch, wrench_patches
from fem_check.mesh import MeshSettings
from fem_check.recovery import recover_nodal_stress, stress_at_corners

E, NU = 20e9, 0.25


def random_rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def hex_prism(rot, shift, radius=1e-3, length=2.5e-3):
    """A right prism on an irregular hexagon, axis along rot[:, 2]."""
    ang = np.array([0.0, 1.1, 2.0, 3.3, 4.1, 5.2])
    ring = np.c_[radius * np.cos(ang), 0.8 * radius * np.sin(ang)]
    pts = np.concatenate([np.c_[ring, np.zeros(6)], np.c_[ring, np.full(6, length)]])
    return convex_block(pts @ rot.T + shift)


def end_caps(block, axis):
    lo = int(np.argmin(block.normals @ axis))
    hi = int(np.argmax(block.normals @ axis))
    return block.vertices[block.faces[lo]], block.vertices[block.faces[hi]]


@pytest.mark.parametrize(("degree", "mesh_order"), [(1, 1), (2, 1), (2, 2)])
def test_patch_uniform_compression_is_exact(degree, mesh_order):
    """Uniform pressure p on the end caps of a prism: sigma = -p a (x) a exactly."""
    p = 3e6
    settings = MeshSettings(size=0.8e-3, order=mesh_order)
    solver = BlockSolver(ElasticMaterial(E, NU), settings, degree=degree)
    for seed in (1, 2):  # the second prism is a rigid motion of the first: cached shape
        rot = random_rotation(seed)
        block = hex_prism(rot, np.array([0.01, -0.02, 0.03]) * seed)
        axis = rot[:, 2]
        cap_lo, cap_hi = end_caps(block, axis)
        zero = np.zeros(3)
        load = BlockLoad(
            patches=(
                TractionPatch(cap_lo, p * axis, zero, zero),
                TractionPatch(cap_hi, -p * axis, zero, zero),
            )
        )
        sol = solver.solve(block, load)
        exact = -p * np.outer(axis, axis)
        nodal = recover_nodal_stress(sol)
        for sig in (stress_at_corners(sol), nodal):
            assert np.abs(sig - exact).max() <= 1e-10 * p
        assert len(nodal) == len(sol.block_mesh.world_points()) == len(sol.displacement_world())
    assert len(solver.cache.shapes) == 1


def _integrals(sol):
    """int u dV and int (x - c) x u dV by the displacement basis quadrature (world frame)."""
    op = sol.operator
    u = np.asarray(op.basis.interpolate(sol.u))  # (3, n_tets, n_qp), reference frame
    x = op.basis.mapping.F(op.basis.quadrature[0])  # (3, n_tets, n_qp)
    r = x - op.reference.centroid[:, None, None]
    dx = op.basis.dx
    mean_u = np.einsum("ieq,eq->i", u, dx)
    mean_rot = np.einsum("ieq,eq->i", np.cross(r, u, axis=0), dx)
    abs_u = np.einsum("eq,eq->", np.linalg.norm(u, axis=0), dx)
    return mean_u, mean_rot, abs_u, float(np.linalg.norm(r, axis=0).max())


@pytest.mark.parametrize("degree", [1, 2])
def test_self_equilibrated_load_has_zero_mean_motion(degree):
    rng = np.random.default_rng(7)
    block = hex_prism(random_rotation(5), np.zeros(3))
    # random point forces on the side faces, balanced by the least traction on one cap
    faces = rng.integers(0, len(block.faces), size=40)
    pts = np.array([block.vertices[block.faces[f]].mean(axis=0) for f in faces])
    forces = rng.normal(size=(40, 3))
    c = block.centroid
    f_tot, m_tot = forces.sum(axis=0), np.cross(pts - c, forces).sum(axis=0)
    cap, _ = end_caps(block, random_rotation(5)[:, 2])
    patches = wrench_patches([cap], -f_tot, -m_tot, c)
    load = BlockLoad(pts, forces, tuple(patches))
    sol = BlockSolver(ElasticMaterial(E, NU), MeshSettings(size=0.8e-3), degree=degree).solve(
        block, load
    )
    mean_u, mean_rot, abs_u, size = _integrals(sol)
    assert np.linalg.norm(mean_u) <= 1e-10 * abs_u
    assert np.linalg.norm(mean_rot) <= 1e-10 * abs_u * size
    assert abs_u > 0


def test_cantilever_tip_deflection_matches_timoshenko():
    """Tip-loaded cantilever, clamp replaced by the balancing root tractions.

    Timoshenko beam: delta = V L^3 / (3 E I) + V L / (kappa G A), kappa = 10 (1 + nu) /
    (12 + 11 nu) (Cowper 1966, rectangle). Deflection is measured relative to the root
    section's rigid motion (mean displacement and least-squares rotation of the root face).
    Tolerance 2 %: 3-D end effects of a beam with L / h = 10.
    """
    length, width, height = 20e-3, 2e-3, 2e-3
    corners = np.array([[x, y, z] for x in (0, length) for y in (0, width) for z in (0, height)])
    block = convex_block(corners - [0, width / 2, height / 2])
    root, tip = end_caps(block, np.array([1.0, 0, 0]))
    v = 10.0
    zero = np.zeros(3)
    area = width * height
    tip_patch = TractionPatch(tip, np.array([0, 0, v / area]), zero, zero)
    root_c = np.array([0.0, 0, 0])
    root_patches = wrench_patches(
        [root], np.array([0, 0, -v]), np.array([0, length * v, 0]), root_c
    )
    load = BlockLoad(patches=(tip_patch, *root_patches))
    sol = BlockSolver(ElasticMaterial(E, NU), MeshSettings(size=1.0e-3), degree=2).solve(
        block, load
    )
    # Gauss-Legendre points on the two end faces, nudged inside for point location
    g, w = np.polynomial.legendre.leggauss(6)
    yy, zz = np.meshgrid(g * width / 2, g * height / 2, indexing="ij")
    ww = np.outer(w, w).ravel() / 4

    def face_u(x):
        pts = np.c_[np.full(yy.size, x), yy.ravel(), zz.ravel()]
        u = (sol.operator.basis.probes(pts.T) @ sol.u).reshape(3, -1)
        return u, pts

    eps = 1e-9
    u_root, p_root = face_u(eps)
    u_tip, _ = face_u(length - eps)
    w_root, w_tip = u_root[2] @ ww, u_tip[2] @ ww
    theta_y = (u_root[0] * p_root[:, 2]) @ ww / ((p_root[:, 2] ** 2) @ ww)
    delta = w_tip - w_root + theta_y * length
    inertia = width * height**3 / 12
    g_mod = E / (2 * (1 + NU))
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    expected = v * length**3 / (3 * E * inertia) + v * length / (kappa * g_mod * area)
    np.testing.assert_allclose(delta, expected, rtol=0.02)
    # bending stress at the root's top fibre mid-span: M c / I (beam theory), 2 %
    sig = recover_nodal_stress(sol)
    pts = sol.block_mesh.world_points()
    mid = np.argmin(
        np.abs(pts[:, 0] - length / 2) + np.abs(pts[:, 2] - height / 2) + np.abs(pts[:, 1])
    )
    np.testing.assert_allclose(
        sig[mid, 0, 0], -v * (length - pts[mid, 0]) * pts[mid, 2] / inertia, rtol=0.03
    )


def test_unbalanced_load_raises_before_solving():
    block = hex_prism(np.eye(3), np.zeros(3))
    cap, _ = end_caps(block, np.array([0, 0, 1.0]))
    zero = np.zeros(3)
    load = BlockLoad(patches=(TractionPatch(cap, np.array([0, 0, 1e6]), zero, zero),))
    solver = BlockSolver(ElasticMaterial(E, NU), MeshSettings(size=1e-3), degree=1)
    with pytest.raises(EquilibriumError, match="not in equilibrium"):
        solver.solve(block, load)
    assert solver.timings["solve"] == 0.0  # nothing was solved
    assert issubclass(EquilibriumError, ValueError)


def test_weight_balanced_by_support_traction_and_inertia():
    """Gravity balanced by a base traction, and the same block in free fall (a = g)."""
    block = hex_prism(np.eye(3), np.zeros(3))
    base, _ = end_caps(block, np.array([0, 0, 1.0]))
    rho, g = 2500.0, np.array([0, 0, -9.81])
    weight = rho * block.volume * g
    patches = wrench_patches([base], -weight, np.zeros(3), block.centroid)
    load = BlockLoad(patches=tuple(patches), density=rho, gravity=g)
    solver = BlockSolver(ElasticMaterial(E, NU), MeshSettings(size=1e-3), degree=1)
    sol = solver.solve(block, load)
    assert sol.equilibrium.rel < 1e-12
    falling = BlockLoad(density=rho, gravity=g, acceleration=np.r_[g, 0, 0, 0])
    sol = solver.solve(block, falling)  # d'Alembert load cancels gravity: no stress
    assert np.abs(sol.u).max() == pytest.approx(0.0, abs=1e-25)
    with pytest.raises(EquilibriumError):
        solver.solve(block, BlockLoad(density=rho, gravity=g))


def test_material_rejects_bad_input():
    with pytest.raises(ValueError, match="Poisson"):
        ElasticMaterial(1e9, 0.5)
    with pytest.raises(ValueError, match="Young"):
        ElasticMaterial(-1.0, 0.2)
    assert math.isclose(ElasticMaterial(1e9, 0.25).lame[1], 0.4e9)
