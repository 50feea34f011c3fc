"""Run one task and turn its outcome, success or error, into a record for the store."""

from __future__ import annotations

import contextlib
import json
import os
import socket
import time
import traceback
from collections.abc import Callable, Mapping
from typing import Any

from validation.sweep.tasks import Task, jsonable

TaskFunction = Callable[[dict, int], Mapping[str, Any]]
"""``fn(params, seed) -> result``: a module-level function (workers import it by name) whose
result is a small mapping of JSON-able values (scalars, short lists). Bulk data belongs in files
the function writes itself."""

MAX_RESULT_BYTES = 1_000_000


def base_record(task: Task) -> dict:
    return {"key": task.key, "index": task.index, "params": task.params, "seed": task.seed}


def execute_task(fn: TaskFunction, task: Task) -> dict:
    """Call ``fn(task.params, task.seed)``; an exception becomes a record with status "error".

    Returns
    -------
    dict
        ``key, index, params, seed, status ("ok" or "error"), result, error, traceback,
        wall_s [s], worker ("host:pid")``.
    """
    start = time.perf_counter()
    record = base_record(task)
    try:
        result = fn(dict(task.params), task.seed)
        if not isinstance(result, Mapping):
            raise TypeError(f"a task function must return a mapping, got {type(result).__name__}")
        result = jsonable(result)
        size = len(json.dumps(result, allow_nan=False))
        if size > MAX_RESULT_BYTES:
            raise ValueError(
                f"result of {size} bytes is over {MAX_RESULT_BYTES}: write bulk data to a file "
                "and return its path"
            )
        record.update(status="ok", result=result, error=None, traceback=None)
    except Exception as exc:  # a failed task is recorded, never fatal to the sweep
        record.update(
            status="error",
            result=None,
            error=f"{type(exc).__name__}: {exc}",
            traceback=traceback.format_exc(limit=20),
        )
    record["wall_s"] = time.perf_counter() - start
    record["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    return record


@contextlib.contextmanager
def one_numba_thread():
    """Limit numba's parallel kernels to one thread in this thread, restored on exit.

    A cluster runs one task per worker thread, usually one per core: the kernels' own threads
    (``prange``, default one per core) would oversubscribe the cores many times over.
    """
    import numba

    previous = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(previous)


def execute_task_one_thread(fn: TaskFunction, task: Task) -> dict:
    """:func:`execute_task` under :func:`one_numba_thread` (what cluster workers run)."""
    with one_numba_thread():
        return execute_task(fn, task)


def lost_task_record(task: Task, exc: BaseException) -> dict:
    """Record of a task whose worker died or whose future failed outside the function."""
    return {
        **base_record(task),
        "status": "error",
        "result": None,
        "error": f"{type(exc).__name__}: {exc}",
        "traceback": None,
        "wall_s": None,
        "worker": None,
    }
