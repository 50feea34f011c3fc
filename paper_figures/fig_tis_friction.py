"""Friction study (seed 000 Fig. 9): smaller mu, and realisations of per-block mu.

Reads only ``validation/results/tis-friction-curves.npz`` (run ``python -m validation run
tis-friction``); writes ``paper_figures/out/fig_tis_friction.png``: (a) P-delta for mu = 0.23,
0.21, 0.19; (b) the realisations of mu ~ N(0.23, 0.06) per block (thin), their mean curve
(thick) and the deterministic mu = 0.23 curve (dashed).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paper_figures.tis_common import MM, OUT, keys, load_npz  # noqa: E402


def main() -> list:
    store = load_npz("tis-friction-curves.npz", "tis-friction")
    runs = keys(store)
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(10, 4))
    for key in runs:
        if key.startswith("mu="):
            ax_a.plot(store[f"{key}/delta"] / MM, store[f"{key}/load"], label=key)
    ax_a.set_title("(a) deterministic mu")
    reals = [k for k in runs if k.startswith("real")]
    grid = np.linspace(0, max(store[f"{k}/delta"].max() for k in reals), 400) if reals else []
    curves = []
    for key in reals:
        d, p = store[f"{key}/delta"], store[f"{key}/load"]
        ax_b.plot(d / MM, p, lw=0.8, alpha=0.7)
        curves.append(np.interp(grid, d, p, right=np.nan))
    if curves:
        ax_b.plot(grid / MM, np.nanmean(curves, axis=0), "k", lw=2.5, label="mean realisation")
    if "mu=0.23" in runs:
        ax_b.plot(store["mu=0.23/delta"] / MM, store["mu=0.23/load"], "k--", label="mu = 0.23")
    ax_b.set_title(f"(b) {len(reals)} realisations, mu ~ N(0.23, 0.06) per block")
    for ax in (ax_a, ax_b):
        ax.set_xlabel("indenter travel delta [mm]")
        ax.set_ylabel("P [N]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "fig_tis_friction.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    main()
