"""P-delta curves of the nine TIS panels, perfect and gap-calibrated (seed 000 Figs. 5a, 7).

Reads only ``validation/results/tis-panels-curves.npz`` (run ``python -m validation run
tis-panels``); writes ``paper_figures/out/fig_tis_curves.png``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from paper_figures.tis_common import MM, OUT, keys, load_npz  # noqa: E402


def main() -> list:
    store = load_npz("tis-panels-curves.npz", "tis-panels")
    runs = keys(store)
    thetas = sorted({float(k.split("_")[1]) for k in runs})
    fig, axes = plt.subplots(1, len(thetas), figsize=(4.5 * len(thetas), 3.8), squeeze=False)
    colours = {"3x3": "tab:blue", "5x5": "tab:orange", "7x7": "tab:green"}
    for ax, theta in zip(axes[0], thetas, strict=True):
        for key in runs:
            size, th, model = key.split("_")
            if float(th) != theta or model not in ("perfect", "calibrated"):
                continue
            style = "-" if model == "perfect" else "--"
            ax.plot(store[f"{key}/delta"] / MM, store[f"{key}/load"], style,
                    color=colours.get(size, "k"), label=f"{size} {model}")  # fmt: skip
            p, d = store[f"{key}/summary"][:2]
            ax.plot([d / MM], [p], "o", color=colours.get(size, "k"), ms=4)
        ax.set_title(f"theta = {theta:g} deg")
        ax.set_xlabel("indenter travel delta [mm]")
        ax.set_ylabel("P [N]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Explicit DEM: P-delta of the TIS panels (solid: k_def, dashed: k_imp)")
    fig.tight_layout()
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "fig_tis_curves.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    main()
