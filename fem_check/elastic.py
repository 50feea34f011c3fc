r"""Linear elasticity of one free-floating block under DEM loads (scikit-fem, P1 or P2).

A block of the assembly is in equilibrium under its contact forces, weight and d'Alembert load
but is not held anywhere: its stiffness matrix is singular with the six rigid-body modes ``R``
(translations, small rotations about the centroid) as kernel. The problem solved is the one
with six Lagrange multipliers,

.. math::

    K u + M R \lambda = f, \qquad R^T M u = 0,

(``M``: mass matrix of unit density): the mean displacement and the mean rotation of the block
vanish, and ``M R lambda`` is a rigid-body-acceleration body force that carries the load's
resultant, zero for a balanced load. The load's imbalance is checked *before* the solve
(:func:`fem_check.loads.check_equilibrium`) and never hidden: the resultant ``R^T f`` of the
assembled load must equal the checked one (:func:`check_load_transfer`), so that no load lost
in assembly is carried away by the multipliers unseen.

It is solved exactly without the saddle-point matrix (whose six dense rows ruin the sparse
factorisation): multiplying by ``R^T`` gives :math:`\lambda = (R^T M R)^{-1} R^T f`; the
balanced load :math:`f - M R \lambda` is applied to the block held at six dofs of three
corners (an isostatic 3-2-1 support, whose reactions are then exactly zero because ``R`` is
non-singular on those dofs), and the rigid part is removed afterwards,
:math:`u \leftarrow u - R (R^T M R)^{-1} R^T M u`. The reduced stiffness is symmetric
positive definite and factorised once per block shape (SuperLU, symmetric mode).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from functools import cached_property
from itertools import combinations

import numpy as np
import skfem
from scipy.sparse.linalg import splu
from scipy.spatial import cKDTree
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTri

from dem.geometry.clipping import clip_convex_polygons
from dem.geometry.polyhedron import ConvexBlock, plane_basis
from fem_check.loads import (
    EQUILIBRIUM_REL_TOL,
    BlockLoad,
    EquilibriumReport,
    TractionPatch,
    check_equilibrium,
    check_patch_on_face,
)
from fem_check.mesh import BlockMesh, MeshCache, MeshingError, MeshSettings, TetMesh

log = logging.getLogger(__name__)

FACE_REL_TOL = 1e-7
"""A mesh facet lies on a block face if its corners are this close to the plane (x size)."""
LOCATE_CANDIDATES = 8
"""Nearest facets (by centroid) searched for the facet that holds a point."""
TRACTION_QUAD_DEGREE = 4
"""Quadrature degree on facets for traction patches (P2 basis x affine traction = 3)."""


class LoadTransferError(RuntimeError):
    """The assembled FE load does not carry the resultant that was checked (load lost or added)."""


@dataclass(frozen=True)
class ElasticMaterial:
    """Isotropic linear elastic material.

    Attributes
    ----------
    young : float
        Young's modulus E [Pa].
    poisson : float
        Poisson's ratio nu [-], ``-1 < nu < 0.5``.
    """

    young: float
    poisson: float

    def __post_init__(self):
        if not np.isfinite(self.young) or self.young <= 0:
            raise ValueError(f"Young's modulus must be finite and positive [Pa], got {self.young}")
        if not -1.0 < self.poisson < 0.5:
            raise ValueError(f"Poisson's ratio must lie in (-1, 0.5), got {self.poisson}")

    @property
    def lame(self) -> tuple[float, float]:
        """Lame parameters (lambda, mu) [Pa]."""
        return lame_parameters(self.young, self.poisson)

    def stress(self, strain: np.ndarray) -> np.ndarray:
        """Stress [Pa] of strain tensors ``(..., 3, 3)`` (Hooke's law)."""
        lam, mu = self.lame
        tr = np.trace(strain, axis1=-2, axis2=-1)[..., None, None]
        return 2.0 * mu * strain + lam * tr * np.eye(3)


class ShapeOperator:
    """Stiffness, mass, rigid modes and the factorised anchored stiffness of one block shape.

    Parameters
    ----------
    tet_mesh : TetMesh
        Mesh of the reference block.
    reference : ConvexBlock
        The reference block (its faces classify the boundary facets).
    material : ElasticMaterial
    degree : int
        Polynomial degree of the displacement: 1 or 2.

    Attributes
    ----------
    basis : skfem.CellBasis
        Vector basis of the displacement.
    stiffness, mass : scipy.sparse.csr_matrix
        ``K`` [N/m] and unit-density ``M`` [m^3], (n_dofs, n_dofs).
    modes : (n_dofs, 6) float
        Rigid-body modes: unit translations x, y, z, then unit rotations about x, y, z through
        the reference centroid.
    facet_face : (n_boundary_facets,) int64
        Face of ``reference`` that each boundary facet lies on (-1: none).
    """

    def __init__(
        self, tet_mesh: TetMesh, reference: ConvexBlock, material: ElasticMaterial, degree: int
    ):
        if degree not in (1, 2):
            raise ValueError(f"displacement degree must be 1 or 2, got {degree}")
        self.tet_mesh = tet_mesh
        self.reference = reference
        self.material = material
        self.degree = degree
        mesh = tet_mesh.mesh
        self.scalar_element = skfem.ElementTetP1() if degree == 1 else skfem.ElementTetP2()
        self.basis = skfem.Basis(mesh, skfem.ElementVector(self.scalar_element))
        self.scalar_basis = skfem.Basis(mesh, self.scalar_element, quadrature=self.basis.quadrature)
        lam, mu = material.lame
        self.stiffness = linear_elasticity(lam, mu).assemble(self.basis).tocsr()
        self.mass = _vector_mass.assemble(self.basis).tocsr()
        self.n_dofs = self.basis.N
        comp = np.arange(self.n_dofs) % 3  # ElementVector interleaves x, y, z per scalar dof
        r = self.basis.doflocs.T - reference.centroid  # (n_dofs, 3)
        modes = np.zeros((self.n_dofs, 6))
        for c in range(3):
            modes[comp == c, c] = 1.0
            rot = _cross_any(np.eye(3)[c], r)  # e_c x r at every dof location
            modes[:, 3 + c] = rot[np.arange(self.n_dofs), comp]
        self.modes = modes
        self._facets()

    def _anchor_dofs(self) -> np.ndarray:
        """Six dofs of three far-apart vertices on which the rigid modes are non-singular."""
        pts = self.tet_mesh.points
        a = int(np.argmax(np.linalg.norm(pts - self.reference.centroid, axis=1)))
        b = int(np.argmax(np.linalg.norm(pts - pts[a], axis=1)))
        ab = (pts[b] - pts[a]) / np.linalg.norm(pts[b] - pts[a])
        rel = pts - pts[a]
        c = int(np.argmax(np.linalg.norm(rel - np.outer(rel @ ab, ab), axis=1)))
        # vertex dofs come first in skfem's numbering, interleaved x, y, z
        cand = np.array([3 * v + k for v in (a, b, c) for k in range(3)])
        best = max(
            combinations(range(9), 6),
            key=lambda sel: abs(np.linalg.det(self.modes[cand[list(sel)]])),
        )
        return cand[list(best)]

    @cached_property
    def factor(self):
        """SuperLU factors of the stiffness held at the six anchor dofs (built on first use)."""
        self._anchors = self._anchor_dofs()
        self._free = np.setdiff1d(np.arange(self.n_dofs), self._anchors)
        self._gram = self.modes.T @ (self.mass @ self.modes)
        k_red = self.stiffness[self._free][:, self._free].tocsc()
        return splu(
            k_red,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )

    def solve(self, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Displacement (n_dofs,) [m] and multipliers (6,) of a load vector (n_dofs,) [N].

        The multipliers are the rigid-body acceleration (per unit density) that the load's
        resultant would cause: zero for a balanced load.
        """
        factor = self.factor
        lam = np.linalg.solve(self._gram, self.modes.T @ f)
        f_bal = f - self.mass @ (self.modes @ lam)
        u = np.zeros(self.n_dofs)
        u[self._free] = factor.solve(f_bal[self._free])
        u -= self.modes @ np.linalg.solve(self._gram, self.modes.T @ (self.mass @ u))
        return u, lam

    # -- boundary facets and point evaluation ----------------------------------------------
    def _facets(self):
        mesh = self.tet_mesh.mesh
        bf = mesh.boundary_facets()
        corners = mesh.p[:, mesh.facets[:, bf]]  # (3, 3 corners, nb)
        dist = (
            np.einsum("fi,icb->fcb", self.reference.normals, corners)
            - self.reference.offsets[:, None, None]
        )
        on = np.all(np.abs(dist) < FACE_REL_TOL * self.reference.size, axis=1)  # (n_faces, nb)
        face = np.where(on.any(axis=0), on.argmax(axis=0), -1)
        self.boundary_facets = bf
        self.facet_face = face
        self._face_frames = []
        for f in range(len(self.reference.faces)):
            n = self.reference.normals[f]
            t1, t2 = plane_basis(n)
            ids = bf[face == f]
            tri = mesh.p[:, mesh.facets[:, ids]].transpose(2, 1, 0)  # (k, 3 corners, 3)
            tri2 = np.stack([tri @ t1, tri @ t2], axis=-1)  # (k, 3, 2)
            # counter-clockwise about n in the (t1, t2) basis
            cross = _cross_any(tri2[:, 1] - tri2[:, 0], tri2[:, 2] - tri2[:, 0])
            tri2[cross < 0] = tri2[cross < 0][:, ::-1]
            tree = cKDTree(tri2.mean(axis=1)) if len(ids) else None
            self._face_frames.append((ids, np.stack([t1, t2]), tri2, tree))

    def _scatter(self, points: np.ndarray, values: np.ndarray, facets: np.ndarray) -> np.ndarray:
        """Consistent nodal load of forces ``values`` (q, 3) [N] at ``points`` (q, 3) [m].

        ``facets[q]`` is the boundary facet holding point q; the force enters through the
        basis functions of the tetrahedron behind that facet (work-equivalent load).
        """
        f = np.zeros(self.n_dofs)
        if len(points) == 0:
            return f
        mesh = self.tet_mesh.mesh
        tets = mesh.f2t[0, facets]
        x_ref = mesh.mapping().invF(points.T[:, :, None], tind=tets)[:, :, 0]
        dofs = self.scalar_basis.element_dofs[:, tets]  # (n_local, q)
        for i in range(dofs.shape[0]):
            phi = self.scalar_element.lbasis(x_ref, i)[0]  # (q,)
            for c in range(3):
                f += np.bincount(3 * dofs[i] + c, phi * values[:, c], minlength=self.n_dofs)
        return f

    def locate_on_face(self, points: np.ndarray, face: int) -> tuple[np.ndarray, np.ndarray]:
        """Project points onto a face and find the boundary facet holding each.

        Returns
        -------
        points : (q, 3) float
            Projected onto the face plane and, if outside the face, onto its nearest facet [m].
        facets : (q,) int64
            Mesh facet index of each point.

        Notes
        -----
        Candidate facets are the ``LOCATE_CANDIDATES`` nearest by centroid (k-d tree); of
        these the one whose smallest barycentric coordinate is largest holds the point.
        """
        n, d = self.reference.normals[face], self.reference.offsets[face]
        pts = points - np.outer(points @ n - d, n)
        ids, basis, tri2, tree = self._face_frames[face]
        p2 = pts @ basis.T  # (q, 2)
        k = min(LOCATE_CANDIDATES, len(ids))
        _, cand = tree.query(p2, k=k)
        cand = cand.reshape(len(p2), k)
        tri = tri2[cand]  # (q, k, 3, 2)
        a, b, c = tri[:, :, 0], tri[:, :, 1], tri[:, :, 2]
        den = _cross_any(b - a, c - a)  # (q, k)
        rel = p2[:, None, :] - a
        l1 = _cross_any(rel, c - a) / den  # weight of b
        l2 = _cross_any(b - a, rel) / den  # weight of c
        bary = np.stack([1.0 - l1 - l2, l1, l2], axis=-1)  # (q, k, 3)
        pick = bary.min(axis=-1).argmax(axis=1)
        rows = np.arange(len(pts))
        best = cand[rows, pick]
        lam = np.clip(bary[rows, pick], 0.0, None)
        lam /= lam.sum(axis=1, keepdims=True)
        # the weights refer to the 2-D corners of tri2 (possibly reversed): map those back
        tri3 = np.einsum("qkj,jm->qkm", tri2[best], basis) + d * n
        return np.einsum("qk,qkm->qm", lam, tri3), ids[best]

    def face_of_points(self, points: np.ndarray) -> np.ndarray:
        """(q,) index of the face whose plane is nearest each point (largest signed distance)."""
        return np.argmax(points @ self.reference.normals.T - self.reference.offsets, axis=1)

    def point_load_vector(self, points: np.ndarray, forces: np.ndarray) -> tuple:
        """Load vector of point forces (reference frame) and the largest projection shift [m]."""
        f = np.zeros(self.n_dofs)
        if len(points) == 0:
            return f, 0.0
        faces = self.face_of_points(points)
        shift = 0.0
        for face in np.unique(faces):
            sel = faces == face
            pts, facets = self.locate_on_face(points[sel], int(face))
            shift = max(shift, float(np.linalg.norm(pts - points[sel], axis=1).max()))
            f += self._scatter(pts, forces[sel], facets)
        return f, shift

    def patch_load_vector(self, patch: TractionPatch) -> np.ndarray:
        """Load vector of a traction patch (reference frame), integrated exactly per facet.

        Raises ``ValueError`` if the patch leaves its face
        (:func:`fem_check.loads.check_patch_on_face`): the facets cover the face only.
        """
        face = check_patch_on_face(self.reference, patch, "traction patch")
        n, d = self.reference.normals[face], self.reference.offsets[face]
        ids, basis, tri2, _ = self._face_frames[face]
        poly2 = patch.polygon @ basis.T
        if _cross_any(poly2[1] - poly2[0], poly2[2] - poly2[0]) < 0:
            poly2 = poly2[::-1]
        tol = 1e-12 * self.reference.size
        # facets wholly inside the polygon need no clipping
        edge = np.roll(poly2, -1, axis=0) - poly2
        side = _cross_any(edge[None, None], tri2[:, :, None, :] - poly2[None, None])  # (k, 3, m)
        inside = np.all(side >= -tol * np.linalg.norm(edge, axis=1), axis=(1, 2))
        x_ref, w_ref = get_quadrature(RefTri, TRACTION_QUAD_DEGREE)
        pts2, wts, fac = [], [], []
        full = tri2[inside]
        if len(full):
            a, b, c = full[:, 0], full[:, 1], full[:, 2]
            area = 0.5 * np.abs(_cross_any(b - a, c - a))
            q = (
                a[:, None]
                + x_ref[0][None, :, None] * (b - a)[:, None]
                + x_ref[1][None, :, None] * (c - a)[:, None]
            )
            pts2.append(q.reshape(-1, 2))
            wts.append((2.0 * area[:, None] * w_ref[None]).reshape(-1))
            fac.append(np.repeat(ids[inside], len(w_ref)))
        lo, hi = poly2.min(axis=0), poly2.max(axis=0)
        for k in np.flatnonzero(~inside):
            t = tri2[k]
            if np.any(t.max(axis=0) < lo) or np.any(t.min(axis=0) > hi):
                continue
            piece = clip_convex_polygons(t, poly2, 0.0)
            if len(piece) < 3:
                continue
            a, b, c = piece[0], piece[1:-1], piece[2:]
            area = 0.5 * np.abs(_cross_any(b - a, c - a))
            q = (
                a
                + x_ref[0][None, :, None] * (b - a)[:, None]
                + x_ref[1][None, :, None] * (c - a)[:, None]
            )
            pts2.append(q.reshape(-1, 2))
            wts.append((2.0 * area[:, None] * w_ref[None]).reshape(-1))
            fac.append(np.full(q.shape[0] * q.shape[1], ids[k]))
        if not pts2:
            return np.zeros(self.n_dofs)
        p2 = np.concatenate(pts2)
        pts = p2 @ basis + d * n
        w = np.concatenate(wts)
        return self._scatter(pts, patch.at(pts) * w[:, None], np.concatenate(fac))

    def body_load_vector(self, density: float, uniform: np.ndarray, grad: np.ndarray) -> np.ndarray:
        """Load of the body force ``rho (uniform + grad (x - c))`` [N/m^3], exactly.

        The field is affine, hence in the finite element space: its dof values ``v`` give
        ``int phi . b dV = M v``.
        """
        r = self.basis.doflocs.T - self.reference.centroid
        comp = np.arange(self.n_dofs) % 3
        values = np.asarray(uniform)[comp] + np.einsum("qj,qj->q", grad[comp], r)
        return density * (self.mass @ values)


@skfem.BilinearForm
def _vector_mass(u, v, w):
    return dot(u, v)


def _cross_any(a, b):
    """Cross product; the scalar z component for 2-D vectors (NumPy 2 deprecates those)."""
    a, b = np.asarray(a), np.asarray(b)
    if a.shape[-1] == 2:
        return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return np.cross(a, b)


@dataclass(frozen=True, eq=False)
class BlockSolution:
    """Elastic solution of one block (reference frame of its shape).

    Attributes
    ----------
    block_mesh : BlockMesh
    operator : ShapeOperator
    u : (n_dofs,) float
        Displacement dofs in the reference frame [m].
    multipliers : (6,) float
        Lagrange multipliers of the rigid-mode constraints (the rigid-body acceleration per unit
        density that carries the load's resultant); zero for a balanced load.
    equilibrium : EquilibriumReport
        Resultant of the loads (world frame), checked before the solve.
    discrete_resultant : (6,) float
        ``R^T f``: force [N] and moment about the centroid [N m] of the assembled load vector,
        world frame (equals ``equilibrium`` up to the projection of DEM points onto the faces).
    projection_shift : float
        Largest distance a point force was moved to reach the block surface [m].
    """

    block_mesh: BlockMesh
    operator: ShapeOperator
    u: np.ndarray
    multipliers: np.ndarray
    equilibrium: EquilibriumReport
    discrete_resultant: np.ndarray
    projection_shift: float

    def displacement_world(self) -> np.ndarray:
        """(n_vertices, 3) displacement of the mesh corners, world frame [m]."""
        n_vert = self.operator.tet_mesh.mesh.nvertices
        u_ref = self.u[: 3 * n_vert].reshape(-1, 3)  # vertex dofs come first, interleaved
        return u_ref @ self.block_mesh.rotation.T


def to_reference(block_mesh: BlockMesh, load: BlockLoad) -> BlockLoad:
    """The load expressed in the reference frame of the block's shape."""
    rot = block_mesh.rotation
    patches = tuple(
        TractionPatch(
            block_mesh.to_reference(p.polygon),
            p.traction @ rot,
            p.spin @ rot,
            block_mesh.to_reference(p.centre[None])[0],
        )
        for p in load.patches
    )
    return BlockLoad(
        block_mesh.to_reference(load.points),
        block_mesh.vector_to_reference(load.forces),
        patches,
        load.density,
        load.gravity @ rot,
        np.concatenate([load.acceleration[:3] @ rot, load.acceleration[3:] @ rot]),
        load.angular_velocity @ rot,
        load.label,
    )


def load_vector(op: ShapeOperator, ref_load: BlockLoad) -> tuple[np.ndarray, float]:
    """Assembled load vector (reference frame) and the largest point projection shift [m]."""
    f, shift = op.point_load_vector(ref_load.points, ref_load.forces)
    for p in ref_load.patches:
        f += op.patch_load_vector(p)
    if ref_load.density > 0:
        acc = ref_load.acceleration
        f += op.body_load_vector(
            ref_load.density, ref_load.gravity - acc[:3], -ref_load.acceleration_gradient
        )
    return f, shift


@dataclass(eq=False)
class BlockSolver:
    """Solves blocks of any shape, meshing and factorising each shape once.

    Attributes
    ----------
    material : ElasticMaterial
    mesh_settings : MeshSettings
    degree : int
        Displacement degree, 1 or 2.
    rel_tol : float
        Largest accepted load imbalance (see :func:`fem_check.loads.check_equilibrium`).
    timings : dict
        Accumulated wall time [s] of ``mesh``, ``assemble`` (K, M, modes, facets),
        ``factorise``, ``load`` and ``solve``.
    """

    material: ElasticMaterial
    mesh_settings: MeshSettings
    degree: int = 2
    rel_tol: float = EQUILIBRIUM_REL_TOL
    timings: dict = field(
        default_factory=lambda: dict.fromkeys(
            ("mesh", "assemble", "factorise", "load", "solve"), 0.0
        )
    )

    def __post_init__(self):
        self.cache = MeshCache(self.mesh_settings)
        self.operators: dict[int, ShapeOperator] = {}

    def operator(self, block_mesh: BlockMesh) -> ShapeOperator:
        """The shape operator of a block's shape (assembled and factorised on first use)."""
        op = self.operators.get(block_mesh.shape_id)
        if op is None:
            t0 = time.perf_counter()
            op = ShapeOperator(
                block_mesh.tet_mesh, block_mesh.reference, self.material, self.degree
            )
            t1 = time.perf_counter()
            op.factor  # noqa: B018 (factorise now, to time it)
            self.timings["assemble"] += t1 - t0
            self.timings["factorise"] += time.perf_counter() - t1
            self.operators[block_mesh.shape_id] = op
        return op

    def mesh(self, block: ConvexBlock) -> BlockMesh:
        t0 = time.perf_counter()
        bm = self.cache.get(block)
        self.timings["mesh"] += time.perf_counter() - t0
        return bm

    def solve(self, block: ConvexBlock, load: BlockLoad, name: str = "block") -> BlockSolution:
        """Check the load's equilibrium, then solve the free-floating block.

        Raises
        ------
        fem_check.loads.EquilibriumError
            If the load's imbalance exceeds ``rel_tol`` (checked before any solve).
        fem_check.mesh.MeshingError
            If gmsh cannot mesh the block (named by ``name``).
        LoadTransferError
            If the resultant of the assembled load vector differs from the checked one by more
            than ``rel_tol`` (beyond the moment of moving point forces onto the surface).
        """
        report = check_equilibrium(block, load, self.rel_tol, name)
        log.info(
            "%s: load imbalance |F| = %.3e N (%.1e of %.3e N), |M| = %.3e N m (%.1e)",
            name,
            np.linalg.norm(report.force),
            report.rel_force,
            report.scale,
            np.linalg.norm(report.moment),
            report.rel_moment,
        )
        try:
            bm = self.mesh(block)
        except MeshingError as exc:
            raise MeshingError(f"{name}: {exc}") from exc
        op = self.operator(bm)
        t0 = time.perf_counter()
        f, shift = load_vector(op, to_reference(bm, load))
        t1 = time.perf_counter()
        u, lam = op.solve(f)
        t2 = time.perf_counter()
        self.timings["load"] += t1 - t0
        self.timings["solve"] += t2 - t1
        res = op.modes.T @ f
        rot = bm.rotation
        discrete = np.concatenate([rot @ res[:3], rot @ res[3:]])
        moved = shift * float(np.linalg.norm(load.forces, axis=1).sum())
        check_load_transfer(report, discrete, moved, self.rel_tol, name)
        return BlockSolution(bm, op, u, lam, report, discrete, shift)


def check_load_transfer(
    report: EquilibriumReport,
    discrete: np.ndarray,
    moved_moment: float,
    rel_tol: float = EQUILIBRIUM_REL_TOL,
    name: str = "block",
) -> None:
    """Raise unless the assembled FE load carries the resultant that was checked.

    The rigid-mode multipliers absorb whatever resultant the load vector has, so a load lost
    in assembly (a patch clipped, a point force dropped) would otherwise pass unseen.

    Parameters
    ----------
    report : EquilibriumReport
        The checked resultant (world frame, moment about the block centroid).
    discrete : (6,) float
        ``R^T f`` of the load vector, same frame and centre [N, N m].
    moved_moment : float
        Bound on the moment change from moving point forces onto the surface:
        projection shift x sum of their magnitudes [N m].
    rel_tol : float
        Largest accepted difference, relative to ``scale`` (force) and ``scale size`` (moment).
    name : str
        Used in the error message.

    Raises
    ------
    LoadTransferError
    """
    d_force = float(np.linalg.norm(discrete[:3] - report.force))
    d_moment = float(np.linalg.norm(discrete[3:] - report.moment))
    if d_force > rel_tol * report.scale or (
        d_moment > rel_tol * report.scale * report.size + moved_moment
    ):
        raise LoadTransferError(
            f"{name}: the assembled FE load differs from the checked loads by "
            f"{d_force:.3e} N and {d_moment:.3e} N m (load scale {report.scale:.3e} N, "
            f"tolerance {rel_tol:.1e}); load was lost or added in assembly"
        )
