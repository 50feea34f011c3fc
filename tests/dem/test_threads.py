"""Thread settings of the DEM solvers: OpenMP workers sleep between parallel regions, and the
static DEM runs its BLAS on one thread (:func:`dem.static.solve_collapse`)."""

import os
import subprocess
import sys

import pytest
from threadpoolctl import threadpool_info

import dem.static.solve as static_solve
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import StaticSettings, solve_collapse


def _blas_threads() -> int:
    return max(pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas")


def _policy_after_import(env: dict) -> str:
    """``OMP_WAIT_POLICY`` in a fresh interpreter after ``import dem``, from ``env``."""
    code = "import os, dem; print(os.environ['OMP_WAIT_POLICY'])"
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return out.stdout.strip()


def test_import_dem_makes_openmp_workers_sleep_unless_the_user_chose():
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    assert _policy_after_import(env) == "passive"
    assert _policy_after_import(env | {"OMP_WAIT_POLICY": "active"}) == "active"


def test_the_static_dem_runs_its_blas_on_one_thread_and_gives_the_rest_back(monkeypatch):
    before = _blas_threads()
    if before < 2:
        pytest.skip("the BLAS has one thread here already")
    seen = []
    inner = static_solve._solve

    def spy(*args, **kwargs):
        seen.append(_blas_threads())
        return inner(*args, **kwargs)

    monkeypatch.setattr(static_solve, "_solve", spy)
    wall = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="weight")
    solve_collapse(wall, StaticSettings(max_steps=2, on_failure="return"))
    assert seen == [1]
    assert _blas_threads() == before
