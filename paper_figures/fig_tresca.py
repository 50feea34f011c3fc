"""Seed 003 Figs. 6-11 style: normal forces on the packings and the RT0 stress per cell.

Reads only ``validation/results/tresca_fields.npz`` and ``tresca-reconstruction.json``
(run ``python -m validation run tresca-reconstruction --quick`` first); never solves.
Writes ``paper_figures/out/fig_tresca_<scene>.png``.
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

from validation.report import reading_dir

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
OUT = Path(__file__).resolve().parent / "out"
SCENES = {
    "four-cells": "4 cells, uniform compression (seed 003 Fig. 6)",
    "five-cells": "5 cells, uniform compression (seed 003 Fig. 7)",
    "brick-wall": "brick wall under shear (seed 003 Figs. 8-9)",
    "hom60": "60 cells, interior-point duals (seed 003 Figs. 10-11)",
    "hom60-min-energy": "60 cells, min-energy forces",
}
COMPONENTS = (
    (0, 0, r"$\sigma_{xx}$"),
    (1, 1, r"$\sigma_{yy}$"),
    (0, 1, r"$\sigma_{xy}$"),
    (1, 0, r"$\sigma_{yx}$"),
)


def _cells(fields: dict, key: str) -> list[np.ndarray]:
    ptr, xy = fields[f"{key}__cell_ptr"], fields[f"{key}__cell_xy"]
    return [xy[ptr[c] : ptr[c + 1]] for c in range(len(ptr) - 1)]


def _draw_forces(ax, fields: dict, key: str) -> None:
    cells = _cells(fields, key)
    ax.add_collection(PolyCollection(cells, facecolors="0.93", edgecolors="0.6", linewidths=0.4))
    stress = fields[f"{key}__normal_force"] / fields[f"{key}__edge_length"]
    top = max(float(np.percentile(stress, 95)), 1e-300)  # a few tiny edges carry huge stresses
    width = 0.3 + 3.0 * np.clip(stress / top, 0.0, 1.0)
    ax.add_collection(LineCollection(fields[f"{key}__edge_xy"], linewidths=width, colors="C3"))
    centres = fields[f"{key}__centres"]
    ax.plot(centres[:, 0], centres[:, 1], ".", color="C0", ms=3)
    ax.set_title(r"normal stress $\lambda_e/|e|$ (width, clipped at p95)", fontsize=8)


def _draw_component(fig, ax, fields: dict, key: str, i: int, j: int, label: str) -> None:
    values = fields[f"{key}__sigma_mean"][:, i, j]
    lo, hi = np.percentile(values, [2, 98])  # tiny triangles near short edges saturate the scale
    if hi - lo < 1e-9 * max(abs(lo), abs(hi), 1.0):
        lo, hi = lo - 0.5, hi + 0.5
    coll = PolyCollection(
        fields[f"{key}__tri_xy"], array=values, cmap="coolwarm", edgecolors="face", linewidths=0.1
    )
    coll.set_clim(lo, hi)
    ax.add_collection(coll)
    ax.add_collection(
        PolyCollection(_cells(fields, key), facecolors="none", edgecolors="k", linewidths=0.4)
    )
    fig.colorbar(coll, ax=ax, shrink=0.7).ax.tick_params(labelsize=6)
    ax.set_title(label + " [Pa], triangle means", fontsize=8)


def main() -> list[Path]:
    """Draw one figure per scene; return the written paths."""
    npz_path = RESULTS / "tresca_fields.npz"
    if not npz_path.exists():
        raise FileNotFoundError(
            f"{npz_path} missing: run `python -m validation run tresca-reconstruction --quick`"
        )
    fields = dict(np.load(npz_path))
    meta = json.loads((RESULTS / "tresca-reconstruction.json").read_text())
    OUT.mkdir(parents=True, exist_ok=True)
    written = []
    for key, title in SCENES.items():
        if f"{key}__cell_ptr" not in fields:
            continue
        fig, axes = plt.subplots(1, 5, figsize=(17, 3.4))
        _draw_forces(axes[0], fields, key)
        for ax, (i, j, label) in zip(axes[1:], COMPONENTS, strict=True):
            _draw_component(fig, ax, fields, key, i, j, label)
        for ax in axes:
            ax.set_aspect("equal")
            ax.autoscale_view()
            ax.set_xticks([])
            ax.set_yticks([])
        fig.suptitle(f"{title}  (commit {meta['git_commit'][:8]})", fontsize=9)
        path = OUT / f"fig_tresca_{key}.png"
        fig.savefig(path, dpi=150, bbox_inches="tight")
        plt.close(fig)
        written.append(path)
    return written


if __name__ == "__main__":
    for p in main():
        print(p)
