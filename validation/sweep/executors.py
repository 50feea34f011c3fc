"""Where tasks run: in this process, or on a dask.distributed cluster (local or remote).

An executor is anything with ``run(fn, tasks) -> iterator of records`` (records in completion
order) and ``n_workers``. :func:`open_executor` picks one:

1. inside a task on a dask worker (a validation case run by ``validation all --workers N``):
   the same cluster, through ``distributed.worker_client`` (the task secedes from the worker's
   thread pool while its sub-tasks run, so a single-threaded worker does not deadlock);
2. ``scheduler`` or the environment variable ``BLOCKMECH_SCHEDULER`` (``tcp://HOST:PORT`` or a
   scheduler file): an existing cluster;
3. ``workers=0``: serially in this process (debugging, and the reference for tests);
4. otherwise a ``LocalCluster`` of ``workers`` (default: ``$BLOCKMECH_WORKERS``, else one per
   core) single-threaded worker processes. Processes, not threads: the numba kernels are
   compiled without ``nogil``, so they hold the GIL and threads of one process do not run them
   in parallel (``benchmarks/bench_sweep.py`` measures it). On a cluster every task runs with
   one numba thread (:func:`validation.sweep.execute.execute_task_one_thread`): one task per
   core already fills the machine.
"""

from __future__ import annotations

import contextlib
import logging
import os
import uuid
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Protocol

from validation.sweep.execute import (
    TaskFunction,
    execute_task,
    execute_task_one_thread,
    lost_task_record,
)
from validation.sweep.tasks import Task

logger = logging.getLogger(__name__)

SCHEDULER_ENV = "BLOCKMECH_SCHEDULER"
WORKERS_ENV = "BLOCKMECH_WORKERS"
IN_FLIGHT_PER_WORKER = 2
QUIET_WORKERS = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.scheduler.work-stealing-interval": "1s",
}
"""dask settings of the local clusters this module starts. Every 10 ms the statistical profiler
samples the task's stack and every 20 ms the event-loop tick wakes each process; on a machine
with as many workers as cores those wake-ups (and the scheduler's work stealing, every 100 ms)
preempt the tasks; ``benchmarks/bench_sweep.py`` measures the speed-up. The memory monitor keeps
its default, so memory limits act as promptly."""


def local_cluster(n_workers: int, threads_per_worker: int = 1):
    """A ``LocalCluster`` of ``n_workers`` worker processes with :data:`QUIET_WORKERS` (the
    worker processes receive the settings when they start). The numba kernels are compiled
    here first, so that the workers load the on-disk cache rather than write it at the same
    time (:mod:`dem.warmup`)."""
    import dask
    from distributed import LocalCluster

    from dem.warmup import compile_kernels

    compile_kernels()
    with dask.config.set(QUIET_WORKERS):
        return LocalCluster(
            n_workers=n_workers,
            threads_per_worker=threads_per_worker,
            processes=True,
            dashboard_address=":0",
        )


class Executor(Protocol):
    n_workers: int

    def run(self, fn: TaskFunction, tasks: Iterable[Task]) -> Iterator[dict]: ...


@dataclass
class SerialExecutor:
    """Every task in this process, in order."""

    n_workers: int = 1

    def run(self, fn: TaskFunction, tasks: Iterable[Task]) -> Iterator[dict]:
        for task in tasks:
            yield execute_task(fn, task)


@dataclass
class DaskExecutor:
    """Tasks on a dask.distributed cluster, at most ``in_flight`` submitted at once.

    The task iterator is read only as results come back, so a sweep of a million parameter
    sets holds a few futures at a time, not a million.
    """

    client: object
    in_flight: int | None = None

    @property
    def n_workers(self) -> int:
        return max(1, sum(self.client.nthreads().values()))

    def run(self, fn: TaskFunction, tasks: Iterable[Task]) -> Iterator[dict]:
        from distributed import as_completed

        window = self.in_flight or IN_FLIGHT_PER_WORKER * self.n_workers + 1
        # keys must be unique on a cluster that several sweeps share
        token = uuid.uuid4().hex[:8]
        source = iter(tasks)
        pending: dict = {}
        running = as_completed()
        for task in _take(source, window):
            running.add(self._submit(fn, task, pending, token))
        for future in running:
            task = pending.pop(future.key)
            try:
                record = future.result()
            except Exception as exc:  # worker died (KilledWorker), cancelled, ...
                record = lost_task_record(task, exc)
            future.release()
            for nxt in _take(source, 1):
                running.add(self._submit(fn, nxt, pending, token))
            yield record

    def _submit(self, fn, task: Task, pending: dict, token: str):
        key = f"sweep-{token}-{task.key}"
        future = self.client.submit(execute_task_one_thread, fn, task, pure=False, key=key)
        if future.key in pending:
            raise ValueError(f"task key {task.key!r} appears twice in the sweep")
        pending[future.key] = task
        return future


def _take(source: Iterator[Task], n: int) -> list[Task]:
    out = []
    for _ in range(n):
        try:
            out.append(next(source))
        except StopIteration:
            break
    return out


def in_dask_worker() -> bool:
    try:
        from distributed import get_worker

        get_worker()
    except (ImportError, ValueError):
        return False
    return True


@contextlib.contextmanager
def open_executor(workers: int | None = None, scheduler: str | None = None) -> Iterator[Executor]:
    """The executor of the module docstring's rules, closed (cluster shut down) on exit.

    Parameters
    ----------
    workers : int, optional
        Local worker processes; 0 for serial in this process; default ``$BLOCKMECH_WORKERS``,
        else one per core.
    scheduler : str, optional
        Address (``tcp://HOST:PORT``) or scheduler-file path of a running cluster; default
        ``$BLOCKMECH_SCHEDULER``.
    """
    if workers is None and os.environ.get(WORKERS_ENV):
        workers = int(os.environ[WORKERS_ENV])
    if workers is not None and (not isinstance(workers, int) or workers < 0):
        raise ValueError(f"workers must be a non-negative integer, got {workers!r}")
    scheduler = scheduler or os.environ.get(SCHEDULER_ENV) or None
    if in_dask_worker():
        from distributed import worker_client

        with worker_client() as client:
            yield DaskExecutor(client)
        return
    if scheduler is not None:
        from distributed import Client

        kw = {"scheduler_file": scheduler} if os.path.isfile(scheduler) else {"address": scheduler}
        with Client(timeout="20s", **kw) as client:
            logger.info("sweep on %s (%d threads)", scheduler, sum(client.nthreads().values()))
            yield DaskExecutor(client)
        return
    if workers == 0:
        yield SerialExecutor()
        return
    from distributed import Client

    n = workers or os.cpu_count() or 1
    with local_cluster(n) as cluster, Client(cluster) as client:
        logger.info("sweep on a local cluster of %d single-threaded processes", n)
        yield DaskExecutor(client)
