"""Running-bond wall with return walls built as real blocks (L- or U-shaped assemblies).

Seed 001 (Sec. 3.2) models the return walls of the Restrepo-Velez specimens by fixing a column
of blocks and blames that over-restraint for part of its mismatch. This builder offers the
alternative: the orthogonal walls are blocks that interlock with the main wall course by course
(corner bond), so a mechanism may drag blocks of the return walls along.

Axes as in :mod:`dem.scenes.running_bond_wall`: x along the main wall (``0 <= x <= L = n b``),
y out of plane (main wall ``-s/2 <= y <= s/2``), z up, foundation top at ``z = 0``. A return wall
at the left (right) end occupies ``0 <= x <= b/2`` (``L - b/2 <= x <= L``) and runs towards
``-y`` (behind the loaded face, as the side walls of a building stand behind a facade that falls
outward). Corner bond:

- even courses: the main wall's full end block covers the corner; the return wall starts
  behind it at ``y = -s/2``;
- odd courses: the return wall's end block covers the corner (``s/2 - b <= y <= s/2``) in place
  of the main wall's half block, so the head joints of the return wall are staggered by
  ``b - s``; a closer of length ``s`` ends the course flush with the even courses. (Without
  it, the last block of an even course would overhang by ``s``; with the Restrepo-Velez
  blocks, ``s`` just under ``b/2``, its centre of mass would sit 0.21 mm inside the edge of the
  block below.)

The return-wall blocks are ``b/2`` thick (instead of ``s``) so that the corner block of an odd
course fills exactly the half-block slot of the main wall; for the Restrepo-Velez blocks
(``b/2 = 39.89`` mm, ``s = 39.68`` mm) this thickens the return walls by 0.5 %.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from dem.scene import Loads, Scene, Supports, check_finite, proportional_to_weight
from dem.scenes.running_bond_wall import (
    beam_load_wrench,
    box_corners,
    check_sides,
    check_wall_numbers,
    course_spans,
    cut_openings,
    parse_openings,
    wall_assembly,
    wall_meta,
)
from dem.units import MM, G

SIDES = ("left", "right")
WALL_MAIN, WALL_LEFT, WALL_RIGHT, WALL_BASE = 0, 1, 2, -1


def wall_with_returns(
    n_per_course: int,
    n_courses: int,
    a_mm: float,
    b_mm: float,
    s_mm: float,
    unit_weight_kn_m3: float,
    mu: float | None = None,
    returns: Sequence[str] = ("left",),
    return_blocks: int = 3,
    beam_loads_kn: Sequence[tuple[float, float]] = (),
    openings_mm: Sequence[tuple[float, float, float, float]] = (),
    name: str = "wall_with_returns",
) -> Scene:
    """A running-bond wall with one or two return walls made of blocks, on a fixed foundation.

    Parameters
    ----------
    n_per_course, n_courses : int
        Blocks in an even course of the main wall and number of courses.
    a_mm, b_mm, s_mm : float
        Block height, length and thickness [mm].
    unit_weight_kn_m3 : float
        Unit weight of the blocks [kN/m^3].
    mu : float, optional
        Friction coefficient of the blocks.
    returns : subset of {"left", "right"}
        Ends of the main wall that carry a return wall ("left" gives an L, both a U).
    return_blocks : int
        Length of each return wall behind the main wall, in blocks (an even course holds this
        many full blocks behind the corner; every course ends at ``y = -s/2 - n b``).
    beam_loads_kn : sequence of (x, force)
        Dead downward forces [kN] at ``x`` [mm] on the top course of the main wall.
    openings_mm : sequence of (x0, z0, x1, z1)
        Rectangular openings in the main wall [mm], edges ``z`` on bed joints; blocks crossing
        a vertical edge are cut there. Openings must stay clear of the corners.

    Returns
    -------
    Scene
        Main-wall blocks, then return-wall blocks, then the foundation (one fixed box under the
        whole footprint). The live load is every free block's weight along +y (a tilting
        table). ``meta["wall"]`` labels blocks 0 (main), 1 (left return), 2 (right return),
        -1 (foundation); ``meta["course"]`` gives the course (-1 for the foundation).
    """
    check_wall_numbers(
        n_per_course, n_courses, a_mm, b_mm, s_mm, unit_weight_kn_m3, openings_mm, beam_loads_kn
    )
    n, nc, nr = _checked_options(n_per_course, n_courses, return_blocks, returns, b_mm, s_mm)
    a, b, s = a_mm * MM, b_mm * MM, s_mm * MM
    # openings keep clear of the corners, where the return walls bond in
    openings = parse_openings(openings_mm, a, (b, n * b - b), nc * a)
    corners, course, wall = _main_wall(n, nc, a, b, s, openings, returns)
    y_min = -s / 2 - nr * b
    for side in returns:
        blocks = _return_wall(side, nc, nr, a, b, s, n * b)
        corners += [c for c, _ in blocks]
        course += [k for _, k in blocks]
        wall += [WALL_LEFT if side == "left" else WALL_RIGHT] * len(blocks)
    corners.append(box_corners(0.0, n * b, y_min, s / 2, -a, 0.0))
    course.append(-1)
    wall.append(WALL_BASE)
    assembly = wall_assembly(corners, unit_weight_kn_m3, mu)
    wall_arr = np.array(wall)
    fixed = wall_arr == WALL_BASE
    supports = Supports(fixed, np.zeros((assembly.n_blocks, 6), dtype=bool))
    live = proportional_to_weight(assembly, (0.0, 1.0, 0.0))
    live[fixed] = 0.0
    top = np.flatnonzero((np.array(course) == nc - 1) & (wall_arr == WALL_MAIN))
    dead = beam_load_wrench(assembly, top, beam_loads_kn)
    loads = Loads(np.array([0.0, 0.0, -G]), dead, live)
    options = {"returns": list(returns), "return_blocks": nr, "return_thickness_mm": b / 2 / MM}
    numbers = (n, nc, a_mm, b_mm, s_mm, unit_weight_kn_m3)
    loads_meta = (openings_mm, beam_loads_kn, "weight")
    meta = wall_meta("wall_with_returns", numbers, options, loads_meta, course)
    meta["wall"] = wall
    return Scene(assembly, supports, loads, name, meta)


def _checked_options(n_per_course, n_courses, return_blocks, returns, b_mm, s_mm):
    """The block counts as integers, after a ``ValueError`` unless n_per_course >= 2,
    n_courses >= 1 and return_blocks >= 1 are whole numbers, ``returns`` names one or both
    sides and the blocks are longer than thick (the corner bond needs s < b)."""
    check_finite(return_blocks=return_blocks)
    n, nc, nr = int(n_per_course), int(n_courses), int(return_blocks)
    if n != n_per_course or n < 2 or nc != n_courses or nc < 1:
        raise ValueError(
            f"n_per_course >= 2 and n_courses >= 1 must be integers, got {n_per_course}, "
            f"{n_courses}"
        )
    if nr != return_blocks or nr < 1:
        raise ValueError(f"return_blocks must be a positive integer, got {return_blocks}")
    check_sides("returns", returns, SIDES)
    if not returns:
        raise ValueError(f"returns must be a non-empty subset of {SIDES}, got {list(returns)}")
    if s_mm * MM >= b_mm * MM:
        raise ValueError(f"the corner bond needs s < b, got s = {s_mm} mm, b = {b_mm} mm")
    return n, nc, nr


def _main_wall(n, nc, a, b, s, openings, returns):
    """Corners (8, 3) [m], courses and wall labels of the main wall's blocks; in odd courses
    the return walls' end blocks take the place of the half blocks at their corners."""
    corners, course = [], []
    for k in range(nc):
        spans = course_spans(n, b, k)
        if k % 2 == 1:
            spans = spans[1:] if "left" in returns else spans
            spans = spans[:-1] if "right" in returns else spans
        for xl, xr in cut_openings(spans, k, openings, 1e-9 * b):
            corners.append(box_corners(xl, xr, -s / 2, s / 2, k * a, (k + 1) * a))
            course.append(k)
    return corners, course, [WALL_MAIN] * len(corners)


def _return_wall(side: str, nc: int, nr: int, a: float, b: float, s: float, length: float):
    """(corners (8, 3) [m], course) of the blocks of the return wall at ``side``, course by
    course: even courses start behind the main wall's end block, odd ones cover the corner
    and end with a closer of length s, flush with the even ones."""
    xl, xr = (0.0, b / 2) if side == "left" else (length - b / 2, length)
    y_min = -s / 2 - nr * b
    out = []
    for k in range(nc):
        if k % 2 == 0:
            edges = [-s / 2 - i * b for i in range(nr + 1)]
        else:
            edges = [s / 2 - i * b for i in range(nr + 1)] + [y_min]
        for y_hi, y_lo in zip(edges[:-1], edges[1:], strict=True):
            out.append((box_corners(xl, xr, y_lo, y_hi, k * a, (k + 1) * a), k))
    return out
