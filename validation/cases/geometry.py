"""Case `geometry`: the nine TIS panels of seed 000 and a running-bond wall against closed forms.

TIS closed forms are derived in :mod:`dem.scenes.tis_panel`: block volumes plus the pinwheel
voids fill the box, ``2 (n+1)(n+2)`` lateral interfaces of total area
``2 (n+1)^2 (l - t tan(theta)) t / cos(theta)``. The wall rows are hand counts.

Counts are exact (bar 0). Volumes and areas are exact formulas evaluated in float64: their bar
is a round-off bound (:func:`round_off_bound`) counted from the operations that make them,
never below the difference measured on a rigidly moved copy of the assembly
(:func:`validation.cases.bars.round_off`). A closed-form reference carries the rounding of its
own few operations (``reference_error``).
"""

from __future__ import annotations

import math
import time

import numpy as np

from dem.estimate import Estimate
from dem.geometry.interfaces import Interfaces
from dem.scene import Assembly
from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.tis_panel import tis_interface_area, tis_panel, tis_void_volume
from dem.units import MM, MM2, MM3
from validation.cases.bars import EPS, exact, moved_copy, round_off, sum_round_off
from validation.report import Row

SIZE_MM, THICKNESS_MM = 50.0, 3.18  # seed 000, Sec. 3

COORDINATE_OPS = 16
"""Floating-point operations behind each corner coordinate of a face or an interface polygon:
the scene's construction (4: a product and a sum of trigonometric terms), the projection on a
face plane (4: a difference and a 3-term dot product) and one Sutherland-Hodgman intersection
(8: two signed distances, their ratio, a point on the edge)."""
TRIPLE_PRODUCT_OPS = 6
"""Operations of a tetrahedron's volume ``a . (b x c) / 6`` beyond its corners."""
CLOSED_FORM_OPS = 10
"""An upper count of the operations of a closed form of this case (the interface area:
a tangent, a cosine, 2 products, a difference, a quotient and the product by 2 (n+1)^2)."""


def round_off_bound(boundary: float, extent: float, abs_terms: float, n_terms: int) -> float:
    r"""Bound on the float64 round-off of a measure (area, volume) computed from corners, in
    the unit of ``abs_terms``, by Higham's :math:`\gamma_n = n \epsilon` (Accuracy and
    Stability of Numerical Algorithms, 2nd ed., Sec. 3.1): each corner coordinate is off by at
    most :math:`\gamma_c\,` ``extent`` (``c`` = :data:`COORDINATE_OPS`, ``extent`` the largest
    coordinate magnitude), which moves the measure by at most ``boundary`` (the perimeters for
    areas, the surfaces for volumes) times that; the sums (shoelace or tetrahedra, then over
    interfaces or blocks) add :math:`\gamma_n \sum |t_i|`, ``n_terms`` counting every
    operation along the longest chain (:func:`validation.cases.bars.sum_round_off`)."""
    coordinates = boundary * COORDINATE_OPS * EPS * extent
    return coordinates + sum_round_off(abs_terms, n_terms)


def _extent(assembly: Assembly) -> float:
    return float(max(np.abs(b.vertices).max() for b in assembly.blocks))


def interface_area_bound(iface: Interfaces, extent: float) -> float:
    """:func:`round_off_bound` of the summed interface area [m^2]: the perimeters of the
    polygons, the absolute shoelace terms of each (about its first corner, as computed) and
    a chain of ``n_interfaces + corners + 1`` operations."""
    perimeter = abs_terms = 0.0
    corners = 0
    for k in range(iface.n_interfaces):
        p = iface.local_polygon(k)
        p = p - p[0]
        q = np.roll(p, -1, axis=0)
        perimeter += float(np.linalg.norm(q - p, axis=1).sum())
        abs_terms += 0.5 * float((np.abs(p[:, 0] * q[:, 1]) + np.abs(q[:, 0] * p[:, 1])).sum())
        corners = max(corners, len(p))
    return round_off_bound(perimeter, extent, abs_terms, iface.n_interfaces + corners + 1)


def volume_bound(assembly: Assembly, extent: float) -> float:
    """:func:`round_off_bound` of the summed block volume [m^3]: the block surfaces, the
    volumes (every tetrahedron about an inner point is positive) and a chain of
    ``n_blocks + triangles + TRIPLE_PRODUCT_OPS`` operations."""
    surface = 0.0
    triangles = 0
    for b in assembly.blocks:
        for f in b.faces:
            v = b.vertices[f]
            surface += 0.5 * float(np.linalg.norm(np.cross(v, np.roll(v, -1, axis=0)).sum(0)))
            triangles += len(f) - 2
    n_terms = len(assembly.blocks) + triangles + TRIPLE_PRODUCT_OPS
    return round_off_bound(surface, extent, float(np.abs(assembly.volume).sum()), n_terms)


def bounded(value: float, again: float, bound: float) -> Estimate:
    """``value`` with the round-off bar ``max(bound, |value - again|)``: the counted bound,
    never below the difference the moved copy shows."""
    measured = round_off(value, again)
    width = max(bound, measured.error)
    return Estimate(value, {"round-off": width}, notes=f"bound {bound:.3g}; {measured.notes}")


def closed_form_error(value: float) -> float:
    """The rounding of a closed form of this case evaluated in float64."""
    return CLOSED_FORM_OPS * EPS * abs(value)


def tis_rows(n: int, theta_deg: float) -> list[Row]:
    start = time.perf_counter()
    scene = tis_panel(n, theta_deg, SIZE_MM, THICKNESS_MM)
    iface = scene.assembly.interfaces()
    wall = time.perf_counter() - start
    moved = moved_copy(scene.assembly)
    theta, t, side = math.radians(theta_deg), THICKNESS_MM * MM, SIZE_MM * MM / (n + 1)
    label = f"{n}x{n} theta={theta_deg:g}"
    settings = {"n": n, "theta_deg": theta_deg, "size_mm": SIZE_MM, "thickness_mm": THICKNESS_MM}
    box = SIZE_MM**2 * THICKNESS_MM
    voids = tis_void_volume(n, theta, t) / MM3
    extent = _extent(scene.assembly)
    area = 2 * (n + 1) ** 2 * tis_interface_area(side, theta, t) / MM2
    return [
        Row(
            f"{label}: blocks",
            exact(scene.n_blocks),
            (n + 2) ** 2,
            "seed 000 Sec. 3: (n+2)^2",
            wall,
            settings,
        ),
        Row(
            f"{label}: block volume + voids [mm^3]",
            bounded(
                scene.assembly.volume.sum() / MM3 + voids,
                moved.volume.sum() / MM3 + voids,
                volume_bound(scene.assembly, extent) / MM3 + closed_form_error(voids),
            ),
            box,
            "closed form: 50 x 50 x 3.18 box",
            wall,
            settings,
            {"voids_mm3": voids},
            reference_error=closed_form_error(box),
        ),
        Row(
            f"{label}: lateral interfaces",
            exact(iface.n_interfaces),
            2 * (n + 1) * (n + 2),
            "closed form 2(n+1)(n+2)",
            wall,
            settings,
        ),
        Row(
            f"{label}: interface area [mm^2]",
            bounded(
                iface.area.sum() / MM2,
                moved.interfaces().area.sum() / MM2,
                interface_area_bound(iface, extent) / MM2,
            ),
            area,
            "closed form 2(n+1)^2 (l - t tan) t / cos",
            wall,
            settings,
            reference_error=closed_form_error(area),
        ),
    ]


def wall_rows() -> list[Row]:
    a, b, s = 81.0, 210.0, 70.0  # seed 001 Table 1 blocks [mm]
    start = time.perf_counter()
    scene = running_bond_wall(13, 6, a, b, s, 20.0, openings_mm=[(315.0, 162.0, 735.0, 405.0)])
    iface = scene.assembly.interfaces()
    wall = time.perf_counter() - start
    moved = moved_copy(scene.assembly)
    settings = {"n_per_course": 13, "n_courses": 6, "opening_mm": [315, 162, 735, 405]}
    # Courses 2-4 cross the opening (x 315-735 mm). Even courses lose [420, 630] and keep the
    # cut bricks [210, 315] and [735, 840]: 12 blocks; odd course 3 loses [315, 525] and
    # [525, 735]: 12 blocks. Head joints: 12 + 13 + 10 + 10 + 10 + 13 = 68. Bed-joint pieces
    # (b/2 long): 13 on the foundation, 26 between courses 0-1, 22 for each of the four
    # joints that border the opening (4 pieces missing), 127 in all.
    blocks_by_hand = 13 + 14 + 12 + 12 + 12 + 14 + 1
    interfaces_by_hand = 68 + 13 + 26 + 4 * 22
    return [
        Row(
            "wall 13x6 with opening: blocks",
            exact(scene.n_blocks),
            blocks_by_hand,
            "hand count",
            wall,
            settings,
        ),
        Row(
            "wall 13x6 with opening: volume [mm^3]",
            bounded(
                scene.assembly.volume.sum() / MM3,
                moved.volume.sum() / MM3,
                volume_bound(scene.assembly, _extent(scene.assembly)) / MM3,
            ),
            (13 * b * 6 * a - 420 * 243 + 13 * b * a) * s,
            "closed form (integers: exact)",
            wall,
            settings,
        ),
        Row(
            "wall 13x6 with opening: interfaces",
            exact(iface.n_interfaces),
            interfaces_by_hand,
            "hand count",
            wall,
            settings,
        ),
    ]


def run(quick: bool) -> tuple[list[Row], str]:
    rows = [r for n in (3, 5, 7) for th in (2.5, 5.0, 7.5) for r in tis_rows(n, th)]
    rows += wall_rows()
    notes = (
        "TIS panels: seed 000 Sec. 3 (50 x 50 x 3.18 mm, n x n internal blocks, half and quarter "
        "boundary blocks). The construction and its closed forms are derived in the docstring of "
        "`dem.scenes.tis_panel`. Each grid vertex leaves a pinwheel void of side 2 z tan(theta). "
        "Quick and full modes are the same (geometry is cheap)."
    )
    return rows, notes


CASES = {"geometry": run}
