"""The sweep runner: seeds, store, resume after a kill, failures, laziness, serial = dask.

Expectations come from outside the runner: numpy's own ``SeedSequence.spawn`` for the seeds,
the closed form of the tilting block (slide at tan(alpha) = mu, overturn at b / h) for results.
"""

import io
import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from validation.sweep import (
    SCHEDULER_ENV,
    DaskExecutor,
    ResultStore,
    SweepStoreError,
    Task,
    make_tasks,
    run_sweep,
    task_seeds,
)
from validation.sweep.demo import tilting_block
from validation.sweep.executors import local_cluster
from validation.sweep.progress import ConsoleProgress

BLOCK = {"b": 0.2, "h": 0.4, "mu_mean": 0.5, "mu_std": 0.1}


def _params(n, **kw):
    return [{**BLOCK, **kw} for _ in range(n)]


def _expected(seed, b=0.2, h=0.4):
    """Closed form of the tilting block with the task's own friction draw."""
    mu = max(0.0, np.random.default_rng(seed).normal(0.5, 0.1))
    return mu, min(mu, b / h)


def _results(summary):
    return {r["key"]: r["result"] for r in summary.records()}


# -- tasks and seeds ---------------------------------------------------------------------------
def test_task_seeds_are_numpys_spawned_children():
    children = np.random.SeedSequence(42).spawn(5)
    expected = [int(c.generate_state(1, dtype=np.uint64)[0]) for c in children]
    assert task_seeds(42, 5) == expected
    assert [t.seed for t in make_tasks(_params(5), 42)] == expected
    assert len(set(expected)) == 5
    assert task_seeds(43, 5) != expected


def test_make_tasks_reads_a_generator_lazily():
    def endless():
        i = 0
        while True:
            yield {"i": i}
            i += 1

    tasks = make_tasks(endless(), 0)
    first = [next(tasks) for _ in range(3)]
    assert [t.key for t in first] == ["task-00000", "task-00001", "task-00002"]


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"key": ""}, "key"),
        ({"key": "a\nb"}, "key"),
        ({"key": "k", "seed": -1}, "seed"),
        ({"key": "k", "params": {"x": float("nan")}}, "JSON"),
        ({"key": "k", "params": {"x": object()}}, "JSON"),
    ],
)
def test_bad_tasks_are_rejected(kw, match):
    with pytest.raises(ValueError, match=match):
        Task(**kw)


# -- serial runs, failures, store ----------------------------------------------------------------
def test_serial_sweep_matches_the_closed_form(tmp_path):
    tasks = list(make_tasks(_params(6), 7))
    summary = run_sweep(tilting_block, tasks, tmp_path / "s", workers=0, progress=False)
    assert (summary.n_run, summary.n_skipped, summary.n_failed) == (6, 0, 0)
    for task, rec in zip(tasks, summary.records(), strict=True):
        mu, lam = _expected(task.seed)
        assert rec["key"] == task.key and rec["status"] == "ok"
        np.testing.assert_allclose([rec["result"]["mu"], rec["result"]["lam"]], [mu, lam])


def test_a_failed_task_is_recorded_and_the_sweep_goes_on(tmp_path):
    params = _params(5)
    params[2] = {**BLOCK, "h": -1.0}
    summary = run_sweep(
        tilting_block, list(make_tasks(params, 1)), tmp_path / "s", workers=0, progress=False
    )
    assert (summary.n_run, summary.n_failed) == (5, 1)
    recs = summary.records()
    assert [r["status"] for r in recs] == ["ok", "ok", "error", "ok", "ok"]
    assert "ValueError" in recs[2]["error"] and "height" in recs[2]["error"]
    assert recs[2]["result"] is None and "Traceback" in recs[2]["traceback"]
    # a failure is a result: a rerun skips it, unless asked to retry
    again = run_sweep(
        tilting_block, list(make_tasks(params, 1)), tmp_path / "s", workers=0, progress=False
    )
    assert (again.n_run, again.n_skipped) == (0, 5)
    retry = run_sweep(
        tilting_block,
        list(make_tasks(params, 1)),
        tmp_path / "s",
        workers=0,
        progress=False,
        retry_failed=True,
    )
    assert (retry.n_run, retry.n_failed) == (1, 1)


def _bad_result(params, seed):
    return {"value": object()} if params["kind"] == "object" else ["not", "a", "mapping"]


@pytest.mark.parametrize("kind, match", [("object", "TypeError"), ("list", "mapping")])
def test_results_that_cannot_be_stored_are_failures(tmp_path, kind, match):
    summary = run_sweep(
        _bad_result, [Task("t", {"kind": kind})], tmp_path / "s", workers=0, progress=False
    )
    (rec,) = summary.records()
    assert rec["status"] == "error" and match in rec["error"]


def test_store_refuses_another_sweep_and_changed_parameters(tmp_path):
    tasks = list(make_tasks(_params(2), 1))
    run_sweep(tilting_block, tasks, tmp_path / "s", workers=0, progress=False, manifest={"v": 1})
    with pytest.raises(SweepStoreError, match="manifest differs"):
        run_sweep(tilting_block, tasks, tmp_path / "s", workers=0, manifest={"v": 2})
    changed = list(make_tasks(_params(2, h=0.5), 1))
    with pytest.raises(SweepStoreError, match="other parameters"):
        run_sweep(tilting_block, changed, tmp_path / "s", workers=0, manifest={"v": 1})
    fresh = run_sweep(
        tilting_block, tasks, tmp_path / "s", workers=0, progress=False, manifest={"v": 2},
        overwrite=True,
    )  # fmt: skip
    assert (fresh.n_run, fresh.n_skipped) == (2, 0)
    # the first sweep's two records are set aside with its manifest, not deleted
    kept = tmp_path / "s" / "superseded" / "1"
    assert len((kept / "results.jsonl").read_text().splitlines()) == 2
    assert json.loads((kept / "manifest.json").read_text())["v"] == 1


def test_duplicate_keys_are_rejected(tmp_path):
    with pytest.raises(ValueError, match="twice"):
        run_sweep(tilting_block, [Task("a", BLOCK), Task("a", BLOCK)], tmp_path, workers=0)


def test_a_store_has_one_writer(tmp_path):
    first = ResultStore(tmp_path, {"f": 1})
    first.open()
    try:
        with pytest.raises(SweepStoreError, match="another process"):
            ResultStore(tmp_path, {"f": 1}).open()
    finally:
        first.close()


RUNNING_SWEEP = textwrap.dedent(
    """
    import sys
    from validation.sweep import ResultStore
    store = ResultStore(sys.argv[1], {"study": "running"})
    store.open()
    store.append({"key": "a", "status": "ok", "params": {}, "result": {}})
    print("open", flush=True)
    sys.stdin.readline()
    store.close()
    """
)


def test_a_second_sweep_cannot_touch_a_running_sweeps_records(tmp_path):
    """A second process with another manifest and overwrite=True is refused before it reads
    the manifest: the running sweep's manifest and record stay where they are."""
    proc = subprocess.Popen(
        [sys.executable, "-c", RUNNING_SWEEP, str(tmp_path)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout.readline().strip() == "open"
        with pytest.raises(SweepStoreError, match="another process"):
            ResultStore(tmp_path, {"study": "other"}, overwrite=True).open()
        assert json.loads((tmp_path / "manifest.json").read_text()) == {"study": "running"}
        assert len((tmp_path / "results.jsonl").read_text().splitlines()) == 1
        assert not (tmp_path / "superseded").exists()
    finally:
        proc.communicate("\n", timeout=30)
    assert proc.returncode == 0
    # once the first sweep has closed, the second one sets its records aside
    second = ResultStore(tmp_path, {"study": "other"}, overwrite=True)
    second.open()
    second.close()
    assert (tmp_path / "superseded" / "1" / "results.jsonl").exists()


KILLED_SWEEP = textwrap.dedent(
    """
    import sys
    from validation.sweep import make_tasks, run_sweep
    from validation.sweep.demo import tilting_block
    params = [dict(b=0.2, h=0.4, mu_mean=0.5, mu_std=0.1, hold_s=0.15) for _ in range(12)]
    run_sweep(tilting_block, list(make_tasks(params, 5)), sys.argv[1], workers=0, progress=False)
    """
)


def test_a_killed_sweep_resumes_and_skips_finished_tasks(tmp_path):
    store = tmp_path / "killed"
    results = store / "results.jsonl"
    proc = subprocess.Popen([sys.executable, "-c", KILLED_SWEEP, str(store)])
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None:
            if results.exists() and results.read_text().count("\n") >= 3:
                break
            time.sleep(0.02)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=10)
    done = results.read_text().count("\n")
    assert 3 <= done < 12, "the sweep must be killed part-way"
    with results.open("a") as fh:  # a record torn by the kill: it must run again
        fh.write('{"key": "task-000')
    params = [{**BLOCK, "hold_s": 0.15} for _ in range(12)]
    tasks = list(make_tasks(params, 5))
    resumed = run_sweep(tilting_block, tasks, store, workers=0, progress=False)
    assert (resumed.n_skipped, resumed.n_run) == (done, 12 - done)
    recs = resumed.records()
    assert [r["key"] for r in recs] == [t.key for t in tasks]
    assert len(results.read_text().splitlines()) == 12  # no duplicates, no torn line
    for task, rec in zip(tasks, recs, strict=True):
        np.testing.assert_allclose(rec["result"]["lam"], _expected(task.seed)[1])


def test_console_progress_counts_and_failures():
    out = io.StringIO()
    bar = ConsoleProgress(4, label="demo", stream=out)
    for status in ("ok", "error", "ok", "ok"):
        bar.update({"status": status})
    bar.close()
    last = out.getvalue().strip().splitlines()[-1]
    assert "demo [" in last and "4/4" in last and "failed 1" in last and "ok 3" in last


# -- on a local dask cluster (worker processes) -------------------------------------------------
@pytest.fixture(scope="module")
def cluster():
    from distributed import Client

    with local_cluster(2) as lc, Client(lc) as client:
        yield client


def _profiler_and_tick():
    import dask

    return (
        dask.config.get("distributed.worker.profile.enabled"),
        dask.config.get("distributed.admin.tick.interval"),
    )


def test_local_cluster_workers_start_without_the_profiler_wake_ups(cluster):
    # the settings must reach the worker processes, not only this one (the speed-up they buy
    # is measured by benchmarks/bench_sweep.py)
    assert set(cluster.run(_profiler_and_tick).values()) == {(False, "1s")}


def test_dask_results_equal_serial_for_the_same_seeds(tmp_path, cluster):
    tasks = list(make_tasks(_params(10), 11))
    serial = run_sweep(tilting_block, tasks, tmp_path / "serial", workers=0, progress=False)
    remote = run_sweep(
        tilting_block, tasks, tmp_path / "dask", executor=DaskExecutor(cluster), progress=False
    )
    assert _results(remote) == _results(serial)
    workers = {r["worker"] for r in remote.records()}
    assert f":{os.getpid()}" not in " ".join(workers)


def test_the_scheduler_variable_selects_an_existing_cluster(tmp_path, cluster, monkeypatch):
    monkeypatch.setenv(SCHEDULER_ENV, cluster.scheduler.address)
    summary = run_sweep(tilting_block, list(make_tasks(_params(4), 2)), tmp_path, progress=False)
    pids = {int(p) for p in cluster.run(os.getpid).values()}
    assert {int(r["worker"].rsplit(":", 1)[1]) for r in summary.records()} <= pids


def test_dask_reads_the_task_generator_lazily(tmp_path, cluster):
    results = tmp_path / "s" / "results.jsonl"
    lag = []

    def tasks():
        for task in make_tasks(_params(12, hold_s=0.05), 3):
            written = results.read_text().count("\n") if results.exists() else 0
            lag.append(task.index - written)
            yield task

    summary = run_sweep(
        tilting_block, tasks(), tmp_path / "s", executor=DaskExecutor(cluster, in_flight=3),
        progress=False,
    )  # fmt: skip
    assert summary.n_run == 12
    assert max(lag) <= 3, "never more than in_flight tasks ahead of the store"


# -- validation cases as dask tasks --------------------------------------------------------------
def _nested_study(directory):
    """A task that runs a sweep itself: on a worker, its tasks go to the same cluster."""
    summary = run_sweep(tilting_block, list(make_tasks(_params(4), 9)), directory, progress=False)
    return [r["result"] for r in summary.records()], summary.n_workers


def test_a_sweep_inside_a_dask_task_uses_the_same_cluster(tmp_path, cluster):
    nested, n_workers = cluster.submit(_nested_study, str(tmp_path / "nested")).result()
    serial = run_sweep(
        tilting_block, list(make_tasks(_params(4), 9)), tmp_path / "s", workers=0, progress=False
    )
    assert nested == [r["result"] for r in serial.records()]
    assert n_workers == 2


def test_cases_on_a_cluster_write_the_serial_results(tmp_path, cluster):
    from validation.cluster import run_cases_on_cluster

    names = ["geometry", "limit-closed-forms"]
    address = cluster.scheduler.address
    done = list(run_cases_on_cluster(names, True, scheduler=address, out_dir=tmp_path / "d"))
    assert sorted(n for n, _, exc in done if exc is None) == sorted(names)
    list(run_cases_on_cluster(names, True, workers=0, out_dir=tmp_path / "s"))
    for name in names:
        rows = [json.loads((tmp_path / d / f"{name}.json").read_text())["rows"] for d in "ds"]
        assert [(r["quantity"], r["ours"]) for r in rows[0]] == [
            (r["quantity"], r["ours"]) for r in rows[1]
        ]


def test_a_case_that_needs_the_main_thread_runs_there_beside_the_cluster(
    tmp_path, cluster, monkeypatch
):
    """crosscheck-examples' 3D export needs a main thread, which a worker's task has not."""
    import threading

    import validation.catalogue as catalogue
    import validation.cluster as runner

    threads = []

    def probe(quick):
        threads.append(threading.current_thread() is threading.main_thread())
        return []

    monkeypatch.setitem(catalogue.CASES, "main-thread-probe", probe)
    monkeypatch.setattr(runner, "MAIN_THREAD_CASES", frozenset({"main-thread-probe"}))
    assert "crosscheck-examples" in catalogue.MAIN_THREAD_CASES
    names = ["geometry", "main-thread-probe"]
    address = cluster.scheduler.address
    done = list(runner.run_cases_on_cluster(names, True, scheduler=address, out_dir=tmp_path))
    assert sorted(n for n, _, exc in done if exc is None) == sorted(names)
    assert threads == [True]


def _numba_threads(params, seed):
    import numba

    return {"threads": numba.get_num_threads()}


def test_tasks_on_a_cluster_run_numba_on_one_thread(tmp_path, cluster):
    # the worker processes see 2 cores; one task per core must not start 2 numba threads each
    summary = run_sweep(_numba_threads, [Task("a"), Task("b")], tmp_path,
                        executor=DaskExecutor(cluster), progress=False)  # fmt: skip
    assert [r["result"]["threads"] for r in summary.records()] == [1, 1]
