"""Force chains of the 5 x 5, 2.5 degree panel as cylinders (seed 000 Figs. 5c, 6d-g).

Reads only ``validation/results/tis-panels-curves.npz`` (run ``python -m validation run
tis-panels``); writes ``paper_figures/out/fig_tis_force_chains.png``. Each block-block interface
resultant is a cylinder at its point of action, its axis along the force and its width
proportional to the force magnitude (the largest interface force of each view has the widest
cylinder); blocks are drawn transparent in their deformed pose. Views at four deflections up
to just past the peak load. Rendered off-screen with pyvista (VTK).
"""

from __future__ import annotations

import numpy as np

from paper_figures.tis_common import MM, OUT, load_npz, posed_blocks

KEY = "5x5_2.5_perfect"
LENGTH = 4.0  # cylinder length [mm]
MAX_RADIUS = 0.9  # radius of the largest force [mm]


def _nearest_pose(store: dict, delta: float) -> int:
    return int(np.argmin(np.abs(store[f"{KEY}/pose_delta"] - delta)))


def main() -> list:
    import pyvista as pv

    store = load_npz("tis-panels-curves.npz", "tis-panels")
    if f"{KEY}/snap_delta" not in store:
        raise KeyError(f"{KEY} is not in tis-panels-curves.npz: run tis-panels")
    snap_d = store[f"{KEY}/snap_delta"]
    ptr = store[f"{KEY}/snap_ptr"]
    peak_d = store[f"{KEY}/summary"][1]
    targets = [0.25 * peak_d, 0.5 * peak_d, peak_d, 1.3 * peak_d]
    picks = [int(np.argmin(np.abs(snap_d - t))) for t in targets]
    pv.OFF_SCREEN = True
    plotter = pv.Plotter(shape=(2, 2), off_screen=True, window_size=(1400, 1200))
    fixed = store[f"{KEY}/fixed"]
    for view, s in enumerate(picks):
        plotter.subplot(view // 2, view % 2)
        blocks = posed_blocks(store, KEY, _nearest_pose(store, snap_d[s]))
        for b, is_fixed in zip(blocks, fixed, strict=True):
            hull = pv.PolyData(b / MM).delaunay_3d().extract_surface(algorithm="dataset_surface")
            plotter.add_mesh(hull, color="lightgrey" if is_fixed else "wheat", opacity=0.15)
        force = store[f"{KEY}/snap_force"][ptr[s] : ptr[s + 1]]
        point = store[f"{KEY}/snap_point"][ptr[s] : ptr[s + 1]] / MM
        mag = np.linalg.norm(force, axis=1)
        top = mag.max() if len(mag) else 1.0
        for f, p, m in zip(force, point, mag, strict=True):
            if m < 0.02 * top:
                continue
            cyl = pv.Cylinder(center=p, direction=f / m, radius=MAX_RADIUS * m / top,
                              height=LENGTH, resolution=16)  # fmt: skip
            plotter.add_mesh(cyl, color="firebrick")
        plotter.add_text(f"delta = {snap_d[s] / MM:.2f} mm, max {top:.0f} N", font_size=10)
        plotter.view_isometric()
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "fig_tis_force_chains.png"
    plotter.screenshot(str(path))
    plotter.close()
    return [path]


if __name__ == "__main__":
    main()
