"""masonry-uq: scatter of the collapse multiplier of a Restrepo-Velez wall (seed 001 Table 2).

Reads ``validation/results/masonry-uq.json`` and its sweep store; writes
``paper_figures/out/fig_uq_masonry.png``: (a) empirical CDF (fragility-style) of the static
DEM lambda of the runs that collapsed and of the limit upper bound, with the experiment, the
seed's DEM and the nominal wall marked; (b) lambda against the return-wall length, with the
runs that did not collapse (the lambda they reached, a lower bound of theirs) as crosses.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from dem.scenes.seed001_walls import SPECIMENS
from paper_figures.uq_common import load_study, ok_results, save
from validation.sweep.stats import ecdf


def main() -> list:
    data, records = load_study("masonry-uq")
    runs = ok_results(records)
    nominal = [r for r in runs if r["params"]["nominal"]]
    reals = [r for r in runs if not r["params"]["nominal"]]
    spec = SPECIMENS[f"restrepo-{reals[0]['params']['specimen']}"] if reals else None
    dem = [r for r in reals if r["collapsed"]]
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for values, label, style in (
        ([r["lam_dem"] for r in dem], f"static DEM, fibre ({len(dem)} collapsed)", "C0-"),
        ([r["lam_upper"] for r in reals if r["lam_upper"] is not None],
         "limit upper bound, vertex", "C1-"),
    ):  # fmt: skip
        if values:
            x, f = ecdf(values)
            ax_a.step(x, f, style, where="post", label=label)
    if spec is not None:
        ax_a.axvline(spec.reference, color="k", lw=2, label=f"experiment {spec.reference}")
        ax_a.axvline(spec.seed_dem, color="k", ls=":", label=f"seed 001 DEM {spec.seed_dem}")
    if nominal:
        ax_a.axvline(nominal[0]["lam_dem"], color="C0", ls="--", label="nominal wall, DEM")
    ax_a.set(xlabel="lambda [-]", ylabel="P(collapse multiplier <= lambda)",
             title="(a) empirical CDF")  # fmt: skip
    n_ret = np.array([r["return_blocks"] for r in dem])
    ax_b.plot(n_ret - 0.05, [r["lam_dem"] for r in dem], "o", alpha=0.6, label="static DEM")
    open_ = [r for r in reals if not r["collapsed"]]
    if open_:
        ax_b.plot([r["return_blocks"] - 0.05 for r in open_], [r["lam_dem"] for r in open_], "x",
                  color="C0", label="static DEM, no collapse (lambda reached)")  # fmt: skip
    up = [r for r in reals if r["lam_upper"] is not None]
    ax_b.plot(np.array([r["return_blocks"] for r in up]) + 0.05, [r["lam_upper"] for r in up],
              "^", alpha=0.6, label="limit upper bound")  # fmt: skip
    if spec is not None:
        ax_b.axhline(spec.reference, color="k", lw=2, label="experiment")
    ax_b.set(xlabel="return-wall length [blocks]", ylabel="lambda [-]",
             title="(b) against the return-wall length")  # fmt: skip
    for ax in (ax_a, ax_b):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"masonry-uq{' (quick)' if data['quick'] else ''}: Restrepo-Velez wall")
    return save(fig, "fig_uq_masonry")


if __name__ == "__main__":
    main()
