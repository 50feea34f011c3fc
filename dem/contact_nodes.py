"""Surface contact nodes with tributary areas on every face that can meet another block.

Which block's nodes count a contact between two blocks is decided per pair of blocks
(``weight[a, b]``, below); the block that counts carries nodes on all of its faces, so a
contact between any of its faces and any feature of the other block (a face, an edge, a corner)
is represented, also one that appears only after large motions: a block sliding out of a panel
ends with its top edge against its neighbour's bottom edge, faces that were a block's
thickness apart at the start.

- An **interface face** (a face with a face of another block opposite to it, normals within
  ``FACE_ANGLE_DEG`` of anti-parallel, overlapping it in projection and within ``margin`` of
  its plane) gets nodes in the requested layout.
- Every other face of a block that counts against some block (an **exposed face**) gets nodes
  in the vertex layout, those on or near its edges pulled to ``EXPOSED_INSET_MARGINS`` margins
  inside them (all to the centroid on a face narrower than twice that), tributary areas
  unchanged (:func:`pull_inside`): near enough to an edge to meet a feature of another block
  that crosses it before the overlap outgrows the margin, beyond the margin of a neighbour
  that shares the edge (no contact entry at rest), and clear of the penalty deflection of an
  interface that shares it (micrometres under a sound stiffness), which the nodes would
  otherwise count a second time.
- A free block's upward face under the indenter's path (a vertical line, within the tip radius
  plus ``margin``) gets indenter nodes as well; those act against the indenter only.

Each face is covered by a square grid of spacing ``h`` aligned with its longest edge; every grid
cell is clipped exactly to the face polygon, and its area goes either to a node at its centroid
or in equal shares to nodes at its corners (see :func:`seed_face`), so the tributary areas of a
face sum to the face area exactly and a uniform penetration ``d`` gives the force
``k_n d A_face`` at any ``h``.

**Counting each contact once.** A contact between blocks ``a`` and ``b`` carries the force of
``a``'s nodes inside ``b`` times ``weight[a, b]`` plus that of ``b``'s nodes inside ``a`` times
``weight[b, a]``; the two weights add up to 1 and hold for every face of the pair:

- a pair that shares an interface in the reference configuration counts on one side only: the
  block whose interface face is the narrower (ties: the free block, then the lower index) gets
  ``weight = 1``, the other 0. Its nodes on the interface face carry the interface; its nodes
  on its other faces carry whatever else of the two blocks meets later.
- a free block and a fixed one without an interface: the free block counts (1 and 0), so that
  fixed blocks (supports, often large) carry nodes only where they are the narrower side of an
  interface;
- two free blocks without an interface (contacts that appear only after large motions, e.g.
  diagonal TIS neighbours at the pinwheel corners) use halving: nodes of either block act
  against the other with weight 1/2;
- two fixed blocks never interact (weight 0).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from dem.geometry.clipping import clip_convex_polygons, polygon_properties
from dem.scene import Assembly

logger = logging.getLogger(__name__)

MIN_REACH = 0.6
"""Contact faces whose nodes reach less than this fraction of the face's extent (fewer than
2.5 centroid cells across) are logged: the lever of their contact moments is that fraction;
faces whose nodes reach 0 (one node or one row) are refused."""
FACE_ANGLE_DEG = 20.0
"""Largest angle between one face normal and the reversed other for faces that can touch."""
MIN_TOUCH_FRACTION = 0.05
"""Faces touch when the part of their overlap within the margin is at least this fraction of the
smaller face (pinwheel corners of diagonal TIS neighbours meet along a line only)."""
EXPOSED_INSET_MARGINS = 2.0
"""Nodes of exposed faces stand this many margins inside the face's edges (module docstring):
beyond the margin of a neighbour that shares the edge, so that they make no contact entries
at rest."""
MAX_GRID_CELLS = 5_000_000
"""Most grid cells seeded on one face (about 1 GB of scratch arrays); more is refused."""


@dataclass(frozen=True, eq=False)
class ContactNodes:
    """Surface nodes of an assembly (reference configuration).

    Attributes
    ----------
    block : (n_nodes,) int64
        Owner block of each node.
    point : (n_nodes, 3) float64
        Node position in the reference configuration [m].
    normal : (n_nodes, 3) float64
        Outward normal of the owner's face.
    area : (n_nodes,) float64
        Tributary area [m^2].
    face : (n_nodes,) int64
        Global face index (into ``assembly.arrays``).
    weight : (n_blocks, n_blocks) float64
        Counting weight of nodes of block ``a`` acting against block ``b`` (1, 1/2 or 0).
    patch_centre, patch_u, patch_v : (n_nodes, 3) float64
        The box of face each node stands for (:func:`node_patches`): centre [m] and half
        sides along the face's axes [m].
    indenter_block, indenter_point, indenter_area
        The nodes that act against the indenter only: (k,) int64, (k, 3) [m], (k,) [m^2].
    spacing : float
        Grid spacing ``h`` [m].
    """

    block: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    area: np.ndarray
    face: np.ndarray
    weight: np.ndarray
    patch_centre: np.ndarray
    patch_u: np.ndarray
    patch_v: np.ndarray
    indenter_block: np.ndarray
    indenter_point: np.ndarray
    indenter_area: np.ndarray
    spacing: float

    @property
    def n_nodes(self) -> int:
        return len(self.area)


def node_reach(polygon: np.ndarray, normal: np.ndarray, points: np.ndarray) -> float:
    """Smallest ratio, over the face's two in-plane axes, of the nodes' extent to the face's
    [-]: the lever of the contact's moment about an edge, relative to the face's (1 with nodes
    on the edges; ``1 - 1 / n`` for ``n`` centroid cells across; 0 for one node or one row)."""
    u, v = _face_frame(polygon, normal)
    ratios = []
    for axis in (u, v):
        face = np.ptp(polygon @ axis)
        ratios.append(np.ptp(points @ axis) / face if face > 0 else 1.0)
    return float(min(ratios))


def _face_frame(polygon: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """In-plane unit axes: along the longest edge, and ``normal x`` that axis."""
    edges = np.roll(polygon, -1, axis=0) - polygon
    u = edges[np.argmax(np.linalg.norm(edges, axis=1))]
    u = u - np.dot(u, normal) * normal
    u /= np.linalg.norm(u)
    return u, np.cross(normal, u)


def _face_plane(polygon: np.ndarray, normal: np.ndarray) -> tuple:
    """The face's axes ``u``, ``v`` (:func:`_face_frame`), origin (its first corner) [m] and
    the polygon in ``(u, v)`` coordinates (k, 2) [m]."""
    u, v = _face_frame(polygon, normal)
    origin = polygon[0]
    return u, v, origin, np.column_stack([(polygon - origin) @ u, (polygon - origin) @ v])


def seed_face(
    polygon: np.ndarray,
    normal: np.ndarray,
    spacing: float,
    layout: str = "centroid",
    window: tuple[np.ndarray, float] | None = None,
) -> tuple[np.ndarray, ...]:
    """Nodes and tributary areas on one convex planar face.

    Parameters
    ----------
    polygon : (k, 3) float
        Corners, counter-clockwise about ``normal`` [m].
    normal : (3,) float
        Outward unit normal.
    spacing : float
        Grid spacing ``h`` [m].
    layout : {"centroid", "vertex"}
        ``"centroid"`` (default): one node at the centroid of each grid cell clipped to the
        face, with the clipped cell's area (midpoint rule). ``"vertex"``: nodes at the corners
        of the clipped cells, each corner taking an equal share of every cell it belongs to
        (trapezoidal rule on full cells: ``h^2`` inside, ``h^2 / 2`` on edges, ``h^2 / 4`` at
        corners); nodes then lie on the face's edges.
    window : ((3,) float, float), optional
        ``(centre, half_width)`` [m]: seed only the cells of the whole face's grid that meet
        the square of that half-width about ``centre`` (a point on the face's plane), sides
        along the face's axes. The grid and the cells are those of the whole face, so the nodes
        are a subset of the whole face's (a vertex-layout node keeps its whole area when every
        cell around it meets the square).

    Returns
    -------
    points : (m, 3) float
        Node positions [m].
    areas : (m,) float
        Their areas [m^2]; without ``window`` they sum to the face area.

    Raises
    ------
    ValueError
        A spacing that is not positive and finite, or more than ``MAX_GRID_CELLS`` cells.
    """
    if not spacing > 0 or not math.isfinite(spacing):
        raise ValueError(f"node spacing must be positive and finite, got {spacing}")
    if layout not in ("centroid", "vertex"):
        raise ValueError(f"layout must be 'vertex' or 'centroid', got {layout!r}")
    u, v, origin, poly2, start, counts = _face_grid(polygon, normal, spacing)
    first, stop = _cell_range(counts, start, spacing, window, (origin, u, v))
    n_cells = int(np.prod(np.maximum(stop - first, 0)))
    if n_cells > MAX_GRID_CELLS:
        extent = np.ptp(poly2, axis=0)
        raise ValueError(
            f"node spacing {spacing:.3g} m gives {n_cells:.3g} grid cells on a face of "
            f"{extent[0]:.3g} m x {extent[1]:.3g} m (at most {MAX_GRID_CELLS:.0e}): "
            "raise the node spacing"
        )
    if n_cells == 0:
        return np.zeros((0, 3)), np.zeros(0)
    corners = _cell_corners(first, stop, start, spacing)
    inside = _boxes_inside(corners, poly2, spacing)
    pieces = _edge_pieces(corners[~inside], poly2, spacing)
    if layout == "centroid":
        c0, c1 = corners[inside, 0, 0], corners[inside, 0, 1]
        full = np.column_stack([c0 + 0.5 * spacing, c1 + 0.5 * spacing])
        p2 = np.concatenate([full] + [centroid[None, :] for _, _, centroid in pieces])
        areas = np.concatenate([np.full(int(inside.sum()), spacing * spacing)]
                               + [np.array([area]) for _, area, _ in pieces])  # fmt: skip
    else:
        if not inside.any() and not pieces:  # a window that misses the face
            return np.zeros((0, 3)), np.zeros(0)
        p2, areas = _vertex_nodes(corners[inside], [piece for piece, _, _ in pieces], start,
                                  spacing)  # fmt: skip
    return origin + p2[:, :1] * u + p2[:, 1:] * v, areas


def _cell_range(counts, start, spacing: float, window, frame) -> tuple[np.ndarray, np.ndarray]:
    """First and stop cell indices (2,) of the face's grid (``counts`` cells along each axis,
    from ``start`` (2,) [m]) to seed: all of them, or those meeting ``window`` (see
    :func:`seed_face`) in the face's ``frame = (origin, u, v)``."""
    first, stop = np.zeros(2, dtype=np.int64), np.array(counts, dtype=np.int64)
    if window is not None:
        origin, u, v = frame
        centre, half = window
        c2 = np.array([(centre - origin) @ u, (centre - origin) @ v])
        # cells meeting the square, plus one on each side against round-off
        first = np.maximum(first, np.floor((c2 - half - start) / spacing).astype(np.int64) - 1)
        stop = np.minimum(stop, np.ceil((c2 + half - start) / spacing).astype(np.int64) + 1)
    return first, stop


def _cell_corners(first: np.ndarray, stop: np.ndarray, start: np.ndarray, spacing: float):
    """(cells, 4, 2) corners [m], counter-clockwise, of the grid cells ``first:stop`` (2,) of
    the grid from ``start`` (2,) [m], row-major in the cell indices."""
    iu, iv = np.meshgrid(np.arange(first[0], stop[0]), np.arange(first[1], stop[1]), indexing="ij")
    c0 = start[0] + iu.ravel() * spacing
    c1 = start[1] + iv.ravel() * spacing
    return np.stack(
        [
            np.column_stack([c0, c1]),
            np.column_stack([c0 + spacing, c1]),
            np.column_stack([c0 + spacing, c1 + spacing]),
            np.column_stack([c0, c1 + spacing]),
        ],
        axis=1,
    )


def _boxes_inside(corners: np.ndarray, poly2: np.ndarray, spacing: float) -> np.ndarray:
    """(m,) bool: the boxes ``corners`` (m, 4, 2) lie inside the convex CCW polygon ``poly2``
    (k, 2), to a tolerance of 1e-12 of ``spacing`` times each edge's length."""
    edge = np.roll(poly2, -1, axis=0) - poly2
    scale = spacing * np.linalg.norm(edge, axis=1)
    # inside of every edge of the CCW polygon: cross(edge, p - start) >= 0 (one edge at a
    # time: scratch of (m, 4), not (m, 4, edges))
    inside = np.ones(len(corners), dtype=bool)
    for k in range(len(poly2)):
        rel = corners - poly2[k]
        side = edge[k, 0] * rel[..., 1] - edge[k, 1] * rel[..., 0]
        inside &= np.all(side >= -1e-12 * scale[k], axis=1)
    return inside


def _edge_pieces(corners: np.ndarray, poly2: np.ndarray, spacing: float) -> list[tuple]:
    """``(piece (j, 2), area, centroid (2,))`` of each cell ``corners`` (m, 4, 2) clipped to
    the polygon, in order, leaving out pieces of zero area (below 1e-12 of a cell)."""
    pieces = []
    for cell in corners:
        piece = clip_convex_polygons(cell, poly2)
        if len(piece) < 3:
            continue
        area, centroid, _ = polygon_properties(piece)
        if area > 1e-12 * spacing * spacing:
            pieces.append((piece, area, centroid))
    return pieces


def _vertex_nodes(full: np.ndarray, pieces: list, start: np.ndarray, spacing: float) -> tuple:
    """Nodes at the corners of the full cells ``full`` (m, 4, 2) and of the clipped cells
    ``pieces`` ((j, 2) each), each corner taking an equal share of every cell's area it belongs
    to: points (n, 2) [m] and areas (n,) [m^2]."""
    corner_pts = np.concatenate([full.reshape(-1, 2)] + pieces)
    shares = np.concatenate([np.full(4 * len(full), 0.25 * spacing * spacing)]
                            + [np.full(len(c), polygon_properties(c)[0] / len(c))
                               for c in pieces])  # fmt: skip
    # merge coincident corners of neighbouring cells
    key = np.round((corner_pts - start) / (1e-7 * spacing)).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    area = np.zeros(len(first))
    np.add.at(area, inverse, shares)
    return corner_pts[first], area


def _face_grid(polygon: np.ndarray, normal: np.ndarray, spacing: float) -> tuple:
    """The face's grid: axes ``u``, ``v`` (3,), origin (3,) [m], the polygon in ``(u, v)``
    (k, 2) [m], the grid's corner ``start`` (2,) [m] and its cell counts ``(n_u, n_v)``; the
    grid is centred on the face's bounding box so that the edge cells are symmetric."""
    u, v, origin, poly2 = _face_plane(polygon, normal)
    lo, hi = poly2.min(axis=0), poly2.max(axis=0)
    n_u = max(1, math.ceil((hi[0] - lo[0]) / spacing - 1e-9))
    n_v = max(1, math.ceil((hi[1] - lo[1]) / spacing - 1e-9))
    start = 0.5 * (lo + hi) - 0.5 * spacing * np.array([n_u, n_v])
    return u, v, origin, poly2, start, (n_u, n_v)


def node_patches(
    polygon: np.ndarray, normal: np.ndarray, spacing: float, points: np.ndarray, layout: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The patch of face each node of :func:`seed_face` stands for, as a box on the face.

    A node's patch is its grid cell (``"centroid"`` layout) or, ``"vertex"`` layout, the box
    reaching half way to the next grid line (or face edge) on either side along each axis
    (the quarters of the cells around a corner, whose areas it shares), clipped to the face;
    the box is the clipped patch's bounding box along the face's axes. On a face that is a
    rectangle along the grid (masonry faces) the boxes tile the face. The contact law uses it
    to count only the part of a node's patch that lies over the neighbour
    (:func:`dem.kernels.contact_force._compatible_plane`).

    Parameters
    ----------
    polygon, normal, spacing
        As :func:`seed_face`.
    points : (m, 3) float
        The nodes of :func:`seed_face` on this face [m].
    layout : {"centroid", "vertex"}

    Returns
    -------
    centre : (m, 3) float
        Centre of each box [m].
    half_u, half_v : (m, 3) float
        Half sides of each box as vectors along the face's axes [m].
    """
    u, v, origin, poly2, start, counts = _face_grid(polygon, normal, spacing)
    p2 = np.column_stack([(points - origin) @ u, (points - origin) @ v])
    if layout == "vertex":
        lo, hi = np.empty_like(p2), np.empty_like(p2)
        for k in range(2):
            lines = np.unique(np.clip(start[k] + spacing * np.arange(counts[k] + 1),
                                      poly2[:, k].min(), poly2[:, k].max()))  # fmt: skip
            tol = 1e-9 * spacing
            below = np.searchsorted(lines, p2[:, k] - tol) - 1
            above = np.searchsorted(lines, p2[:, k] + tol, side="right")
            prev = np.where(below >= 0, lines[np.maximum(below, 0)], p2[:, k])
            nxt = np.where(above < len(lines), lines[np.minimum(above, len(lines) - 1)],
                           p2[:, k])  # fmt: skip
            lo[:, k], hi[:, k] = 0.5 * (p2[:, k] + prev), 0.5 * (p2[:, k] + nxt)
    else:
        lo = start + spacing * np.floor((p2 - start) / spacing)
        hi = lo + spacing
    corners = np.stack([lo, np.column_stack([hi[:, 0], lo[:, 1]]), hi,
                        np.column_stack([lo[:, 0], hi[:, 1]])], axis=1)  # fmt: skip
    inside = _boxes_inside(corners, poly2, spacing)
    for k in np.flatnonzero(~inside):
        piece = clip_convex_polygons(corners[k], poly2)
        if len(piece) >= 3:
            lo[k], hi[k] = piece.min(axis=0), piece.max(axis=0)
        else:  # a patch that meets the face in a point or a line (round-off): the node alone
            lo[k], hi[k] = p2[k], p2[k]
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    centre = origin + mid[:, :1] * u + mid[:, 1:] * v
    return centre, half[:, :1] * u, half[:, 1:] * v


def _touching_face_pairs(assembly: Assembly, margin: float) -> list[tuple[int, int, int, int]]:
    """``(a, fa, b, fb)`` for faces of different blocks that can touch (``a < b``)."""
    blocks = assembly.blocks
    lo = np.array([b.vertices.min(axis=0) for b in blocks]) - margin
    hi = np.array([b.vertices.max(axis=0) for b in blocks]) + margin
    cos_max = math.cos(math.radians(FACE_ANGLE_DEG))
    out = []
    for a in range(len(blocks)):
        overlap = np.all((lo[a + 1 :] <= hi[a]) & (hi[a + 1 :] >= lo[a]), axis=1)
        for b in a + 1 + np.flatnonzero(overlap):
            ba, bb = blocks[a], blocks[b]
            dots = ba.normals @ bb.normals.T
            for fa, fb in zip(*np.nonzero(dots < -cos_max), strict=True):
                if _faces_touch(ba, fa, bb, fb, margin):
                    out.append((a, int(fa), int(b), int(fb)))
    return out


def _faces_touch(ba, fa: int, bb, fb: int, margin: float) -> bool:
    n = ba.normals[fa]
    u, v = _face_frame(ba.vertices[ba.faces[fa]], n)
    origin = ba.vertices[ba.faces[fa][0]]
    pa = ba.vertices[ba.faces[fa]] - origin
    pb = bb.vertices[bb.faces[fb]] - origin
    poly_a = np.column_stack([pa @ u, pa @ v])
    poly_b = np.column_stack([pb @ u, pb @ v])[::-1]  # b's face is CCW about -n
    piece = clip_convex_polygons(poly_a, poly_b)
    if len(piece) < 3 or polygon_properties(piece)[0] <= (1e-9 * np.ptp(poly_a)) ** 2:
        return False
    # keep the part of the overlap where the planes are within the margin of each other: the
    # gap along n is linear over a's plane, gap = g0 + gu u + gv v
    nb, db = bb.normals[fb], bb.offsets[fb]
    denom = np.dot(nb, n)
    g0 = (db - np.dot(nb, origin)) / denom
    gu, gv = -np.dot(nb, u) / denom, -np.dot(nb, v) / denom
    for sign in (1.0, -1.0):
        piece = _clip_halfplane(piece, sign * gu, sign * gv, margin - sign * g0)
        if len(piece) < 3:
            return False
    near = polygon_properties(piece)[0]
    face_area = min(polygon_properties(poly_a)[0], polygon_properties(poly_b)[0])
    return bool(near >= MIN_TOUCH_FRACTION * face_area)


def _clip_halfplane(poly: np.ndarray, cu: float, cv: float, c: float) -> np.ndarray:
    """The part of a convex polygon (k, 2) with ``cu u + cv v <= c``."""
    value = poly[:, 0] * cu + poly[:, 1] * cv - c
    out = []
    for j in range(len(poly)):
        k = (j + 1) % len(poly)
        if value[j] <= 0:
            out.append(poly[j])
        if (value[j] < 0) != (value[k] < 0) and value[j] != value[k]:
            w = value[j] / (value[j] - value[k])
            out.append(poly[j] + w * (poly[k] - poly[j]))
    return np.array(out).reshape(-1, 2)


def seed_contact_nodes(
    assembly: Assembly,
    fixed: np.ndarray,
    spacing: float,
    margin: float,
    indenter_axis_xy: np.ndarray | None = None,
    indenter_radius: float = 0.0,
    indenter_spacing: float | None = None,
    layout: str = "centroid",
) -> ContactNodes:
    """Seed nodes on the faces of the blocks that count contacts, and under the indenter.

    Interface faces get ``layout``, the other faces of a counting block the vertex layout
    pulled inside their edges (module docstring).

    Parameters
    ----------
    assembly : Assembly
    fixed : (n_blocks,) bool
        Fixed blocks (two fixed blocks never interact).
    spacing : float
        Node spacing ``h`` on block faces [m].
    margin : float
        Faces within this distance count as touching [m].
    indenter_axis_xy : (2,) float, optional
        ``(x, y)`` of the vertical indenter path [m]; None for no indenter.
    indenter_radius : float
        Tip radius [m].
    indenter_spacing : float, optional
        Node spacing on the faces under the indenter [m] (default ``spacing``).
    layout : {"centroid", "vertex"}
        Node layout on the interface faces and under the indenter, see :func:`seed_face`.

    Returns
    -------
    ContactNodes

    Raises
    ------
    ValueError
        Bad ``fixed`` or ``margin``, an interface face with nodes on one point or one row, or a
        face grid of more than ``MAX_GRID_CELLS`` cells (only the cells within the indenter's
        reach count on faces under it).
    """
    n_blocks = assembly.n_blocks
    fixed = np.asarray(fixed, dtype=bool)
    if fixed.shape != (n_blocks,):
        raise ValueError(f"fixed must have shape ({n_blocks},), got {fixed.shape}")
    if not margin > 0:
        raise ValueError(f"margin must be positive [m], got {margin}")
    weight, seeded = _count_once(assembly, fixed, margin)
    interface = _face_nodes(assembly, seeded, spacing, layout, check_reach=True)
    exposed = _face_nodes(assembly, _exposed_faces(assembly, weight, seeded), spacing,
                          "vertex", check_reach=False,
                          inset=EXPOSED_INSET_MARGINS * margin)  # fmt: skip
    faces = tuple(i + e for i, e in zip(interface, exposed, strict=True))
    indenter: tuple = ([], [], [])
    if indenter_axis_xy is not None:
        axis = np.asarray(indenter_axis_xy, dtype=float)
        h_ind = spacing if indenter_spacing is None else indenter_spacing
        indenter = _indenter_nodes(assembly, fixed, axis, indenter_radius + margin, h_ind, layout)
    ind_b, ind_p, ind_a = indenter
    blocks_l, points_l, normals_l, areas_l, faces_l, patches_l = faces
    return ContactNodes(
        block=_cat(blocks_l, (0,), np.int64),
        point=_cat(points_l, (0, 3)),
        normal=_cat(normals_l, (0, 3)),
        area=_cat(areas_l, (0,)),
        face=_cat(faces_l, (0,), np.int64),
        weight=weight,
        patch_centre=_cat([p[0] for p in patches_l], (0, 3)),
        patch_u=_cat([p[1] for p in patches_l], (0, 3)),
        patch_v=_cat([p[2] for p in patches_l], (0, 3)),
        indenter_block=_cat(ind_b, (0,), np.int64),
        indenter_point=_cat(ind_p, (0, 3)),
        indenter_area=_cat(ind_a, (0,)),
        spacing=float(spacing),
    )


def _cat(parts: list, empty_shape: tuple, dtype=np.float64) -> np.ndarray:
    """The parts concatenated, or an empty array of ``empty_shape`` when there are none."""
    return np.concatenate(parts) if parts else np.zeros(empty_shape, dtype=dtype)


def _count_once(assembly: Assembly, fixed: np.ndarray, margin: float):
    """The counting weights (n_blocks, n_blocks) and the seeded interface faces, a set of
    ``(block, face)``: each pair of blocks counted on one side or halved (module docstring)."""
    n_blocks = assembly.n_blocks
    weight = np.full((n_blocks, n_blocks), 0.5)
    free = ~fixed
    weight[np.ix_(free, fixed)] = 1.0
    weight[np.ix_(fixed, free)] = 0.0
    weight[np.ix_(fixed, fixed)] = 0.0
    np.fill_diagonal(weight, 0.0)
    seeded: set[tuple[int, int]] = set()
    counter: dict[tuple[int, int], int] = {}  # (a, b) with a < b -> the block that counts
    for a, fa, b, fb in _touching_face_pairs(assembly, margin):
        if fixed[a] and fixed[b]:
            continue
        area_a = polygon_properties(_local(assembly.blocks[a], fa))[0]
        area_b = polygon_properties(_local(assembly.blocks[b], fb))[0]
        rel = (area_a - area_b) / max(area_a, area_b)
        if abs(rel) > 1e-9:
            side_a = rel < 0
        elif fixed[a] != fixed[b]:
            side_a = not fixed[a]
        else:
            side_a = True
        # a pair with several touching faces counts on the side its first interface chose,
        # and seeds the face on that side for coverage
        owner = counter.setdefault((a, b), a if side_a else b)
        other, face = (b, fa) if owner == a else (a, fb)
        weight[owner, other] = 1.0
        weight[other, owner] = 0.0
        seeded.add((owner, face))
    return weight, seeded


def pull_inside(polygon: np.ndarray, normal: np.ndarray, points: np.ndarray,
                inset: float) -> np.ndarray:  # fmt: skip
    """Points of a convex face moved to the nearest point at least ``inset`` inside its edges.

    Parameters
    ----------
    polygon : (k, 3) float
        Corners, counter-clockwise about ``normal`` [m].
    normal : (3,) float
        Outward unit normal.
    points : (m, 3) float
        Points on the face [m].
    inset : float
        [m].

    Returns
    -------
    (m, 3) float
        Points inside the face shrunk by ``inset`` (every edge moved in by it) stay; the others
        go to its nearest point (a point on an edge moves ``inset`` along the edge's inward
        normal). On a face narrower than ``2 inset`` every point goes to the face's centroid.
    """
    u, v, origin, poly2 = _face_plane(polygon, normal)
    p2 = np.column_stack([(points - origin) @ u, (points - origin) @ v])
    edge = np.roll(poly2, -1, axis=0) - poly2
    inward = np.column_stack([-edge[:, 1], edge[:, 0]]) / np.linalg.norm(edge, axis=1)[:, None]
    shrunk = poly2
    for k in range(len(poly2)):  # keep inward . (p - corner_k) >= inset
        shrunk = _clip_halfplane(shrunk, -inward[k, 0], -inward[k, 1],
                                 -(inward[k] @ poly2[k] + inset))  # fmt: skip
        if len(shrunk) < 3:
            centroid = polygon_properties(poly2)[1]
            return np.repeat((origin + centroid[0] * u + centroid[1] * v)[None, :],
                             len(points), axis=0)  # fmt: skip
    outside = ((p2 - poly2[:, None, :]) * inward[:, None, :]).sum(axis=2).min(axis=0) < inset
    p2[outside] = _nearest_on_boundary(shrunk, p2[outside])
    return origin + p2[:, :1] * u + p2[:, 1:] * v


def _nearest_on_boundary(poly: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(m, 2) nearest points to ``points`` (m, 2) on the boundary of the polygon ``poly``
    (k, 2)."""
    edge = np.roll(poly, -1, axis=0) - poly
    rel = points[:, None, :] - poly[None, :, :]
    t = np.clip((rel * edge).sum(axis=2) / (edge * edge).sum(axis=1), 0.0, 1.0)
    foot = poly[None, :, :] + t[:, :, None] * edge[None, :, :]
    best = np.argmin(np.linalg.norm(foot - points[:, None, :], axis=2), axis=1)
    return foot[np.arange(len(points)), best]


def _exposed_faces(assembly: Assembly, weight: np.ndarray, seeded: set) -> set:
    """``(block, face)`` of every face of a block that counts against some block (a positive
    row of ``weight``) and is not one of its ``seeded`` interface faces."""
    counting = np.flatnonzero(weight.max(axis=1) > 0.0)
    return {(int(i), f) for i in counting for f in range(len(assembly.blocks[i].faces))
            if (int(i), f) not in seeded}  # fmt: skip


def _face_nodes(assembly: Assembly, faces: set, spacing: float, layout: str,
                check_reach: bool, inset: float = 0.0) -> tuple:  # fmt: skip
    """Nodes of ``faces`` (a set of ``(block, face)``), in ``(block, face)`` order: lists of
    per-face arrays of blocks, points, normals, areas, global faces and patches
    (:func:`node_patches`, of the nodes where :func:`seed_face` put them); ``check_reach``:
    refuse or log faces whose nodes fall short of their edges (:func:`_warn_short_reach`);
    ``inset`` [m]: nodes nearer an edge are pulled inside (:func:`pull_inside`)."""
    arrays = assembly.arrays
    blocks_l, points_l, normals_l, areas_l, faces_l, patches_l = [], [], [], [], [], []
    short = []  # (reach, block, face) of faces whose nodes fall short of their edges
    for owner, face in sorted(faces):
        blk = assembly.blocks[owner]
        polygon = blk.vertices[blk.faces[face]]
        pts, areas = seed_face(polygon, blk.normals[face], spacing, layout)
        if check_reach and (reach := node_reach(polygon, blk.normals[face], pts)) < MIN_REACH:
            short.append((reach, owner, face))
        blocks_l.append(np.full(len(areas), owner, dtype=np.int64))
        points_l.append(pull_inside(polygon, blk.normals[face], pts, inset) if inset > 0 else pts)
        normals_l.append(np.repeat(blk.normals[face][None, :], len(areas), axis=0))
        areas_l.append(areas)
        faces_l.append(np.full(len(areas), arrays.face_ptr[owner] + face, dtype=np.int64))
        patches_l.append(node_patches(polygon, blk.normals[face], spacing, pts, layout))
    if short:
        _warn_short_reach(short, spacing, layout)
    return blocks_l, points_l, normals_l, areas_l, faces_l, patches_l


def _indenter_nodes(assembly: Assembly, fixed: np.ndarray, axis: np.ndarray, reach: float,
                    h_ind: float, layout: str) -> tuple[list, list, list]:  # fmt: skip
    """Nodes on the free blocks' upward faces within ``reach`` [m] (tip radius plus margin)
    of the indenter's axis ``(x, y)`` in plan, at spacing ``h_ind`` [m]: lists of per-face
    blocks, points and areas."""
    ind_b, ind_p, ind_a = [], [], []
    for i, blk in enumerate(assembly.blocks):
        if fixed[i]:
            continue
        for f, normal in enumerate(blk.normals):
            if normal[2] < 0.5:
                continue
            poly = blk.vertices[blk.faces[f]]
            if _polygon_xy_distance(poly[:, :2], axis) > reach:
                continue
            # a kept node lies within reach + h of the axis in plan, so within
            # (reach + h) / n_z, in the face's plane, of the plane's point above the axis:
            # seed only the cells about that point (memory as the nodes kept)
            above = np.append(axis, poly[0, 2] + normal[:2] @ (poly[0, :2] - axis) / normal[2])
            window = (above, (reach + h_ind) / normal[2])
            pts, areas = seed_face(poly, normal, h_ind, layout, window)
            keep = np.linalg.norm(pts[:, :2] - axis, axis=1) <= reach + h_ind
            ind_b.append(np.full(int(keep.sum()), i, dtype=np.int64))
            ind_p.append(pts[keep])
            ind_a.append(areas[keep])
    return ind_b, ind_p, ind_a


def _warn_short_reach(short: list, spacing: float, layout: str) -> None:
    """Refuse contact faces whose nodes carry no moment about an axis (one node, or one row);
    log those whose nodes reach less than ``MIN_REACH`` of their extent."""
    reach, block, face = min(short)
    hint = f"use node_layout='vertex' (nodes on the edges) or a node_spacing below {spacing:.3g} m"
    if reach == 0.0:
        raise ValueError(
            f"the contact nodes of block {block} face {face} ({layout} layout, node_spacing "
            f"{spacing:.3g} m) lie on one point or one row: the contact there would be a hinge "
            f"that carries no moment about that axis; {hint}"
        )
    logger.warning(
        "the contact nodes of %d face(s) fall short of their edges (%s layout, node_spacing "
        "%.3g m): the worst, block %d face %d, reach %.2f of the face's extent; rocking and "
        "overturning capacities of those contacts shrink with that lever; %s",
        len(short), layout, spacing, block, face, reach, hint,
    )  # fmt: skip


def _local(block, face: int) -> np.ndarray:
    return _face_plane(block.vertices[block.faces[face]], block.normals[face])[3]


def _polygon_xy_distance(poly_xy: np.ndarray, point: np.ndarray) -> float:
    """Distance in the plane from ``point`` to a convex polygon's projection (0 if inside)."""
    centre = poly_xy.mean(axis=0)
    rel = poly_xy - centre
    order = np.argsort(np.arctan2(rel[:, 1], rel[:, 0]))
    poly = poly_xy[order]
    best = math.inf
    inside = True
    for k in range(len(poly)):
        p, q = poly[k], poly[(k + 1) % len(poly)]
        e = q - p
        w = point - p
        if e[0] * w[1] - e[1] * w[0] < 0:
            inside = False
        s = np.clip(np.dot(w, e) / np.dot(e, e), 0.0, 1.0)
        best = min(best, float(np.linalg.norm(w - s * e)))
    return 0.0 if inside else best


@dataclass(frozen=True, eq=False)
class LevelSets:
    """Signed-distance grids of all blocks in their reference frames (LS-DEM representation).

    Attributes
    ----------
    origin : (n_blocks, 3) float64
        Grid corner of each block [m].
    spacing : (n_blocks,) float64
        Grid spacing [m].
    dims : (n_blocks, 3) int64
        Grid points per axis.
    ptr : (n_blocks + 1,) int64
        Block ``i``'s values are ``values[ptr[i]:ptr[i + 1]]`` (last axis fastest).
    values : (n_values,) float64
        Signed distance at the grid points [m].
    """

    origin: np.ndarray
    spacing: np.ndarray
    dims: np.ndarray
    ptr: np.ndarray
    values: np.ndarray


def build_level_sets(
    assembly: Assembly, spacing: float, pad: float, sdf_functions: list | None = None
) -> LevelSets:
    """Sample each block's signed distance on a regular grid.

    Parameters
    ----------
    assembly : Assembly
    spacing : float
        Grid spacing [m] (seed 000: 0.025 mm).
    pad : float
        Extent of the grid beyond the block's bounding box [m] (at least the contact margin).
    sdf_functions : list of callables, optional
        ``phi_i(points (k, 3)) -> (k,)`` per block; default: the convex face-plane distance
        ``max_f (n_f . x - d_f)``, exact inside and on the surface.
    """
    if not spacing > 0:
        raise ValueError(f"level-set spacing must be positive [m], got {spacing}")
    n = assembly.n_blocks
    origin = np.zeros((n, 3))
    dims = np.zeros((n, 3), dtype=np.int64)
    chunks = []
    for i, blk in enumerate(assembly.blocks):
        lo = blk.vertices.min(axis=0) - pad
        hi = blk.vertices.max(axis=0) + pad
        counts = np.ceil((hi - lo) / spacing).astype(np.int64) + 1
        axes = [lo[k] + spacing * np.arange(counts[k]) for k in range(3)]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        phi = blk.signed_distance(grid) if sdf_functions is None else sdf_functions[i](grid)
        origin[i], dims[i] = lo, counts
        chunks.append(np.asarray(phi, dtype=np.float64))
    ptr = np.concatenate([[0], np.cumsum([len(c) for c in chunks])]).astype(np.int64)
    return LevelSets(origin, np.full(n, float(spacing)), dims, ptr, np.concatenate(chunks))
