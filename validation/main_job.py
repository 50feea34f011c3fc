"""``python -m validation all``: one progress line per case, a summary table, the rest logged.

The summary separates numerical errors (rows whose reference is a value of our own model: a
closed form, an exact count or another method) from model errors (rows whose reference is
another model: a seed's table or experiment, an approximate formula), by
:attr:`validation.report.Row.reference_is_model`, as ``paper_figures/fig_speed_error.py`` does, and
counts the rows whose reference lies outside our error bar (numerical / model) and the rows
whose bar is not estimated.
"""

from __future__ import annotations

import math
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from validation.quiet import quiet, table
from validation.report import Row


@dataclass(frozen=True)
class CaseSummary:
    """One line of the final table.

    Attributes
    ----------
    case : str
    rows : int
    worst_numerical, worst_model : float or None
        Largest relative error of the rows with a numerical / published reference [-].
    outside_numerical, outside_model, outside_partial : int
        Rows whose reference lies outside our error bar, by
        :attr:`~validation.report.Row.error_kind`: numerical, model, or a partial bar (one
        that omits known sources).
    no_bar : int
        Rows with a value whose error bar is not estimated (``inf``).
    wall_s : float
        [s].
    failed : str
        Empty, or the error that ended the case.
    """

    case: str
    rows: int
    worst_numerical: float | None
    worst_model: float | None
    wall_s: float
    failed: str = ""
    outside_numerical: int = 0
    outside_model: int = 0
    outside_partial: int = 0
    no_bar: int = 0

    @classmethod
    def of(cls, case: str, rows: Sequence[Row], wall_s: float) -> CaseSummary:
        worst: dict[bool, float | None] = {True: None, False: None}
        for r in rows:
            err = r.rel_error
            if err is None or not math.isfinite(err):
                continue
            kind = r.reference_is_model
            worst[kind] = err if worst[kind] is None else max(worst[kind], err)
        kinds = [r.error_kind for r in rows]
        no_bar = sum(r.estimate is not None and math.isinf(r.ours_error) for r in rows)
        return cls(
            case,
            len(rows),
            worst[False],
            worst[True],
            wall_s,
            outside_numerical=kinds.count("numerical"),
            outside_model=kinds.count("model"),
            outside_partial=kinds.count("partial bar"),
            no_bar=no_bar,
        )

    def cells(self) -> list:
        return [
            self.case,
            self.rows,
            self.worst_numerical,
            self.worst_model,
            f"{self.outside_numerical}/{self.outside_model}/{self.outside_partial}",
            self.no_bar,
            round(self.wall_s, 1),
            self.failed or "no",
        ]


HEADER = (
    "case",
    "rows",
    "worst numerical error",
    "worst model error",
    "outside bar (num/model/partial)",
    "no bar",
    "wall [s]",
    "failed",
)


def run_all(
    names: Sequence[str],
    run_case: Callable[[str, bool], list[Row]],
    quick: bool,
    log_path: Path,
) -> list[CaseSummary]:
    """Run every case quietly; print a line per case and the summary table to the terminal.

    Parameters
    ----------
    names : sequence of str
    run_case : callable
        ``run_case(name, quick)`` runs a case, writes its files and returns its rows.
    quick : bool
    log_path : Path
        Where warnings, solver output and tracebacks go.
    """
    summaries = []
    with quiet(log_path) as console:
        console.write(f"{len(names)} cases{' (quick)' if quick else ''}; log: {log_path}\n")
        for i, name in enumerate(names, 1):
            console.write(f"[{i}/{len(names)}] {name} ... ")
            start = time.perf_counter()
            print(f"===== {name} =====")  # goes to the log, marks where each case starts
            try:
                rows = run_case(name, quick)
                s = CaseSummary.of(name, rows, time.perf_counter() - start)
                console.write(f"ok, {s.rows} rows, {s.wall_s:.1f} s\n")
            except Exception as exc:  # report every case, fail at the end
                traceback.print_exc()
                s = CaseSummary(
                    name, 0, None, None, time.perf_counter() - start, f"{type(exc).__name__}"
                )
                console.write(f"FAILED ({type(exc).__name__}: {exc}; see the log)\n")
            summaries.append(s)
        console.write("\n" + table(HEADER, [s.cells() for s in summaries]) + "\n")
    return summaries
