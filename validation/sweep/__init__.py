"""Parameter sweeps and Monte Carlo studies on dask.distributed.

A sweep is a task function ``fn(params, seed) -> dict``, a list or generator of
:class:`Task` (parameters + a per-task seed from :func:`make_tasks`), and a store directory
where each finished task's record is appended as it arrives::

    from validation.sweep import make_tasks, run_sweep

    tasks = make_tasks(({"mu": mu} for mu in (0.5, 0.6, 0.7)), root_seed=1)
    summary = run_sweep(my_module.my_task, tasks, "out/my-sweep")   # local cluster
    rows = summary.records()

Run it again with the same directory after a kill and only the missing tasks run. Pass
``scheduler="tcp://HOST:PORT"`` (or set ``BLOCKMECH_SCHEDULER``) to use a running cluster, and
``workers=0`` to run serially in this process.
"""

from validation.sweep.executors import (
    SCHEDULER_ENV,
    DaskExecutor,
    SerialExecutor,
    open_executor,
)
from validation.sweep.runner import SweepSummary, run_sweep
from validation.sweep.store import ResultStore, SweepStoreError, latest_records, read_records
from validation.sweep.tasks import Task, make_tasks, task_seeds

__all__ = [
    "SCHEDULER_ENV",
    "DaskExecutor",
    "ResultStore",
    "SerialExecutor",
    "SweepStoreError",
    "SweepSummary",
    "Task",
    "latest_records",
    "make_tasks",
    "open_executor",
    "read_records",
    "run_sweep",
    "task_seeds",
]
