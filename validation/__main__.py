"""Command line: ``python -m validation list | run CASE [--quick] | all [--quick] |
crosscheck SCENE [--live x] [--out DIR] [--methods ...] [--quick]``."""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import sys
import time
import warnings
from collections.abc import Callable
from pathlib import Path

import validation.cases
from validation.crosscheck.cli import add_arguments as add_crosscheck_arguments
from validation.crosscheck.cli import join_signed_values
from validation.crosscheck.cli import run as run_crosscheck
from validation.main_job import run_all
from validation.report import RESULTS_DIR, staged, write_results


def discover_cases() -> dict[str, Callable]:
    """Every case: each module of ``validation.cases`` exposes ``CASES = {name: run}``.

    ``run(quick: bool)`` returns a list of :class:`validation.report.Row`, or a pair
    ``(rows, notes)`` where ``notes`` is markdown stating the case's assumptions.
    """
    cases: dict[str, Callable] = {}
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
    return cases


def _failed_import(module: str, exc: Exception) -> Callable:
    def run(quick: bool):
        raise RuntimeError(f"validation.cases.{module} failed to import: {exc!r}") from exc

    return run


CASES = discover_cases()


def run_case(name: str, quick: bool, out_dir: Path | None = None) -> list:
    """Run one case and write ``validation/results/NAME.{json,md}`` and its side products
    together (:func:`validation.report.staged`); warning filters the case sets end with it.
    Returns the case's rows."""
    start = time.perf_counter()
    with staged(name, out_dir) as stage, warnings.catch_warnings():
        out = CASES[name](quick=quick)
        rows, notes = out if isinstance(out, tuple) else (out, "")
        wall = time.perf_counter() - start
        write_results(name, rows, quick=quick, wall_s=wall, notes=notes, out_dir=stage)
    final = Path(RESULTS_DIR if out_dir is None else out_dir)
    print(f"{name}: {len(rows)} rows in {wall:.1f} s -> {final / name}.{{json,md}}")
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m validation")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="name every case")
    run = sub.add_parser("run", help="run one case")
    run.add_argument("case", choices=sorted(CASES))
    run.add_argument("--quick", action="store_true", help="small, fast version")
    every = sub.add_parser("all", help="run every case")
    every.add_argument("--quick", action="store_true", help="small, fast versions")
    every.add_argument(
        "--verbose", action="store_true", help="print everything instead of one line per case"
    )
    for p in (run, every):
        _add_cluster_args(p)
    cross = sub.add_parser("crosscheck", help="every method on one scene -> report")
    add_crosscheck_arguments(cross)
    args = parser.parse_args(join_signed_values(sys.argv[1:] if argv is None else argv))

    if args.command == "list":
        for name in CASES:
            print(name)
        return 0
    if args.command == "crosscheck":
        return run_crosscheck(args)
    names = [args.case] if args.command == "run" else list(CASES)
    if args.workers is not None or args.scheduler:
        return _run_on_cluster(names, args)
    if args.command == "all" and not args.verbose:
        summaries = run_all(names, run_case, args.quick, RESULTS_DIR / "validation.log")
        return 1 if any(s.failed for s in summaries) else 0
    failed = []
    for name in names:
        try:
            run_case(name, args.quick)
        except Exception as exc:  # report every case, fail at the end
            print(f"{name}: FAILED: {type(exc).__name__}: {exc}", file=sys.stderr)
            failed.append(name)
            if args.command == "run":
                raise
    if failed:
        print(f"failed cases: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


def _add_cluster_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--workers",
        type=_worker_count,
        default=None,
        help="run the cases as dask tasks on a local cluster of N worker processes",
    )
    parser.add_argument(
        "--scheduler",
        default=None,
        help="run the cases as dask tasks on a running cluster (tcp://HOST:PORT)",
    )


def _worker_count(text: str) -> int:
    """``--workers N``: an integer >= 0 (0 runs serially in this process)."""
    try:
        n = int(text)
    except ValueError:
        n = -1
    if n < 0:
        raise argparse.ArgumentTypeError(
            f"must be an integer >= 0 (0: serially in this process), got {text!r}"
        )
    return n


def _run_on_cluster(names: list[str], args) -> int:
    """The cases as dask tasks (validation.sweep.cases); each writes its results as it ends.

    A case's failure is reported and the others go on (1 at the end); a cluster that cannot
    be used is one line naming it: 2 for an address that is none (bad usage), 1 for one that
    cannot be reached or a cluster that fails."""
    from validation.sweep.cases import run_cases_on_cluster
    from validation.sweep.executors import SCHEDULER_ENV

    failed = []
    cases = run_cases_on_cluster(names, args.quick, args.workers, args.scheduler)
    scheduler = args.scheduler or os.environ.get(SCHEDULER_ENV)
    where = f"the scheduler {scheduler}" if scheduler else f"{args.workers} local workers"
    try:
        for name, wall, exc in cases:
            if exc is not None:
                print(f"{name}: FAILED: {type(exc).__name__}: {exc}", file=sys.stderr)
                failed.append(name)
            else:
                print(f"{name}: finished on the cluster in {wall:.1f} s")
    except ValueError as exc:  # a case's own errors are yielded, not raised
        print(f"validation: cannot use {where}: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"validation: cannot use {where}: {exc}", file=sys.stderr)
        return 1
    if failed:
        print(f"failed cases: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
