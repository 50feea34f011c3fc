"""tis-friction-uq: per-block random mu on the 5 x 5, theta = 2.5 deg panel.

Reads ``validation/results/tis-friction-uq.json`` and its sweep store (and
``tis-friction.json`` for the seed-style 8-realisation spread); writes
``paper_figures/out/fig_uq_tis_friction.png``: (a) P-delta of every realisation and the
deterministic panel; (b) P_max / P_max(mu = 0.23) of every realisation beside the
``tis-friction`` realisations; (c) running mean of P_max and its 95 % confidence interval;
(d) failure modes and ultimate deflections.
"""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np

from paper_figures.tis_common import RESULTS
from paper_figures.uq_common import load_study, ok_results, save
from validation.sweep.stats import running_mean_ci


def _seed_style_spread() -> np.ndarray:
    path = RESULTS / "tis-friction.json"
    if not path.exists():
        return np.array([])
    rows = json.loads(path.read_text())["rows"]
    peaks = {r["quantity"]: r["ours"] for r in rows if "peak load" in r["quantity"]}
    det = peaks.get("5x5 theta=5 calibrated, mu=0.23: peak load [N]")
    return np.array([v for k, v in peaks.items() if "N(0.23, 0.06)" in k]) / det


def main() -> list:
    data, records = load_study("tis-friction-uq")
    runs = ok_results(records)
    det = [r for r in runs if r["params"]["mu_std"] == 0]
    reals = [r for r in runs if r["params"]["mu_std"] > 0]
    fig, ((ax_a, ax_b), (ax_c, ax_d)) = plt.subplots(2, 2, figsize=(10, 8))
    for r in reals:
        ax_a.plot(r["delta_mm"], r["load_n"], lw=0.6, alpha=0.6)
    if det:
        ax_a.plot(det[0]["delta_mm"], det[0]["load_n"], "k--", lw=2, label="mu = 0.23 (all blocks)")
        ax_a.legend(fontsize=8)
    ax_a.set(xlabel="indenter travel delta [mm]", ylabel="P [N]",
             title=f"(a) {len(reals)} realisations, mu ~ N(0.23, 0.06) per block")  # fmt: skip
    peaks = np.array([r["peak_load"] for r in reals])
    if det:
        ratio = peaks / det[0]["peak_load"]
        seed = _seed_style_spread()
        groups = [ratio] + ([seed] if seed.size else [])
        labels = [f"this study\n({ratio.size}, theta = 2.5)"]
        labels += [f"tis-friction\n({seed.size}, theta = 5)"] if seed.size else []
        ax_b.boxplot(groups, tick_labels=labels, showmeans=True)
        for i, g in enumerate(groups, start=1):
            ax_b.plot(np.full(g.size, i) + np.linspace(-0.08, 0.08, g.size), g, "o", ms=3,
                      alpha=0.6)  # fmt: skip
        ax_b.axhline(1.0, color="k", ls="--", lw=1)
    ax_b.set(ylabel="P_max / P_max(mu = 0.23)", title="(b) peak load spread")
    if peaks.size >= 2:
        n, mean, half = running_mean_ci(peaks)
        ax_c.fill_between(n, mean - half, mean + half, alpha=0.3, label="95 % CI of the mean")
        ax_c.plot(n, mean, "k", label="running mean")
        ax_c.axvline(8, color="r", ls=":", label="8 runs (seed 000 Fig. 9b)")
        ax_c.legend(fontsize=8)
    ax_c.set_ylim(bottom=0)
    ax_c.set(xlabel="number of runs", ylabel="mean P_max [N]", title="(c) convergence of the mean")
    modes = [r["failure_mode"] for r in reals]
    names = ["central out", "several blocks", "not out"]
    ax_d.bar(names, [modes.count(m) for m in names], color="0.6")
    ult = np.array([r["ultimate_deflection_mm"] for r in reals], dtype=float)
    ax_d.set(ylabel="runs", title="(d) failure mode; ultimate deflection (inset)")
    inset = ax_d.inset_axes([0.55, 0.45, 0.4, 0.45])
    inset.hist(ult[np.isfinite(ult)], bins=10, color="C0")
    inset.set_xlabel("ultimate deflection [mm]", fontsize=7)
    inset.tick_params(labelsize=7)
    for ax in (ax_a, ax_b, ax_c):
        ax.grid(alpha=0.3)
    fig.suptitle(f"tis-friction-uq{' (quick)' if data['quick'] else ''}")
    return save(fig, "fig_uq_tis_friction")


if __name__ == "__main__":
    main()
