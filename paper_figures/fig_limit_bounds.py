"""Bounds vs DEM vs experiment per specimen (seed 001 Tables 1-3).

Reads only ``validation/results/limit-{orduna,restrepo,chee-liang,vs-dem}.json`` (run those
validation cases first); never solves. Writes ``paper_figures/out/fig_limit_bounds.png``: per
specimen, the associated upper bounds of both interface models (bars), the non-associated
estimates (markers), our DEM (from ``limit-vs-dem``, where available), the seed's DEM and the
reference (experiment, or for Table 1 the seed's limit-analysis value).
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from validation.report import reading_dir

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
OUT = Path(__file__).resolve().parent / "out"
MODELS = ("vertex", "resultant")
TABLES = (
    ("limit-orduna", "Table 1 (lambda)", "seed limit analysis"),
    ("limit-restrepo", "Table 2 (lambda)", "experiment"),
    ("limit-chee-liang", "Table 3 (p [kN/m^2])", "experiment (mean)"),
)


def _rows(case: str) -> list[dict]:
    path = RESULTS / f"{case}.json"
    if not path.exists():
        raise FileNotFoundError(f"{path} is missing: run 'python -m validation run {case} --quick'")
    return json.loads(path.read_text())["rows"]


def _collect(rows: list[dict]) -> dict:
    """specimen -> {model -> {kind -> value}}, plus reference and seed DEM."""
    out: dict = {}
    for r in rows:
        q = r["quantity"]
        label, rest = q.split(" [", 1)
        model = rest.split("]", 1)[0]
        if "f_c" in label or ", fixed" in label:
            continue  # Table 1: the seed's supports and the u_y-only variant
        if "inscribed" in r["extra"].get("kind", ""):
            continue
        spec = out.setdefault(label, {"reference": r["reference"]["value"], "models": {}})
        spec["seed_dem"] = r["extra"].get("seed_dem")
        kind = r["extra"].get("kind", "")
        if "inscribed" in kind:
            continue
        key = (
            "upper"
            if kind.startswith("upper")
            else "a"
            if kind.startswith("estimate (a)")
            else "b"
            if kind.startswith("estimate (b)")
            else "lower"
        )
        spec["models"].setdefault(model, {})[key] = r["ours"]
    return out


def _dem_values() -> dict:
    path = RESULTS / "limit-vs-dem.json"
    if not path.exists():
        return {}
    out: dict = {}
    for r in json.loads(path.read_text())["rows"]:
        key = r["quantity"].split(":", 1)[0]
        dem_model = r["settings"].get("dem_model")
        out.setdefault(key, {})[dem_model] = (r["ours"], r["extra"].get("within_bounds"))
    return out


def _spec_key(label: str) -> str:
    return label.replace("orduna 3x13, translations", "orduna-3x13").replace(
        "orduna 6x13, translations", "orduna-6x13"
    )


def main() -> list[Path]:
    OUT.mkdir(parents=True, exist_ok=True)
    dem = _dem_values()
    fig, axes = plt.subplots(3, 1, figsize=(12, 12))
    for ax, (case, title, ref_label) in zip(axes, TABLES, strict=True):
        data = _collect(_rows(case))
        labels = list(data)
        x = np.arange(len(labels))
        _plot_bounds(ax, x, labels, data)
        _plot_references(ax, x, labels, data, ref_label)
        _plot_our_dem(ax, x, labels, dem)
        if case == "limit-orduna":
            _annotate_arching(ax, labels, data, dem)
        ax.set_xticks(x, labels, rotation=20, fontsize=8, ha="right")
        ax.legend(fontsize=6, ncol=5, loc="upper left")
        ax.set_title(f"seed 001 {title}", fontsize=10)
        ax.set_yscale("log")
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    path = OUT / "fig_limit_bounds.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]


def _nan_for_none(values) -> list[float]:
    return [np.nan if v is None else v for v in values]


def _plot_bounds(ax, x, labels, data) -> None:
    """Upper bounds (bars) and estimates (a) and (b) (markers) of both interface models."""
    for i, (model, colour) in enumerate((("vertex", "C0"), ("resultant", "C1"))):
        shift = x + (i - 0.5) * 0.35
        up = _nan_for_none(data[k]["models"].get(model, {}).get("upper") for k in labels)
        ax.bar(shift, up, 0.35, color=colour, alpha=0.35, label=f"upper bound [{model}]")
        for est, marker in (("a", "v"), ("b", "o")):
            vals = _nan_for_none(data[k]["models"].get(model, {}).get(est) for k in labels)
            label = f"estimate ({est}) [{model}]"
            ax.plot(shift, vals, marker, color=colour, ls="none", label=label)


def _plot_references(ax, x, labels, data, ref_label: str) -> None:
    """The reference (experiment or the seed's limit analysis) and the seed's DEM."""
    ref = _nan_for_none(data[k]["reference"] for k in labels)
    ax.plot(x, ref, "k*", ms=11, label=ref_label)
    seed_dem = _nan_for_none(data[k].get("seed_dem") for k in labels)
    ax.plot(x, seed_dem, "kx", ms=9, label="seed DEM")


def _plot_our_dem(ax, x, labels, dem) -> None:
    """Our DEM's collapse multipliers (limit-vs-dem), both interface laws, where there are."""
    for dem_model, marker in (("resultant", "s"), ("fibre", "D")):
        vals = _nan_for_none(
            dem.get(_spec_key(k), {}).get(dem_model, (None, None))[0] for k in labels
        )
        if np.isfinite(vals).any():
            label = f"our DEM [{dem_model}]"
            ax.plot(x, vals, marker, color="C2", mfc="none", ms=8, ls="none", label=label)


def _annotate_arching(ax, labels, data, dem, top: float = 2.0) -> None:
    """The 6 x 13 panel between rigid columns is unbounded (arching): name the values above
    ``top`` and the missing upper bounds, and keep the scale."""
    for k, lab in enumerate(labels):
        for dem_model in ("resultant", "fibre"):
            v = dem.get(_spec_key(lab), {}).get(dem_model, (None, None))[0]
            if v is not None and v > top:
                text = f"DEM {dem_model} {v:.1f} (arching)"
                ax.annotate(text, (k, 1.0), fontsize=7, ha="center")
        if all(data[lab]["models"].get(m, {}).get("upper") is None for m in MODELS):
            text = "upper bound unbounded\n(rigid columns, f_c = inf)"
            ax.annotate(text, (k, 0.5), fontsize=7, ha="center")
    ax.set_ylim(0.03, top)


if __name__ == "__main__":
    print(main())
