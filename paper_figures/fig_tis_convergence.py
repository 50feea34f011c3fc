"""Speed against error of the 5 x 5, 2.5 degree panel (tis-convergence).

Reads only ``validation/results/tis-convergence.json`` and ``tis-convergence-curves.npz`` (run
``python -m validation run tis-convergence``); writes
``paper_figures/out/fig_tis_convergence.png``: (a) peak-load error against the finest run of
each sweep versus wall time (node spacing, loading rate, mass scaling, time step), with the
converged full run marked; (b) the P-delta curves of the node-spacing sweep.
"""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from paper_figures.tis_common import MM, OUT, RESULTS, keys, load_npz  # noqa: E402


def main() -> list:
    path = RESULTS / "tis-convergence.json"
    if not path.exists():
        raise FileNotFoundError(
            f"{path} is missing: run 'python -m validation run tis-convergence'"
        )
    rows = json.loads(path.read_text())["rows"]
    store = load_npz("tis-convergence-curves.npz", "tis-convergence")
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4.2))
    sweeps: dict = {}
    for r in rows:
        q = r["quantity"]
        if q.startswith("peak load, "):
            param, value = q[len("peak load, ") :].split(" [")[0].split("=")
            err = r["rel_error"]
            if err is not None and err > 0:
                sweeps.setdefault(param, []).append((r["wall_s"], err, value))
        elif q.startswith("converged"):
            ax_a.plot([r["wall_s"]], [max(r["rel_error"] or 1e-6, 1e-6)], "k*", ms=14,
                      label=f"converged full run ({r['wall_s']:.0f} s)")  # fmt: skip
    for param, pts in sweeps.items():
        pts.sort()
        ax_a.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=param)
        for w, e, v in pts:
            ax_a.annotate(v, (w, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax_a.axhline(0.01, color="grey", ls=":", label="1 %")
    ax_a.set_xscale("log")
    ax_a.set_yscale("log")
    ax_a.set_xlabel("wall time of the run [s]")
    ax_a.set_ylabel("|P_max - P_max(finest)| / P_max(finest)")
    ax_a.set_title("(a) error vs cost")
    ax_a.legend(fontsize=7)
    for key in keys(store):
        if key.startswith("node_spacing_mm="):
            ax_b.plot(store[f"{key}/delta"] / MM, store[f"{key}/load"], label=key)
    ax_b.set_xlabel("indenter travel delta [mm]")
    ax_b.set_ylabel("P [N]")
    ax_b.set_title("(b) node spacing sweep")
    ax_b.legend(fontsize=7)
    for ax in (ax_a, ax_b):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    OUT.mkdir(parents=True, exist_ok=True)
    out = OUT / "fig_tis_convergence.png"
    fig.savefig(out, dpi=130)
    plt.close(fig)
    return [out]


if __name__ == "__main__":
    main()
