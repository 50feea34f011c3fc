"""Stress maps of the blocks (largest principal stress): TIS panel at peak, wall at collapse.

Reads only ``validation/results/fem-tis-stress.{json,vtu}`` and
``validation/results/fem-masonry-stress.{json,vtu}`` (run ``python -m validation run
fem-tis-stress`` / ``fem-masonry-stress`` first; ``*.vtu`` files are not committed); never
solves. Writes ``paper_figures/out/fig_fem_tis_stress.png`` and
``paper_figures/out/fig_fem_masonry_stress.png``. The title says which state was drawn (the
DEM state, or the labelled synthetic admissible state when the DEM state is missing or
unbalanced).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from validation.report import reading_dir

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
OUT = Path(__file__).resolve().parent / "out"
CASES = {
    "fem-tis-stress": (
        "fig_fem_tis_stress.png",
        "5x5 TIS panel at peak load",
        (("from above", "xy", False), ("from below", "xy", True)),
    ),
    "fem-masonry-stress": (
        "fig_fem_masonry_stress.png",
        "masonry wall at collapse",
        (("front face (-y)", "xz", False), ("back face (+y)", "xz", True)),
    ),
}


def _state(case: str) -> str:
    data = json.loads((RESULTS / f"{case}.json").read_text())
    for row in data["rows"]:
        state = row.get("extra", {}).get("state")
        if state:
            return state
    return data.get("notes", "")[:80]


def draw(case: str) -> Path:
    """Largest principal stress on the block surfaces, seen from two opposite sides."""
    os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
    import pyvista as pv

    vtu = RESULTS / f"{case}.vtu"
    if not vtu.exists():
        raise FileNotFoundError(f"{vtu} is missing: run `python -m validation run {case}` first")
    png, what, views = CASES[case]
    grid = pv.read(str(vtu))
    mpa = np.asarray(grid.point_data["max_principal"]) / 1e6
    grid.point_data["largest principal stress [MPa]"] = mpa
    # colour range: tension up to the 99.5th percentile (point loads make singular peaks)
    top = float(np.percentile(np.abs(mpa), 99.5)) or 1.0
    surface = grid.extract_surface(algorithm="dataset_surface")
    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1800, 800))
    for col, (label, plane, negative) in enumerate(views):
        plotter.subplot(0, col)
        plotter.add_mesh(
            surface,
            scalars="largest principal stress [MPa]",
            cmap="coolwarm",
            clim=(-top, top),
            show_scalar_bar=col == 1,
        )
        getattr(plotter, f"view_{plane}")(negative=negative)
        plotter.add_text(f"{what}, {label}", font_size=10)
    plotter.subplot(0, 0)
    plotter.add_text(_state(case), position="lower_left", font_size=8)
    OUT.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(OUT / png))
    plotter.close()
    return OUT / png


def main() -> None:
    missing = []
    for case in CASES:
        try:
            print(draw(case))
        except FileNotFoundError as exc:
            missing.append(str(exc))
    if missing:
        raise FileNotFoundError("; ".join(missing))


if __name__ == "__main__":
    main()
