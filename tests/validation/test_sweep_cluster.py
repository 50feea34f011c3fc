"""A real cluster: ``dask scheduler`` and two ``dask worker`` processes on 127.0.0.1.

The scheduler and the workers are separate processes started with dask's own command line (not
a LocalCluster inside the test process); a small sweep goes through the scheduler's address and
must give the serial run's results. Everything is torn down, whatever happens, within ~30 s.
"""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from validation.sweep import make_tasks, run_sweep
from validation.sweep.demo import tilting_block

START_TIMEOUT_S = 25.0


def _dask(*args, log):
    return subprocess.Popen(
        [sys.executable, "-m", "dask", *args],
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,  # its own process group, killed as a whole on teardown
    )


def _stop(procs):
    for p in procs:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGTERM)
    deadline = time.monotonic() + 5
    for p in procs:
        try:
            p.wait(timeout=max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=5)


@pytest.fixture
def dask_cluster(tmp_path):
    """Address of a scheduler with two single-threaded worker processes."""
    from distributed import Client

    sched_file = tmp_path / "scheduler.json"
    log = (tmp_path / "cluster.log").open("w")
    procs = [
        _dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
              "--scheduler-file", str(sched_file), "--idle-timeout", "120", log=log)
    ]  # fmt: skip
    try:
        deadline = time.monotonic() + START_TIMEOUT_S
        while not sched_file.exists() and time.monotonic() < deadline:
            assert procs[0].poll() is None, (tmp_path / "cluster.log").read_text()
            time.sleep(0.1)
        address = json.loads(sched_file.read_text())["address"]
        for i in range(2):
            procs.append(_dask(
                "worker", address, "--nthreads", "1", "--nworkers", "1", "--name", f"w{i}",
                "--no-dashboard", "--death-timeout", "60", "--local-directory", str(tmp_path),
                log=log,
            ))  # fmt: skip
        with Client(address, timeout="20s") as client:
            client.wait_for_workers(2, timeout=max(1.0, deadline - time.monotonic()))
        yield address
    finally:
        _stop(procs[::-1])
        log.close()


def test_sweep_through_a_scheduler_address_equals_the_serial_run(tmp_path, dask_cluster):
    assert dask_cluster.startswith("tcp://127.0.0.1:")
    # each task holds 50 ms so that both workers take some
    params = [{"b": 0.2, "h": 0.4, "mu_mean": 0.5, "mu_std": 0.1, "hold_s": 0.05}] * 16
    tasks = list(make_tasks(params, 2026))
    serial = run_sweep(tilting_block, tasks, tmp_path / "serial", workers=0, progress=False)
    remote = run_sweep(
        tilting_block, tasks, tmp_path / "remote", scheduler=dask_cluster, progress=False
    )
    assert remote.n_run == 16 and remote.n_failed == 0 and remote.n_workers == 2
    assert [r["result"] for r in remote.records()] == [r["result"] for r in serial.records()]
    workers = {r["worker"] for r in remote.records()}
    assert len(workers) == 2, "both worker processes took tasks"
