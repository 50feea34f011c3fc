"""Convex polyhedral blocks: planar faces from a convex hull, exact mass properties.

A block is the convex hull of its vertices. Coplanar hull triangles are merged into one planar
polygon per face, ordered counter-clockwise seen from outside, so that every face carries its
outward unit normal ``n`` and plane offset ``d`` (points ``x`` of the face satisfy ``n . x = d``).

The hull and the face planes are computed about a local origin (the vertex mean), so a block far
from the origin (national-grid coordinates, ``x ~ 4e6 m``) gets the faces and mass properties it
has at the origin: products of large coordinates would lose the digits that separate its corners.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.spatial import ConvexHull, QhullError

# Relative tolerances, scaled by the block's bounding-box diagonal.
PLANE_TOL = 1e-9
"""Distance tolerance for a point on a face plane, relative to the block size."""
VOLUME_TOL = 1e-12
"""Smallest volume accepted, relative to the cube of the block size."""
ROUNDOFF = 64 * np.finfo(np.float64).eps
"""Coordinates ``x`` are known to ``ROUNDOFF * max |x|`` (a few float64 spacings): distance
tolerances never go below this, or the corners of a face far from the origin (rounded to
~5e-10 m at 4e6 m) would no longer lie on a common plane."""


def plane_tolerance(points: np.ndarray, size: float) -> float:
    """Distance within which a point lies on a plane [m].

    ``PLANE_TOL * size`` for a block of bounding-box diagonal ``size`` [m], but at least the
    resolution ``ROUNDOFF * max |x|`` of the coordinates ``points`` (n, 3) [m].
    """
    return max(PLANE_TOL * size, ROUNDOFF * float(np.max(np.abs(points))))


class DegenerateFaceError(ValueError):
    """A face of a block has fewer than 3 corners on its plane: the hull's facets could not be
    merged into planar faces within the tolerance."""


@dataclass(frozen=True, eq=False)
class ConvexBlock:
    """A convex polyhedron with planar polygonal faces.

    Attributes
    ----------
    vertices : (n_vert, 3) float
        Corner points [m].
    faces : tuple of (k_f,) int arrays
        Vertex indices of each face, counter-clockwise seen from outside.
    normals : (n_faces, 3) float
        Outward unit normals.
    offsets : (n_faces,) float
        Plane offsets ``d`` with ``n . x = d`` on the face [m].
    volume : float
        [m^3].
    centroid : (3,) float
        [m].
    inertia : (3, 3) float
        Inertia tensor about the centroid per unit density [m^5] (multiply by density [kg/m^3]).
    """

    vertices: np.ndarray
    faces: tuple[np.ndarray, ...]
    normals: np.ndarray
    offsets: np.ndarray
    volume: float
    centroid: np.ndarray
    inertia: np.ndarray

    @property
    def size(self) -> float:
        """Diagonal of the axis-aligned bounding box [m]."""
        return float(np.linalg.norm(np.ptp(self.vertices, axis=0)))

    @cached_property
    def thickness(self) -> float:
        """Smallest width of the block across one of its faces [m]: the largest depth of a
        corner below each face plane, minimised over the faces (a plate's thickness)."""
        depth = self.offsets[None, :] - self.vertices @ self.normals.T
        return float(np.min(np.max(depth, axis=0)))

    @cached_property
    def edges(self) -> np.ndarray:
        """(n_edges, 2) int vertex index pairs, each edge once."""
        pairs = np.concatenate([np.column_stack([f, np.roll(f, -1)]) for f in self.faces])
        return np.unique(np.sort(pairs, axis=1), axis=0)

    def signed_distance(self, points: np.ndarray) -> np.ndarray:
        """Largest face-plane distance ``max_f (n_f . x - d_f)`` of each point [m].

        Negative inside, zero on the surface, positive outside. Exact inside and on the
        surface; outside it is a lower bound on the Euclidean distance (exact in face regions).
        """
        pts = np.atleast_2d(points)
        return np.max(pts @ self.normals.T - self.offsets, axis=1)

    def transformed(self, rotation: np.ndarray, translation: np.ndarray) -> ConvexBlock:
        """The block moved rigidly, ``x -> R x + t`` (value semantics: a new block)."""
        rotation = np.asarray(rotation, dtype=float)
        translation = np.asarray(translation, dtype=float)
        return ConvexBlock(
            vertices=self.vertices @ rotation.T + translation,
            faces=self.faces,
            normals=self.normals @ rotation.T,
            offsets=self.offsets + self.normals @ rotation.T @ translation,
            volume=self.volume,
            centroid=rotation @ self.centroid + translation,
            inertia=rotation @ self.inertia @ rotation.T,
        )


def convex_block(points: np.ndarray, *, exact: bool = False) -> ConvexBlock:
    """Build a convex block as the convex hull of ``points``.

    Parameters
    ----------
    points : (n, 3) array_like
        Vertex coordinates [m], n >= 4.
    exact : bool
        If True, every point must be a corner of the hull (the caller says the points *are*
        the polyhedron); a point inside the hull, on a face or edge, or repeated raises.

    Raises
    ------
    ValueError
        Fewer than 4 points, NaN or inf, all points coplanar, (near) zero volume, or, with
        ``exact``, points not in convex position.
    DegenerateFaceError
        A face with fewer than 3 corners (a ValueError).
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"block vertices must have shape (n, 3), got {pts.shape}")
    if pts.shape[0] < 4:
        raise ValueError(f"a block needs at least 4 vertices, got {pts.shape[0]}")
    if not np.all(np.isfinite(pts)):
        raise ValueError("block vertices contain NaN or inf")
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    if size == 0.0:
        raise ValueError("block vertices are all the same point (zero volume)")
    # Everything below works on coordinates about a local origin (module notes); the
    # differences of nearby large coordinates are exact.
    origin = pts.mean(axis=0)
    local = pts - origin
    # Coplanarity test before qhull, which would otherwise fail with an opaque message.
    singular = np.linalg.svd(local, compute_uv=False)
    if singular[2] <= PLANE_TOL * singular[0]:
        raise ValueError("block vertices are coplanar (zero volume)")
    try:
        hull = ConvexHull(local)
    except QhullError as exc:
        raise ValueError(f"convex hull of the block vertices failed: {exc}") from exc
    if hull.volume <= VOLUME_TOL * size**3:
        raise ValueError(f"block volume {hull.volume:.3e} m^3 is zero or negative")
    if exact and len(hull.vertices) != len(pts):
        interior = sorted(set(range(len(pts))) - set(hull.vertices.tolist()))
        raise ValueError(
            f"block vertices are not in convex position: points {interior} are inside the hull, "
            "on a face or edge, or repeated"
        )

    corner_ids = np.sort(hull.vertices)
    normals, offsets, faces = _merge_coplanar_facets(
        hull.equations, local[hull.simplices], local[corner_ids], plane_tolerance(pts, size)
    )
    vertices = pts[corner_ids]
    volume, centroid, inertia = mass_properties(vertices, faces)
    return ConvexBlock(
        vertices, faces, normals, offsets + normals @ origin, volume, centroid, inertia
    )


def _merge_coplanar_facets(
    equations: np.ndarray, triangles: np.ndarray, vertices: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...]]:
    """Group qhull facets into planar faces with ordered vertices.

    Parameters
    ----------
    equations : (n_facets, 4) float
        qhull facet planes ``n . x + c = 0``.
    triangles : (n_facets, 3, 3) float
        Corners of each facet [m].
    vertices : (n_vert, 3) float
        Hull corners [m].
    tol : float
        A corner within ``tol`` of a plane lies on it [m].

    Returns
    -------
    normals (n_faces, 3), offsets (n_faces,) [m], faces (tuple of (k_f,) int arrays).

    Raises
    ------
    DegenerateFaceError
        A face with fewer than 3 corners within ``tol`` of its plane.
    """
    # qhull splits a planar face into triangles with (nearly) the same plane; a facet whose
    # corners all lie on the plane of a face already kept adds nothing. Largest facets first,
    # so that a sliver along an edge never becomes a face of its own.
    area = np.linalg.norm(
        np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]), axis=1
    )
    normals: list[np.ndarray] = []
    offsets: list[float] = []
    for k in np.argsort(-area, kind="stable"):
        scale = np.linalg.norm(equations[k, :3])
        n, d = equations[k, :3] / scale, -equations[k, 3] / scale
        if any(
            np.all(np.abs(triangles[k] @ nk - dk) < tol)
            for nk, dk in zip(normals, offsets, strict=True)
        ):
            continue
        normals.append(n)
        offsets.append(d)
    normals_arr = np.array(normals)
    offsets_arr = np.array(offsets)
    faces = []
    for n, d in zip(normals_arr, offsets_arr, strict=True):
        on_plane = np.flatnonzero(np.abs(vertices @ n - d) < tol)
        if len(on_plane) < 3:
            raise DegenerateFaceError(
                f"degenerate block face: {len(on_plane)} corners lie on the plane with normal "
                f"{np.array2string(n, precision=6)}"
            )
        faces.append(_order_ccw(vertices, on_plane, n))
    return normals_arr, offsets_arr, tuple(faces)


def _order_ccw(vertices: np.ndarray, ids: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Order the corner ids of a convex planar face counter-clockwise about ``normal``."""
    t1, t2 = plane_basis(normal)
    rel = vertices[ids] - vertices[ids].mean(axis=0)
    angle = np.arctan2(rel @ t2, rel @ t1)
    return ids[np.argsort(angle)].astype(np.int64)


def plane_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents ``t1, t2`` with ``(n, t1, t2)`` right-handed.

    ``t1`` is the projection of the global z axis onto the plane (for vertical planes, so that
    ``t1`` points up) or, for planes closer to horizontal, of the global x axis.
    """
    n = np.asarray(normal, dtype=float)
    ref = np.array([0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    t1 = ref - np.dot(ref, n) * n
    t1 /= math.sqrt(np.dot(t1, t1))
    # n x t1, written out: np.cross costs ten times more on one pair of 3-vectors
    t2 = np.array(
        [n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]]
    )
    return t1, t2


def mass_properties(
    vertices: np.ndarray, faces: tuple[np.ndarray, ...]
) -> tuple[float, np.ndarray, np.ndarray]:
    """Exact volume, centroid and inertia tensor (unit density) of a closed polyhedron.

    Parameters
    ----------
    vertices : (n, 3) float
        [m].
    faces : tuple of int arrays
        Planar faces, counter-clockwise seen from outside.

    Returns
    -------
    volume : float
        [m^3].
    centroid : (3,) float
        [m].
    inertia : (3, 3) float
        ``tr(C) I - C`` with ``C = int (x - c)(x - c)^T dV`` [m^5].

    Notes
    -----
    Each face is fanned into triangles, each triangle coned to a reference point ``o`` (the
    vertex mean) into a tetrahedron with signed volume ``V = det[a, b, c] / 6``. For a
    tetrahedron with corners ``v_0..v_3``,
    :math:`\\int x x^T dV = \\frac{V}{20}(\\sum_k v_k v_k^T + s s^T)`, :math:`s = \\sum_k v_k`
    (Tonon 2004). Shifting to ``o`` first keeps round-off small for blocks far from the origin.
    """
    origin = vertices.mean(axis=0)
    v = vertices - origin
    tri = np.array([(f[0], f[i], f[i + 1]) for f in faces for i in range(1, len(f) - 1)])
    a, b, c = v[tri[:, 0]], v[tri[:, 1]], v[tri[:, 2]]
    vol_t = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
    volume = float(vol_t.sum())
    s = a + b + c  # the fourth corner is the origin
    centroid_rel = (vol_t[:, None] * s).sum(axis=0) / 4.0 / volume
    outer = (
        np.einsum("ti,tj->tij", a, a)
        + np.einsum("ti,tj->tij", b, b)
        + np.einsum("ti,tj->tij", c, c)
        + np.einsum("ti,tj->tij", s, s)
    )
    second = np.einsum("t,tij->ij", vol_t / 20.0, outer)
    cov = second - volume * np.outer(centroid_rel, centroid_rel)
    inertia = np.trace(cov) * np.eye(3) - cov
    return volume, centroid_rel + origin, inertia


def penetration_depth(a: ConvexBlock, b: ConvexBlock, tol: float = 0.0) -> float:
    """Depth of interpenetration of two convex blocks by the separating axis theorem [m].

    The smallest overlap of the two blocks' projections over all candidate axes (face
    normals of both, cross products of edge directions). At most ``tol`` when the blocks are
    separated or merely touch: once a face normal shows an overlap of at most ``tol`` the
    edge axes are skipped, and that overlap is returned.
    """
    # projections about a point of the pair, not about the global origin (module notes)
    va = a.vertices - a.centroid
    vb = b.vertices - a.centroid
    face_axes = np.concatenate([a.normals, b.normals])
    depth = _smallest_overlap(va, vb, face_axes)
    if depth <= tol:
        return depth
    edges_a = va[a.edges[:, 1]] - va[a.edges[:, 0]]
    edges_b = vb[b.edges[:, 1]] - vb[b.edges[:, 0]]
    cross = np.cross(edges_a[:, None, :], edges_b[None, :, :]).reshape(-1, 3)
    norm = np.linalg.norm(cross, axis=1)
    scale = np.linalg.norm(edges_a, axis=1).max() * np.linalg.norm(edges_b, axis=1).max()
    keep = norm > 1e-9 * scale
    if not keep.any():
        return depth
    return min(depth, _smallest_overlap(va, vb, cross[keep] / norm[keep, None]))


def _smallest_overlap(va: np.ndarray, vb: np.ndarray, axes: np.ndarray) -> float:
    pa = va @ axes.T
    pb = vb @ axes.T
    overlap = np.minimum(pa.max(axis=0) - pb.min(axis=0), pb.max(axis=0) - pa.min(axis=0))
    return float(overlap.min())


def clip_halfspace(block: ConvexBlock, normal: np.ndarray, offset: float) -> ConvexBlock | None:
    """The part of a block with ``normal . x <= offset``, or None if nothing of volume is left.

    The kept corners plus the points where edges cross the plane span the clipped block,
    which is convex as the intersection of two convex sets.
    """
    n = np.asarray(normal, dtype=float)
    dist = block.vertices @ n - offset
    tol = plane_tolerance(block.vertices, block.size)
    if np.all(dist <= tol):
        return block
    if np.all(dist >= -tol):
        return None
    keep = [block.vertices[dist <= tol]]
    i, j = block.edges.T
    cross = (dist[i] < -tol) & (dist[j] > tol) | (dist[i] > tol) & (dist[j] < -tol)
    w = dist[i[cross]] / (dist[i[cross]] - dist[j[cross]])
    keep.append(
        block.vertices[i[cross]]
        + w[:, None] * (block.vertices[j[cross]] - block.vertices[i[cross]])
    )
    points = np.concatenate(keep)
    # drop points repeated by the crossing (a corner lying on the plane)
    points = points[
        np.unique(np.round(points / tol).astype(np.int64), axis=0, return_index=True)[1]
    ]
    try:
        return convex_block(points)
    except DegenerateFaceError:
        raise
    except ValueError:
        return None  # a sliver without volume
