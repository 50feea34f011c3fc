"""Compile the cached numba kernels in this process before parallel workers start.

numba's on-disk cache is not safe against processes that write it at the same time: two workers
that compile the same kernel (or new signatures of it) at once can leave an index that points at
the other's machine code, and every later process that loads it crashes (numba issues 4807 and
10128; here a segmentation fault in the explicit DEM's parallel node loop after ``pytest -n 2``
compiled a fresh cache). :func:`compile_kernels` runs tiny scenes through the static and explicit
solvers in one process, so that workers started afterwards load the cache instead of writing it.
"""

from __future__ import annotations

import logging
import time

from dem.scene import Scene, proportional_to_weight
from dem.scenes.running_bond_wall import box_corners


def _block_on_ground() -> Scene:
    """A 0.1 x 0.1 x 0.2 m block on a fixed base, pushed along x by its weight."""
    ground = box_corners(-0.3, 0.3, -0.3, 0.3, -0.1, 0.0)
    block = box_corners(-0.05, 0.05, -0.05, 0.05, 0.0, 0.2)
    scene = Scene.from_convex_blocks([block, ground], 2000.0, fixed=[1], mu=0.6)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def compile_kernels() -> float:
    """Run the static DEM (both laws) and the explicit DEM (indentation, serial and parallel
    node loops, and a lateral ramp) on tiny scenes; returns the wall time [s]. The solvers'
    warnings are held back meanwhile: the tiny runs end where they are cut short."""
    start = time.perf_counter()
    dem_logger = logging.getLogger("dem")
    level = dem_logger.level
    dem_logger.setLevel(logging.ERROR)
    try:
        _run_tiny_scenes()
    finally:
        dem_logger.setLevel(level)
    return time.perf_counter() - start


def _run_tiny_scenes() -> None:
    from dem.explicit import (
        ExplicitSettings,
        IndentationSettings,
        LiveLoadRamp,
        simulate_indentation,
        simulate_lateral,
    )
    from dem.scenes.tis_panel import tis_panel
    from dem.static import StaticSettings, solve_collapse
    from dem.tis_stiffness import tis_panel_k_def
    from dem.units import MM

    scene = _block_on_ground()
    for law in ("resultant", "fibre"):
        solve_collapse(scene, StaticSettings(interface_model=law, on_failure="return"))
    simulate_lateral(scene, driver=LiveLoadRamp(step=0.2, refinements=1))
    panel = tis_panel(3, 2.5)
    short = IndentationSettings(speed=50 * MM, max_deflection=0.01 * MM, record_interval=0.005 * MM)
    for parallel in (False, True):
        settings = ExplicitSettings(
            k_n=tis_panel_k_def(3), node_spacing=1.5 * MM, parallel=parallel
        )
        simulate_indentation(panel, settings, short)
