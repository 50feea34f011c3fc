"""Tetrahedral meshes of convex blocks (gmsh), converted to scikit-fem, cached by shape.

A block is meshed once per *shape*: two blocks that are equal up to a rigid motion (rotation
and translation, no reflection) share one mesh, one stiffness matrix and one factorisation.
The mesh lives in the frame of the first block of that shape (the *reference* block); a
:class:`BlockMesh` carries the rigid motion ``x_world = R x_ref + t`` to its own block.

This is the only module of ``fem_check`` that handles scikit-fem's ``(3, n)`` arrays; the rest
of the package sees ``(n, 3)`` rows.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import combinations

import meshio
import numpy as np
import skfem
from skfem.io.meshio import from_meshio

from dem.geometry.polyhedron import ConvexBlock

log = logging.getLogger(__name__)

GMSH_TET4 = 4
GMSH_TET10 = 11
# gmsh orders the last two edge nodes of a 10-node tetrahedron (2-3), (1-3); VTK/meshio the
# other way round (gmsh manual, "Node ordering"; meshio's gmsh reader applies the same swap).
_GMSH_TO_VTK_TET10 = np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])
MATCH_REL_TOL = 1e-7
"""Tolerance of the rigid-motion shape match, relative to the block size."""


class MeshingError(ValueError):
    """gmsh could not build or mesh a block; the message names the block and the cause."""


def shortest_edge(block: ConvexBlock) -> float:
    """Length of the block's shortest edge [m]."""
    v = block.vertices
    return min(
        float(np.min(np.linalg.norm(v[np.roll(face, -1)] - v[face], axis=1)))
        for face in block.faces
    )


@dataclass(frozen=True, eq=False)
class MeshSettings:
    """How a block is meshed.

    Attributes
    ----------
    size : float
        Target edge length of the tetrahedra [m].
    order : int
        Geometric order of the tetrahedra: 1 (4 nodes, ``skfem.MeshTet1``) or 2 (10 nodes,
        ``skfem.MeshTet2``). Planar blocks are exact with order 1; the field order is chosen
        separately in :mod:`fem_check.elastic`.
    algorithm_3d : int
        gmsh ``Mesh.Algorithm3D`` (1 = Delaunay, deterministic on one thread).
    optimize : bool
        gmsh ``Mesh.Optimize`` (tetrahedron quality pass).
    """

    size: float
    order: int = 1
    algorithm_3d: int = 1
    optimize: bool = True

    def __post_init__(self):
        if not np.isfinite(self.size) or self.size <= 0:
            raise ValueError(f"mesh size must be finite and positive [m], got {self.size}")
        if self.order not in (1, 2):
            raise ValueError(f"mesh order must be 1 or 2, got {self.order}")


@dataclass(frozen=True, eq=False)
class TetMesh:
    """A tetrahedral mesh with one region tag per tetrahedron.

    Attributes
    ----------
    mesh : skfem.MeshTet1 or skfem.MeshTet2
        The scikit-fem mesh (its arrays are ``(3, n)``, skfem's layout).
    region : (n_tets,) int64
        Index of the input polyhedron that each tetrahedron fills.
    """

    mesh: skfem.Mesh
    region: np.ndarray

    @property
    def points(self) -> np.ndarray:
        """(n_vertices, 3) corner nodes [m] (the edge nodes of a MeshTet2 follow in ``mesh.p``)."""
        return np.ascontiguousarray(self.mesh.p[:, : self.mesh.nvertices].T)

    @property
    def tets(self) -> np.ndarray:
        """(n_tets, 4) int64 corner indices."""
        return np.ascontiguousarray(self.mesh.t.T).astype(np.int64)


def mesh_polyhedra(blocks: Sequence[ConvexBlock], settings: MeshSettings) -> TetMesh:
    """Mesh one or more convex blocks as one bonded continuum with gmsh.

    Touching faces of different blocks are fragmented (OpenCASCADE boolean) so that the mesh
    is conforming across them: the blocks are glued, as in a monolithic specimen.

    Parameters
    ----------
    blocks : sequence of ConvexBlock
        Vertices in [m]; blocks may touch but must not overlap.
    settings : MeshSettings

    Returns
    -------
    TetMesh
        ``region[k]`` is the index in ``blocks`` of the block that tetrahedron ``k`` fills.

    Notes
    -----
    gmsh is a process-wide singleton: it is initialised here if needed (and finalised again
    only in that case), with the terminal off, one thread and fixed algorithms so that the
    same input always gives the same mesh.
    """
    import gmsh

    if len(blocks) == 0:
        raise ValueError("mesh_polyhedra needs at least one block")
    owns = not gmsh.isInitialized()
    if owns:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        _set_options(gmsh, settings)
        gmsh.model.add(f"fem_check_{id(blocks)}")
        pieces = _fragmented_volumes(gmsh, blocks)
        gmsh.model.occ.synchronize()
        gmsh.model.mesh.generate(3)
        coords, conn, region = _read_tets(gmsh, pieces, settings.order)
    finally:
        gmsh.model.remove()
        if owns:
            gmsh.finalize()
    mesh = _used_nodes_mesh(coords, conn, settings.order)
    log.debug("meshed %d block(s): %d tets, h=%.3g m", len(blocks), mesh.t.shape[1], settings.size)
    return TetMesh(mesh, region)


def _set_options(gmsh, settings: MeshSettings) -> None:
    """Quiet, one thread, fixed algorithms (the same input gives the same mesh), the size and
    order of ``settings``."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MaxNumThreads3D", 1)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.Algorithm3D", settings.algorithm_3d)
    gmsh.option.setNumber("Mesh.Optimize", int(settings.optimize))
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", settings.size)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.ElementOrder", settings.order)
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)  # planar faces: straight edges


def _fragmented_volumes(gmsh, blocks: Sequence[ConvexBlock]) -> list[list[int]]:
    """Build every block as an OpenCASCADE volume and fragment touching faces so that the
    mesh conforms across them; returns the volume tags of each block's pieces."""
    labels = [f"block {i}" if len(blocks) > 1 else "the block" for i in range(len(blocks))]
    volumes = [_occ_volume(gmsh, b, label) for b, label in zip(blocks, labels, strict=True)]
    if len(volumes) == 1:
        return [volumes]
    _, out_map = gmsh.model.occ.fragment([(3, v) for v in volumes], [])
    return [[tag for dim, tag in m if dim == 3] for m in out_map]


def _read_tets(gmsh, pieces: list[list[int]], order: int):
    """The meshed nodes ``(n, 3)`` [m], tetrahedra ``(m, 4 or 10)`` (gmsh node order, rows of
    the nodes) and the block of each tetrahedron ``(m,)``."""
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = coords.reshape(-1, 3)
    index = np.full(int(node_tags.max()) + 1, -1, dtype=np.int64)
    index[node_tags.astype(np.int64)] = np.arange(len(node_tags))
    etype = GMSH_TET4 if order == 1 else GMSH_TET10
    n_nodes = 4 if order == 1 else 10
    cells, region = [], []
    for i_block, tags in enumerate(pieces):
        for tag in tags:
            types, _, elem_nodes = gmsh.model.mesh.getElements(3, tag)
            for t, en in zip(types, elem_nodes, strict=True):
                if t != etype:
                    raise RuntimeError(f"gmsh returned element type {t}, expected {etype}")
                conn = index[np.asarray(en, dtype=np.int64)].reshape(-1, n_nodes)
                cells.append(conn)
                region.append(np.full(len(conn), i_block, dtype=np.int64))
    return coords, np.concatenate(cells), np.concatenate(region)


def _used_nodes_mesh(coords: np.ndarray, conn: np.ndarray, order: int):
    """The skfem mesh of the tetrahedra ``conn`` over only the nodes they use."""
    used = np.unique(conn)
    remap = np.full(len(coords), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    conn = remap[conn]
    coords = coords[used]
    if order == 1:
        m = meshio.Mesh(coords, [("tetra", conn)])
    else:
        m = meshio.Mesh(coords, [("tetra10", conn[:, _GMSH_TO_VTK_TET10])])
    return from_meshio(m)


def _occ_volume(gmsh, block: ConvexBlock, label: str) -> int:
    """Build one convex block as an OpenCASCADE volume; returns its tag.

    Raises
    ------
    MeshingError
        gmsh refused the block (it raises a bare ``Exception``), naming it by ``label`` with
        its shortest edge: OpenCASCADE merges points closer than its tolerance (about
        1e-7 m, absolute), so a sliver or a block thinner than that cannot be built.
    """
    try:
        return _occ_faces_volume(gmsh, block)
    except Exception as exc:  # gmsh raises Exception, nothing narrower
        raise MeshingError(
            f"gmsh could not build {label} ({exc}): its shortest edge "
            f"{shortest_edge(block):.3g} m is at or below OpenCASCADE's tolerance of about "
            "1e-7 m (absolute), which merges its corners; a sliver that thin cannot be meshed"
        ) from exc


def _occ_faces_volume(gmsh, block: ConvexBlock) -> int:
    occ = gmsh.model.occ
    pts = [occ.addPoint(*map(float, v)) for v in block.vertices]
    lines: dict[tuple[int, int], int] = {}
    surfaces = []
    for face in block.faces:
        loop = []
        for a, b in zip(face, np.roll(face, -1), strict=True):
            key = (min(a, b), max(a, b))
            if key not in lines:
                lines[key] = occ.addLine(pts[key[0]], pts[key[1]])
            loop.append(lines[key] if a < b else -lines[key])
        surfaces.append(occ.addPlaneSurface([occ.addCurveLoop(loop)]))
    return occ.addVolume([occ.addSurfaceLoop(surfaces)])


# -- shapes up to a rigid motion ---------------------------------------------------------------
def shape_key(block: ConvexBlock, rel_tol: float = 1e-4) -> tuple:
    """A hashable summary that is equal for blocks equal up to a rigid motion.

    Sorted centroid-to-vertex distances (relative to the largest, rounded to ``rel_tol``) and
    face sizes. Equal keys are necessary, not sufficient (mirror images share a key):
    :func:`rigid_match` decides. A value falling on a rounding boundary only costs a second
    mesh of the same shape, never a wrong match.
    """
    d = np.linalg.norm(block.vertices - block.centroid, axis=1)
    d = np.sort(d) / d.max()
    sides = sorted(len(f) for f in block.faces)
    q = np.round(d / rel_tol).astype(np.int64)
    return (len(block.vertices), tuple(sides), tuple(q.tolist()))


def rigid_match(
    reference: ConvexBlock, other: ConvexBlock, rel_tol: float = MATCH_REL_TOL
) -> tuple[np.ndarray, np.ndarray] | None:
    """The rigid motion that carries ``reference`` onto ``other``, if there is one.

    Parameters
    ----------
    reference, other : ConvexBlock
    rel_tol : float
        Vertex match tolerance relative to the block size.

    Returns
    -------
    (R, t) or None
        ``R`` (3, 3) proper rotation and ``t`` (3,) [m] with
        ``other.vertices ~ reference.vertices @ R.T + t`` as sets; None if the blocks differ
        (different shape, or mirror images).
    """
    if len(reference.vertices) != len(other.vertices):
        return None
    tol = rel_tol * max(reference.size, other.size)
    a = reference.vertices - reference.centroid
    b = other.vertices - other.centroid
    da, db = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    if np.max(np.abs(np.sort(da) - np.sort(db))) > 10 * tol:
        return None
    # the best-conditioned triple of reference vertices spans space with the centroid
    triple = max(combinations(range(len(a)), 3), key=lambda ijk: abs(np.linalg.det(a[list(ijk)])))
    a3 = a[list(triple)]
    inv = np.linalg.inv(a3)
    cand = [np.flatnonzero(np.abs(db - da[i]) < 10 * tol) for i in triple]
    for i in cand[0]:
        for j in cand[1]:
            if (
                j == i
                or abs(np.linalg.norm(b[j] - b[i]) - np.linalg.norm(a3[1] - a3[0])) > 10 * tol
            ):
                continue
            for k in cand[2]:
                if k in (i, j):
                    continue
                rot = (inv @ b[[i, j, k]]).T  # rows: b = a @ R.T
                if np.linalg.norm(rot.T @ rot - np.eye(3)) > 1e-6 or np.linalg.det(rot) < 0:
                    continue
                mapped = a @ rot.T
                dist = np.linalg.norm(mapped[:, None, :] - b[None, :, :], axis=2)
                if np.all(dist.min(axis=1) < 10 * tol) and len(set(dist.argmin(axis=1))) == len(b):
                    # re-fit on all vertices (Kabsch) for a rotation exact to round-off
                    pairs = dist.argmin(axis=1)
                    u, _, vt = np.linalg.svd(a.T @ b[pairs])
                    s = np.diag([1.0, 1.0, np.sign(np.linalg.det(vt.T @ u.T))])
                    rot = vt.T @ s @ u.T
                    return rot, other.centroid - rot @ reference.centroid
    return None


@dataclass(frozen=True, eq=False)
class BlockMesh:
    """The mesh of one block: a shared reference mesh and the rigid motion to the block.

    Attributes
    ----------
    shape_id : int
        Index of the shape in its :class:`MeshCache` (blocks with equal ids share everything).
    reference : ConvexBlock
        The shape's reference block, in whose frame ``tet_mesh`` lies.
    tet_mesh : TetMesh
    rotation : (3, 3) float
        ``x_world = rotation @ x_ref + translation``.
    translation : (3,) float
        [m].
    block : ConvexBlock
        The block itself (world frame).
    """

    shape_id: int
    reference: ConvexBlock
    tet_mesh: TetMesh
    rotation: np.ndarray
    translation: np.ndarray
    block: ConvexBlock

    def to_reference(self, points: np.ndarray) -> np.ndarray:
        """(k, 3) world points [m] in the reference frame."""
        return (np.asarray(points, dtype=float) - self.translation) @ self.rotation

    def vector_to_reference(self, vectors: np.ndarray) -> np.ndarray:
        """(k, 3) world vectors in the reference frame (rotation only)."""
        return np.asarray(vectors, dtype=float) @ self.rotation

    def world_points(self) -> np.ndarray:
        """(n_vertices, 3) mesh corner nodes in the world frame [m]."""
        return self.tet_mesh.points @ self.rotation.T + self.translation


@dataclass(eq=False)
class MeshCache:
    """Meshes of block shapes, each meshed once; look blocks up with :meth:`get`.

    Attributes
    ----------
    settings : MeshSettings
    shapes : list of (ConvexBlock, TetMesh)
        Reference block and mesh of each shape met so far.
    """

    settings: MeshSettings
    shapes: list = field(default_factory=list)
    _by_key: dict = field(default_factory=dict)

    def get(self, block: ConvexBlock) -> BlockMesh:
        """The mesh of ``block``, meshing its shape on first sight."""
        key = shape_key(block)
        for shape_id in self._by_key.get(key, []):
            reference, tet_mesh = self.shapes[shape_id]
            match = rigid_match(reference, block)
            if match is not None:
                return BlockMesh(shape_id, reference, tet_mesh, match[0], match[1], block)
        tet_mesh = mesh_polyhedra([block], self.settings)
        self.shapes.append((block, tet_mesh))
        shape_id = len(self.shapes) - 1
        self._by_key.setdefault(key, []).append(shape_id)
        return BlockMesh(shape_id, block, tet_mesh, np.eye(3), np.zeros(3), block)
