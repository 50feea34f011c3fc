"""The scene every method reads: convex blocks, supports and loads (SI units).

Degrees of freedom of a block are ordered ``(ux, uy, uz, rx, ry, rz)``: translation of the
centroid [m] and small rotation about the centroid [rad]. Wrenches are ordered the same way:
``(Fx, Fy, Fz, Mx, My, Mz)``, force [N] at the centroid and moment about it [N m].
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from numbers import Real
from pathlib import Path

import numpy as np

from dem.geometry.clipping import polygon_properties
from dem.geometry.interfaces import Interfaces, find_interfaces
from dem.geometry.polyhedron import ConvexBlock, convex_block, plane_basis
from dem.units import G

DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")

SIZE_RATIO = 100.0
"""Blocks whose sizes differ by more than this factor get a :class:`MixedUnitsWarning`."""
DENSITY_RATIO = 500.0
"""Blocks whose densities differ by more than this factor get a :class:`MixedUnitsWarning`
(masses follow from sizes and densities; a thin plate's small mass is no units mistake)."""


LARGE_BLOCK = 100.0
"""Scenes whose median block is larger than this [m] get a :class:`MixedUnitsWarning` (a
scene typed in mm: 200 x 200 x 400 "m" blocks)."""
LIGHT_DENSITY = 10.0
"""Scenes whose median density is below this [kg/m^3] get a :class:`MixedUnitsWarning` (a
density typed in t/m^3)."""


class MixedUnitsWarning(UserWarning):
    """Block sizes or densities (hence masses) differ by orders of magnitude, or are far from
    any masonry or TIS scene in SI units: a block typed in mm among blocks in m, a whole scene
    in mm, a density in t/m^3. Filter it when the scene is meant so."""


def check_finite(**params) -> None:
    """Raise ValueError naming the first parameter that holds a NaN or an infinity.

    Parameters
    ----------
    **params
        Numbers or (nested) sequences of numbers, by name; None and non-numeric values are
        skipped (their own checks apply).
    """
    for name, value in params.items():
        if value is None:
            continue
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            continue
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite (no NaN or inf), got {value!r}")


def warn_mixed_units(blocks: Sequence[ConvexBlock], density: np.ndarray) -> None:
    """Warn, naming the blocks, when sizes differ by more than :data:`SIZE_RATIO` or
    densities by more than :data:`DENSITY_RATIO`, or when the typical block is larger than
    :data:`LARGE_BLOCK` or lighter than :data:`LIGHT_DENSITY` (a scene typed in mm, a density
    in t/m^3)."""
    size = np.array([b.size for b in blocks])
    typical_size, typical_density = float(np.median(size)), float(np.median(density))
    for far, what in (
        (typical_size > LARGE_BLOCK, f"the median block is {typical_size:.3g} m across"),
        (typical_density < LIGHT_DENSITY, f"the median density is {typical_density:.3g} kg/m^3"),
    ):
        if far:
            warnings.warn(
                f"{what}: is the scene in SI units (m, kg/m^3), not mm or t/m^3?",
                MixedUnitsWarning,
                stacklevel=4,
            )
    for what, values, unit, limit in (
        ("size", size, "m", SIZE_RATIO),
        ("density", density, "kg/m^3", DENSITY_RATIO),
    ):
        big, small = int(np.argmax(values)), int(np.argmin(values))
        if values[big] > limit * values[small]:
            warnings.warn(
                f"block {big} ({what} {values[big]:.3g} {unit}) and block {small} "
                f"({what} {values[small]:.3g} {unit}) differ by a factor "
                f"{values[big] / values[small]:.3g}: are they in the same units (m, kg/m^3)?",
                MixedUnitsWarning,
                stacklevel=4,
            )
            return


@dataclass(frozen=True, eq=False)
class BlockArrays:
    """Flat arrays of all block geometry for numba kernels (CSR-style offsets).

    Attributes
    ----------
    vert_ptr : (n_blocks + 1,) int64
        Block ``i`` has vertices ``vertices[vert_ptr[i]:vert_ptr[i + 1]]``.
    vertices : (n_vert, 3) float64
        [m].
    face_ptr : (n_blocks + 1,) int64
        Block ``i`` has faces ``face_ptr[i]:face_ptr[i + 1]``.
    face_normal : (n_faces, 3) float64
        Outward unit normals.
    face_offset : (n_faces,) float64
        ``n . x = d`` on the face [m].
    face_vert_ptr : (n_faces + 1,) int64
        Face ``f`` has corners ``face_vert[face_vert_ptr[f]:face_vert_ptr[f + 1]]``.
    face_vert : (n_corner,) int64
        Global indices into ``vertices``, counter-clockwise seen from outside.
    """

    vert_ptr: np.ndarray
    vertices: np.ndarray
    face_ptr: np.ndarray
    face_normal: np.ndarray
    face_offset: np.ndarray
    face_vert_ptr: np.ndarray
    face_vert: np.ndarray


def per_block(name: str, value, n_blocks: int) -> np.ndarray:
    """``value`` as a ``(n_blocks,)`` float array: one number for every block, or one each.

    Strings and booleans are refused (``"0.6"`` is not silently read as 0.6).
    """
    try:
        raw = np.asarray(value)
        arr = raw.astype(float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a number or one number per block, got {value!r}") from exc
    if raw.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be a number or one number per block, got {value!r}")
    if arr.ndim == 0:
        return np.full(n_blocks, float(arr))
    if arr.shape != (n_blocks,):
        raise ValueError(
            f"{name} must be one number or one per block ({n_blocks} blocks), "
            f"got shape {arr.shape}: got {arr.size} values"
        )
    return arr.copy()


@dataclass(frozen=True, eq=False)
class Assembly:
    """Convex rigid blocks with their density and (optional) friction coefficient.

    Attributes
    ----------
    blocks : tuple of ConvexBlock
    density : (n_blocks,) float
        [kg/m^3].
    mu : (n_blocks,) float or None
        Friction coefficient of each block's surface [-]; None when the scene leaves friction
        to the solver settings. How two blocks' values combine is the solver's documented rule.
    """

    blocks: tuple[ConvexBlock, ...]
    density: np.ndarray
    mu: np.ndarray | None = None

    def __post_init__(self):
        n = len(self.blocks)
        if n == 0:
            raise ValueError("an assembly needs at least one block")
        density = per_block("density", self.density, n)
        if not np.all(np.isfinite(density)) or np.any(density <= 0):
            raise ValueError("density must be finite and positive for every block [kg/m^3]")
        object.__setattr__(self, "density", density)
        if self.mu is not None:
            mu = per_block("mu", self.mu, n)
            if np.any(np.isnan(mu)) or np.any(mu < 0):
                raise ValueError(
                    "friction coefficient mu must be >= 0 for every block (inf: no sliding)"
                )
            object.__setattr__(self, "mu", mu)
        warn_mixed_units(self.blocks, density)

    @classmethod
    def from_convex_blocks(
        cls,
        vertex_arrays: Iterable[np.ndarray],
        density: float | Sequence[float],
        mu: float | Sequence[float] | None = None,
        exact: bool = True,
    ) -> Assembly:
        """Blocks from a list of vertex arrays, each the corners of one convex block.

        Parameters
        ----------
        vertex_arrays : iterable of (n_i, 3) array_like
            [m].
        density : float or (n_blocks,)
            [kg/m^3].
        mu : float or (n_blocks,), optional
            Friction coefficient [-].
        exact : bool
            Require each vertex list to be exactly the corners of a convex block (see
            :func:`convex_block`), so that a non-convex block, or a point inside, raises
            instead of being replaced by its convex hull. Pass False to accept the hull.
        """
        blocks = []
        for i, v in enumerate(vertex_arrays):
            try:
                blocks.append(convex_block(v, exact=exact))
            except ValueError as exc:
                raise ValueError(f"block {i}: {exc}") from exc
        return cls(tuple(blocks), density, mu)

    @property
    def n_blocks(self) -> int:
        return len(self.blocks)

    @cached_property
    def volume(self) -> np.ndarray:
        """(n_blocks,) [m^3]."""
        return np.array([b.volume for b in self.blocks])

    @cached_property
    def mass(self) -> np.ndarray:
        """(n_blocks,) [kg]."""
        return self.volume * self.density

    @cached_property
    def centroid(self) -> np.ndarray:
        """(n_blocks, 3) [m]."""
        return np.array([b.centroid for b in self.blocks])

    @cached_property
    def inertia(self) -> np.ndarray:
        """(n_blocks, 3, 3) inertia tensors about the centroids [kg m^2]."""
        return np.array([b.inertia * rho for b, rho in zip(self.blocks, self.density, strict=True)])

    @cached_property
    def arrays(self) -> BlockArrays:
        """Flat geometry arrays for numba kernels."""
        nv = np.array([len(b.vertices) for b in self.blocks])
        nf = np.array([len(b.faces) for b in self.blocks])
        vert_ptr = np.concatenate([[0], np.cumsum(nv)]).astype(np.int64)
        faces = [f + vert_ptr[i] for i, b in enumerate(self.blocks) for f in b.faces]
        return BlockArrays(
            vert_ptr=vert_ptr,
            vertices=np.ascontiguousarray(np.concatenate([b.vertices for b in self.blocks])),
            face_ptr=np.concatenate([[0], np.cumsum(nf)]).astype(np.int64),
            face_normal=np.ascontiguousarray(np.concatenate([b.normals for b in self.blocks])),
            face_offset=np.concatenate([b.offsets for b in self.blocks]),
            face_vert_ptr=np.concatenate([[0], np.cumsum([len(f) for f in faces])]).astype(
                np.int64
            ),
            face_vert=np.concatenate(faces).astype(np.int64),
        )

    def interfaces(self, rel_tol: float | None = None) -> Interfaces:
        """Face-to-face interfaces (see :func:`dem.geometry.interfaces.find_interfaces`)."""
        if rel_tol is None:
            return self._interfaces
        return find_interfaces(self.blocks, rel_tol)

    @cached_property
    def _interfaces(self) -> Interfaces:
        return find_interfaces(self.blocks)


def _kind(x) -> str:
    if isinstance(x, bool | np.bool_):
        return "bool"
    if isinstance(x, int | np.integer):
        return "int"
    return type(x).__name__


def fixed_mask(n_blocks: int, fixed) -> np.ndarray:
    """``(n_blocks,)`` bool mask from block indices or a boolean mask.

    Parameters
    ----------
    n_blocks : int
    fixed : sequence of int, or sequence of bool of length ``n_blocks``
        Integer indices (``numpy`` integers included), or booleans, one per block. Floats,
        strings, a mix of booleans and integers, or a mask of another length are errors.
    """
    if isinstance(fixed, np.ndarray) and fixed.ndim != 1:
        raise ValueError(f"fixed must be one-dimensional, got shape {fixed.shape}")
    if isinstance(fixed, str | bytes) or not isinstance(fixed, Iterable):
        raise ValueError(
            f"fixed must be a list of block indices (or a boolean mask of length {n_blocks}), "
            f"e.g. fixed=[0]; got {fixed!r}"
        )
    items = list(fixed)
    kinds = {_kind(x) for x in items}
    mask = np.zeros(n_blocks, dtype=bool)
    if not items:
        return mask
    if kinds == {"bool"}:
        if len(items) != n_blocks:
            raise ValueError(
                f"fixed given as booleans is a mask and needs one per block ({n_blocks}), "
                f"got {len(items)}; give integer indices to fix single blocks"
            )
        return np.array(items, dtype=bool)
    if kinds != {"int"}:
        raise ValueError(
            "fixed must hold integer block indices or booleans (a mask of length "
            f"{n_blocks}), got {sorted(kinds)} values: {items[:10]}"
        )
    ids = np.array(items, dtype=np.int64)
    if ids.min() < 0 or ids.max() >= n_blocks:
        raise ValueError(f"fixed block index out of range 0..{n_blocks - 1}: {ids.tolist()}")
    mask[ids] = True
    return mask


@dataclass(frozen=True, eq=False)
class Supports:
    """Which blocks or block dofs are held fixed.

    Attributes
    ----------
    fixed : (n_blocks,) bool
        Blocks held in place entirely (foundations, frames, return walls modelled as rigid).
    restrained : (n_blocks, 6) bool
        Single restrained dofs ``(ux, uy, uz, rx, ry, rz)`` of otherwise free blocks, e.g. the
        out-of-plane translation of the blocks along a simply supported edge.
    """

    fixed: np.ndarray
    restrained: np.ndarray

    def __post_init__(self):
        for name in ("fixed", "restrained"):
            arr = np.asarray(getattr(self, name))
            if arr.dtype != bool:
                raise ValueError(
                    f"supports.{name} must be a boolean array, got dtype {arr.dtype}: "
                    "use Supports.fixed_blocks(n_blocks, indices or mask) for fixed blocks"
                )
            object.__setattr__(self, name, arr)

    @classmethod
    def none(cls, n_blocks: int) -> Supports:
        return cls(np.zeros(n_blocks, dtype=bool), np.zeros((n_blocks, 6), dtype=bool))

    @classmethod
    def fixed_blocks(cls, n_blocks: int, fixed: Iterable[int] | Sequence[bool]) -> Supports:
        """Blocks held in place, given as integer indices or as a boolean mask of length
        ``n_blocks`` (see :func:`fixed_mask`)."""
        return cls(fixed_mask(n_blocks, fixed), np.zeros((n_blocks, 6), dtype=bool))

    @property
    def free_dofs(self) -> np.ndarray:
        """(n_blocks, 6) bool: dofs that are unknowns of a solver."""
        return ~self.fixed[:, None] & ~self.restrained

    @property
    def has_any(self) -> bool:
        return bool(self.fixed.any() or self.restrained.any())


@dataclass(frozen=True, eq=False)
class Loads:
    """Dead and live loads on the blocks.

    Attributes
    ----------
    gravity : (3,) float
        Acceleration of self weight [m/s^2], part of the dead load.
    dead_wrench : (n_blocks, 6) float
        Further dead forces at the centroids and moments about them [N, N m] (e.g. beams).
    live_wrench : (n_blocks, 6) float
        The live-load pattern, scaled by the load multiplier lambda [N, N m].
    """

    gravity: np.ndarray
    dead_wrench: np.ndarray
    live_wrench: np.ndarray

    @classmethod
    def gravity_only(cls, n_blocks: int, g: float = G) -> Loads:
        zero = np.zeros((n_blocks, 6))
        return cls(np.array([0.0, 0.0, -g]), zero, zero.copy())


def weight_wrench(assembly: Assembly, gravity: np.ndarray) -> np.ndarray:
    """(n_blocks, 6) self weight ``m g`` at each centroid [N]."""
    out = np.zeros((assembly.n_blocks, 6))
    out[:, :3] = assembly.mass[:, None] * np.asarray(gravity, dtype=float)
    return out


def proportional_to_weight(
    assembly: Assembly, direction: Sequence[float], g: float = G
) -> np.ndarray:
    """(n_blocks, 6) live pattern: each block's weight ``m g`` acting along ``direction`` [N]."""
    d = np.asarray(direction, dtype=float)
    if d.shape != (3,) or not np.isfinite(d).all() or np.linalg.norm(d) == 0:
        raise ValueError(f"load direction must be a finite non-zero 3-vector, got {direction}")
    return weight_wrench(assembly, g * d / np.linalg.norm(d))


def uniform_pressure(
    assembly: Assembly, direction: Sequence[float], blocks: Iterable[int] | None = None
) -> np.ndarray:
    """(n_blocks, 6) unit pressure (1 Pa) pushing along ``direction`` on the loaded faces.

    The loaded faces of a block are those whose outward normal is ``-direction``; each gets
    the force ``area * direction`` [N] at its centroid, moved to the block centroid.
    """
    d = np.asarray(direction, dtype=float)
    if d.shape != (3,) or not np.isfinite(d).all() or np.linalg.norm(d) == 0:
        raise ValueError(f"pressure direction must be a finite non-zero 3-vector, got {direction}")
    d = d / np.linalg.norm(d)
    out = np.zeros((assembly.n_blocks, 6))
    ids = range(assembly.n_blocks) if blocks is None else list(blocks)
    bad = [i for i in ids if not isinstance(i, int | np.integer) or not 0 <= i < assembly.n_blocks]
    if bad:
        raise ValueError(f"blocks must be block indices 0..{assembly.n_blocks - 1}, got {bad[:10]}")
    for i in ids:
        blk = assembly.blocks[i]
        for face, normal in zip(blk.faces, blk.normals, strict=True):
            if normal @ d > -1.0 + 1e-9:
                continue
            t1, t2 = plane_basis(normal)
            pts = blk.vertices[face]
            area, c2, _ = polygon_properties((pts - pts[0]) @ np.stack([t1, t2]).T)
            centre = pts[0] + c2 @ np.stack([t1, t2])
            out[i, :3] += area * d
            out[i, 3:] += np.cross(centre - blk.centroid, area * d)
    return out


def point_load(
    assembly: Assembly, block: int, point: Sequence[float], force: Sequence[float]
) -> np.ndarray:
    """(n_blocks, 6) a force [N] applied at ``point`` [m] of one block, moved to its centroid."""
    if not isinstance(block, int | np.integer) or not 0 <= block < assembly.n_blocks:
        raise ValueError(f"block index {block!r} out of range 0..{assembly.n_blocks - 1}")
    check_finite(point=point, force=force)
    out = np.zeros((assembly.n_blocks, 6))
    f = np.asarray(force, dtype=float)
    out[block, :3] = f
    out[block, 3:] = np.cross(np.asarray(point, dtype=float) - assembly.centroid[block], f)
    return out


def _json_bools(name: str, value, shape: tuple) -> np.ndarray:
    """A JSON array of true/false of the given shape (nothing else is read as a boolean)."""
    arr = np.array(value, dtype=object)
    if arr.shape != shape or not all(isinstance(x, bool) for x in arr.ravel()):
        raise ValueError(
            f"scene JSON field {name!r} must be an array of true/false of shape {shape}, "
            f"got {str(value)[:80]}"
        )
    return arr.astype(bool)


def _json_floats(name: str, value, shape: tuple) -> np.ndarray:
    """A JSON array of numbers of the given shape (strings and booleans are refused)."""
    arr = np.array(value, dtype=object)
    if arr.shape != shape or not all(
        isinstance(x, Real) and not isinstance(x, bool) for x in arr.ravel()
    ):
        raise ValueError(
            f"scene JSON field {name!r} must be an array of numbers of shape {shape}, "
            f"got {str(value)[:80]}"
        )
    return arr.astype(float)


JSON_FIELDS = (
    "blocks",
    "density",
    "mu",
    "fixed",
    "restrained",
    "gravity",
    "dead_wrench",
    "live_wrench",
)
"""Fields every scene JSON holds (see :meth:`Scene.to_dict`)."""


@dataclass(frozen=True, eq=False)
class Scene:
    """Blocks, supports and loads: the input of every solver.

    Attributes
    ----------
    assembly : Assembly
    supports : Supports
    loads : Loads
    name : str
    meta : dict
        The builder's parameters in paper units, for the record.
    """

    assembly: Assembly
    supports: Supports
    loads: Loads
    name: str = "scene"
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        n = self.assembly.n_blocks
        checks = {
            "supports.fixed": (self.supports.fixed, (n,)),
            "supports.restrained": (self.supports.restrained, (n, 6)),
            "loads.gravity": (self.loads.gravity, (3,)),
            "loads.dead_wrench": (self.loads.dead_wrench, (n, 6)),
            "loads.live_wrench": (self.loads.live_wrench, (n, 6)),
        }
        for name, (arr, shape) in checks.items():
            if np.shape(arr) != shape:
                raise ValueError(f"{name} must have shape {shape}, got {np.shape(arr)}")
        for name in ("gravity", "dead_wrench", "live_wrench"):
            if not np.all(np.isfinite(getattr(self.loads, name))):
                raise ValueError(f"loads.{name} contains NaN or inf")

    @classmethod
    def from_convex_blocks(
        cls,
        vertex_arrays: Iterable[np.ndarray],
        density: float | Sequence[float],
        fixed: Iterable[int] | Sequence[bool] = (),
        mu: float | Sequence[float] | None = None,
        g: float = G,
        name: str = "scene",
    ) -> Scene:
        """A scene under self weight from user blocks; add live loads with :meth:`with_loads`."""
        assembly = Assembly.from_convex_blocks(vertex_arrays, density, mu)
        n = assembly.n_blocks
        return cls(assembly, Supports.fixed_blocks(n, fixed), Loads.gravity_only(n, g), name)

    @property
    def n_blocks(self) -> int:
        return self.assembly.n_blocks

    @property
    def free_blocks(self) -> np.ndarray:
        """(n_free,) int64 indices of blocks that are not fixed."""
        return np.flatnonzero(~self.supports.fixed)

    @property
    def dead_wrench(self) -> np.ndarray:
        """(n_blocks, 6) total dead load: self weight plus extra dead forces [N, N m]."""
        return weight_wrench(self.assembly, self.loads.gravity) + self.loads.dead_wrench

    def with_loads(
        self, *, dead: np.ndarray | None = None, live: np.ndarray | None = None
    ) -> Scene:
        """A copy with extra dead and/or live wrenches added (value semantics).

        Parameters
        ----------
        dead, live : (n_blocks, 6) array_like, optional
            Wrenches ``(Fx, Fy, Fz, Mx, My, Mz)`` at the block centroids [N, N m]; exactly
            this shape (nothing is broadcast).
        """
        loads = Loads(
            self.loads.gravity,
            self.loads.dead_wrench + self._wrench("dead", dead),
            self.loads.live_wrench + self._wrench("live", live),
        )
        return Scene(self.assembly, self.supports, loads, self.name, self.meta)

    def _wrench(self, name: str, value) -> np.ndarray | float:
        if value is None:
            return 0.0
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{name} must be a (n_blocks, 6) array of numbers: {exc}") from exc
        shape = (self.n_blocks, 6)
        if arr.shape != shape:
            raise ValueError(
                f"{name} must have shape {shape} (one wrench Fx, Fy, Fz, Mx, My, Mz per "
                f"block), got {arr.shape}"
            )
        return arr

    def with_supports(self, supports: Supports) -> Scene:
        return Scene(self.assembly, supports, self.loads, self.name, self.meta)

    # -- JSON -------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        a = self.assembly
        return {
            "name": self.name,
            "meta": self.meta,
            "blocks": [b.vertices.tolist() for b in a.blocks],
            "density": a.density.tolist(),
            "mu": None if a.mu is None else a.mu.tolist(),
            "fixed": self.supports.fixed.tolist(),
            "restrained": self.supports.restrained.tolist(),
            "gravity": self.loads.gravity.tolist(),
            "dead_wrench": self.loads.dead_wrench.tolist(),
            "live_wrench": self.loads.live_wrench.tolist(),
        }

    @classmethod
    def from_dict(cls, data: dict) -> Scene:
        """The scene of :meth:`to_dict`; a ValueError names missing or malformed fields."""
        if not isinstance(data, dict):
            raise ValueError(f"a scene must be a JSON object, got {type(data).__name__}")
        missing = [k for k in JSON_FIELDS if k not in data]
        if missing:
            raise ValueError(
                f"scene JSON is missing field(s) {missing}; a scene has {list(JSON_FIELDS)} "
                "(and optionally name, meta)"
            )
        assembly = Assembly.from_convex_blocks(data["blocks"], data["density"], data["mu"])
        n = assembly.n_blocks
        supports = Supports(
            _json_bools("fixed", data["fixed"], (n,)),
            _json_bools("restrained", data["restrained"], (n, 6)),
        )
        loads = Loads(
            _json_floats("gravity", data["gravity"], (3,)),
            _json_floats("dead_wrench", data["dead_wrench"], (n, 6)),
            _json_floats("live_wrench", data["live_wrench"], (n, 6)),
        )
        return cls(assembly, supports, loads, data.get("name", "scene"), data.get("meta", {}))

    def to_json(self, path: str | Path) -> None:
        Path(path).write_text(json.dumps(self.to_dict()))

    @classmethod
    def from_json(cls, path: str | Path) -> Scene:
        """Read a scene written by :meth:`to_json`; a ValueError names the file and the field."""
        try:
            return cls.from_dict(json.loads(Path(path).read_text()))
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from exc
