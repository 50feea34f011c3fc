"""One-leaf running-bond masonry wall (seed 001, Fig. 1) with the supports used in its tests.

Axes: x along the wall, y out of plane (wall mid-plane ``y = 0``), z up; the top of the
foundation is ``z = 0``. Course ``k`` spans ``k a <= z <= (k + 1) a``. Even courses hold
``n`` blocks of length ``b``; odd courses start and end with a half block, so the wall is
``L = n b`` long and the head joints of consecutive courses are offset by ``b / 2``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from dem.geometry.polyhedron import convex_block
from dem.scene import (
    Assembly,
    Loads,
    Scene,
    Supports,
    check_finite,
    point_load,
    proportional_to_weight,
    uniform_pressure,
)
from dem.units import KN, KN_M3, MM, G

SIDES = ("bottom", "top", "left", "right")


def check_sides(name: str, value, allowed: tuple[str, ...]) -> None:
    """Refuse ``value`` unless it is a collection of names from ``allowed`` (not one string:
    ``"left"`` is no collection of sides)."""
    if isinstance(value, str):
        raise ValueError(f"{name} must be a collection of sides, e.g. ({value!r},); got {value!r}")
    bad = sorted(set(value) - set(allowed))
    if bad:
        raise ValueError(f"{name} must be a subset of {allowed}, got {bad}")


LIVE_LOADS = ("weight", "pressure", "in_plane", "none")
OUT_OF_PLANE = 1  # index of uy among the block dofs


def box_corners(x0, x1, y0, y1, z0, z1) -> np.ndarray:
    """(8, 3) corners of the axis-aligned box ``[x0, x1] x [y0, y1] x [z0, z1]`` [m]."""
    return np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])


def course_spans(n: int, b: float, k: int) -> list[tuple[float, float]]:
    """x ranges ``(x0, x1)`` of the blocks of course ``k`` [m]."""
    if k % 2 == 0:
        return [(i * b, (i + 1) * b) for i in range(n)]
    edges = [0.0] + [b / 2 + i * b for i in range(n)] + [n * b]
    return list(zip(edges[:-1], edges[1:], strict=True))


Opening = tuple[float, float, int, int]
"""``(x0, x1, k0, k1)``: x range [m] and the courses ``k0 <= k < k1`` an opening spans."""


def parse_openings(
    openings_mm: Sequence[tuple[float, float, float, float]],
    a: float,
    x_range: tuple[float, float],
    height: float,
) -> list[Opening]:
    """Check rectangular openings ``(x0, z0, x1, z1)`` [mm] and turn them into course ranges.

    Raises ValueError when an opening leaves ``x_range`` or the wall height [m], or when its
    bottom or top is not on a bed joint (a multiple of the block height ``a`` [m]).
    """
    out = []
    for x0, z0, x1, z1 in openings_mm:
        x0, z0, x1, z1 = x0 * MM, z0 * MM, x1 * MM, z1 * MM
        if not (x_range[0] <= x0 < x1 <= x_range[1] and 0 <= z0 < z1 <= height):
            raise ValueError(
                f"opening {(x0 / MM, z0 / MM, x1 / MM, z1 / MM)} mm is not inside the wall "
                f"(x from {x_range[0] / MM:g} to {x_range[1] / MM:g} mm)"
            )
        for z in (z0, z1):
            if abs(z / a - round(z / a)) > 1e-9:
                raise ValueError(
                    f"opening edge z = {z / MM} mm is not on a bed joint (multiple of a)"
                )
        out.append((x0, x1, round(z0 / a), round(z1 / a)))
    return out


def cut_openings(
    spans: list[tuple[float, float]], k: int, openings: Sequence[Opening], tiny: float
) -> list[tuple[float, float]]:
    """Block x ranges of course ``k`` with the openings taken out; bricks crossing an
    opening's edge are cut there (pieces shorter than ``tiny`` [m] are dropped)."""
    for x0, x1, k0, k1 in openings:
        if not k0 <= k < k1:
            continue
        cut = []
        for xl, xr in spans:
            if xr <= x0 + tiny or xl >= x1 - tiny:
                cut.append((xl, xr))
                continue
            if x0 - xl > tiny:
                cut.append((xl, x0))
            if xr - x1 > tiny:
                cut.append((x1, xr))
        spans = cut
    return spans


def beam_load_wrench(
    assembly: Assembly, top_blocks: Sequence[int], beam_loads_kn: Sequence[tuple[float, float]]
) -> np.ndarray:
    """(n_blocks, 6) downward beam forces ``(x [mm], force [kN])`` on the top blocks [N, N m].

    Each force acts at ``x`` on the mid-plane of the top face of the top block under ``x``.
    """
    out = np.zeros((assembly.n_blocks, 6))
    for x_mm, force_kn in beam_loads_kn:
        x = x_mm * MM
        hit = [
            i
            for i in top_blocks
            if assembly.blocks[i].vertices[:, 0].min()
            <= x
            <= assembly.blocks[i].vertices[:, 0].max()
        ]
        if not hit:
            raise ValueError(f"beam load at x = {x_mm} mm is not above any top block")
        z_top = assembly.blocks[hit[0]].vertices[:, 2].max()
        out += point_load(assembly, hit[0], (x, 0.0, z_top), (0.0, 0.0, -force_kn * KN))
    return out


def check_wall_numbers(
    n_per_course, n_courses, a_mm, b_mm, s_mm, unit_weight_kn_m3, openings_mm, beam_loads_kn
) -> None:
    """Name the first of a wall builder's numbers that is NaN or infinite, then a block
    dimension or unit weight that is not positive (the counts are checked by the builder)."""
    check_finite(
        n_per_course=n_per_course,
        n_courses=n_courses,
        a_mm=a_mm,
        b_mm=b_mm,
        s_mm=s_mm,
        unit_weight_kn_m3=unit_weight_kn_m3,
        openings_mm=openings_mm,
        beam_loads_kn=beam_loads_kn,
    )
    for label, v in (
        ("a_mm", a_mm),
        ("b_mm", b_mm),
        ("s_mm", s_mm),
        ("unit_weight_kn_m3", unit_weight_kn_m3),
    ):
        if v <= 0:
            raise ValueError(f"{label} must be positive and finite, got {v}")


def wall_assembly(corners: list[np.ndarray], unit_weight_kn_m3: float, mu) -> Assembly:
    """Blocks of the given (8, 3) corner arrays [m] with unit weight [kN/m^3] and friction."""
    density = unit_weight_kn_m3 * KN_M3 / G
    return Assembly(tuple(convex_block(c) for c in corners), density, mu)


def wall_meta(builder: str, numbers: tuple, options: dict, loads: tuple, course: list) -> dict:
    """A wall builder's ``meta``: its name, ``numbers`` (n_per_course, n_courses, a_mm, b_mm,
    s_mm, unit_weight_kn_m3), its ``options``, ``loads`` (openings_mm, beam_loads_kn, live)
    and the blocks' courses."""
    n, nc, a_mm, b_mm, s_mm, unit_weight_kn_m3 = numbers
    openings_mm, beam_loads_kn, live = loads
    return {
        "builder": builder,
        "n_per_course": n,
        "n_courses": nc,
        "a_mm": a_mm,
        "b_mm": b_mm,
        "s_mm": s_mm,
        "unit_weight_kn_m3": unit_weight_kn_m3,
        **options,
        "openings_mm": [list(o) for o in openings_mm],
        "beam_loads_kn": [list(p) for p in beam_loads_kn],
        "live": live,
        "course": course,
    }


def running_bond_wall(
    n_per_course: int,
    n_courses: int,
    a_mm: float,
    b_mm: float,
    s_mm: float,
    unit_weight_kn_m3: float,
    mu: float | None = None,
    base: bool = True,
    fixed_columns: Sequence[str] = (),
    simply_supported: Sequence[str] = (),
    openings_mm: Sequence[tuple[float, float, float, float]] = (),
    beam_loads_kn: Sequence[tuple[float, float]] = (),
    live: str = "weight",
    name: str = "running_bond_wall",
) -> Scene:
    """A running-bond wall of ``n_courses`` courses of ``n_per_course`` blocks.

    Parameters
    ----------
    n_per_course, n_courses : int
        Blocks in an even course, and number of courses.
    a_mm, b_mm, s_mm : float
        Block height, length and thickness [mm].
    unit_weight_kn_m3 : float
        Unit weight of the blocks [kN/m^3]; density = unit weight / g.
    mu : float, optional
        Friction coefficient of the blocks.
    base : bool
        Add a fixed foundation block (the wall's length and thickness, height ``a``) under
        the first course.
    fixed_columns : subset of {"left", "right"}
        Fix the end block of every course on that side (the seed's model of return walls).
    simply_supported : subset of {"bottom", "top", "left", "right"}
        Restrain the out-of-plane translation ``uy`` of the blocks along that edge (first
        course, last course, or the end block of every course).
    openings_mm : sequence of (x0, z0, x1, z1)
        Rectangular openings [mm]; ``z0`` and ``z1`` must lie on bed joints. Blocks crossing an
        opening's vertical edges are cut there (cut bricks).
    beam_loads_kn : sequence of (x, force)
        Dead downward forces [kN] at ``x`` [mm] on top of the wall (beams), applied to the top
        block under ``x`` at the middle of its top face.
    live : {"weight", "pressure", "in_plane", "none"}
        Live load scaled by lambda: each free block's weight acting along +y
        (lambda dimensionless), a uniform pressure on the face ``y = -s/2`` pushing along
        +y (lambda in Pa), or each free block's weight along +x, in the wall's plane
        (lambda dimensionless).

    Returns
    -------
    Scene
        Wall blocks first, course by course from the left, then the foundation.
        ``meta["course"]`` gives each block's course (-1 for the foundation).
    """
    check_wall_numbers(
        n_per_course, n_courses, a_mm, b_mm, s_mm, unit_weight_kn_m3, openings_mm, beam_loads_kn
    )
    n, nc = _checked_options(n_per_course, n_courses, fixed_columns, simply_supported, live)
    a, b, s = a_mm * MM, b_mm * MM, s_mm * MM
    openings = parse_openings(openings_mm, a, (0.0, n * b), nc * a)
    corners, course, ends = _wall_courses(n, nc, a, b, s, openings)
    if base:
        corners.append(box_corners(0.0, n * b, -s / 2, s / 2, -a, 0.0))
        course.append(-1)
    assembly = wall_assembly(corners, unit_weight_kn_m3, mu)
    edge_blocks = _edge_blocks(np.array(course), ends, nc)
    supports = _wall_supports(np.array(course) == -1, edge_blocks, fixed_columns, simply_supported)
    dead = beam_load_wrench(assembly, edge_blocks["top"], beam_loads_kn)
    live_wrench = _live_wrench(assembly, live, supports.fixed)
    loads = Loads(np.array([0.0, 0.0, -G]), dead, live_wrench)
    options = {
        "base": base,
        "fixed_columns": list(fixed_columns),
        "simply_supported": list(simply_supported),
    }
    numbers = (n, nc, a_mm, b_mm, s_mm, unit_weight_kn_m3)
    loads_meta = (openings_mm, beam_loads_kn, live)
    meta = wall_meta("running_bond_wall", numbers, options, loads_meta, course)
    return Scene(assembly, supports, loads, name, meta)


def _checked_options(n_per_course, n_courses, fixed_columns, simply_supported, live):
    """The block counts as integers, after a ``ValueError`` naming a count that is no positive
    integer, an unknown side or live load."""
    n, nc = int(n_per_course), int(n_courses)
    if n != n_per_course or n < 1 or nc != n_courses or nc < 1:
        raise ValueError(
            f"n_per_course and n_courses must be positive integers, got {n_per_course}, {n_courses}"
        )
    check_sides("fixed_columns", fixed_columns, ("left", "right"))
    check_sides("simply_supported", simply_supported, SIDES)
    if live not in LIVE_LOADS:
        raise ValueError(f"live must be one of {LIVE_LOADS}, got {live!r}")
    return n, nc


def _wall_courses(n: int, nc: int, a: float, b: float, s: float, openings: Sequence[Opening]):
    """Corners (8, 3) [m] of the wall's blocks course by course from the left, their courses,
    and each course's first and last block (None for a course the openings empty)."""
    corners, course, ends = [], [], []
    for k in range(nc):
        spans = cut_openings(course_spans(n, b, k), k, openings, 1e-9 * b)
        first = len(corners)
        for xl, xr in spans:
            corners.append(box_corners(xl, xr, -s / 2, s / 2, k * a, (k + 1) * a))
            course.append(k)
        ends.append((first, len(corners) - 1) if spans else None)
    return corners, course, ends


def _edge_blocks(course: np.ndarray, ends: list, nc: int) -> dict[str, np.ndarray]:
    """Blocks along each side of the wall: first and last course, end blocks of every course."""
    return {
        "bottom": np.flatnonzero(course == 0),
        "top": np.flatnonzero(course == nc - 1),
        "left": np.array([e[0] for e in ends if e is not None]),
        "right": np.array([e[1] for e in ends if e is not None]),
    }


def _wall_supports(foundation, edge_blocks: dict, fixed_columns, simply_supported) -> Supports:
    """The foundation (bool mask) and the end columns ``fixed_columns`` fixed; ``uy``
    restrained along the ``simply_supported`` edges (blocks of each side in ``edge_blocks``)."""
    fixed = np.array(foundation, dtype=bool)
    restrained = np.zeros((len(fixed), 6), dtype=bool)
    for side in fixed_columns:
        fixed[edge_blocks[side]] = True
    for side in simply_supported:
        restrained[edge_blocks[side], OUT_OF_PLANE] = True
    restrained[fixed] = False
    return Supports(fixed, restrained)


def _live_wrench(assembly: Assembly, live: str, fixed: np.ndarray) -> np.ndarray:
    """(n_blocks, 6) live pattern of :func:`running_bond_wall`, zero on fixed blocks."""
    if live == "weight":
        out = proportional_to_weight(assembly, (0.0, 1.0, 0.0))
    elif live == "in_plane":
        out = proportional_to_weight(assembly, (1.0, 0.0, 0.0))
    elif live == "pressure":
        out = uniform_pressure(assembly, (0.0, 1.0, 0.0), np.flatnonzero(~fixed))
    else:
        out = np.zeros((assembly.n_blocks, 6))
    out[fixed] = 0.0
    return out
