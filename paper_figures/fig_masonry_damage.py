"""Collapse mechanisms and damage maps of seed 001 masonry specimens (Figs. 13, 15-18, 20-21).

Reads only ``validation/results/masonry/*.npz`` and the scenes saved beside them (run the
``masonry-*`` validation cases first) and writes ``paper_figures/out/fig_masonry_damage_*.png``
with pyvista off screen: the blocks displaced by the collapse mechanism (exaggerated) and the
interfaces coloured by state at collapse: green elastic, red shear (sliding / torsion),
magenta flexural (rocking hinge), blue crushed (compressive strength reached), grey detached.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from validation.report import reading_dir

os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
RUNS = RESULTS / "masonry"
OUT = Path(__file__).resolve().parent / "out"
COLOURS = {
    "elastic": "green",
    "shear": "red",
    "flexural": "magenta",
    "crushed": "blue",
    "detached": "lightgrey",
}
MAX_FIGURES = 20


def _label(state: int) -> str:
    # bits of dem.static's interface states: 1 shear, 2 flexure, 8 crushed; 4 detached
    if state == 4:
        return "detached"
    if state & 8:
        return "crushed"
    if state & 2:
        return "flexural"
    if state & 1:
        return "shear"
    return "elastic"


def _render(npz: Path, out: Path) -> None:
    import pyvista as pv

    from dem.scene import Scene

    with np.load(npz) as data:
        arr = {k: data[k] for k in data.files}
    scene = Scene.from_json(RESULTS.parent.parent / str(arr["scene_json"]))
    itf = scene.assembly.interfaces()
    mech = arr["mechanism"]
    size = np.ptp(np.concatenate([b.vertices for b in scene.assembly.blocks]), axis=0).max()
    amp = 0.08 * size  # largest mechanism translation drawn as 8 % of the specimen
    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1400, 650))
    plotter.subplot(0, 0)
    for i, blk in enumerate(scene.assembly.blocks):
        if scene.supports.fixed[i] and np.array(scene.meta.get("course", [0] * 10**6))[i] < 0:
            continue
        c = scene.assembly.centroid[i]
        u, r = mech[i, :3], mech[i, 3:]
        pts = blk.vertices + amp * (u + np.cross(r, blk.vertices - c))
        faces = np.concatenate([[len(f), *f] for f in blk.faces])
        mesh = pv.PolyData(pts, faces)
        colour = "dimgrey" if scene.supports.fixed[i] else "tan"
        plotter.add_mesh(mesh, color=colour, show_edges=True, edge_color="black", line_width=0.5)
    plotter.add_text("collapse mechanism (exaggerated)", font_size=9)
    plotter.view_vector((0.6, -1.0, 0.5))
    plotter.subplot(0, 1)
    state = arr["interface_state"]
    for label, colour in COLOURS.items():
        ids = [k for k in range(itf.n_interfaces) if _label(int(state[k])) == label]
        if not ids:
            continue
        pts, faces, start = [], [], 0
        for k in ids:
            poly = itf.polygon(k)
            pts.append(poly)
            faces.append([len(poly), *range(start, start + len(poly))])
            start += len(poly)
        mesh = pv.PolyData(np.concatenate(pts), np.concatenate(faces))
        plotter.add_mesh(mesh, color=colour, label=label)
    plotter.add_legend(size=(0.18, 0.18))
    plotter.add_text("interface states at collapse", font_size=9)
    plotter.view_vector((0.35, -1.0, 0.8))
    plotter.screenshot(str(out))
    plotter.close()


def main() -> list[Path]:
    runs = sorted(RUNS.glob("*.npz"))
    if not runs:
        raise FileNotFoundError(
            f"no runs in {RUNS}: run 'python -m validation run masonry-orduna --quick' first"
        )
    OUT.mkdir(parents=True, exist_ok=True)
    outs = []
    # the seed's figures: one run per specimen, the fibre model first
    chosen: dict[str, Path] = {}
    for npz in runs:
        key = npz.name.split("_")[0]
        if key not in chosen or "_fibre_" in npz.name and "_fibre_" not in chosen[key].name:
            chosen[key] = npz
    for key, npz in list(chosen.items())[:MAX_FIGURES]:
        out = OUT / f"fig_masonry_damage_{key}.png"
        _render(npz, out)
        outs.append(out)
    return outs


if __name__ == "__main__":
    print(main())
