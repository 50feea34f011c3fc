"""Geometric imperfections of a scene: face planes moved inward, box walls with jittered joints.

Both keep every block convex and every remaining contact exact, so that an imperfection is
real geometry that any solver sees, not a changed stiffness.

- :func:`offset_faces`: each face plane ``n . x = d`` of a block moves inward to
  ``n . x = d - delta`` (``delta >= 0``). Where two faces touched, a gap ``delta_a + delta_b``
  opens between them (measured along the normal). The new block is the intersection of its
  half-spaces (:func:`dem.geometry.polyhedron.clip_halfspace`).
- :func:`jitter_box_wall`: the blocks of a wall of axis-aligned boxes (a running-bond wall,
  with or without return walls) are mapped through monotone piecewise-linear maps: one of
  ``z`` for the whole wall (every bed joint moves by its own random amount), one of ``x`` and
  one of ``y`` per course (every head joint and face of a course moves by its own random
  amount). Two blocks that shared a face still share it, so the wall keeps every contact while
  each block's length, height and thickness scatter.
"""

from __future__ import annotations

import numpy as np

from dem.geometry.polyhedron import ConvexBlock, clip_halfspace, convex_block
from dem.scene import Assembly, Loads, Scene, proportional_to_weight

KNOT_DECIMALS = 9  # coordinates equal to 1 nm are the same joint [m]


def offset_faces(scene: Scene, offsets: list[np.ndarray], tag: str = "face offsets") -> Scene:
    """The scene with every face plane of every block moved inward by its offset.

    Parameters
    ----------
    scene : Scene
    offsets : list of (n_faces_i,) float
        ``offsets[i][f]`` >= 0 [m] moves face ``f`` of block ``i`` (in ``blocks[i].normals``
        order) to ``n . x = d - offset``.
    tag : str
        Recorded in ``meta["imperfection"]``.

    Returns
    -------
    Scene
        Same supports, loads, friction and density; ``meta["imperfection"]`` names it.
        Dead and live wrenches are kept as given (a block's weight follows its new volume
        through gravity).

    Raises
    ------
    ValueError
        Wrong number of blocks or faces, a negative or non-finite offset, or an offset that
        leaves no volume of a block.
    """
    blocks = scene.assembly.blocks
    if len(offsets) != len(blocks):
        raise ValueError(f"offsets for {len(offsets)} blocks, the scene has {len(blocks)}")
    new = []
    for i, (block, delta) in enumerate(zip(blocks, offsets, strict=True)):
        delta = np.asarray(delta, dtype=float)
        if delta.shape != (len(block.normals),):
            raise ValueError(f"block {i}: {delta.shape} offsets for {len(block.normals)} faces")
        if not np.all(np.isfinite(delta)) or np.any(delta < 0):
            raise ValueError(f"block {i}: face offsets must be finite and >= 0 [m], got {delta}")
        new.append(_shrink(block, delta, i))
    asm = scene.assembly
    meta = dict(scene.meta, imperfection=tag)
    return Scene(Assembly(tuple(new), asm.density, asm.mu), scene.supports, scene.loads,
                 scene.name, meta)  # fmt: skip


def _shrink(block: ConvexBlock, delta: np.ndarray, i: int) -> ConvexBlock:
    out = block
    for normal, d, dd in zip(block.normals, block.offsets, delta, strict=True):
        if dd == 0:
            continue
        out = clip_halfspace(out, normal, d - dd)
        if out is None:
            raise ValueError(f"block {i}: face offset {dd} m leaves no volume")
    return out


def interface_faces(scene: Scene) -> list[np.ndarray]:
    """(n_faces_i,) bool per block: the faces that carry an interface (touch another block)."""
    ifc = scene.assembly.interfaces()
    out = [np.zeros(len(b.normals), dtype=bool) for b in scene.assembly.blocks]
    for blocks, faces in ((ifc.block_a, ifc.face_a), (ifc.block_b, ifc.face_b)):
        for b, f in zip(blocks, faces, strict=True):
            out[int(b)][int(f)] = True
    return out


def uniform_contact_face_offsets(
    scene: Scene, max_offset: float, rng: np.random.Generator
) -> list[np.ndarray]:
    """Offsets ``U(0, max_offset)`` [m], independent for every face in contact, 0 elsewhere.

    An interface then opens a gap ``delta_a + delta_b`` with mean ``max_offset`` and the
    triangular density of the sum of two uniforms on ``[0, 2 max_offset]``.
    """
    if not (np.isfinite(max_offset) and max_offset >= 0):
        raise ValueError(f"max_offset must be finite and >= 0 [m], got {max_offset}")
    return [np.where(mask, rng.uniform(0.0, max_offset, mask.size), 0.0)
            for mask in interface_faces(scene)]  # fmt: skip


def jitter_box_wall(
    scene: Scene, sigma: tuple[float, float, float], rng: np.random.Generator
) -> Scene:
    """A wall of boxes with every joint and face position moved by ``N(0, sigma)``.

    Parameters
    ----------
    scene : Scene
        Blocks that are axis-aligned boxes, ``meta["course"]`` per block (-1 for the
        foundation, which stays as it is), and, if ``meta["live"] == "weight"``, a live load
        proportional to weight (recomputed for the new volumes, zero on fixed blocks).
    sigma : (3,) float
        Standard deviation of the knot positions along x, y (per course) and z (bed joints;
        ``z = 0``, the top of the foundation, stays) [m]. A block dimension, the difference of
        two knots, then has standard deviation ``sqrt(2) sigma``. Along y only the faces of
        the main wall (``meta["wall"] == 0``, or every block without that key) move.
    rng : numpy.random.Generator

    Returns
    -------
    Scene
        ``meta["imperfection"]`` records sigma.

    Notes
    -----
    The return walls of :func:`dem.scenes.return_walls.wall_with_returns` keep their block
    lengths along y: the top course of a return wall ends with a block whose centroid lies
    only ``b/2 - s`` inside the edge of the block below (0.21 mm for the Restrepo-Velez
    blocks), and a jitter there topples it under its own weight.

    Raises
    ------
    ValueError
        A block that is not an axis-aligned box, no ``course`` in the meta, or a jitter large
        enough to swap two knots.
    """
    course = np.asarray(scene.meta.get("course", []), dtype=int)
    blocks = scene.assembly.blocks
    if course.shape != (len(blocks),):
        raise ValueError("jitter_box_wall needs meta['course'] for every block")
    for i, b in enumerate(blocks):
        if len(b.vertices) != 8 or not np.allclose(np.abs(b.normals).max(axis=1), 1.0):
            raise ValueError(f"block {i} is not an axis-aligned box")
    sx, sy, sz = (float(s) for s in sigma)
    wall = course >= 0
    main = wall & (np.asarray(scene.meta.get("wall", np.zeros(len(blocks))), dtype=int) == 0)
    ids = np.flatnonzero(wall)
    z_map = _knot_map([blocks[i].vertices[:, 2] for i in ids], sz, rng, keep=(0.0,))
    maps = {}
    for k in np.unique(course[wall]):
        ids = np.flatnonzero(course == k)
        x_map = _knot_map([blocks[i].vertices[:, 0] for i in ids], sx, rng)
        # y: only the faces of the main wall (its thickness); see the Notes
        y_only = [blocks[i].vertices[:, 1] for i in ids if main[i]]
        y_map = _knot_map([blocks[i].vertices[:, 1] for i in ids], sy, rng, only=y_only)
        maps[k] = (x_map, y_map)
    new = []
    for i, b in enumerate(blocks):
        if course[i] < 0:
            new.append(b)
            continue
        v = b.vertices.copy()
        v[:, 0] = maps[course[i]][0](v[:, 0])
        v[:, 1] = maps[course[i]][1](v[:, 1])
        v[:, 2] = z_map(v[:, 2])
        lo, hi = v.min(axis=0), v.max(axis=0)
        new.append(_box(lo, hi))
    asm = Assembly(tuple(new), scene.assembly.density, scene.assembly.mu)
    loads = scene.loads
    if scene.meta.get("live") == "weight":
        live = proportional_to_weight(asm, _live_direction(scene))
        live[scene.supports.fixed] = 0.0
        loads = Loads(loads.gravity, loads.dead_wrench, live)
    meta = dict(scene.meta, imperfection={"jitter_sigma_m": [sx, sy, sz]})
    return Scene(asm, scene.supports, loads, scene.name, meta)


def _live_direction(scene: Scene) -> np.ndarray:
    live = scene.loads.live_wrench[:, :3].sum(axis=0)
    return live / np.linalg.norm(live)


def _box(lo: np.ndarray, hi: np.ndarray) -> ConvexBlock:
    corners = np.array([(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])  # fmt: skip
    return convex_block(corners, exact=True)


def _knot_map(coords: list[np.ndarray], sigma: float, rng: np.random.Generator, keep=(), only=None):
    """Piecewise-linear map that moves every distinct coordinate by ``N(0, sigma)``.

    ``keep``: values that stay; ``only``: if given, coordinates outside it stay too.
    """
    knots = np.unique(np.round(np.concatenate(coords), KNOT_DECIMALS))
    moved = knots + rng.normal(0.0, sigma, knots.size)
    fixed = np.isin(knots, np.round(np.asarray(keep, dtype=float), KNOT_DECIMALS))
    if only is not None:
        fixed |= ~np.isin(knots, np.round(np.concatenate(only), KNOT_DECIMALS))
    moved[fixed] = knots[fixed]
    if np.any(np.diff(moved) <= 0):
        raise ValueError(
            f"jitter sigma {sigma} m swaps two joints {np.min(np.diff(knots))} m apart: "
            "use a smaller sigma"
        )
    return lambda x: np.interp(np.round(x, KNOT_DECIMALS), knots, moved)
