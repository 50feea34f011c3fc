"""Speed of sweeps on dask.distributed: parallel speed-up, overhead, memory, projections.

Run ``python benchmarks/bench_sweep.py [--tasks 16] [--workers 2]``. Prints

1. GIL: (a) the rate of a pure-Python counter in a second thread while one small DEM task
   runs, over its rate while idle (about 1: the task leaves the GIL free; about 0: it holds
   it); (b) four small tasks on one worker process with one thread and with two threads, and
   on two single-threaded processes;
2. the same ``--tasks`` small tasks (3 x 3 TIS panel to 85 % past the peak, per-block random
   mu) serially in this process and on ``--workers`` local worker processes: wall times and
   the speed-up (target >= 1.8 on 2 workers), split into the share of the workers' time
   spent inside tasks and the slowdown of a task when the workers run side by side;
3. scheduler overhead per task: 400 closed-form tasks through ``run_sweep`` (store writes with
   fsync included) and through bare ``client.submit`` (target < 50 ms per task);
4. resident memory of each worker after the tasks;
5. a projection (printed, not claimed) of the full studies on 2, 16 and 128 workers from the
   per-task wall times recorded in their sweep stores (``validation/results/sweeps/``).

Wall-clock times on a shared machine: compare ratios within one run. The first task on each
worker loads the numba cache; every timing below comes after a warm-up on every worker.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import tempfile
import threading
import time
from pathlib import Path

from dem.tis_stiffness import K_GAPS_SEED_000, k_series, tis_panel_k_def
from dem.units import GPA, MM
from validation.cases.tis import QUICK
from validation.cases.uq import tis_friction_task
from validation.report import reading_dir
from validation.sweep import DaskExecutor, SerialExecutor, latest_records, make_tasks, run_sweep
from validation.sweep.demo import tilting_block
from validation.sweep.execute import execute_task_one_thread, one_numba_thread
from validation.sweep.executors import local_cluster

RESULTS = reading_dir()  # validation/results, or BLOCKMECH_RESULTS (quick or a path)
K_IMP_3 = k_series(tis_panel_k_def(3), K_GAPS_SEED_000) / (GPA / MM)
SMALL = {"n": 3, "theta_deg": 2.5, "k_n_gpa_mm": K_IMP_3, "disc": QUICK, "mu_mean": 0.23,
         "mu_std": 0.06, "stop_below_peak_fraction": 0.85}  # fmt: skip
STUDIES = {"tis-friction-uq": 65, "tis-gaps-uq": 66, "masonry-uq": 65}
"""Tasks of each full study (64 + 1, 4 x 16 + 2, 64 + 1)."""


def _cluster(n_workers: int, threads: int = 1):
    from distributed import Client

    cluster = local_cluster(n_workers, threads)
    return cluster, Client(cluster)


def _timed_sweep(executor, n: int, root: int, tmp: Path, fn=tis_friction_task, params=SMALL):
    out = tmp / f"s{root}-{type(executor).__name__}-{time.perf_counter_ns()}"
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    summary = run_sweep(fn, list(make_tasks([params] * n, root)), out, executor=executor,
                        progress=False)  # fmt: skip
    wall = time.perf_counter() - start
    assert summary.n_failed == 0, [r["error"] for r in summary.records()][:3]
    return wall, summary


def _warm(client) -> None:
    """One small task pinned to every worker (each loads and compiles the numba kernels)."""
    tasks = list(make_tasks([SMALL], 999))
    futures = [client.submit(execute_task_one_thread, tis_friction_task, tasks[0], workers=[w],
                             pure=False) for w in client.nthreads()]  # fmt: skip
    client.gather(futures)


def _probe_rate(work, seconds: float | None = None) -> tuple[float, float]:
    """Iterations per second of a pure-Python counter in a second thread while ``work`` runs
    in this one (or while this thread sleeps ``seconds``); and the wall time."""
    count, stop = [0], threading.Event()

    def probe():
        while not stop.is_set():
            count[0] += 1

    thread = threading.Thread(target=probe)
    start = time.perf_counter()
    thread.start()
    if work is None:
        time.sleep(seconds)
    else:
        work()
    stop.set()
    thread.join()
    wall = time.perf_counter() - start
    return count[0] / wall, wall


def gil_probe() -> None:
    print("== 1a. GIL probe: does a second thread run while a DEM task runs? ==")
    task = next(make_tasks([SMALL], 997))
    with one_numba_thread():
        tis_friction_task(task.params, task.seed)  # compile / load the cache
        busy, wall = _probe_rate(lambda: tis_friction_task(task.params, task.seed))
    idle, _ = _probe_rate(None, wall)
    print(
        f"  probe thread rate during the task / while idle: {busy / idle:.2f} "
        "(about 1: the task leaves the GIL free; about 0: it holds it)"
    )


def gil(tmp: Path) -> None:
    print("== 1b. threads or processes: 4 small DEM tasks ==")
    times = {}
    for label, (workers, threads) in {"1 process x 1 thread": (1, 1),
                                      "1 process x 2 threads": (1, 2),
                                      "2 processes x 1 thread": (2, 1)}.items():  # fmt: skip
        cluster, client = _cluster(workers, threads)
        try:
            _warm(client)
            times[label], _ = _timed_sweep(DaskExecutor(client), 4, 1, tmp)
        finally:
            client.close()
            cluster.close()
        print(f"  {label:24s} {times[label]:7.2f} s")
    base = times["1 process x 1 thread"]
    print(f"  speed-up with 2 threads:   {base / times['1 process x 2 threads']:.2f}")
    print(f"  speed-up with 2 processes: {base / times['2 processes x 1 thread']:.2f}")


def speedup(n_tasks: int, n_workers: int, tmp: Path) -> None:
    print(f"== 2. {n_tasks} small tasks: serial vs {n_workers} worker processes ==")
    _timed_sweep(SerialExecutor(), 1, 998, tmp)  # warm this process
    # the explicit solver's prange kernels use every core in a serial run: time both
    serial, s_sum = _timed_sweep(SerialExecutor(), n_tasks, 2, tmp)
    with one_numba_thread():
        serial_1, s1_sum = _timed_sweep(SerialExecutor(), n_tasks, 2, tmp)
    cluster, client = _cluster(n_workers)
    try:
        _warm(client)
        parallel, p_sum = _timed_sweep(DaskExecutor(client), n_tasks, 2, tmp)
        same = [r["result"] for r in s_sum.records()] == [r["result"] for r in p_sum.records()]
        per_task = statistics.median(r["wall_s"] for r in s_sum.records())
        print(
            f"  serial {serial:.2f} s ({per_task:.2f} s per task, numba on every core), serial "
            f"on one numba thread {serial_1:.2f} s, dask {parallel:.2f} s; results identical: "
            f"{same}"
        )
        print(
            f"  speed-up {serial / parallel:.2f} over serial, {serial_1 / parallel:.2f} over "
            "serial on one numba thread (target >= 1.8)"
        )
        _explain(serial_1, parallel, s1_sum, p_sum, n_workers)
        overhead(client, tmp)
        memory(client)
    finally:
        client.close()
        cluster.close()


def _explain(serial_1: float, parallel: float, s1_sum, p_sum, n_workers: int) -> None:
    """Split the gap to ``n_workers`` x into idle workers and slower tasks.

    speed-up = n_workers * busy / slowdown * serial_1 / sum(serial task times), where busy is
    the share of the workers' time spent inside tasks (scheduling, transfer and the tail of
    the last wave are the rest) and slowdown is how much longer a task takes when the
    workers run side by side (shared caches, memory bandwidth, other processes).
    """
    serial_tasks = sum(r["wall_s"] for r in s1_sum.records())
    parallel_tasks = sum(r["wall_s"] for r in p_sum.records())
    busy = parallel_tasks / (n_workers * parallel)
    print(
        f"  workers busy inside tasks {100 * busy:.1f} % of the dask wall time; a task takes "
        f"{parallel_tasks / serial_tasks:.3f} x its serial time when {n_workers} run at once; "
        f"the serial loop spends {100 * serial_tasks / serial_1:.1f} % inside tasks"
    )


def overhead(client, tmp: Path, n: int = 400) -> None:
    print(f"== 3. scheduler overhead, {n} closed-form tasks ==")
    params = {"b": 0.2, "h": 0.4, "mu_mean": 0.5, "mu_std": 0.1}
    wall, _ = _timed_sweep(DaskExecutor(client), n, 3, tmp, tilting_block, params)
    start = time.perf_counter()
    futures = [client.submit(tilting_block, params, i, pure=False) for i in range(n)]
    client.gather(futures)
    bare = time.perf_counter() - start
    print(
        f"  run_sweep (store + fsync): {1e3 * wall / n:.1f} ms per task; bare submit/gather: "
        f"{1e3 * bare / n:.1f} ms per task (target < 50 ms)"
    )


def memory(client) -> None:
    import psutil

    print("== 4. memory per worker (resident, after the tasks) ==")
    rss = client.run(lambda: psutil.Process().memory_info().rss)
    for addr, value in rss.items():
        print(f"  {addr}: {value / 2**20:.0f} MiB")


def projection() -> None:
    print("== 5. projection of the full studies (median wall per run from CASE-runs.jsonl) ==")
    print(f"  {'study':16s} {'runs':>5s} {'t/run':>7s} {'2 workers':>10s} {'16':>7s} {'128':>7s}")
    for study, n in STUDIES.items():
        runs, case = RESULTS / f"{study}-runs.jsonl", RESULTS / f"{study}.json"
        if not (runs.exists() and case.exists()):
            print(f"  {study:16s} (no results: run the case first)")
            continue
        t = statistics.median(r["wall_s"] for r in latest_records(runs) if r["wall_s"])
        cells = [f"{math.ceil(n / w) * t / 60:6.1f}m" for w in (2, 16, 128)]
        mode = "quick" if json.loads(case.read_text())["quick"] else "full"
        print(
            f"  {study:16s} {n:5d} {t:6.1f}s {cells[0]:>10s} {cells[1]:>7s} {cells[2]:>7s}"
            f"  (t/run of the {mode} results)"
        )
    print(
        "  waves of ceil(runs / workers) runs of the median time; quick runs are coarser (shorter)"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--tasks", type=int, default=16)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--skip-gil", action="store_true")
    args = parser.parse_args()
    print(f"load average at start: {os.getloadavg()}, cores: {os.cpu_count()}")
    with tempfile.TemporaryDirectory() as tmp:
        if not args.skip_gil:
            gil_probe()
            gil(Path(tmp))
        speedup(args.tasks, args.workers, Path(tmp))
    projection()
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
