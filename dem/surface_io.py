"""Closed bodies of surface files (OBJ, STL, PLY, OFF), kept apart by object and by face.

Blocks of a wall share corners, edges and whole faces, so a body is never found by merging
coincident corners across the file. Instead:

1. The file's objects are kept apart: OBJ ``o`` and ``g`` parts, the ``solid`` sections of an
   ASCII STL. A file without objects (binary STL, PLY, OFF, an OBJ without ``o``/``g``) is one
   object.
2. Within an object, coincident corners are merged (STL repeats every corner) and faces are
   joined across the edges they share. An edge shared by two faces joins them. An edge shared
   by more faces (two blocks of one object that touch along it) joins each face to its
   neighbour around the edge on the side its block lies: faces are sorted by angle about the
   edge, and a face whose outward normal (right-hand rule of its corner order) turns the
   other way than the sweep opens a solid wedge that the next face closes.
3. A body some of whose edges belong to one face only is open (a face missing) and refused,
   naming the body and those edges.

The reader is small on purpose: trimesh's loader returns an OBJ's objects in no file order,
and its split by face adjacency drops edges shared by more than two faces, so the touching
faces of an object-free stack of boxes fall out as loose pieces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["SurfaceBody", "read_surface_bodies", "split_bodies", "open_edges"]

MERGE_TOL = 1e-9
"""Corners closer than this times the object's extent are one corner [-]."""
ANGLE_TOL = 1e-9
"""Faces about an edge whose angles differ by less than this are coincident [rad]."""


@dataclass(frozen=True)
class SurfaceBody:
    """One connected closed surface of a file.

    Attributes
    ----------
    name : str
        Its object's name (OBJ ``o``/``g``, STL ``solid``), ``""`` if the file has none.
    points : (k, 3) float
        Its corners [file units].
    faces : list of (m_i,) int arrays
        Its polygons, indices into ``points``, in the file's corner order.
    """

    name: str
    points: np.ndarray
    faces: list


def _obj_objects(path: Path) -> list[tuple[str, np.ndarray, list[np.ndarray]]]:
    """(name, points, faces) of every ``o``/``g`` part of an OBJ file that has faces."""
    vertices: list[list[float]] = []
    parts: list[tuple[str, list]] = [("", [])]
    for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        words = line.split("#", 1)[0].split()
        try:
            if words[:1] == ["v"]:
                vertices.append([float(w) for w in words[1:4]])
            elif words[:1] in (["o"], ["g"]):
                parts.append((" ".join(words[1:]), []))
            elif words[:1] == ["f"]:
                ids = [int(w.split("/")[0]) for w in words[1:]]
                ids = [i - 1 if i > 0 else len(vertices) + i for i in ids]
                if len(ids) < 3 or min(ids) < 0 or max(ids) >= len(vertices):
                    raise ValueError("not a polygon of the vertices above it")
                parts[-1][1].append(ids)
        except ValueError as exc:
            raise ValueError(f"{path}:{number}: cannot read {line.strip()!r} ({exc})") from exc
    points = np.asarray(vertices, dtype=float).reshape(-1, 3)
    return [(name, points, [np.asarray(f) for f in faces]) for name, faces in parts if faces]


def _stl_ascii_objects(path: Path) -> list[tuple[str, np.ndarray, list[np.ndarray]]] | None:
    """(name, points, triangles) of every ``solid`` of an ASCII STL; None for a binary STL."""
    raw = path.read_bytes()
    if not raw.lstrip().startswith(b"solid") or b"facet" not in raw[:1000]:
        return None
    try:
        text = raw.decode("ascii")
    except UnicodeDecodeError:
        return None
    solids: list[tuple[str, list]] = []
    for line in text.splitlines():
        words = line.split()
        if words[:1] == ["solid"]:
            solids.append((" ".join(words[1:]), []))
        elif words[:1] == ["vertex"] and solids:
            solids[-1][1].append([float(w) for w in words[1:4]])
    out = []
    for name, corners in solids:
        pts = np.asarray(corners, dtype=float).reshape(-1, 3)
        if len(pts) % 3:
            raise ValueError(f"{path}: solid {name!r} has a facet without three vertices")
        out.append((name, pts, list(np.arange(len(pts)).reshape(-1, 3))))
    return out


def _meshio_object(path: Path) -> list[tuple[str, np.ndarray, list[np.ndarray]]]:
    """The whole surface of a file meshio reads, as one unnamed object."""
    import meshio

    try:
        with np.errstate(over="ignore"):  # meshio's binary-STL size test overflows on ASCII
            mesh = meshio.read(path)
    except meshio.ReadError as exc:
        raise ValueError(f"{path}: meshio cannot read it ({exc})") from exc
    faces = [np.asarray(f) for cb in mesh.cells if cb.dim == 2 for f in cb.data]
    return [("", np.asarray(mesh.points, dtype=float), faces)]


def _objects(path: Path) -> list[tuple[str, np.ndarray, list[np.ndarray]]]:
    suffix = path.suffix.lower()
    if suffix == ".obj":
        return _obj_objects(path)
    if suffix == ".stl":
        return _stl_ascii_objects(path) or _meshio_object(path)
    return _meshio_object(path)


def _merge_corners(points: np.ndarray, faces: list[np.ndarray]):
    """Corners closer than ``MERGE_TOL`` times the extent merged: (points, faces)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    used = np.unique(np.concatenate(faces))
    scale = float(np.linalg.norm(np.ptp(points[used], axis=0))) or 1.0
    pairs = cKDTree(points[used]).query_pairs(MERGE_TOL * scale, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (len(used),) * 2)
    _, label = connected_components(graph, directed=False)
    _, first = np.unique(label, return_index=True)
    new_id = np.full(len(points), -1)
    new_id[used] = label
    return points[used[first]], [new_id[f] for f in faces]


def _face_edges(faces: list[np.ndarray]) -> dict[tuple[int, int], list[int]]:
    """Undirected edge (low, high) -> the faces that use it."""
    edges: dict[tuple[int, int], list[int]] = {}
    for k, face in enumerate(faces):
        for a, b in zip(face, np.roll(face, -1), strict=True):
            if a != b:
                edges.setdefault((min(a, b), max(a, b)), []).append(k)
    return edges


def _newell_normal(corners: np.ndarray) -> np.ndarray:
    """Area-weighted normal of a polygon, by the right-hand rule of its corner order."""
    nxt = np.roll(corners, -1, axis=0)
    return np.cross(corners, nxt).sum(axis=0)


def _pairs_about_edge(points, faces, edge: tuple[int, int], around: list[int]) -> list:
    """Face pairs that bound one solid wedge each, about an edge of more than two faces."""
    p0, p1 = points[edge[0]], points[edge[1]]
    axis = (p1 - p0) / np.linalg.norm(p1 - p0)
    keys = []
    ref = None
    for k in around:
        inward = points[faces[k]].mean(axis=0) - p0
        inward -= (inward @ axis) * axis
        ref = inward / np.linalg.norm(inward) if ref is None else ref
        angle = math.atan2(np.cross(ref, inward) @ axis, ref @ inward) % (2 * math.pi)
        angle = 0.0 if angle > 2 * math.pi - ANGLE_TOL else angle
        # outward normal along axis x inward: the face's block lies behind it, i.e. before it
        closes = float(_newell_normal(points[faces[k]]) @ np.cross(axis, inward)) > 0
        keys.append((angle, closes, k))
    keys.sort(key=lambda t: t[0])
    ordered, i = [], 0
    while i < len(keys):  # within coincident faces, those that close a wedge come first
        j = i
        while j + 1 < len(keys) and keys[j + 1][0] - keys[i][0] < ANGLE_TOL:
            j += 1
        ordered += sorted(keys[i : j + 1], key=lambda t: not t[1])
        i = j + 1
    pairs = []
    for n, (_, closes, k) in enumerate(ordered):
        after = ordered[(n + 1) % len(ordered)]
        if not closes and after[1]:
            pairs.append((k, after[2]))
    return pairs


def split_bodies(points: np.ndarray, faces: list[np.ndarray]) -> list[list[int]]:
    """Faces of each connected body of one object, joined across shared edges (see the
    module notes); bodies in the order of their first face."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    links = []
    for edge, around in _face_edges(faces).items():
        if len(around) == 2:
            links.append(tuple(around))
        elif len(around) > 2:
            links += _pairs_about_edge(points, faces, edge, around)
    links_arr = np.asarray(links, dtype=np.int64).reshape(-1, 2)
    n = len(faces)
    graph = coo_matrix((np.ones(len(links_arr)), (links_arr[:, 0], links_arr[:, 1])), (n, n))
    _, label = connected_components(graph, directed=False)
    order = list(dict.fromkeys(label.tolist()))
    return [np.flatnonzero(label == c).tolist() for c in order]


def open_edges(faces: list[np.ndarray]) -> list[tuple[int, int]]:
    """Edges (corner ids) that only one face of a body uses: a closed body has none."""
    return [e for e, around in _face_edges(faces).items() if len(around) == 1]


def _body(name: str, points: np.ndarray, faces: list[np.ndarray]) -> SurfaceBody:
    ids = np.unique(np.concatenate(faces))
    local = np.full(len(points), -1)
    local[ids] = np.arange(len(ids))
    return SurfaceBody(name, points[ids], [local[f] for f in faces])


def read_surface_bodies(path: str | Path) -> list[SurfaceBody]:
    """The closed bodies of a surface file, objects in file order, and within an object in
    the order of their first face.

    Raises
    ------
    ValueError
        An unreadable file, no polygons, or an open body (named by its index in the file and
        its object, with its open edges).
    """
    path = Path(path)
    objects = _objects(path)
    if not objects:
        raise ValueError(f"{path}: no surface polygons to make bodies of")
    bodies = []
    for name, points, faces in objects:
        points, faces = _merge_corners(points, faces)
        for members in split_bodies(points, faces):
            body = _body(name, points, [faces[k] for k in members])
            _refuse_open(body, len(bodies), path)
            bodies.append(body)
    return bodies


def _refuse_open(body: SurfaceBody, index: int, path: Path) -> None:
    edges = open_edges(body.faces)
    if not edges:
        return
    shown = "; ".join(
        f"{np.round(body.points[a], 6).tolist()}-{np.round(body.points[b], 6).tolist()}"
        for a, b in edges[:4]
    )
    more = f" and {len(edges) - 4} more" if len(edges) > 4 else ""
    named = f" (object {body.name!r})" if body.name else ""
    raise ValueError(
        f"body {index} of {path.name}{named} is open: {len(edges)} edges belong to one face "
        f"only ({shown}{more}); a face is missing, its corners do not meet, or the block's faces "
        "are spread over several objects (o/g, solid)"
    )
