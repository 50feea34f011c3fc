"""Speed against error, one figure per method: cost against the estimated error bar and
against the true error.

Reads only results; never solves. Two sources:

- every validation row with a wall time (the folder :func:`validation.report.reading_dir`
  names): its estimated relative error ``ours_error / |ours|``
  (rows that carry a finite bar) and, where its reference is a closed form, an exact count or
  another method (not a published value, not a bound), its true relative error
  ``rel_error``;
- the speed-error sweeps of the benchmarks (``benchmarks/results/speed-error-*.json``,
  written by
  ``python benchmarks/bench_limit.py --speed-error`` and ``python benchmarks/bench_fem.py
  --speed-error``): one discretisation refined step by step, each step with its cost [s], its
  estimated and its true relative error, drawn as a line.

Writes ``paper_figures/out/fig_speed_error_<method>.png`` for every method with data: the left
panel the estimated error against cost, the right one the true error against cost (where a
reference exists), log-log. A relative error of exactly 0 is drawn at 1e-16.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paper_figures.fig_speed_error import FLOOR, SKIP, method_of, style_axes  # noqa: E402
from validation.report import is_published, reading_dir  # noqa: E402

RESULTS = reading_dir()
SWEEPS = Path(__file__).resolve().parents[1] / "benchmarks" / "results"
OUT = Path(__file__).resolve().parent / "out"
SWEEP_GLOB = "speed-error-*.json"


def _number(x) -> float | None:
    return float(x) if isinstance(x, int | float) and math.isfinite(x) else None


def _row_point(row: dict) -> tuple[float, float | None, float | None] | None:
    """``(wall_s, estimated relative error, true relative error)`` of a row, None without
    a wall time or anything to draw (a cost row is itself a wall time, not a result)."""
    if row.get("cost"):
        return None
    wall, ours = _number(row.get("wall_s")), _number(row.get("ours"))
    if wall is None or wall <= 0 or ours is None:
        return None
    bar = _number(row.get("ours_error"))
    est = bar / abs(ours) if bar is not None and ours != 0 else None
    ref = row.get("reference")
    source = ref.get("source", "") if isinstance(ref, dict) else ""
    err = _number(row.get("rel_error"))
    model = row.get("reference_is_model", is_published(source))
    numerical = source and not model and not any(w in source.lower() for w in SKIP)
    true = abs(err) if err is not None and numerical else None
    if est is None and true is None:
        return None
    return wall, est, true


def collect_rows() -> dict:
    """method -> list of ``(wall_s, estimated, true)`` relative errors (None where absent)."""
    out: dict = {}
    for path in sorted(RESULTS.glob("*.json")):
        if path.name.endswith(".scene.json") or path.name.startswith("speed-error-"):
            continue
        data = json.loads(path.read_text())
        for row in data.get("rows", []):
            point = _row_point(row)
            if point is not None:
                out.setdefault(method_of(data.get("case", path.stem)), []).append(point)
    return out


def collect_sweeps() -> dict:
    """method -> list of series ``{"label", "cost_s", "estimated", "true"}`` (relative
    errors; ``true`` entries may be None)."""
    out: dict = {}
    for path in sorted(SWEEPS.glob(SWEEP_GLOB)):
        data = json.loads(path.read_text())
        for series in data.get("series", []):
            n = len(series["cost_s"])
            if not (len(series["estimated"]) == len(series.get("true", [None] * n)) == n):
                raise ValueError(f"{path}: series {series.get('label')!r} has ragged columns")
            out.setdefault(data["method"], []).append(series)
    return out


def slug(label: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", label.lower().split("(")[0]).strip("_")


def _draw(ax, rows: list, series: list, column: int, key: str) -> int:
    """Rows as points and series as lines on one panel; the number of things drawn."""
    drawn = 0
    pts = np.array([(r[0], r[column]) for r in rows if r[column] is not None], float)
    if len(pts):
        ax.scatter(pts[:, 0], np.maximum(pts[:, 1], FLOOR), s=14, alpha=0.6, color="0.4",
                   label=f"validation rows ({len(pts)})")  # fmt: skip
        drawn += len(pts)
    for s in series:
        xy = [(c, v) for c, v in zip(s["cost_s"], s[key], strict=True) if v is not None]
        if xy:
            x, y = np.array(xy, float).T
            ax.plot(x, np.maximum(y, FLOOR), "o-", ms=4, label=s["label"])
            drawn += len(xy)
    return drawn


def figure(method: str, rows: list, series: list) -> Path:
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharex=True)
    panels = ((1, "estimated", "estimated error (the method's own bar)"),
              (2, "true", "true error (closed forms, other methods, finest runs)"))  # fmt: skip
    for ax, (column, key, title) in zip(axes, panels, strict=True):
        if not _draw(ax, rows, series, column, key):
            ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center", color="0.5")
        style_axes(ax, title, "cost: wall time [s]", "best")
    fig.suptitle(f"speed against error: {method}", fontsize=11)
    fig.tight_layout()
    path = OUT / f"fig_speed_error_{slug(method)}.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def main() -> list[Path]:
    rows, sweeps = collect_rows(), collect_sweeps()
    methods = sorted(set(rows) | set(sweeps))
    if not methods:
        raise FileNotFoundError(
            f"no rows with a wall time in {RESULTS} and no {SWEEP_GLOB} in {SWEEPS}: run "
            "'python -m validation all --quick' or the benchmarks' --speed-error first"
        )
    OUT.mkdir(parents=True, exist_ok=True)
    return [figure(m, rows.get(m, []), sweeps.get(m, [])) for m in methods]


if __name__ == "__main__":
    print(main())
