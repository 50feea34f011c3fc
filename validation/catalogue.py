"""The validation cases and how one is run: found in ``validation.cases``, run with staged
writes into the full or the quick results folder.

The command line (``validation.__main__``) and the dask runner of cases
(``validation.cluster``) both run cases through :func:`run_case`; neither imports the other.
"""

from __future__ import annotations

import importlib
import logging
import pkgutil
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import validation.cases
from validation.report import results_dir, staged, write_results

logger = logging.getLogger(__name__)


def discover_cases() -> tuple[dict[str, Callable], frozenset[str]]:
    """Every case, and those that must run in a process's main thread.

    Each module of ``validation.cases`` exposes ``CASES = {name: run}``; ``run(quick: bool)``
    returns a list of :class:`validation.report.Row`, or a pair ``(rows, notes)`` where
    ``notes`` is markdown stating the case's assumptions. A module may name in
    ``MAIN_THREAD`` the cases that need the main thread (a library that installs signal
    handlers), which a dask worker's task threads are not.
    """
    cases: dict[str, Callable] = {}
    main_thread: set[str] = set()
    for info in sorted(pkgutil.iter_modules(validation.cases.__path__), key=lambda m: m.name):
        try:
            module = importlib.import_module(f"validation.cases.{info.name}")
        except Exception as exc:  # a broken module must not hide the other cases
            cases[f"{info.name} (import failed)"] = _failed_import(info.name, exc)
            continue
        for name, run in getattr(module, "CASES", {}).items():
            if name in cases:
                raise RuntimeError(f"validation case {name!r} is defined twice")
            cases[name] = run
        main_thread.update(getattr(module, "MAIN_THREAD", ()))
    return cases, frozenset(main_thread)


def _failed_import(module: str, exc: Exception) -> Callable:
    def run(quick: bool):
        raise RuntimeError(f"validation.cases.{module} failed to import: {exc!r}") from exc

    return run


CASES, MAIN_THREAD_CASES = discover_cases()


def run_case(name: str, quick: bool, out_dir: str | Path | None = None) -> list:
    """Run one case and write ``OUT/NAME.{json,md}`` and its side products together
    (:func:`validation.report.staged`); warning filters the case sets end with it.

    ``OUT`` is ``out_dir``, by default :func:`validation.report.results_dir` of ``quick`` (a
    quick run never writes into the committed full results). Returns the case's rows.
    """
    if name not in CASES:
        raise ValueError(f"no validation case {name!r}; cases: {sorted(CASES)}")
    final = results_dir(quick) if out_dir is None else Path(out_dir)
    start = time.perf_counter()
    with staged(name, final) as stage, warnings.catch_warnings():
        out = CASES[name](quick=quick)
        rows, notes = out if isinstance(out, tuple) else (out, "")
        wall = time.perf_counter() - start
        write_results(name, rows, quick=quick, wall_s=wall, notes=notes, out_dir=stage)
    logger.info("%s: %d rows in %.1f s -> %s", name, len(rows), wall, final / name)
    return rows
