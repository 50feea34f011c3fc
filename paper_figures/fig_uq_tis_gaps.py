"""tis-gaps-uq: real random gaps against the calibrated single-k_gaps model (seed 000 Eq. 4).

Reads ``validation/results/tis-gaps-uq.json`` and its sweep store; writes
``paper_figures/out/fig_uq_tis_gaps.png``: (a) P-delta of the perfect panel, the calibrated
model and every gap realisation (coloured by mean gap); (b) P_max of every realisation against
its mean gap, with the perfect and calibrated peaks.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from paper_figures.uq_common import load_study, ok_results, save


def main() -> list:
    data, records = load_study("tis-gaps-uq")
    runs = ok_results(records)
    refs = [r for r in runs if r["params"]["mean_gap_mm"] == 0]
    gaps = [r for r in runs if r["params"]["mean_gap_mm"] > 0]
    levels = sorted({r["params"]["mean_gap_mm"] for r in gaps})
    colours = dict(zip(levels, plt.cm.viridis(np.linspace(0.1, 0.9, max(1, len(levels)))),
                       strict=False))  # fmt: skip
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for r in gaps:
        g = r["params"]["mean_gap_mm"]
        ax_a.plot(r["delta_mm"], r["load_n"], color=colours[g], lw=0.7, alpha=0.7)
    for g in levels:
        ax_a.plot([], [], color=colours[g], label=f"gaps, mean {1e3 * g:.1f} um")
    styles = {0: ("k-", "perfect (k_def)"), 1: ("r--", "calibrated k_imp (k_gaps = 0.65)")}
    for i, r in enumerate(sorted(refs, key=lambda r: -r["params"]["k_n_gpa_mm"])):
        style, label = styles[i]
        ax_a.plot(r["delta_mm"], r["load_n"], style, lw=2, label=label)
        ax_b.axhline(r["peak_load"], color=style[0], ls=style[1:], label=label)
    ax_a.set(xlabel="indenter travel delta [mm]", ylabel="P [N]", title="(a) P-delta")
    x = np.array([1e3 * r["params"]["mean_gap_mm"] for r in gaps])
    y = np.array([r["peak_load"] for r in gaps])
    ax_b.plot(x, y, "o", ms=4, alpha=0.7, label="realisations")
    for g in levels:
        sel = np.isclose(x, 1e3 * g)
        ax_b.errorbar(1e3 * g, y[sel].mean(), yerr=y[sel].std(ddof=1) if sel.sum() > 1 else 0,
                      fmt="s", color="k", capsize=4)  # fmt: skip
    ax_b.set_xlim(left=0)
    ax_b.set(xlabel="mean interface gap [um]", ylabel="P_max [N]",
             title="(b) peak load against the mean gap (mean +/- std)")  # fmt: skip
    for ax in (ax_a, ax_b):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"tis-gaps-uq{' (quick)' if data['quick'] else ''}: 5x5, theta = 2.5 deg")
    return save(fig, "fig_uq_tis_gaps")


if __name__ == "__main__":
    main()
