"""Interfaces between convex blocks, found from geometry.

Two blocks share an interface where a face of one and a face of the other lie in the same plane
with opposite outward normals and their polygons overlap with positive area. The interface is
the exact intersection of the two face polygons.

Blocks that touch only along an edge or at a corner share no polygon, so no interface: the
face-interface models (the static DEM, the limit analysis) pass no force between them, while
the explicit DEM's nodes do see such contacts. They are listed in
:attr:`Interfaces.edge_contacts`, which those models log as a warning, so that a scene whose
load path runs through one is not analysed without it unknowingly.
"""

from __future__ import annotations

import logging
import weakref
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from dem.geometry.clipping import clip_convex_polygons, polygon_properties
from dem.geometry.polyhedron import ROUNDOFF, ConvexBlock, penetration_depth, plane_basis

logger = logging.getLogger(__name__)

REL_TOL = 1e-6
"""Default tolerance for coplanarity and overlap, relative to the median block size."""
THIN_FRACTION = 1e-2
"""The tolerance never exceeds this fraction of the thinnest block's thickness, so that a very
thin block (a plate, a membrane) is a real block: no contact is found through it."""


class OverlapError(ValueError):
    """Blocks interpenetrate in the input geometry.

    Attributes
    ----------
    overlaps : list of (int, int, float)
        ``(i_block, j_block, depth [m])`` for every overlapping pair.
    """

    def __init__(self, overlaps: list[tuple[int, int, float]]):
        self.overlaps = overlaps
        shown = ", ".join(f"blocks {i} and {j} by {d:.3e} m" for i, j, d in overlaps[:5])
        more = f" (and {len(overlaps) - 5} more pairs)" if len(overlaps) > 5 else ""
        super().__init__(f"{len(overlaps)} pairs of blocks overlap: {shown}{more}")


@dataclass(frozen=True, eq=False)
class Interfaces:
    """Contact interfaces of an assembly, as struct-of-arrays.

    The normal ``n`` is the outward normal of ``block_a``'s face (it points from block a into
    block b); ``block_a < block_b``. Local coordinates ``y1, y2`` along ``t1, t2`` are measured
    from the interface centroid.

    Attributes
    ----------
    block_a, block_b : (m,) int64
        The two blocks.
    face_a, face_b : (m,) int64
        Face index within each block.
    poly_ptr : (m + 1,) int64
        Interface ``k`` has corners ``poly_points[poly_ptr[k]:poly_ptr[k + 1]]``.
    poly_points : (p, 3) float
        Corners of the contact polygons, counter-clockwise about ``n`` [m].
    area : (m,) float
        [m^2].
    centroid : (m, 3) float
        [m].
    frame : (m, 3, 3) float
        Rows ``n, t1, t2`` (right-handed).
    second_moments : (m, 3) float
        ``J11 = int y1^2 dA``, ``J22 = int y2^2 dA``, ``J12 = int y1 y2 dA`` [m^4]; the polar
        moment is ``J11 + J22``.
    edge_contacts : (k, 2) int64
        Pairs of blocks (``i < j``) that touch, within the tolerance, without sharing a contact
        polygon: along an edge, at a corner, or over a sliver thinner than the tolerance. No
        interface carries force between them (module notes).
    """

    block_a: np.ndarray
    block_b: np.ndarray
    face_a: np.ndarray
    face_b: np.ndarray
    poly_ptr: np.ndarray
    poly_points: np.ndarray
    area: np.ndarray
    centroid: np.ndarray
    frame: np.ndarray
    second_moments: np.ndarray
    edge_contacts: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))

    def warn_edge_contacts(self) -> None:
        """Log :attr:`edge_contacts` as a warning (once per object): called by the models
        that carry force through interfaces only."""
        pairs = self.edge_contacts
        if len(pairs) == 0 or self in _WARNED:
            return
        _WARNED.add(self)
        logger.warning(
            "%d pair(s) of blocks touch only along an edge or at a corner (blocks %s): no "
            "interface carries force between them in the static DEM and the limit analysis",
            len(pairs),
            pair_list(pairs),
        )

    @property
    def n_interfaces(self) -> int:
        return len(self.area)

    @property
    def polar_moment(self) -> np.ndarray:
        """(m,) polar second moment about the centroid [m^4]."""
        return self.second_moments[:, 0] + self.second_moments[:, 1]

    def polygon(self, k: int) -> np.ndarray:
        """(n_k, 3) corners of interface ``k`` [m]."""
        return self.poly_points[self.poly_ptr[k] : self.poly_ptr[k + 1]]

    def local_polygon(self, k: int) -> np.ndarray:
        """(n_k, 2) corners of interface ``k`` in ``(y1, y2)`` about its centroid [m]."""
        rel = self.polygon(k) - self.centroid[k]
        return rel @ self.frame[k, 1:].T


_WARNED: weakref.WeakSet[Interfaces] = weakref.WeakSet()


def pair_list(pairs, shown: int = 8) -> str:
    """``"0-1, 1-3 and 12 more"``: the first ``shown`` block pairs of ``pairs`` (k, 2)."""
    text = ", ".join(f"{i}-{j}" for i, j in pairs[:shown])
    return text + (f" and {len(pairs) - shown} more" if len(pairs) > shown else "")


def bounding_boxes(blocks: Sequence[ConvexBlock]) -> tuple[np.ndarray, np.ndarray]:
    """(n, 3) lower and upper corners of each block's axis-aligned box [m]."""
    lo = np.array([b.vertices.min(axis=0) for b in blocks])
    hi = np.array([b.vertices.max(axis=0) for b in blocks])
    return lo, hi


def candidate_pairs(lo: np.ndarray, hi: np.ndarray, margin: float) -> np.ndarray:
    """Pairs of boxes that overlap after growing each by ``margin`` (sort and sweep).

    Sorting by the lower x bound and scanning forward costs ``O(n log n + k)`` for ``k``
    pairs whose x ranges overlap.

    Returns
    -------
    (k, 2) int64
        ``i < j`` for each pair.
    """
    lo = lo - margin
    hi = hi + margin
    order = np.argsort(lo[:, 0], kind="stable")
    lo_x = lo[order, 0]
    ends = np.searchsorted(lo_x, hi[order, 0], side="right")
    pairs = []
    for pos in range(len(order)):
        others = order[pos + 1 : ends[pos]]
        if len(others) == 0:
            continue
        i = order[pos]
        hit = np.all((lo[others, 1:] <= hi[i, 1:]) & (hi[others, 1:] >= lo[i, 1:]), axis=1)
        for j in others[hit]:
            pairs.append((min(i, j), max(i, j)))
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    return np.array(sorted(pairs), dtype=np.int64)


def find_interfaces(
    blocks: Sequence[ConvexBlock], rel_tol: float = REL_TOL, check_overlaps: bool = True
) -> Interfaces:
    """Find every face-to-face interface of a set of convex blocks.

    Parameters
    ----------
    blocks : sequence of ConvexBlock
    rel_tol : float
        Tolerance relative to the median block size: faces closer than this to a common plane
        are coplanar, polygons of smaller area than ``(rel_tol * size)^2`` are dropped,
        interpenetration deeper than this is an error. The tolerance is at most
        :data:`THIN_FRACTION` times the thickness of the thinnest block, and at least the
        resolution ``ROUNDOFF * max |x|`` of the coordinates
        (:data:`dem.geometry.polyhedron.ROUNDOFF`).
    check_overlaps : bool
        Test every candidate pair for interpenetration (separating axis theorem).

    Raises
    ------
    OverlapError
        If blocks interpenetrate by more than the tolerance; it lists the pairs and depths.
    """
    if len(blocks) == 0:
        raise ValueError("an assembly needs at least one block")
    if not 0 < rel_tol < 1:
        raise ValueError(f"rel_tol must lie in (0, 1), got {rel_tol}")
    size = float(np.median([b.size for b in blocks]))
    # A gap thinner than the tolerance counts as contact: a gap that may hold a thin block
    # (here or between any other pair) must not, so the thinnest block caps the tolerance.
    thinnest = min(b.thickness for b in blocks)
    lo, hi = bounding_boxes(blocks)
    # but no tolerance is finer than the coordinates themselves far from the origin
    resolution = ROUNDOFF * float(max(np.abs(lo).max(), np.abs(hi).max()))
    tol = max(min(rel_tol * size, THIN_FRACTION * thinnest), resolution)
    pairs = candidate_pairs(lo, hi, tol)

    rows: list[tuple] = []
    overlaps: list[tuple[int, int, float]] = []
    edge_contacts: list[tuple[int, int]] = []
    for i, j in pairs:
        a, b = blocks[i], blocks[j]
        if check_overlaps:
            depth = penetration_depth(a, b, tol)
            if depth > tol:
                overlaps.append((int(i), int(j), depth))
                continue
        dots = a.normals @ b.normals.T
        # plane offsets about a point of the pair: measured from the global origin, a normal
        # off by round-off (1e-9) moves a plane at 4e6 m by millimetres
        local = a.centroid
        gap = np.abs(
            (a.offsets - a.normals @ local)[:, None] + (b.offsets - b.normals @ local)[None, :]
        )
        found = len(rows)
        for fa, fb in zip(*np.nonzero((dots < -1.0 + rel_tol) & (gap < tol)), strict=True):
            row = _face_pair_interface(a, b, fa, fb, tol)
            if row is not None:
                rows.append((i, j, fa, fb, *row))
        # every separating axis (no early exit): the pair touches if none parts it by > tol
        if len(rows) == found and penetration_depth(a, b, -np.inf) >= -tol:
            edge_contacts.append((int(i), int(j)))
    if overlaps:
        raise OverlapError(overlaps)
    return _pack(rows, np.array(edge_contacts, dtype=np.int64).reshape(-1, 2))


def _face_pair_interface(
    a: ConvexBlock, b: ConvexBlock, fa: int, fb: int, tol: float
) -> tuple | None:
    """Polygon, area, centroid, frame and second moments of face ``fa`` of a against ``fb`` of b."""
    n = a.normals[fa]
    t1, t2 = plane_basis(n)
    # in-plane coordinates about a's face centre, projected on the plane (not about the
    # foot of the normal from the global origin: they would be as large as the coordinates)
    centre = a.vertices[a.faces[fa]].mean(axis=0)
    origin = centre - (centre @ n - a.offsets[fa]) * n
    basis = np.stack([t1, t2])
    poly_a = (a.vertices[a.faces[fa]] - origin) @ basis.T
    # b's face is counter-clockwise about -n, hence clockwise in a's basis: reverse it.
    poly_b = ((b.vertices[b.faces[fb]] - origin) @ basis.T)[::-1]
    poly = clip_convex_polygons(poly_a, poly_b, tol)
    if len(poly) < 3:
        return None
    area, centroid_2d, moments = polygon_properties(poly)
    if area <= tol * tol:
        return None
    turn = _rectangle_turn(poly, area)
    if turn is not None:
        basis, poly = turn @ basis, poly @ turn.T
        area, centroid_2d, moments = polygon_properties(poly)
    points = origin + poly @ basis
    centroid = origin + centroid_2d @ basis
    return points, area, centroid, np.stack([n, *basis]), moments


def _rectangle_turn(poly: np.ndarray, area: float, rel_tol: float = 1e-6) -> np.ndarray | None:
    """The rotation (2, 2) that lays ``t1, t2`` along the sides of a rectangular contact whose
    sides are not along them, else None.

    The frame follows the global axes (:func:`plane_basis`), so the joints of a wall built
    along a diagonal are turned rectangles in it; the laws that take a rectangle's sides along
    ``t1, t2`` (the fibre grid with springs on the edges, the resultant law's reduced
    rectangle) would otherwise work on its bounding box.
    """
    size = np.ptp(poly, axis=0)
    if abs(size[0] * size[1] - area) <= rel_tol * area:
        return None  # along the axes already, or no rectangle
    edge = np.roll(poly, -1, axis=0) - poly
    length = np.hypot(edge[:, 0], edge[:, 1])
    # t1 along a longest side; of the sides equally long (the two opposite ones, or all four
    # of a square) the one nearest the old t1, pointing along it, so that round-off (the
    # scene's placement) does not pick the frame
    longest = length >= (1.0 - rel_tol) * length.max()
    sides = edge[longest] / length[longest, None]
    u = sides[np.argmax(np.abs(sides[:, 0]))]
    u = u if u[0] > 0 else -u
    turn = np.array([[u[0], u[1]], [-u[1], u[0]]])  # rows: the new t1, t2 in (t1, t2)
    side = np.ptp(poly @ turn.T, axis=0)
    return turn if abs(side[0] * side[1] - area) <= rel_tol * area else None


def _pack(rows: list[tuple], edge_contacts: np.ndarray) -> Interfaces:
    m = len(rows)
    if m == 0:
        empty_i = np.zeros(0, dtype=np.int64)
        return Interfaces(
            empty_i,
            empty_i,
            empty_i,
            empty_i,
            np.zeros(1, dtype=np.int64),
            np.zeros((0, 3)),
            np.zeros(0),
            np.zeros((0, 3)),
            np.zeros((0, 3, 3)),
            np.zeros((0, 3)),
            edge_contacts,
        )
    counts = np.array([len(r[4]) for r in rows])
    return Interfaces(
        block_a=np.array([r[0] for r in rows], dtype=np.int64),
        block_b=np.array([r[1] for r in rows], dtype=np.int64),
        face_a=np.array([r[2] for r in rows], dtype=np.int64),
        face_b=np.array([r[3] for r in rows], dtype=np.int64),
        poly_ptr=np.concatenate([[0], np.cumsum(counts)]).astype(np.int64),
        poly_points=np.concatenate([r[4] for r in rows]),
        area=np.array([r[5] for r in rows]),
        centroid=np.array([r[6] for r in rows]),
        frame=np.array([r[7] for r in rows]),
        second_moments=np.array([r[8] for r in rows]),
        edge_contacts=edge_contacts,
    )
