"""Contacts the explicit model does not represent: blocks that pass through each other.

The block that counts the contact of a pair carries contact nodes on all of its faces
(:func:`dem.contact_nodes.seed_contact_nodes`), so any feature of the other block that comes
into it meets nodes, within the node spacing: an edge or a corner that presses into one of its
faces between two nodes goes in by up to about half a spacing (times the tangent of the angle
of the wedge) before a node lies inside it. What is left unrepresented: two fixed blocks, and a
motion that carries a block through the other faster, or against a softer contact, than the
penalty can stop. At every neighbour-list rebuild each pair of nearby blocks gets a
separating-axis test (face normals of both blocks and cross products of their edges: exact for
convex polyhedra): its penetration depth is the least distance that separates the two blocks'
projections (:func:`dem.geometry.polyhedron.penetration_depth`, posed). A pair with no contact
entry may overlap by at most the neighbour-list margin; a pair with entries by the penalty
deflection, which a sound stiffness keeps far below ``OVERLAP_LIMIT`` times the thinner
block's thickness (entries can exist between blocks that meet elsewhere, e.g. nodes of a block's
base within the margin of a neighbour's base plane). Beyond that, the overlap is not one the
run represents, and the run stops naming the pair instead of going on with blocks inside each
other.

The indenter, a rigid sphere of radius ``R``, acts only on the indenter nodes (free blocks'
upward faces under its path) with the traction ``k_n (R - |x - c|)`` along ``x - c``. Pressed
``d`` into a flat face it carries ``P = k_n pi d^2 (R - d)``, which peaks at ``d = 2 R / 3``
and falls beyond: a tip that deep measures its own penalty, not the blocks, and goes on through
the block (the load turns negative once its centre passes the nodes). The run stops once the
sphere overlaps a block by more than ``INDENTER_DEPTH_LIMIT R``, or by more than the margin
plus the indenter node spacing beyond what that block's indenter nodes feel (fixed blocks have
none; a tip that slips off the loaded block into the gap meets its neighbour's side face, which
has none).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from dem.explicit.settings import SimulationError
from dem.explicit.state import Bodies, Shapes
from dem.kernels.overlap import penetration_depths

OVERLAP_LIMIT = 0.1
"""Largest overlap of two blocks with contact entries, times the thinner one's thickness."""
INDENTER_DEPTH_LIMIT = 0.5
"""Deepest penetration of the indenter into a block, times its radius (the seed 000 panels of
``tis-panels`` reach 0.12 to 0.35 over their runs, the 3 x 3 panel at 7.5 deg the most)."""


class UnmodelledContactError(SimulationError):
    """Two blocks overlap more than the model represents: they pass through each other."""


class Hulls(NamedTuple):
    """Vertices and edge directions of every block, reference frame.

    Attributes
    ----------
    vertex_ptr : (n + 1,) int64
        Block ``b``'s vertices are ``local[vertex_ptr[b]:vertex_ptr[b + 1]]``.
    local : (n_vertices, 3) float64
        ``X - ref_centroid[b]`` [m].
    edge_ptr : (n + 1,) int64
        Block ``b``'s edge directions are ``edge_dir[edge_ptr[b]:edge_ptr[b + 1]]``.
    edge_dir : (n_edges, 3) float64
        Unit edge directions, one per parallel family.
    thickness : (n,) float64
        Smallest width of each block [m].
    """

    vertex_ptr: np.ndarray
    local: np.ndarray
    edge_ptr: np.ndarray
    edge_dir: np.ndarray
    thickness: np.ndarray


def block_hulls(blocks, ref_centroid: np.ndarray) -> Hulls:
    """Vertices about the centroids and edge directions of ``blocks`` (ConvexBlock)."""
    locals_, edges = [], []
    for blk, c in zip(blocks, ref_centroid, strict=True):
        locals_.append(blk.vertices - c)
        d = blk.vertices[blk.edges[:, 1]] - blk.vertices[blk.edges[:, 0]]
        d /= np.linalg.norm(d, axis=1)[:, None]
        d *= np.where(d @ [1.0, 1e-3, 1e-6] < 0.0, -1.0, 1.0)[:, None]  # one sign per family
        edges.append(np.unique(np.round(d, 9), axis=0))
    thickness = np.array([blk.thickness for blk in blocks])
    return Hulls(
        _ptr(locals_), np.concatenate(locals_), _ptr(edges), np.concatenate(edges), thickness
    )


def _ptr(arrays) -> np.ndarray:
    return np.concatenate([[0], np.cumsum([len(a) for a in arrays])]).astype(np.int64)


def worst_overlap(
    hulls: Hulls,
    bodies: Bodies,
    shapes: Shapes,
    pos: np.ndarray,
    rot: np.ndarray,
    entry_pairs: np.ndarray,
    margin: float,
) -> tuple[int, int, float, float]:
    """The pair of blocks that overlap most beyond what the model represents (module notes).

    Parameters
    ----------
    hulls : Hulls
    bodies, shapes : Bodies, Shapes
        Bounding radii and face normals of the blocks.
    pos : (n, 3) float64
        Current centroids [m].
    rot : (n, 3, 3) float64
        Current rotations (reference to world).
    entry_pairs : (m, 2) int64
        Block pairs with contact entries (either order).
    margin : float
        Neighbour-list margin [m]: the overlap allowed to a pair without entries.

    Returns
    -------
    (a, b, depth, allowed)
        The pair with the largest ratio of its penetration depth [m]
        (:mod:`dem.kernels.overlap`) to its allowed overlap [m]; ``(-1, -1, 0.0, inf)`` if no
        two blocks overlap.
        Pairs of two fixed blocks are left out.
    """
    n = pos.shape[0]
    dist = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
    near = dist < bodies.radius[:, None] + bodies.radius[None, :]
    fixed = np.ones(n, dtype=bool)
    fixed[bodies.free_blocks] = False
    near &= ~(fixed[:, None] & fixed[None, :])
    allowed = np.full((n, n), float(margin))
    thinner = np.minimum(hulls.thickness[:, None], hulls.thickness[None, :])
    entries = np.zeros((n, n), dtype=bool)
    entries[entry_pairs[:, 0], entry_pairs[:, 1]] = True
    entries |= entries.T
    allowed[entries] = np.maximum(margin, OVERLAP_LIMIT * thinner[entries])
    pairs = np.argwhere(np.triu(near, 1))
    if len(pairs) == 0:
        return -1, -1, 0.0, np.inf
    depth = np.empty(len(pairs))
    penetration_depths(
        _world(hulls.local, hulls.vertex_ptr, rot, pos), hulls.vertex_ptr,
        _world(shapes.face_normal, shapes.face_ptr, rot), shapes.face_ptr,
        _world(hulls.edge_dir, hulls.edge_ptr, rot), hulls.edge_ptr, pairs, depth,
    )  # fmt: skip
    ratio = depth / allowed[pairs[:, 0], pairs[:, 1]]
    k = int(ratio.argmax())
    if depth[k] == 0.0:
        return -1, -1, 0.0, np.inf
    a, b = pairs[k]
    return int(a), int(b), float(depth[k]), float(allowed[a, b])


def _world(local: np.ndarray, ptr: np.ndarray, rot: np.ndarray, pos=None) -> np.ndarray:
    """Rows of ``local`` (block ``b``'s are ``ptr[b]:ptr[b + 1]``) turned by their block's
    rotation, plus its centroid when ``pos`` is given."""
    owner = np.repeat(np.arange(len(ptr) - 1), np.diff(ptr))
    out = np.einsum("kij,kj->ki", rot[owner], local)
    return out if pos is None else out + pos[owner]


def sphere_overlap(
    centre: np.ndarray,
    radius: float,
    bodies: Bodies,
    shapes: Shapes,
    pos: np.ndarray,
    rot: np.ndarray,
    n_points: int = 2000,
) -> tuple[np.ndarray, np.ndarray]:
    """The blocks a sphere overlaps, and by how much [m] (points of the sphere sampled).

    The sphere's centre and ``n_points`` points spread evenly over its surface (a Fibonacci
    lattice) are tested against the face planes of every block within reach: a point inside a
    block lies at the distance to its nearest face plane from the outside. The overlap is the
    largest such distance; a cap thinner than about ``(4 pi / n_points) R / 8`` between the
    points can be missed.

    Parameters
    ----------
    centre : (3,) float
        [m].
    radius : float
        [m].
    bodies, shapes : Bodies, Shapes
        Reference centroids, bounding radii and face planes of the blocks.
    pos : (n, 3) float64
        Current centroids [m].
    rot : (n, 3, 3) float64
        Current rotations (reference to world).

    Returns
    -------
    blocks : (k,) int64
        The blocks the sphere overlaps.
    depth : (k,) float64
        Their overlaps [m], positive.
    """
    k = np.arange(n_points) + 0.5
    polar = np.arccos(1.0 - 2.0 * k / n_points)
    azimuth = np.pi * (1.0 + 5.0**0.5) * k
    unit = np.column_stack(
        [np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)]
    )
    points = np.vstack([centre, centre + radius * unit])
    near = np.flatnonzero(np.linalg.norm(pos - centre, axis=1) < bodies.radius + radius)
    depth = np.zeros(len(near))
    for k, b in enumerate(near):
        # the points in b's reference frame, then their distances to b's face planes
        local = (points - pos[b]) @ rot[b] + bodies.ref_centroid[b]
        faces = slice(shapes.face_ptr[b], shapes.face_ptr[b + 1])
        outside = (local @ shapes.face_normal[faces].T - shapes.face_offset[faces]).max(axis=1)
        depth[k] = -outside.min()
    inside = depth > 0.0
    return near[inside].astype(np.int64), depth[inside]
