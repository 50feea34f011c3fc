"""Scenes from the files users have: mesh files of convex cells, multi-body surfaces, TOML.

- A volume mesh read with meshio (gmsh ``.msh``, ``.vtu``, ``.vtk``, ``.xdmf``, ...): one block
  per 3D cell (tetrahedra, hexahedra, wedges, pyramids or VTK polyhedra). Cells must be linear.
- Surfaces of convex bodies (OBJ, STL, PLY, OFF), one file or a folder of them: one block per
  object (OBJ ``o``/``g``, STL ``solid``) and, within an object, per body of faces joined
  across shared edges (:mod:`dem.surface_io`); an open body is refused.
- The project's scene JSON (:meth:`dem.Scene.from_json`).

A cell or body is accepted only if it is convex: its corners are exactly the corners of their
convex hull, and each of its faces lies in one plane of that hull (a warped or re-entrant face
is refused, naming the cell). Material, supports and loads come from a :class:`SceneSpec`,
read from a small TOML file (see :meth:`SceneSpec.from_toml`) or built by the command line.
"""

from __future__ import annotations

import difflib
import logging
import math
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from dem.geometry.polyhedron import ConvexBlock, convex_block
from dem.scene import (
    LARGE_BLOCK,
    LIGHT_DENSITY,
    Assembly,
    Loads,
    Scene,
    Supports,
    point_load,
    proportional_to_weight,
)
from dem.units import LENGTH_UNITS, G

logger = logging.getLogger(__name__)

__all__ = [
    "CELL_FACES",
    "SURFACE_SUFFIXES",
    "SceneSpec",
    "blocks_from_mesh",
    "blocks_from_surfaces",
    "cell_groups",
    "checked_block",
    "read_scene",
]

CELL_FACES: dict[str, tuple[tuple[int, ...], ...]] = {
    "tetra": ((0, 1, 2), (0, 1, 3), (1, 2, 3), (0, 2, 3)),
    "pyramid": ((0, 1, 2, 3), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)),
    "wedge": ((0, 1, 2), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)),
    "hexahedron": (
        (0, 1, 2, 3),
        (4, 5, 6, 7),
        (0, 1, 5, 4),
        (1, 2, 6, 5),
        (2, 3, 7, 6),
        (3, 0, 4, 7),
    ),
}
"""Faces of the linear 3D cells in meshio's (VTK's) node order; gmsh's linear cells map to it."""

SURFACE_SUFFIXES = (".obj", ".stl", ".ply", ".off")
PLANE_TOL = 1e-7
"""Largest distance of a face corner from its hull plane, relative to the block size [-]."""
AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def checked_block(points: np.ndarray, faces: Sequence[Sequence[int]], label: str) -> ConvexBlock:
    """The convex block of one cell or body, or a ValueError naming it.

    Parameters
    ----------
    points : (k, 3) float
        Its corners [m].
    faces : sequence of index sequences
        Its faces (indices into ``points``), in any orientation.
    label : str
        Name used in the error, e.g. ``"cell 12 (hexahedron)"``.
    """
    try:
        block = convex_block(points, exact=True)
    except ValueError as exc:
        raise ValueError(f"{label} is not a convex block: {exc}") from exc
    tol = PLANE_TOL * block.size
    for face in faces:
        dist = np.abs(points[list(face)] @ block.normals.T - block.offsets)  # (corners, planes)
        if not np.any(np.all(dist <= tol, axis=0)):
            raise ValueError(
                f"{label} is not convex: its face with corners {list(face)} does not lie in a "
                "face plane of its convex hull (a warped or re-entrant face); split the cell "
                "into convex cells or flatten the face."
            )
    return block


def _cells(mesh) -> list[tuple[str, np.ndarray, tuple]]:
    """(type, corner ids, faces in local ids) of every 3D cell of a meshio mesh."""
    out = []
    for cb in mesh.cells:
        if cb.type in CELL_FACES:
            out += [(cb.type, np.asarray(ids), CELL_FACES[cb.type]) for ids in cb.data]
        elif cb.type.startswith("polyhedron"):
            for cell in cb.data:
                ids = np.unique(np.concatenate([np.asarray(f) for f in cell]))
                local = {g: i for i, g in enumerate(ids.tolist())}
                faces = tuple(tuple(local[g] for g in np.asarray(f).tolist()) for f in cell)
                out.append((cb.type, ids, faces))
        elif cb.dim == 3:
            raise ValueError(
                f"cell type {cb.type!r} is not supported (only linear tetra, pyramid, wedge, "
                "hexahedron and polyhedron cells; export a linear mesh)"
            )
    return out


def _read(path: str | Path):
    """A meshio mesh, or a ValueError saying why the file cannot be read."""
    import meshio

    try:
        with np.errstate(over="ignore"):  # meshio's binary-STL size test overflows on ASCII
            return meshio.read(path)
    except meshio.ReadError as exc:
        raise ValueError(f"{path}: meshio cannot read it ({exc})") from exc


def cell_groups(mesh) -> dict[str, list[int]]:
    """Named sets of 3D cells (gmsh physical groups, meshio ``cell_sets``) as block indices.

    Block ``i`` is the ``i``-th 3D cell over all cell blocks, as in :func:`blocks_from_mesh`.
    """
    offsets, start = [], 0
    for cb in mesh.cells:
        offsets.append(start if cb.dim == 3 else None)
        start += len(cb.data) if cb.dim == 3 else 0
    groups = {}
    for name, per_block in mesh.cell_sets.items():
        ids = [
            offsets[k] + int(i)
            for k, local in enumerate(per_block)
            if offsets[k] is not None and local is not None
            for i in np.asarray(local).ravel()
        ]
        if ids and not name.startswith("gmsh:"):
            groups[name] = sorted(ids)
    return groups


def blocks_from_mesh(path: str | Path) -> list[ConvexBlock]:
    """One convex block per 3D cell of a volume mesh (any format meshio reads).

    Raises
    ------
    ValueError
        No 3D cell, a higher-order cell type, or a non-convex cell (named by its index over
        all 3D cells, its type and its corners).
    """
    return blocks_of_mesh(_read(path), str(path))


def blocks_of_mesh(mesh, label: str = "mesh") -> list[ConvexBlock]:
    """:func:`blocks_from_mesh` of a mesh already read (``label`` names it in errors)."""
    path = label
    cells = _cells(mesh)
    if not cells:
        raise ValueError(f"{path}: no 3D cells (tetra, wedge, hexahedron, ...) to make blocks of")
    points = np.asarray(mesh.points, dtype=float)
    if points.shape[1] != 3:
        raise ValueError(f"{path}: points must be 3D, got shape {points.shape}")
    return [
        checked_block(points[ids], faces, f"cell {i} ({kind}, nodes {ids.tolist()})")
        for i, (kind, ids, faces) in enumerate(cells)
    ]


def blocks_from_surfaces(path: str | Path) -> list[ConvexBlock]:
    """One convex block per closed body in a surface file, or in every such file of a folder.

    Bodies are found by :func:`dem.surface_io.read_surface_bodies`: by object (OBJ
    ``o``/``g``, STL ``solid``), then by faces joined across shared edges, never by corners
    merged across objects (blocks of a wall share corners). Files of a folder are read in
    name order. A body is named in errors by its file, its index in that file and its object.

    Raises
    ------
    ValueError
        No surface file, an open body (its open edges named) or a body that is not convex.
    """
    from dem.surface_io import read_surface_bodies

    path = Path(path)
    files = (
        sorted(p for p in path.iterdir() if p.suffix.lower() in SURFACE_SUFFIXES)
        if path.is_dir()
        else [path]
    )
    if not files:
        raise ValueError(f"{path}: no {'/'.join(SURFACE_SUFFIXES)} files in the folder")
    blocks = []
    for f in files:
        for k, body in enumerate(read_surface_bodies(f)):
            named = f" (object {body.name!r})" if body.name else ""
            blocks.append(checked_block(body.points, body.faces, f"body {k} of {f.name}{named}"))
    return blocks


def _number(path: Path, key: str, value) -> float:
    """A finite TOML number (int or float, not a boolean or a string)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ValueError(f"{path}: {key} must be a finite number, got {value!r}")
    return float(value)


def _text(path: Path, key: str, value) -> str:
    if not isinstance(value, str):
        raise ValueError(f"{path}: {key} must be a string, got {value!r}")
    return value


def _index(path: Path, key: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{path}: {key} must be an integer block index, got {value!r}")
    return value


def _items(path: Path, key: str, value) -> list:
    if not isinstance(value, list):
        raise ValueError(f"{path}: {key} must be a list, got {value!r}")
    return value


def _vector(path: Path, key: str, value, size: int = 3) -> tuple[float, ...]:
    if not isinstance(value, list) or len(value) != size:
        raise ValueError(f"{path}: {key} must be a list of {size} numbers, got {value!r}")
    return tuple(_number(path, f"{key}[{i}]", v) for i, v in enumerate(value))


def _direction(path: Path, key: str, value) -> tuple[float, ...]:
    """An axis name (``"x"``, ``"-y"``, ...) or a 3-vector."""
    if not isinstance(value, str):
        return _vector(path, key, value)
    try:
        return SceneSpec.direction(value)
    except ValueError as exc:
        raise ValueError(f"{path}: {key}: {exc}") from exc


def _each(item):
    """A reader of a TOML list whose entries ``item`` reads, named ``key[i]`` in errors."""

    def read(path: Path, key: str, value) -> tuple:
        return tuple(item(path, f"{key}[{i}]", v) for i, v in enumerate(_items(path, key, value)))

    return read


def _table(schema: dict):
    """A reader of a TOML table whose keys are those of ``schema`` (key -> reader)."""

    def read(path: Path, key: str, value) -> dict:
        where = f"[{key}]" if key else "the top level"
        if not isinstance(value, dict):
            raise ValueError(f"{path}: {where} must be a table, got {value!r}")
        for name in value:
            if name not in schema:
                close = difflib.get_close_matches(name, schema, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise ValueError(
                    f"{path}: unknown key {name!r} in {where}{hint}; allowed keys: "
                    f"{', '.join(schema)}"
                )
        return {
            name: schema[name](path, f"{key}.{name}" if key else name, v)
            for name, v in value.items()
        }

    return read


TOML_SCHEMA = _table(
    {
        "name": _text,
        "units": _text,
        "material": _table({"density": _number, "mu": _number}),
        "supports": _table(
            {
                "fixed": _each(_index),
                "fixed_below": _number,
                "fixed_groups": _each(_text),
                "fixed_boxes": _each(lambda path, key, box: _vector(path, key, box, size=6)),
            }
        ),
        "loads": _table(
            {
                "gravity": _vector,
                "live": _direction,
                "point": _each(
                    _table({"block": _index, "point": _vector, "force": _vector, "kind": _text})
                ),
            }
        ),
    }
)
"""Reader of a scene TOML (see :meth:`SceneSpec.from_toml`): refuses unknown keys and values
of the wrong type, naming the key."""


@dataclass(frozen=True)
class SceneSpec:
    """Material, supports and loads of a scene read from a mesh or surface file (SI units).

    Attributes
    ----------
    density : float or None
        [kg/m^3]; required for mesh and surface files.
    mu : float or None
        Friction coefficient [-].
    fixed : tuple of int
        Blocks held fixed.
    fixed_below : float or None
        Also fix every block whose centroid lies below this height z [m].
    fixed_groups : tuple of str
        Also fix every block of these named cell groups (gmsh physical groups of a mesh).
    fixed_boxes : tuple of (6,) tuples
        Also fix every block whose centroid lies in a box ``(x0, y0, z0, x1, y1, z1)`` [m].
    gravity : (3,) tuple
        [m/s^2].
    live : (3,) tuple or None
        Live load: the weight of every free block along this direction, scaled by lambda; None
        keeps the live load of the file (none for meshes).
    point_loads : tuple of dict
        ``{"block": i, "point": (x, y, z), "force": (fx, fy, fz), "kind": "dead" | "live"}``
        [m, N].
    name : str or None
    units : {"m", "cm", "mm"} or None
        Length unit of the file's coordinates and of this spec's lengths (``fixed_below``,
        ``fixed_boxes``, point-load points); :meth:`in_si` converts them once. None: metres,
        and a scene whose median block is over :data:`dem.scene.LARGE_BLOCK` m or whose median
        density is below :data:`dem.scene.LIGHT_DENSITY` kg/m^3 is refused as a likely units
        mistake; a unit given (even ``"m"``) says the scene is meant so.
    """

    density: float | None = None
    mu: float | None = None
    fixed: tuple[int, ...] = ()
    fixed_below: float | None = None
    fixed_groups: tuple[str, ...] = ()
    fixed_boxes: tuple[tuple[float, ...], ...] = ()
    gravity: tuple[float, float, float] = (0.0, 0.0, -G)
    live: tuple[float, float, float] | None = None
    point_loads: tuple[dict, ...] = ()
    name: str | None = None
    units: str | None = None

    def __post_init__(self):
        if self.units is not None and self.units not in LENGTH_UNITS:
            raise ValueError(f"units must be one of {', '.join(LENGTH_UNITS)}, got {self.units!r}")
        if self.density is not None and not (math.isfinite(self.density) and self.density > 0):
            raise ValueError(f"density must be finite and positive [kg/m^3], got {self.density}")
        if self.mu is not None and not (math.isfinite(self.mu) and self.mu >= 0):
            raise ValueError(f"mu must be finite and >= 0, got {self.mu}")
        for box in self.fixed_boxes:
            if len(box) != 6 or any(box[k] > box[k + 3] for k in range(3)):
                raise ValueError(f"fixed_boxes: need (x0, y0, z0, x1, y1, z1), x0 <= x1: {box}")
        if len(self.gravity) != 3:
            raise ValueError(f"gravity must be a 3-vector [m/s^2], got {self.gravity}")
        if self.live is not None and (len(self.live) != 3 or not any(self.live)):
            raise ValueError(f"live must be a non-zero 3-vector or an axis, got {self.live}")
        for load in self.point_loads:
            missing = {"block", "point", "force"} - set(load)
            if missing or load.get("kind", "dead") not in ("dead", "live"):
                raise ValueError(
                    f"point load {load} needs block, point, force and kind 'dead' or 'live'"
                )

    def merged(self, other: SceneSpec) -> SceneSpec:
        """A copy with the fields that ``other`` sets (differs from the defaults) replaced."""
        default = SceneSpec()
        changed = {
            f.name: getattr(other, f.name)
            for f in fields(self)
            if getattr(other, f.name) != getattr(default, f.name)
        }
        return replace(self, **changed)

    @staticmethod
    def direction(value: str | Sequence[float]) -> tuple[float, float, float]:
        """A load direction from ``"x"``, ``"-y"``, ... or a 3-vector."""
        if isinstance(value, str):
            sign = -1.0 if value.strip().startswith("-") else 1.0
            axis = value.strip().lstrip("+-").lower()
            if axis not in AXES:
                raise ValueError(f"load direction must be x, y, z, -x, ... or a vector: {value!r}")
            return tuple(sign * c for c in AXES[axis])
        return tuple(float(c) for c in value)

    @classmethod
    def from_toml(cls, path: str | Path) -> SceneSpec:
        """Read a spec from TOML.

        Example::

            name = "barn wall"
            units = "mm"            # lengths of the file and of this TOML (default m)
            [material]
            density = 2000.0        # kg/m^3
            mu = 0.6
            [supports]
            fixed = [0]             # block ids
            fixed_below = 0.05      # and every block with its centroid below z = 0.05 m
            fixed_groups = ["foundation"]   # and the cells of a gmsh physical group
            fixed_boxes = [[-1, -1, -1, 1, 1, 0]]
            [loads]
            gravity = [0.0, 0.0, -9.81]
            live = "x"              # or [1.0, 0.0, 0.0]
            [[loads.point]]
            block = 3
            point = [0.0, 0.0, 1.2]
            force = [0.0, 0.0, -5000.0]
            kind = "dead"

        Raises
        ------
        ValueError
            Invalid TOML, an unknown table or key (named, with the allowed keys), or a value
            of the wrong type or size (named by its key, e.g. ``material.mu``).
        """
        path = Path(path)
        try:
            document = tomllib.loads(path.read_text())
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"{path}: not valid TOML ({exc})") from exc
        data = TOML_SCHEMA(path, "", document)
        mat, sup, loads = data.get("material", {}), data.get("supports", {}), data.get("loads", {})
        try:
            return cls(
                density=mat.get("density"),
                mu=mat.get("mu"),
                fixed=sup.get("fixed", ()),
                fixed_below=sup.get("fixed_below"),
                fixed_groups=sup.get("fixed_groups", ()),
                fixed_boxes=sup.get("fixed_boxes", ()),
                gravity=loads.get("gravity", (0.0, 0.0, -G)),
                live=loads.get("live"),
                point_loads=loads.get("point", ()),
                name=data.get("name"),
                units=data.get("units"),
            )
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from exc

    @property
    def length_scale(self) -> float:
        """Metres per length unit of the input [m]."""
        return LENGTH_UNITS[self.units or "m"]

    def in_si(self) -> SceneSpec:
        """A copy whose lengths are in metres (``units`` kept: the user's word on the units)."""
        f = self.length_scale
        if f == 1.0:
            return self
        return replace(
            self,
            fixed_below=None if self.fixed_below is None else self.fixed_below * f,
            fixed_boxes=tuple(tuple(c * f for c in box) for box in self.fixed_boxes),
            point_loads=tuple(
                {**load, "point": tuple(c * f for c in load["point"])} for load in self.point_loads
            ),
        )

    def fixed_mask(self, assembly: Assembly, groups: dict | None = None) -> np.ndarray:
        """(n_blocks,) bool: the blocks this spec fixes (``groups``: name -> block ids)."""
        n = assembly.n_blocks
        ids = np.asarray(self.fixed, dtype=np.int64)
        if ids.size and (ids.min() < 0 or ids.max() >= n):
            raise ValueError(f"fixed block ids must lie in 0..{n - 1}, got {list(self.fixed)}")
        mask = np.zeros(n, dtype=bool)
        mask[ids] = True
        c = assembly.centroid
        if self.fixed_below is not None:
            mask |= c[:, 2] < self.fixed_below
        for box in self.fixed_boxes:
            lo, hi = np.array(box[:3]), np.array(box[3:])
            mask |= np.all((c >= lo) & (c <= hi), axis=1)
        groups = groups or {}
        for name in self.fixed_groups:
            if name not in groups:
                raise ValueError(
                    f"fixed group {name!r} is not in the scene; its groups: {sorted(groups)}"
                )
            mask[np.asarray(groups[name], dtype=np.int64)] = True
        return mask

    def apply(self, scene: Scene) -> Scene:
        """The scene with this spec's supports and loads added (the file's ones are kept)."""
        a = scene.assembly
        if self.mu is not None and (a.mu is None or np.any(a.mu != self.mu)):
            a = Assembly(a.blocks, a.density, self.mu)
        fixed = scene.supports.fixed | self.fixed_mask(a, scene.meta.get("groups"))
        supports = Supports(fixed, scene.supports.restrained & ~fixed[:, None])
        dead, live = scene.loads.dead_wrench.copy(), scene.loads.live_wrench.copy()
        if self.live is not None:
            live = proportional_to_weight(a, self.live, g=float(np.linalg.norm(self.gravity)))
            live[fixed] = 0.0
        for load in self.point_loads:
            w = point_load(a, int(load["block"]), load["point"], load["force"])
            if load.get("kind", "dead") == "live":
                live = live + w
            else:
                dead = dead + w
        loads = Loads(np.asarray(self.gravity, dtype=float), dead, live)
        return Scene(a, supports, loads, self.name or scene.name, scene.meta)


def read_scene(
    path: str | Path, spec: SceneSpec | None = None, toml: str | Path | None = None
) -> Scene:
    """A scene from a JSON scene, a volume mesh, or surfaces of convex bodies.

    Parameters
    ----------
    path : path
        ``*.json`` (the project's scene), a surface file or folder (``*.obj``, ``*.stl``,
        ...), or any volume mesh meshio reads (``*.msh``, ``*.vtu``, ...).
    spec : SceneSpec, optional
        Overrides on top of the TOML (e.g. from command-line options).
    toml : path, optional
        Supports and loads; default ``<path without suffix>.toml`` if it exists.

    Raises
    ------
    ValueError
        A non-convex or open cell or body (named), a mesh without density, bad TOML content,
        or a scene far from SI without ``units`` (see :func:`check_scale`).
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such scene file or folder")
    toml = path.with_suffix(".toml") if toml is None else Path(toml)
    base = SceneSpec.from_toml(toml) if toml.is_file() else SceneSpec()
    if toml.is_file():
        logger.info("supports and loads from %s", toml)
    spec = base if spec is None else base.merged(spec)
    if path.suffix.lower() == ".json":
        if spec.length_scale != 1.0:
            raise ValueError(
                f"{path}: a scene JSON is in metres; units {spec.units!r} applies to mesh and "
                "surface files only"
            )
        scene = Scene.from_json(path)
        density = scene.assembly.density if spec.density is None else spec.density
        check_scale(scene.assembly.blocks, density, spec, path)
        if spec.density is not None:
            scene = replace(
                scene, assembly=Assembly(scene.assembly.blocks, density, scene.assembly.mu)
            )
        return spec.apply(scene)
    groups: dict[str, list[int]] = {}
    if path.is_dir() or path.suffix.lower() in SURFACE_SUFFIXES:
        blocks = blocks_from_surfaces(path)
    else:
        mesh = _read(path)
        blocks, groups = blocks_of_mesh(mesh, str(path)), cell_groups(mesh)
    if spec.density is None:
        raise ValueError(
            f"{path}: a mesh has no density; give it in the TOML ([material] density) or on the "
            "command line (--density) [kg/m^3]"
        )
    blocks = [scaled_block(b, spec.length_scale) for b in blocks]
    check_scale(blocks, spec.density, spec, path)
    spec = spec.in_si()
    assembly = Assembly(tuple(blocks), spec.density, spec.mu)
    n = assembly.n_blocks
    zero = np.zeros((n, 6))
    scene = Scene(
        assembly,
        Supports.none(n),
        Loads(np.asarray(spec.gravity, dtype=float), zero, zero.copy()),
        spec.name or path.stem,
        {"source": str(path), "groups": groups, "units": spec.units or "m"},
    )
    return spec.apply(scene)


def scaled_block(block: ConvexBlock, factor: float) -> ConvexBlock:
    """``block`` with every length multiplied by ``factor`` (units to metres) [-]."""
    if factor == 1.0:
        return block
    return replace(
        block,
        vertices=block.vertices * factor,
        offsets=block.offsets * factor,
        volume=block.volume * factor**3,
        centroid=block.centroid * factor,
        inertia=block.inertia * factor**5,
    )


def check_scale(blocks, density, spec: SceneSpec, path: Path) -> None:
    """Refuse, unless ``spec.units`` is given, a scene whose median block is over
    :data:`LARGE_BLOCK` m across or whose median density is below :data:`LIGHT_DENSITY`
    kg/m^3: a file in mm read as metres, a density in t/m^3.

    Raises
    ------
    ValueError
        Naming what was seen and ``--units mm`` (or ``units`` in the TOML).
    """
    if spec.units is not None:
        return
    size = float(np.median([b.size for b in blocks]))
    rho = float(np.median(np.broadcast_to(np.asarray(density, dtype=float), (len(blocks),))))
    if size > LARGE_BLOCK:
        raise ValueError(
            f"{path}: the median block is {size:.3g} m across (over {LARGE_BLOCK:g} m): is the "
            'file in mm? give --units mm (or units = "mm" in the TOML; cm and m too, m if '
            "it is meant so)"
        )
    if rho < LIGHT_DENSITY:
        raise ValueError(
            f"{path}: the median density is {rho:.3g} kg/m^3 (below {LIGHT_DENSITY:g}): density "
            "is in kg/m^3 (2400, not 2.4 t/m^3); give --units mm, cm or m to say the scene is "
            "meant so"
        )
