"""Collapse mechanisms of the seed 001 Table 1 panels from the limit-analysis duals.

Reads only ``validation/results/limit_mechanisms/orduna-*_{vertex,resultant}.npz`` (run
``python -m validation run limit-orduna --quick`` first); never solves. Writes
``paper_figures/out/fig_limit_mechanisms.png``: for each panel and interface model, the blocks
displaced by the associated mechanism (colour: block speed) and the centres of pressure of the
compressed joints (the thrust network, size ~ compression).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from validation.report import reading_dir

RESULTS = reading_dir() / "limit_mechanisms"  # BLOCKMECH_RESULTS chooses the folder
OUT = Path(__file__).resolve().parent / "out"
PANELS = ("orduna-3x13", "orduna-6x13")
MODELS = ("vertex", "resultant")


def _load(key: str) -> dict | None:
    path = RESULTS / f"{key}.npz"
    if not path.exists():
        return None
    with np.load(path) as data:
        return {k: data[k] for k in data.files}


def main() -> list[Path]:
    found = {}
    for p in PANELS:
        for m in MODELS:
            # the seed's supports first; the 6 x 13 one is unbounded (arching): then u_y only
            for variant in ("translations", "out-of-plane"):
                arr = _load(f"{p}-{variant}_{m}")
                if arr is not None:
                    arr["variant"] = variant
                    found[(p, m)] = arr
                    break
            else:
                found[(p, m)] = None
    if not any(v is not None for v in found.values()):
        raise FileNotFoundError(
            f"no mechanism files in {RESULTS}: run 'python -m validation run limit-orduna "
            "--quick' first"
        )
    OUT.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=(11, 9))
    for row, panel in enumerate(PANELS):
        for col, model in enumerate(MODELS):
            ax = fig.add_subplot(2, 2, 2 * row + col + 1, projection="3d")
            arr = found[(panel, model)]
            if arr is None:
                ax.set_title(f"{panel} [{model}]: no solution (unbounded: arching)", fontsize=9)
                ax.set_axis_off()
                continue
            ptr = arr["face_ptr"]
            polys = [arr["face_points"][ptr[k] : ptr[k + 1]] for k in range(len(ptr) - 1)]
            speed = arr["speed"][arr["face_block"]]
            coll = Poly3DCollection(polys, cmap="viridis", edgecolor="k", linewidths=0.15)
            coll.set_array(speed)
            ax.add_collection3d(coll)
            tp = arr["thrust_point"]
            if len(tp):
                size = 30 * arr["thrust_compression"] / arr["thrust_compression"].max()
                ax.scatter(tp[:, 0], tp[:, 1], tp[:, 2], s=size, c="C3", depthshade=False)
            pts = arr["face_points"]
            ax.auto_scale_xyz(pts[:, 0], pts[:, 1], pts[:, 2])
            ax.view_init(elev=15, azim=-60)
            ax.set_title(
                f"{panel}, {arr['variant']} [{model}]: upper bound lambda = "
                f"{float(arr['lam']):.3f}",
                fontsize=9,
            )
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
            ax.set_zlabel("z [m]")
    fig.suptitle(
        "Seed 001 Table 1 panels: associated collapse mechanisms (dual velocities, colour = "
        "speed) and centres of pressure (red)",
        fontsize=10,
    )
    path = OUT / "fig_limit_mechanisms.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    print(main())
