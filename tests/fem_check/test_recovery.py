"""Stress recovery, invariants and Cauchy cut resultants."""

import math

import numpy as np
import pytest

from dem.geometry.polyhedron import convex_block
from fem_check.elastic import BlockSolver, ElasticMaterial
from fem_check.loads import BlockLoad, TractionPatch, loads_on_side, wrench_patches
from fem_check.mesh import MeshSettings
from fem_check.recovery import cut_resultant, principal_stresses, von_mises


def test_invariants_closed_form():
    s, tau = 5e6, 2e6
    uniaxial = np.diag([s, 0.0, 0.0])
    shear = np.array([[0, tau, 0], [tau, 0, 0], [0, 0, 0]])
    np.testing.assert_allclose(von_mises(uniaxial), s)
    np.testing.assert_allclose(von_mises(shear), math.sqrt(3) * tau)
    np.testing.assert_allclose(principal_stresses(shear), [tau, 0, -tau], atol=1e-9)


def tis_block():
    """Full TIS block, seed 000 Fig. 4a (l = 8.33 mm, t = 3.18 mm, theta = 5 deg)."""
    l_side, t, lean = 8.33e-3, 3.18e-3, 3.18e-3 * math.tan(math.radians(5))
    h = l_side / 2
    pts = [
        (sx * hx, sy * hy, z)
        for z, hx, hy in ((0, h, h), (t, h + lean, h - lean))
        for sx in (-1, 1)
        for sy in (-1, 1)
    ]
    return convex_block(np.array(pts))


@pytest.mark.parametrize("degree", [1, 2])
def test_cut_of_uniform_stress_is_exact(degree):
    """Uniform sigma = -p e_z e_z in a box: the cut z = c carries -p A e_z (closed form)."""
    p = 2e6
    zero = np.zeros(3)
    box = convex_block(
        np.array([[x, y, z] for x in (0, 2e-3) for y in (0, 1e-3) for z in (0, 3e-3)])
    )
    top = box.vertices[box.faces[int(np.argmax(box.normals[:, 2]))]]
    bottom = box.vertices[box.faces[int(np.argmin(box.normals[:, 2]))]]
    load = BlockLoad(
        patches=(
            TractionPatch(top, [0, 0, -p], zero, zero),
            TractionPatch(bottom, [0, 0, p], zero, zero),
        )
    )
    sol = BlockSolver(ElasticMaterial(1e10, 0.3), MeshSettings(size=0.7e-3), degree).solve(
        box, load
    )
    for kind in ("fe", "recovered"):
        f, m, area = cut_resultant(sol, np.array([0, 0, 1.0]), 1.234e-3, box.centroid, kind)
        np.testing.assert_allclose(area, 2e-6, rtol=1e-12)
        np.testing.assert_allclose(f, [0, 0, -p * 2e-6], atol=1e-10 * p * 2e-6)


def test_cauchy_cut_matches_loads_on_one_side():
    """A TIS block under bending-type interface tractions: the cut x = 0.7 mm carries the
    loads on its +x side (Cauchy), up to the discretisation error of P2 (1 % of the load)."""
    blk = tis_block()
    c = blk.centroid
    lateral = [f for f in range(len(blk.faces)) if abs(blk.normals[f, 2]) < 0.5]
    plus_x = max(lateral, key=lambda f: blk.normals[f, 0])
    minus_x = min(lateral, key=lambda f: blk.normals[f, 0])
    poly_p = blk.vertices[blk.faces[plus_x]]
    poly_m = blk.vertices[blk.faces[minus_x]]
    force = np.array([-30.0, 2.0, 5.0])
    moment = np.array([0.01, 0.02, -0.015])
    (p_plus,) = wrench_patches([poly_p], force, moment, c)
    rest = wrench_patches([poly_m], -force, -moment, c)
    rho, g = 2500.0, np.array([0, 0, -9.81])
    weight = rho * blk.volume * g
    support = wrench_patches(
        [blk.vertices[blk.faces[int(np.argmin(blk.normals[:, 2]))]]], -weight, np.zeros(3), c
    )
    load = BlockLoad(patches=(p_plus, *rest, *support), density=rho, gravity=g)
    sol = BlockSolver(ElasticMaterial(18.75e9, 0.2), MeshSettings(size=0.8e-3), 2).solve(blk, load)
    normal, offset = np.array([1.0, 0, 0]), 0.7e-3
    about = np.array([offset, 0, 1.5e-3])
    f_ref, m_ref = loads_on_side(blk, load, normal, offset, about)
    f_cut, m_cut, _ = cut_resultant(sol, normal, offset, about)
    scale = np.linalg.norm(force)
    assert np.linalg.norm(f_cut - f_ref) < 0.01 * scale
    assert np.linalg.norm(m_cut - m_ref) < 0.01 * scale * blk.size
