"""Reading the uncertainty studies: the case JSON and its sweep store (one record per run)."""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from paper_figures.tis_common import OUT, RESULTS  # noqa: E402
from validation.sweep.store import latest_records  # noqa: E402


def load_study(case: str) -> tuple[dict, list[dict]]:
    """``(case JSON, records of its runs)``, or an error naming the case to run."""
    path, runs = RESULTS / f"{case}.json", RESULTS / f"{case}-runs.jsonl"
    if not (path.exists() and runs.exists()):
        raise FileNotFoundError(f"{path} or {runs.name} is missing: run 'python -m validation "
                                f"run {case} --quick'")  # fmt: skip
    return json.loads(path.read_text()), latest_records(runs)


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
