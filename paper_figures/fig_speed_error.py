"""Speed against error of every validation row, per method.

Reads only ``validation/results/*.json`` (run ``python -m validation all --quick`` first); never
solves. Writes ``paper_figures/out/fig_speed_error.png`` with two panels of relative error
against wall time [s], log-log, one colour per method:

- numerical error: rows whose reference is a closed form, an exact count, another method of
  this repository or the finest run of a convergence sweep;
- model error: rows whose reference is a published value (a seed's table or the experiments it
  reports), which measures the model as much as the solver.

Rows without a named reference, and comparisons with a bound (a DEM multiplier below an upper
bound is not an error), are left out. A relative error of exactly 0 is drawn at 1e-16.
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from validation.report import is_published, reading_dir  # noqa: E402

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
OUT = Path(__file__).resolve().parent / "out"
FLOOR = 1e-16
SKIP = ("bound", "informational")  # inequalities and side notes, not errors
METHODS = (  # case-name prefix -> label
    ("tis-", "explicit DEM (TIS)"),
    ("masonry-", "static DEM (masonry)"),
    ("interface-strength", "interface spring grid"),
    ("limit-", "limit analysis (cvxpy + Clarabel)"),
    ("tresca-", "Tresca LP / RT0 (seed 003)"),
    ("fem-", "FEM check (scikit-fem)"),
    ("geometry", "scene geometry"),
)


def style_axes(ax, title: str, xlabel: str, legend_loc: str) -> None:
    """Log-log axes of relative error [-] against cost, titled, gridded, with a legend when
    anything drawn has a label."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("relative error [-]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc=legend_loc)


def method_of(case: str) -> str:
    for prefix, label in METHODS:
        if case.startswith(prefix):
            return label
    return "other"


def collect() -> dict:
    """method -> {"numerical" | "model": [(wall_s, rel_error)]} over every case JSON."""
    files = sorted(p for p in RESULTS.glob("*.json") if not p.name.endswith(".scene.json"))
    if not files:
        raise FileNotFoundError(
            f"no results in {RESULTS}: run 'python -m validation all --quick' first"
        )
    out: dict = {}
    for path in files:
        data = json.loads(path.read_text())
        for row in data.get("rows", []):
            err, wall = row.get("rel_error"), row.get("wall_s")
            numbers = all(isinstance(v, int | float) for v in (err, wall))
            if not numbers or not np.isfinite(err) or not wall > 0:
                continue
            ref = row.get("reference")
            source = ref.get("source", "") if isinstance(ref, dict) else ""
            if not source or any(w in source.lower() for w in SKIP):
                continue
            model = row.get("reference_is_model", is_published(source))
            kind = "model" if model else "numerical"
            out.setdefault(method_of(data["case"]), {"numerical": [], "model": []})[kind].append(
                (float(wall), max(abs(float(err)), FLOOR))
            )
    return out


def main() -> list[Path]:
    data = collect()
    OUT.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharex=True)
    colours = plt.cm.tab10(np.linspace(0, 1, 10))
    for i, (_, label) in enumerate((*METHODS, ("", "other"))):
        for ax, kind in zip(axes, ("numerical", "model"), strict=True):
            pts = np.array(data.get(label, {}).get(kind, []), float).reshape(-1, 2)
            if len(pts):
                ax.scatter(
                    pts[:, 0], pts[:, 1], s=14, alpha=0.7, color=colours[i % 10],
                    label=f"{label} ({len(pts)})",
                )  # fmt: skip
    titles = (
        "numerical error (closed forms, other methods, finest runs)",
        "model error (seed tables and experiments)",
    )
    for ax, title in zip(axes, titles, strict=True):
        style_axes(ax, title, "wall time [s]", "lower right")
    fig.tight_layout()
    path = OUT / "fig_speed_error.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return [path]


if __name__ == "__main__":
    print(main())
