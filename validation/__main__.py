"""Command line: ``python -m validation list | run CASE [--quick] | all [--quick] |
manifest [--quick] [--write] | crosscheck SCENE [--live x] [--out DIR] [--methods ...]
[--quick]``.

Full runs write ``validation/results/`` (committed, all from one commit: ``MANIFEST.json``);
quick runs write ``validation/results-quick/`` (git-ignored) and never touch the full results.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from validation import catalogue
from validation.catalogue import CASES
from validation.crosscheck.cli import add_arguments as add_crosscheck_arguments
from validation.crosscheck.cli import join_signed_values
from validation.crosscheck.cli import run as run_crosscheck
from validation.main_job import run_all
from validation.manifest import check_manifest, previous_wall_times, write_manifest
from validation.provenance import git_commit, git_dirty
from validation.report import results_dir


def run_case(name: str, quick: bool, out_dir: Path | None = None) -> list:
    """:func:`validation.catalogue.run_case`, with a line on the terminal."""
    rows = catalogue.run_case(name, quick, out_dir)
    final = results_dir(quick) if out_dir is None else Path(out_dir)
    print(f"{name}: {len(rows)} rows -> {final / name}.{{json,md}}")
    return rows


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m validation")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="name every case")
    run = sub.add_parser("run", help="run one case")
    run.add_argument("case", choices=sorted(CASES))
    every = sub.add_parser("all", help="run every case")
    every.add_argument(
        "--verbose", action="store_true", help="print everything instead of one line per case"
    )
    every.add_argument(
        "--allow-dirty",
        action="store_true",
        help="run the full cases from a tree with uncommitted changes (marked in every file)",
    )
    manifest = sub.add_parser(
        "manifest", help="say which results are not from the manifest's commit"
    )
    manifest.add_argument("--write", action="store_true", help="rebuild it from the files")
    for p in (run, every, manifest):
        p.add_argument(
            "--quick", action="store_true", help=f"small, fast versions, in {_QUICK_NAME}"
        )
    for p in (run, every):
        _add_cluster_args(p)
    cross = sub.add_parser("crosscheck", help="every method on one scene -> report")
    add_crosscheck_arguments(cross)
    return parser


_QUICK_NAME = "validation/results-quick/"


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(join_signed_values(sys.argv[1:] if argv is None else argv))
    if args.command == "list":
        for name in CASES:
            print(name)
        return 0
    if args.command == "crosscheck":
        return run_crosscheck(args)
    if args.command == "manifest":
        return _manifest(args.quick, args.write)
    if args.command == "all" and not args.quick and not args.allow_dirty:
        dirty, files = git_dirty()
        if dirty:
            print(
                f"validation all: the tree has uncommitted changes ({', '.join(files[:5])}): "
                "full results come from one clean commit (commit first, or --allow-dirty)",
                file=sys.stderr,
            )
            return 2
    commit = git_commit()
    status = _run_cases(args)
    if args.command == "all":  # the folder's manifest names the commit of this run
        write_manifest(results_dir(args.quick), commit)
        _manifest(args.quick, write=False)
    return status


def _run_cases(args) -> int:
    names = [args.case] if args.command == "run" else list(CASES)
    if args.workers is not None or args.scheduler:
        return _run_on_cluster(names, args)
    if args.command == "all" and not args.verbose:
        log = results_dir(args.quick) / "validation.log"
        summaries = run_all(names, run_case, args.quick, log)
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


def _manifest(quick: bool, write: bool) -> int:
    """Rebuild (``write``) or check the manifest of the full or quick results; 1 when a
    result is not from its commit."""
    folder = results_dir(quick)
    if write:
        print(f"wrote {write_manifest(folder)}")
    problems = check_manifest(folder, CASES, full=not quick)
    for line in problems:
        print(line)
    if not problems:
        print(f"{folder}: every result is from the manifest's commit, from a clean tree")
    return 1 if problems else 0


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
    """The cases as dask tasks (validation.cluster); each writes its results as it ends.

    A case's failure is reported and the others go on (1 at the end); a cluster that cannot
    be used is one line naming it: 2 for an address that is none (bad usage), 1 for one that
    cannot be reached or a cluster that fails."""
    from validation.cluster import run_cases_on_cluster
    from validation.sweep.executors import SCHEDULER_ENV

    failed = []
    expected = previous_wall_times(results_dir(args.quick))
    cases = run_cases_on_cluster(
        names, args.quick, args.workers, args.scheduler, expected_s=expected
    )
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
