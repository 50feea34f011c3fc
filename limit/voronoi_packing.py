"""2D jammed packings of convex cells: Voronoi tessellations of a rectangle and brick walls.

A :class:`Packing` is a set of convex polygons that tile a domain. Each cell boundary is split
into *facets*: maximal segments that touch exactly one neighbour (an internal edge) or nothing
(a boundary edge). Running-bond walls have T-junctions, so a brick side can carry several facets.

Builders (all lengths in [m]):

- :func:`voronoi_packing`: ``n_cells`` seeds drawn uniformly in a rectangle from
  ``numpy.random.default_rng(seed)``, Voronoi cells clipped to the rectangle (seed 003, Sec. 2.1).
- :func:`voronoi_packing_from_seeds`: the same from given seed points (verification meshes).
- :func:`brick_wall_packing`: running-bond wall of rectangular bricks (seed 003, Sec. 4.4).
- :func:`packing_from_polygons`: any user list of convex polygons.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy.spatial import Voronoi, cKDTree

logger = logging.getLogger(__name__)

#: Default relative tolerance (times the domain size) for matching collinear cell sides.
GEOMETRY_RTOL = 1e-9


@dataclass(frozen=True)
class Packing:
    """Convex cells tiling a 2D domain, with their internal and boundary facets.

    Attributes
    ----------
    cell_ptr : ndarray of int64, shape (n_cells + 1,)
        CSR offsets into ``cell_xy`` / ``facet_edge``.
    cell_xy : ndarray of float64, shape (n_facets, 2)
        Polygon vertices of every cell, counter-clockwise [m]. Facet ``k`` of cell ``c`` runs from
        ``cell_xy[cell_ptr[c] + k]`` to the next vertex of the same cell (cyclically). T-junction
        points are included as vertices.
    facet_edge : ndarray of int64, shape (n_facets,)
        ``e >= 0``: the facet is internal edge ``e``; ``-1 - b``: the facet is boundary edge ``b``.
    centres : ndarray of float64, shape (n_cells, 2)
        Cell centres [m]: Voronoi seeds, or centroids for brick walls. Used to triangulate the
        cells (seed 003, Sec. 3.1); each centre lies strictly inside its cell.
    edge_cells : ndarray of int64, shape (n_edges, 2)
        The two cells ``(a, b)`` of each internal edge, ``a < b``.
    edge_xy : ndarray of float64, shape (n_edges, 2, 2)
        End points of each internal edge [m].
    edge_normal : ndarray of float64, shape (n_edges, 2)
        Unit normal of each internal edge, pointing from cell ``a`` into cell ``b``.
    edge_length : ndarray of float64, shape (n_edges,)
        Length of each internal edge [m].
    bnd_cell : ndarray of int64, shape (n_bnd,)
        The cell owning each boundary edge.
    bnd_xy : ndarray of float64, shape (n_bnd, 2, 2)
        End points of each boundary edge [m].
    bnd_normal : ndarray of float64, shape (n_bnd, 2)
        Outward unit normal of each boundary edge.
    bnd_length : ndarray of float64, shape (n_bnd,)
        Length of each boundary edge [m].
    """

    cell_ptr: np.ndarray
    cell_xy: np.ndarray
    facet_edge: np.ndarray
    centres: np.ndarray
    edge_cells: np.ndarray
    edge_xy: np.ndarray
    edge_normal: np.ndarray
    edge_length: np.ndarray
    bnd_cell: np.ndarray
    bnd_xy: np.ndarray
    bnd_normal: np.ndarray
    bnd_length: np.ndarray

    @property
    def n_cells(self) -> int:
        """Number of cells."""
        return len(self.cell_ptr) - 1

    @property
    def n_edges(self) -> int:
        """Number of internal edges."""
        return len(self.edge_length)

    @property
    def n_bnd(self) -> int:
        """Number of boundary edges."""
        return len(self.bnd_length)

    @property
    def edge_tangent(self) -> np.ndarray:
        """Internal-edge unit tangent, the normal turned by +90 degrees, shape (n_edges, 2)."""
        return np.stack([-self.edge_normal[:, 1], self.edge_normal[:, 0]], axis=1)

    @property
    def edge_midpoint(self) -> np.ndarray:
        """Midpoint of each internal edge [m], shape (n_edges, 2)."""
        return self.edge_xy.mean(axis=1)

    @property
    def bnd_midpoint(self) -> np.ndarray:
        """Midpoint of each boundary edge [m], shape (n_bnd, 2)."""
        return self.bnd_xy.mean(axis=1)

    def polygon(self, i_cell: int) -> np.ndarray:
        """Vertices of cell ``i_cell``, counter-clockwise [m], shape (m, 2)."""
        return self.cell_xy[self.cell_ptr[i_cell] : self.cell_ptr[i_cell + 1]]

    @property
    def cell_area(self) -> np.ndarray:
        """Area of every cell [m^2], shape (n_cells,)."""
        return np.array([_signed_area(self.polygon(c)) for c in range(self.n_cells)])

    @property
    def bbox(self) -> tuple[float, float, float, float]:
        """``(x_min, y_min, x_max, y_max)`` of the packing [m]."""
        lo = self.cell_xy.min(axis=0)
        hi = self.cell_xy.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _clip_convex(poly: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Sutherland-Hodgman clipping of a convex polygon (m, 2) to the box ``[lo, hi]``."""
    out = poly
    # each half plane: sign * (x[axis] - bound) <= 0
    for axis, bound, sign in ((0, lo[0], -1.0), (0, hi[0], 1.0), (1, lo[1], -1.0), (1, hi[1], 1.0)):
        if len(out) == 0:
            break
        dist = sign * (out[:, axis] - bound)
        nxt = np.roll(out, -1, axis=0)
        dist_nxt = np.roll(dist, -1)
        pts = []
        for p, q, dp, dq in zip(out, nxt, dist, dist_nxt, strict=True):
            if dp <= 0.0:
                pts.append(p)
            if (dp < 0.0 < dq) or (dq < 0.0 < dp):
                pts.append(p + (q - p) * (dp / (dp - dq)))
        out = np.array(pts).reshape(-1, 2)
    return out


def _dedupe_polygon(poly: np.ndarray, tol: float) -> np.ndarray:
    """Drop repeated and collinear vertices of a convex polygon."""
    keep = np.linalg.norm(poly - np.roll(poly, -1, axis=0), axis=1) > tol
    poly = poly[keep]
    prev, nxt = np.roll(poly, 1, axis=0), np.roll(poly, -1, axis=0)
    a, b = poly - prev, nxt - poly
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    scale = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    return poly[np.abs(cross) > 1e-12 * scale]


def _check_rectangle(width: float, height: float) -> None:
    for name, value in (("width", width), ("height", height)):
        if not (np.isfinite(value) and value > 0.0):
            raise ValueError(f"rectangle {name} must be a positive finite length [m], got {value}")


def voronoi_packing_from_seeds(seeds: np.ndarray, width: float, height: float) -> Packing:
    """Voronoi cells of ``seeds`` clipped to the rectangle ``[0, width] x [0, height]``.

    Parameters
    ----------
    seeds : array_like, shape (n_cells, 2)
        Voronoi centres [m], strictly inside the rectangle and pairwise distinct.
    width, height : float
        Rectangle size [m].

    Returns
    -------
    Packing
        Cells in the order of ``seeds``; ``centres`` are the seeds.

    Notes
    -----
    The seeds are mirrored across the four sides so that every cell of an original seed is
    bounded; each cell is then clipped to the rectangle (convex clipping), which only removes
    round-off since the mirrored tessellation already ends on the sides.
    """
    _check_rectangle(width, height)
    seeds = np.asarray(seeds, dtype=np.float64)
    if seeds.ndim != 2 or seeds.shape[1] != 2:
        raise ValueError(f"seeds must have shape (n_cells, 2), got {seeds.shape}")
    n_cells = len(seeds)
    if n_cells < 2:
        raise ValueError(f"a packing needs at least 2 seeds (n_cells), got {n_cells}")
    if not np.all(np.isfinite(seeds)):
        raise ValueError("seeds must be finite")
    inside = (seeds[:, 0] > 0) & (seeds[:, 0] < width) & (seeds[:, 1] > 0) & (seeds[:, 1] < height)
    if not np.all(inside):
        raise ValueError(f"seeds must lie strictly inside the rectangle; {np.sum(~inside)} do not")
    size = max(width, height)
    tol = GEOMETRY_RTOL * size
    nearest, _ = cKDTree(seeds).query(seeds, k=2)
    if nearest[:, 1].min() <= 1e3 * tol:
        raise ValueError("seeds must be pairwise distinct")

    mirrored = [seeds]
    for axis, bound in ((0, 0.0), (0, width), (1, 0.0), (1, height)):
        m = seeds.copy()
        m[:, axis] = 2.0 * bound - m[:, axis]
        mirrored.append(m)
    vor = Voronoi(np.concatenate(mirrored))
    lo, hi = np.zeros(2), np.array([width, height])
    polygons = []
    for i in range(n_cells):
        region = vor.regions[vor.point_region[i]]
        if -1 in region or len(region) < 3:
            raise RuntimeError(f"Voronoi cell {i} is unbounded despite mirroring")
        poly = vor.vertices[region]
        # Voronoi regions are convex: order by angle about the seed to make them CCW
        ang = np.arctan2(poly[:, 1] - seeds[i, 1], poly[:, 0] - seeds[i, 0])
        poly = _clip_convex(poly[np.argsort(ang)], lo, hi)
        polygons.append(_dedupe_polygon(poly, tol))
    return packing_from_polygons(polygons, centres=seeds)


def voronoi_packing(n_cells: int, width: float, height: float, seed: int) -> Packing:
    """Voronoi packing of ``n_cells`` random seeds in ``[0, width] x [0, height]``.

    Parameters
    ----------
    n_cells : int
        Number of cells (>= 2).
    width, height : float
        Rectangle size [m].
    seed : int
        Seed of ``numpy.random.default_rng``; the seed points are ``rng.uniform`` scaled to the
        rectangle, shape (n_cells, 2).

    Returns
    -------
    Packing
    """
    _check_rectangle(width, height)
    if int(n_cells) != n_cells or n_cells < 2:
        raise ValueError(f"n_cells must be an integer >= 2, got {n_cells!r}")
    rng = np.random.default_rng(seed)
    seeds = rng.uniform(size=(int(n_cells), 2)) * np.array([width, height])
    return voronoi_packing_from_seeds(seeds, width, height)


def verification_packing(name: str, size: float = 1.0) -> Packing:
    """The small verification meshes of seed 003, Sec. 4.3, on the square ``[0, size]^2``.

    Parameters
    ----------
    name : {"four-cells", "five-cells"}
        ``"four-cells"``: seeds at the quarter points, four square cells (seed 003, Fig. 6a).
        ``"five-cells"``: the quarter points plus the centre, a diamond surrounded by four
        pentagons (our reading of seed 003, Fig. 7a: the figure itself is not in the text).
    size : float
        Side of the square [m].

    Returns
    -------
    Packing
    """
    quarter = np.array([[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]])
    if name == "four-cells":
        seeds = quarter
    elif name == "five-cells":
        seeds = np.vstack([quarter, [[0.5, 0.5]]])
    else:
        raise ValueError(
            f"verification mesh name must be 'four-cells' or 'five-cells', got {name!r}"
        )
    return voronoi_packing_from_seeds(seeds * size, size, size)


def brick_wall_packing(
    n_courses: int, bricks_per_course: int, brick_length: float, brick_height: float
) -> Packing:
    """Running-bond wall: full bricks on even courses, half bricks at both ends of odd courses.

    Parameters
    ----------
    n_courses : int
        Number of courses (>= 1).
    bricks_per_course : int
        Full bricks per even course (>= 1); odd courses hold ``bricks_per_course - 1`` full
        bricks and two half bricks.
    brick_length, brick_height : float
        Brick size [m].

    Returns
    -------
    Packing
        Wall ``[0, bricks_per_course * brick_length] x [0, n_courses * brick_height]``, cells
        course by course from the bottom, left to right; centres are the brick centroids.
    """
    if int(n_courses) != n_courses or n_courses < 1:
        raise ValueError(f"n_courses must be an integer >= 1, got {n_courses!r}")
    if int(bricks_per_course) != bricks_per_course or bricks_per_course < 1:
        raise ValueError(f"bricks_per_course must be an integer >= 1, got {bricks_per_course!r}")
    _check_rectangle(brick_length, brick_height)
    width = bricks_per_course * brick_length
    polygons = []
    for k in range(int(n_courses)):
        y0, y1 = k * brick_height, (k + 1) * brick_height
        if k % 2 == 0:
            xs = np.arange(bricks_per_course + 1) * brick_length
        else:
            inner = (np.arange(bricks_per_course) + 0.5) * brick_length
            xs = np.concatenate([[0.0], inner, [width]])
        for x0, x1 in zip(xs[:-1], xs[1:], strict=True):
            polygons.append(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))
    return packing_from_polygons(polygons)


def packing_from_polygons(
    polygons: list[np.ndarray], centres: np.ndarray | None = None, rtol: float = GEOMETRY_RTOL
) -> Packing:
    """Find the internal and boundary facets of a tiling by convex polygons.

    Parameters
    ----------
    polygons : list of array_like, each shape (m_c, 2)
        Convex cells [m], either orientation; they must not overlap.
    centres : array_like, shape (n_cells, 2), optional
        Interior points used to triangulate the cells [m]; default the polygon centroids.
    rtol : float
        Matching tolerance relative to the packing size.

    Returns
    -------
    Packing

    Notes
    -----
    Two sides touch when they are collinear with opposite outward normals; their overlap is
    an internal edge. The parts of a side covered by no neighbour are boundary edges.
    """
    polys = _counter_clockwise_polygons(polygons)
    n_cells = len(polys)
    all_xy = np.concatenate(polys)
    tol = rtol * float(np.max(all_xy.max(axis=0) - all_xy.min(axis=0)))
    if centres is None:
        centres = np.array([_centroid(p) for p in polys])
    centres = np.asarray(centres, dtype=np.float64)
    if centres.shape != (n_cells, 2):
        raise ValueError(f"centres must have shape ({n_cells}, 2), got {centres.shape}")
    sides = _Sides.of(polys, centres, tol)
    edges, pieces = _shared_edges(sides, tol)
    cell_xy, facet_edge, cell_ptr, bnd = _facets(polys, sides, pieces, tol)
    n_edges = len(edges)
    edge_xy = np.array([[e[2], e[3]] for e in edges]).reshape(n_edges, 2, 2)
    bnd_xy = np.array([[b[1], b[2]] for b in bnd]).reshape(len(bnd), 2, 2)
    packing = Packing(
        cell_ptr=np.asarray(cell_ptr, dtype=np.int64),
        cell_xy=np.asarray(cell_xy, dtype=np.float64).reshape(-1, 2),
        facet_edge=np.asarray(facet_edge, dtype=np.int64),
        centres=centres.copy(),
        edge_cells=np.array([[e[0], e[1]] for e in edges], dtype=np.int64).reshape(n_edges, 2),
        edge_xy=edge_xy,
        edge_normal=np.array([e[4] for e in edges], dtype=np.float64).reshape(n_edges, 2),
        edge_length=np.linalg.norm(edge_xy[:, 1] - edge_xy[:, 0], axis=1),
        bnd_cell=np.array([b[0] for b in bnd], dtype=np.int64),
        bnd_xy=bnd_xy,
        bnd_normal=np.array([b[3] for b in bnd], dtype=np.float64).reshape(len(bnd), 2),
        bnd_length=np.linalg.norm(bnd_xy[:, 1] - bnd_xy[:, 0], axis=1),
    )
    logger.debug(
        "packing: %d cells, %d internal edges, %d boundary edges",
        n_cells,
        packing.n_edges,
        packing.n_bnd,
    )
    return packing


def _counter_clockwise_polygons(polygons) -> list[np.ndarray]:
    """The cells as float (m_c, 2) arrays in counter-clockwise order; raises ``ValueError``
    for no cell, a bad shape or a zero area."""
    if len(polygons) < 1:
        raise ValueError("polygons must hold at least one cell")
    polys = []
    for i, p in enumerate(polygons):
        p = np.asarray(p, dtype=np.float64)
        if p.ndim != 2 or p.shape[1] != 2 or len(p) < 3:
            raise ValueError(f"polygon {i} must have shape (m >= 3, 2), got {p.shape}")
        area = _signed_area(p)
        if area == 0.0:
            raise ValueError(f"polygon {i} has zero area")
        polys.append(p if area > 0 else p[::-1])
    return polys


@dataclass(frozen=True)
class _Sides:
    """Every side of every cell, in cell order: owning cell (n_s,), start and end points
    (n_s, 2) [m], length (n_s,) [m], unit tangent and outward normal (tangent turned by -90
    deg) (n_s, 2)."""

    cell: np.ndarray
    p0: np.ndarray
    p1: np.ndarray
    length: np.ndarray
    t: np.ndarray
    n: np.ndarray

    @classmethod
    def of(cls, polys: list[np.ndarray], centres: np.ndarray, tol: float) -> _Sides:
        """Sides of counter-clockwise cells; raises ``ValueError`` for repeated vertices or a
        centre not strictly inside its cell."""
        cell = np.concatenate([np.full(len(p), i) for i, p in enumerate(polys)])
        p0 = np.concatenate(polys)
        p1 = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
        length = np.linalg.norm(p1 - p0, axis=1)
        if np.any(length <= tol):
            raise ValueError("polygons have repeated vertices")
        t = (p1 - p0) / length[:, None]
        n = np.stack([t[:, 1], -t[:, 0]], axis=1)
        inward = np.einsum("ij,ij->i", n, centres[cell] - p0)
        if np.any(inward >= -tol):
            bad = np.unique(cell[inward >= -tol])
            raise ValueError(
                f"centres of cells {bad.tolist()} are not strictly inside their polygons"
            )
        return cls(cell, p0, p1, length, t, n)


def _shared_edges(sides: _Sides, tol: float):
    """Internal edges: overlaps of pairs of sides of two cells on one line with opposite
    normals. Returns the edges (cell_a, cell_b, p0, p1, normal a -> b) and, per side, the
    pieces (lo, hi, edge) it shares, as distances along the side [m]."""
    # candidates: overlapping sides have midpoints closer than the longest side (KD-tree keeps
    # memory linear in the number of sides instead of an all-pairs matrix)
    mid = 0.5 * (sides.p0 + sides.p1)
    pairs = cKDTree(mid).query_pairs(r=float(sides.length.max()) + tol, output_type="ndarray")
    i_all, j_all = pairs[:, 0], pairs[:, 1]
    anti = np.sum(sides.n[i_all] * sides.n[j_all], axis=1) < -1.0 + 1e-9
    offset = np.abs(np.sum((sides.p0[j_all] - sides.p0[i_all]) * sides.n[i_all], axis=1))
    same_line = anti & (offset <= tol) & (sides.cell[i_all] != sides.cell[j_all])
    i_all, j_all = i_all[same_line], j_all[same_line]
    swap = sides.cell[i_all] > sides.cell[j_all]
    i_all, j_all = np.where(swap, j_all, i_all), np.where(swap, i_all, j_all)
    order = np.lexsort((j_all, i_all))
    pieces: list[list[tuple[float, float, int]]] = [[] for _ in range(len(sides.length))]
    edges = []
    for i, j in zip(i_all[order], j_all[order], strict=True):
        # parameters of side j's end points along side i
        s = (np.stack([sides.p0[j], sides.p1[j]]) - sides.p0[i]) @ sides.t[i]
        lo, hi = max(0.0, float(s.min())), min(float(sides.length[i]), float(s.max()))
        if hi - lo <= tol:
            continue
        e = len(edges)
        p0 = sides.p0[i] + lo * sides.t[i]
        p1 = sides.p0[i] + hi * sides.t[i]
        edges.append((sides.cell[i], sides.cell[j], p0, p1, sides.n[i]))
        pieces[i].append((lo, hi, e))
        sj = float(np.dot(p1 - sides.p0[j], sides.t[j]))  # side j runs the opposite way
        pieces[j].append((sj, sj + hi - lo, e))
    return edges, pieces


def _facets(polys, sides: _Sides, pieces, tol: float):
    """Split every side into its shared pieces and the uncovered rest (boundary edges).

    Returns the facets' start points in cell order, their edge (``>= 0``: internal edge,
    ``-1 - k``: boundary edge ``k``), the CSR pointer of the cells and the boundary edges
    (cell, p0, p1, normal)."""
    cell_xy, facet_edge, cell_ptr = [], [], [0]
    bnd = []
    side = 0
    for c, p in enumerate(polys):
        for _ in range(len(p)):
            p0, t = sides.p0[side], sides.t[side]
            for lo, hi, e in _side_segments(pieces[side], float(sides.length[side]), tol):
                cell_xy.append(p0 + lo * t)
                if e >= 0:
                    facet_edge.append(e)
                else:
                    facet_edge.append(-1 - len(bnd))
                    bnd.append((c, p0 + lo * t, p0 + hi * t, sides.n[side]))
            side += 1
        cell_ptr.append(len(cell_xy))
    return cell_xy, facet_edge, cell_ptr, bnd


def _side_segments(pieces, length: float, tol: float) -> list[tuple[float, float, int]]:
    """The shared ``pieces`` (lo, hi, edge) of a side of ``length`` [m] in order, with the
    gaps longer than ``tol`` between them as (lo, hi, -1)."""
    t = 0.0
    segs = []
    for lo, hi, e in sorted(pieces):
        if lo - t > tol:
            segs.append((t, lo, -1))
        segs.append((lo, hi, e))
        t = hi
    if length - t > tol:
        segs.append((t, length, -1))
    return segs


def _centroid(poly: np.ndarray) -> np.ndarray:
    x, y = poly[:, 0], poly[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = 0.5 * np.sum(cross)
    cx = np.sum((x + np.roll(x, -1)) * cross) / (6.0 * area)
    cy = np.sum((y + np.roll(y, -1)) * cross) / (6.0 * area)
    return np.array([cx, cy])


def uniform_stress_traction(packing: Packing, sigma: np.ndarray) -> np.ndarray:
    """Boundary tractions of a uniform stress: ``g_b = sigma @ n_b``.

    Parameters
    ----------
    packing : Packing
    sigma : array_like, shape (2, 2)
        Cauchy stress [Pa] (compression negative).

    Returns
    -------
    ndarray, shape (n_bnd, 2)
        Traction on every boundary edge [Pa].
    """
    sigma = np.asarray(sigma, dtype=np.float64)
    if sigma.shape != (2, 2):
        raise ValueError(f"sigma must have shape (2, 2), got {sigma.shape}")
    return packing.bnd_normal @ sigma.T
