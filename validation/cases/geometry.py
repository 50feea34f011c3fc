"""Case `geometry`: the nine TIS panels of seed 000 and a running-bond wall against closed forms.

TIS closed forms are derived in :mod:`dem.scenes.tis_panel`: block volumes plus the pinwheel
voids fill the box, ``2 (n+1)(n+2)`` lateral interfaces of total area
``2 (n+1)^2 (l - t tan(theta)) t / cos(theta)``. The wall rows are hand counts.

Counts are exact (bar 0). Volumes and areas are exact formulas evaluated in float64: their bar
is the round-off, measured on a rigidly moved copy of the assembly
(:func:`validation.cases.bars.round_off`).
"""

from __future__ import annotations

import math
import time

from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.tis_panel import tis_interface_area, tis_panel, tis_void_volume
from dem.units import MM, MM2, MM3
from validation.cases.bars import exact, moved_copy, round_off
from validation.report import Row

SIZE_MM, THICKNESS_MM = 50.0, 3.18  # seed 000, Sec. 3


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
            round_off(scene.assembly.volume.sum() / MM3 + voids, moved.volume.sum() / MM3 + voids),
            box,
            "closed form: 50 x 50 x 3.18 box",
            wall,
            settings,
            {"voids_mm3": voids},
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
            round_off(iface.area.sum() / MM2, moved.interfaces().area.sum() / MM2),
            2 * (n + 1) ** 2 * tis_interface_area(side, theta, t) / MM2,
            "closed form 2(n+1)^2 (l - t tan) t / cos",
            wall,
            settings,
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
            round_off(scene.assembly.volume.sum() / MM3, moved.volume.sum() / MM3),
            (13 * b * 6 * a - 420 * 243 + 13 * b * a) * s,
            "closed form",
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
