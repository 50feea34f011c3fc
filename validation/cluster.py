"""Validation cases as dask tasks (``python -m validation all --workers N | --scheduler ADDR``).

Each case runs on a worker through the same :func:`validation.catalogue.run_case` as a serial run
(staged writes of ``CASE.{json,md}`` and side products), so its files are those of a serial
run. A case that runs a sweep itself (the uncertainty studies) fans its realisations out over
the same cluster (:func:`validation.sweep.executors.open_executor` finds the worker it runs
on). The files land on the workers' file system: on a remote cluster, run from a checkout the
workers share.
"""

from __future__ import annotations

import math
import time
import uuid
from collections.abc import Iterator, Mapping
from pathlib import Path

from validation.catalogue import MAIN_THREAD_CASES
from validation.catalogue import run_case as run_catalogued_case
from validation.sweep.execute import one_numba_thread
from validation.sweep.executors import DaskExecutor, open_executor


def run_case(name: str, quick: bool, out_dir: str | Path | None = None) -> float:
    """Run one case as ``python -m validation run`` does; return its wall time [s]."""
    start = time.perf_counter()
    run_catalogued_case(name, quick, None if out_dir is None else Path(out_dir))
    return time.perf_counter() - start


def run_case_task(name: str, quick: bool, out_dir: str | Path | None = None) -> float:
    """:func:`run_case` on a worker: one numba thread, as every task on a cluster."""
    with one_numba_thread():
        return run_case(name, quick, out_dir)


def run_cases_on_cluster(
    names: list[str],
    quick: bool,
    workers: int | None = None,
    scheduler: str | None = None,
    out_dir: str | Path | None = None,
    expected_s: Mapping[str, float] | None = None,
) -> Iterator[tuple[str, float | None, BaseException | None]]:
    """Run cases as dask tasks; yield ``(name, wall_s or None, error or None)`` in completion
    order. A case that needs a main thread (:data:`validation.catalogue.MAIN_THREAD_CASES`)
    runs here, in this process, while the cluster runs the others.

    Parameters
    ----------
    names : list of str
        Validation cases.
    quick : bool
    workers, scheduler :
        See :func:`validation.sweep.executors.open_executor`; ``workers=0`` runs serially here.
    out_dir : path, optional
        Results directory (default: :func:`validation.report.results_dir` of ``quick``).
    expected_s : mapping, optional
        Case -> expected wall time [s]. The cases are submitted and start longest first (a
        case of unknown cost first of all; the first submitted go to idle workers at once,
        whatever their priority): with fewer workers than cases, the run then ends soonest
        after its longest case (longest-processing-time order).
    """
    with open_executor(workers, scheduler) as ex:
        if not isinstance(ex, DaskExecutor):
            yield from _run_here(run_case, names, quick, out_dir)
            return
        from distributed import as_completed

        token = uuid.uuid4().hex[:8]  # keys stay unique on a shared cluster
        expected = expected_s or {}
        priority = {n: _priority(n, expected) for n in names if n not in MAIN_THREAD_CASES}
        futures = {
            ex.client.submit(
                run_case_task,
                name,
                quick,
                out_dir,
                pure=False,
                key=f"case-{token}-{name}",
                priority=priority[name],
            ): name
            for name in sorted(priority, key=priority.get, reverse=True)
        }
        here = [name for name in names if name in MAIN_THREAD_CASES]
        yield from _run_here(run_case_task, here, quick, out_dir)
        for future in as_completed(futures):
            name = futures[future]
            try:
                yield name, future.result(), None
            except Exception as exc:  # report every case, fail at the end
                yield name, None, exc
            future.release()


def _run_here(run, names: list[str], quick: bool, out_dir: str | Path | None):
    """``run`` each case in this thread, yielding as :func:`run_cases_on_cluster` does."""
    for name in names:
        try:
            yield name, run(name, quick, out_dir), None
        except Exception as exc:  # report every case, fail at the end
            yield name, None, exc


def _priority(name: str, expected_s: Mapping[str, float]) -> int:
    """Dask priority of a case (higher starts first): its expected wall time in whole seconds,
    the largest for a case of unknown cost."""
    wall = expected_s.get(name, math.inf)
    return 2**31 - 1 if not math.isfinite(wall) else int(wall)
