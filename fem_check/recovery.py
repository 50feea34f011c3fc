"""Stresses of a solved block: finite element stress, recovered nodal stress, cut resultants.

- :func:`stress_at_corners`: the finite element stress ``C : sym grad u`` at the four corners of
  every tetrahedron. On straight tetrahedra it is constant (P1) or affine (P2) per element, so
  the corner values describe it exactly (a discontinuous P0 / P1 field).
- :func:`recover_nodal_stress`: its L2 projection onto continuous P1 (the recovery space).
- :func:`von_mises`, :func:`principal_stresses`: invariants of ``(..., 3, 3)`` stresses.
- :func:`cut_resultant`: force and moment of ``sigma n`` over a plane cut through the block,
  integrated exactly on the tetrahedra the plane crosses; by Cauchy's theorem it equals the
  loads on the side the normal points to (:func:`fem_check.loads.loads_on_side`).

Results are in the world frame unless a name says ``_ref``.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
import skfem
from scipy.sparse.linalg import splu
from skfem.helpers import sym_grad
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTri

from fem_check.elastic import BlockSolution, ShapeOperator

_TET_CORNERS = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
_TET_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])


# per-shape bases and factors, kept as long as the shape operator lives
_CORNER_BASES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_P1_PROJECTIONS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _corner_basis(op: ShapeOperator) -> skfem.CellBasis:
    """The displacement basis evaluated at the four corners of every tetrahedron."""
    basis = _CORNER_BASES.get(op)
    if basis is None:
        basis = skfem.Basis(
            op.tet_mesh.mesh, op.basis.elem, quadrature=(_TET_CORNERS, np.full(4, 1.0 / 24.0))
        )
        _CORNER_BASES[op] = basis
    return basis


def stress_at_corners_ref(sol: BlockSolution) -> np.ndarray:
    """(n_tets, 4, 3, 3) finite element stress at the tetrahedron corners, reference frame [Pa]."""
    eps = sym_grad(_corner_basis(sol.operator).interpolate(sol.u))  # (3, 3, n_tets, 4)
    return sol.operator.material.stress(np.transpose(eps, (2, 3, 0, 1)))


def stress_at_corners(sol: BlockSolution) -> np.ndarray:
    """(n_tets, 4, 3, 3) finite element stress at the tetrahedron corners, world frame [Pa]."""
    rot = sol.block_mesh.rotation
    return rot @ stress_at_corners_ref(sol) @ rot.T


def recover_nodal_stress_ref(sol: BlockSolution) -> np.ndarray:
    """(n_vertices, 3, 3) L2 projection of the stress onto continuous P1, reference frame [Pa].

    The projection solves ``M1 s = int phi_i sigma_h dV`` per component with the P1 mass
    matrix ``M1``, factorised once per shape.
    """
    op = sol.operator
    p1, lu = _p1_projection(op)
    eps = sym_grad(op.basis.interpolate(sol.u))  # (3, 3, n_tets, n_qp)
    sig = op.material.stress(np.transpose(eps, (2, 3, 0, 1)))  # (n_tets, n_qp, 3, 3)
    out = np.empty((p1.N, 3, 3))
    for i in range(3):
        for j in range(i, 3):
            rhs = _p1_load.assemble(p1, s=sig[:, :, i, j])
            out[:, i, j] = out[:, j, i] = lu.solve(rhs)
    return out


def recover_nodal_stress(sol: BlockSolution) -> np.ndarray:
    """(n_vertices, 3, 3) recovered stress at the mesh corners, world frame [Pa]."""
    rot = sol.block_mesh.rotation
    return rot @ recover_nodal_stress_ref(sol) @ rot.T


@skfem.LinearForm
def _p1_load(v, w):
    return w["s"] * v


@skfem.BilinearForm
def _p1_mass(u, v, w):
    return u * v


def _p1_projection(op: ShapeOperator):
    """P1 basis on the displacement quadrature and the factorised P1 mass matrix of a shape."""
    cached = _P1_PROJECTIONS.get(op)
    if cached is None:
        p1 = skfem.Basis(op.tet_mesh.mesh, skfem.ElementTetP1(), quadrature=op.basis.quadrature)
        cached = (p1, splu(_p1_mass.assemble(p1).tocsc()))
        _P1_PROJECTIONS[op] = cached
    return cached


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress ``sqrt(3/2 s:s)`` of ``(..., 3, 3)`` stresses [Pa]."""
    dev = stress - np.trace(stress, axis1=-2, axis2=-1)[..., None, None] * np.eye(3) / 3.0
    return np.sqrt(1.5 * np.einsum("...ij,...ij->...", dev, dev))


def principal_stresses(stress: np.ndarray) -> np.ndarray:
    """(..., 3) principal stresses, largest (most tensile) first [Pa]."""
    return np.linalg.eigvalsh(stress)[..., ::-1]


@dataclass(frozen=True)
class StressSummary:
    """Extremes of the recovered stress of one block (world frame).

    Attributes
    ----------
    max_principal : float
        Largest principal stress over the corner nodes [Pa] (the most tensile).
    max_principal_at : (3,) float
        Where [m].
    max_von_mises : float
        [Pa].
    min_principal : float
        Most compressive principal stress [Pa].
    max_principal_fe : float
        Largest principal stress of the unrecovered FE stress at tetrahedron corners [Pa].
    """

    max_principal: float
    max_principal_at: np.ndarray
    max_von_mises: float
    min_principal: float
    max_principal_fe: float


def summarise(sol: BlockSolution, nodal: np.ndarray | None = None) -> StressSummary:
    """Stress extremes of a block from its recovered and FE stresses."""
    nodal = recover_nodal_stress(sol) if nodal is None else nodal
    pr = principal_stresses(nodal)
    i = int(np.argmax(pr[:, 0]))
    fe = principal_stresses(stress_at_corners_ref(sol))
    return StressSummary(
        float(pr[i, 0]),
        sol.block_mesh.world_points()[i],
        float(von_mises(nodal).max()),
        float(pr[:, 2].min()),
        float(fe[..., 0].max()),
    )


def cut_resultant(
    sol: BlockSolution,
    normal: np.ndarray,
    offset: float,
    about: np.ndarray,
    stress: str = "fe",
) -> tuple[np.ndarray, np.ndarray, float]:
    """Integral of the traction ``sigma n`` over the plane cut ``n . x = offset`` of a block.

    Parameters
    ----------
    sol : BlockSolution
    normal : (3,) float
        Unit normal of the cut (world frame).
    offset : float
        [m].
    about : (3,) float
        Moment centre [m].
    stress : {"fe", "recovered"}
        Integrate the finite element stress (affine per tetrahedron for P2, constant for P1) or
        the recovered continuous P1 stress.

    Returns
    -------
    force : (3,) float
        :math:`\\int \\sigma n\\,dA` [N], world frame.
    moment : (3,) float
        :math:`\\int (x - o) \\times \\sigma n\\,dA` [N m].
    area : float
        Area of the cut [m^2].

    Notes
    -----
    The plane meets each tetrahedron in a triangle or a quadrilateral; on it the stress is
    affine (interpolated along the crossed edges), so a degree-2 rule on a fan of triangles
    integrates force and moment exactly. Requires straight (order 1) tetrahedra.
    """
    bm, op = sol.block_mesh, sol.operator
    if not isinstance(op.tet_mesh.mesh, skfem.MeshTet1):
        raise ValueError("cut_resultant needs a mesh of straight (order 1) tetrahedra")
    rot = bm.rotation
    scale = float(np.linalg.norm(normal))
    normal = np.asarray(normal, dtype=float) / scale
    n_ref = normal @ rot
    d_ref = float(offset) / scale - float(normal @ bm.translation)
    o_ref = bm.to_reference(np.asarray(about, dtype=float)[None])[0]
    if stress == "fe":
        corner_sig = stress_at_corners_ref(sol)
    elif stress == "recovered":
        corner_sig = recover_nodal_stress_ref(sol)[op.tet_mesh.mesh.t.T]
    else:
        raise ValueError(f"stress must be 'fe' or 'recovered', got {stress!r}")
    force, moment, area = _cut_ref(
        op.tet_mesh.points[op.tet_mesh.tets], corner_sig, n_ref, d_ref, o_ref
    )
    return rot @ force, rot @ moment, area


def _cut_ref(xyz, sig, n, d, o):
    """Cut integral on tetrahedra ``xyz`` (t, 4, 3) with corner stresses ``sig`` (t, 4, 3, 3)."""
    s = xyz @ n - d
    pos = s >= 0.0
    crossing = pos.any(axis=1) & ~pos.all(axis=1)
    xyz, sig, s, pos = xyz[crossing], sig[crossing], s[crossing], pos[crossing]
    i, j = _TET_EDGES.T
    cut_edge = pos[:, i] != pos[:, j]  # (t, 6)
    w = s[:, i] / np.where(cut_edge, s[:, i] - s[:, j], 1.0)
    pts = xyz[:, i] + w[..., None] * (xyz[:, j] - xyz[:, i])  # (t, 6, 3)
    sn = np.einsum("teab,b->tea", sig, n)  # traction at corners (t, 4, 3)
    trac = sn[:, i] + w[..., None] * (sn[:, j] - sn[:, i])  # (t, 6, 3)
    x_ref, w_ref = get_quadrature(RefTri, 2)
    force, moment, area = np.zeros(3), np.zeros(3), 0.0
    t1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    for n_cut in (3, 4):
        sel = cut_edge.sum(axis=1) == n_cut
        if not sel.any():
            continue
        order = np.argsort(~cut_edge[sel], axis=1, kind="stable")[:, :n_cut]
        p = np.take_along_axis(pts[sel], order[..., None], axis=1)  # (k, n_cut, 3)
        tr = np.take_along_axis(trac[sel], order[..., None], axis=1)
        rel = p - p.mean(axis=1, keepdims=True)
        ang = np.arctan2(rel @ t2, rel @ t1)
        ccw = np.argsort(ang, axis=1)
        p = np.take_along_axis(p, ccw[..., None], axis=1)
        tr = np.take_along_axis(tr, ccw[..., None], axis=1)
        for k in range(1, n_cut - 1):
            a, b, c = p[:, 0], p[:, k], p[:, k + 1]
            ta, tb, tc = tr[:, 0], tr[:, k], tr[:, k + 1]
            ar = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
            area += ar.sum()
            for (xi, eta), wq in zip(x_ref.T, w_ref, strict=True):
                x = a + xi * (b - a) + eta * (c - a)
                t = ta + xi * (tb - ta) + eta * (tc - ta)
                wt = (2.0 * ar * wq)[:, None]
                force += (wt * t).sum(axis=0)
                moment += (wt * np.cross(x - o, t)).sum(axis=0)
    return force, moment, float(area)
