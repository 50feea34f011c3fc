"""Validation cases as dask tasks (``python -m validation all --workers N | --scheduler ADDR``).

Each case runs on a worker and returns its rows; this process writes
``validation/results/CASE.{json,md}`` as each case finishes, exactly as the serial loop does.
A case that runs a sweep itself (the uncertainty studies) fans its realisations out over the
same cluster (:func:`validation.sweep.executors.open_executor` finds the worker it runs on).
Side files that cases write (``.npz`` curves, sweep stores) land on the workers' file system:
on a remote cluster, run it from a checkout the workers share.
"""

from __future__ import annotations

import time
import uuid
from collections.abc import Callable, Iterator

from validation.sweep.execute import one_numba_thread
from validation.sweep.executors import DaskExecutor, open_executor


def run_case(run: Callable, quick: bool) -> tuple[list, str, float]:
    """``(rows, notes, wall_s)`` of one case."""
    start = time.perf_counter()
    out = run(quick=quick)
    rows, notes = out if isinstance(out, tuple) else (out, "")
    return rows, notes, time.perf_counter() - start


def run_case_task(run: Callable, quick: bool) -> tuple[list, str, float]:
    """:func:`run_case` on a worker: one numba thread, as every task on a cluster."""
    with one_numba_thread():
        return run_case(run, quick)


def run_cases_on_cluster(
    cases: dict[str, Callable],
    quick: bool,
    workers: int | None = None,
    scheduler: str | None = None,
) -> Iterator[tuple[str, tuple | None, BaseException | None]]:
    """Run cases as dask tasks; yield ``(name, (rows, notes, wall_s) or None, error or None)``
    in completion order.

    Parameters
    ----------
    cases : dict
        ``name -> run(quick)``, module-level functions (workers import them by name).
    workers, scheduler :
        See :func:`validation.sweep.executors.open_executor`; ``workers=0`` runs serially here.
    """
    with open_executor(workers, scheduler) as ex:
        if not isinstance(ex, DaskExecutor):
            for name, run in cases.items():
                try:
                    yield name, run_case(run, quick), None
                except Exception as exc:  # report every case, fail at the end
                    yield name, None, exc
            return
        from distributed import as_completed

        token = uuid.uuid4().hex[:8]  # keys stay unique on a shared cluster
        futures = {
            ex.client.submit(
                run_case_task, run, quick, pure=False, key=f"case-{token}-{name}"
            ): name
            for name, run in cases.items()
        }
        for future in as_completed(futures):
            name = futures[future]
            try:
                yield name, future.result(), None
            except Exception as exc:  # report every case, fail at the end
                yield name, None, exc
            future.release()
