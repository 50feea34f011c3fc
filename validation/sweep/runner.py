"""Run a sweep: tasks in, records streamed to an append-only store, finished tasks skipped.

Each record is stamped as it is stored with the commit and clean flag of the run
(:func:`validation.provenance.stamp`) and the date it finished; the task's own wall time is
``wall_s``. A resumed study may hold records of several commits: the results manifest says so.
"""

from __future__ import annotations

import contextlib
import logging
import time
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from validation import provenance
from validation.sweep.execute import TaskFunction
from validation.sweep.executors import Executor, open_executor
from validation.sweep.progress import ConsoleProgress, NoProgress
from validation.sweep.store import ResultStore, SweepStoreError, latest_records
from validation.sweep.tasks import Task, jsonable

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class SweepSummary:
    """What one call of :func:`run_sweep` did.

    Attributes
    ----------
    directory : Path
        The store (``manifest.json``, ``results.jsonl``).
    n_run, n_skipped, n_failed : int
        Tasks run now, found finished in the store, and failed among those run now.
    wall_s : float
        [s].
    n_workers : int
        Worker threads of the executor.
    """

    directory: Path
    n_run: int
    n_skipped: int
    n_failed: int
    wall_s: float
    n_workers: int

    def records(self) -> list[dict]:
        """The last record of every task in the store, by task index."""
        return latest_records(Path(self.directory) / "results.jsonl")


def function_name(fn: TaskFunction) -> str:
    return f"{fn.__module__}.{fn.__qualname__}"


def run_sweep(
    fn: TaskFunction,
    tasks: Iterable[Task],
    directory: str | Path,
    *,
    manifest: dict | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    executor: Executor | None = None,
    progress: bool = True,
    retry_failed: bool = False,
    overwrite: bool = False,
) -> SweepSummary:
    """Run ``fn(task.params, task.seed)`` for every task not yet in the store at ``directory``.

    Parameters
    ----------
    fn : callable
        Module-level task function (see :data:`validation.sweep.execute.TaskFunction`).
    tasks : iterable of Task
        A list, or a generator read lazily as workers free up.
    directory : path
        The store; a killed sweep rerun with the same directory skips what is done.
    manifest : dict, optional
        What else identifies the study (root seed, settings); with the function's name it must
        match the store's manifest (see :class:`ResultStore`).
    workers, scheduler :
        Where to run (see :func:`validation.sweep.executors.open_executor`); ignored when
        ``executor`` is given.
    progress : bool
        Console progress bar on stderr.
    retry_failed : bool
        Run again the tasks whose last record is a failure (default: a failure is a result).
    overwrite : bool
        Start afresh in a store whose manifest differs instead of raising (its records are
        set aside in ``superseded/N/``, see :class:`validation.sweep.store.ResultStore`).

    Returns
    -------
    SweepSummary
        Counts only: the records stay on disk (``summary.records()`` reads them back).
    """
    store = ResultStore(
        Path(directory), {"function": function_name(fn), **(manifest or {})}, overwrite
    )
    store.open()
    try:
        done = store.finished(include_failed=not retry_failed)
        todo = _unfinished(tasks, done)
        total = None
        if isinstance(tasks, Sequence):
            todo = list(todo)
            total = len(todo)
        bar = ConsoleProgress(total, label=store.directory.name) if progress else NoProgress()
        start = time.perf_counter()
        n_run = n_failed = 0
        origin = provenance.stamp()
        origin = {k: origin[k] for k in ("git_commit", "git_clean")}
        with _maybe_open(executor, workers, scheduler) as ex:
            bar.skipped = len(done)
            for record in ex.run(fn, todo):
                store.append({**record, **origin, "date": provenance.now()})
                n_run += 1
                n_failed += record["status"] != "ok"
                if record["status"] != "ok":
                    logger.warning("task %s failed: %s", record["key"], record["error"])
                bar.update(record)
            n_workers = ex.n_workers
        bar.close()
    finally:
        store.close()
    return SweepSummary(
        store.directory, n_run, len(done), n_failed, time.perf_counter() - start, n_workers
    )


def _unfinished(tasks: Iterable[Task], done: dict) -> Iterator[Task]:
    seen: set[str] = set()
    for task in tasks:
        if task.key in seen:
            raise ValueError(f"task key {task.key!r} appears twice in the sweep")
        seen.add(task.key)
        if task.key in done:
            if jsonable(task.params) != done[task.key]:
                raise SweepStoreError(
                    f"task {task.key} is in the store with other parameters "
                    f"({done[task.key]} vs {task.params}): use a new directory"
                )
            continue
        yield task


def _maybe_open(executor, workers, scheduler):
    if executor is not None:
        return contextlib.nullcontext(executor)
    return open_executor(workers, scheduler)
