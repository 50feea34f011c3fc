"""Reading the uncertainty studies: the case JSON and its sweep store (one record per run)."""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from paper_figures.tis_common import OUT, RESULTS  # noqa: E402
from validation.sweep.store import latest_records  # noqa: E402


def load_study(case: str) -> tuple[dict, list[dict]]:
    """``(case JSON, records of its sweep)``, or an error naming the case to run."""
    path = RESULTS / f"{case}.json"
    if not path.exists():
        raise FileNotFoundError(f"{path} is missing: run 'python -m validation run {case} --quick'")
    data = json.loads(path.read_text())
    store = RESULTS / "sweeps" / (f"{case}-quick" if data["quick"] else case) / "results.jsonl"
    if not store.exists():
        raise FileNotFoundError(f"{store} is missing: rerun 'python -m validation run {case}'")
    return data, latest_records(store)


def ok_results(records: list[dict]) -> list[dict]:
    """Results of the runs that finished, each with its ``params`` under ``"params"``."""
    return [{**r["result"], "params": r["params"]} for r in records if r["status"] == "ok"]


def save(fig, name: str) -> list:
    fig.tight_layout()
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / f"{name}.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return [path]
