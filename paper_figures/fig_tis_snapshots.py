"""Failure snapshots of the TIS panels: block poses at the peak and at the end (Figs. 5b, 8).

Reads only ``validation/results/tis-panels-curves.npz``; writes
``paper_figures/out/fig_tis_snapshots.png``: for each perfect panel, a 3D view (from below) of
the blocks at the peak load and at the end of the run, vertical displacements exaggerated 1x
(true scale), coloured by their drop.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from paper_figures.tis_common import MM, OUT, hull_faces, keys, load_npz, posed_blocks  # noqa: E402


def draw(ax, store: dict, key: str, k: int, title: str) -> None:
    blocks = posed_blocks(store, key, k)
    ref = posed_blocks(store, key, 0)
    drops = np.array(
        [(r[:, 2].mean() - b[:, 2].mean()) / MM for b, r in zip(blocks, ref, strict=True)]
    )
    cmap = plt.get_cmap("viridis")
    top = max(drops.max(), 1e-9)
    for b, drop, fixed in zip(blocks, drops, store[f"{key}/fixed"], strict=True):
        colour = "lightgrey" if fixed else cmap(drop / top)
        poly = Poly3DCollection([f / MM for f in hull_faces(b)], facecolor=colour,
                                edgecolor="k", linewidths=0.1, alpha=0.9)  # fmt: skip
        ax.add_collection3d(poly)
    ax.set_xlim(0, 50)
    ax.set_ylim(0, 50)
    ax.set_zlim(-8, 4)
    ax.view_init(elev=-25, azim=-60)
    ax.set_title(title, fontsize=8)
    ax.set_axis_off()


def main() -> list:
    store = load_npz("tis-panels-curves.npz", "tis-panels")
    runs = [k for k in keys(store) if k.endswith("_perfect") or k.endswith("_rough")]
    fig = plt.figure(figsize=(5.0 * 2, 3.2 * len(runs)))
    for row, key in enumerate(runs):
        d = store[f"{key}/pose_delta"]
        peak_d = store[f"{key}/summary"][1]
        k_peak = int(np.argmin(np.abs(d - peak_d)))
        for col, (k, what) in enumerate(((k_peak, "peak"), (len(d) - 1, "end"))):
            ax = fig.add_subplot(len(runs), 2, 2 * row + col + 1, projection="3d")
            draw(ax, store, key, k, f"{key}: {what}, delta = {d[k] / MM:.2f} mm")
    fig.tight_layout()
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "fig_tis_snapshots.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    main()
