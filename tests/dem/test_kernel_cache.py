"""The on-disk numba cache never runs a stale callee from another file."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numba

from dem.kernels import source_keyed_cache_dir

INIT = """
import numba
from pathlib import Path
from dem.kernels import source_keyed_cache_dir
numba.config.CACHE_DIR = str(source_keyed_cache_dir(Path(__file__).parent))
"""
CALLER = """
from numba import njit
from pkg.callee import g

@njit(cache=True)
def f():
    return g()
"""


def _package(tmp_path: Path, keyed: bool) -> Path:
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text(textwrap.dedent(INIT) if keyed else "")
    (pkg / "caller.py").write_text(textwrap.dedent(CALLER))
    return pkg


def _run_f(tmp_path: Path, callee_value: int) -> int:
    (tmp_path / "pkg" / "callee.py").write_text(
        f"from numba import njit\n\n\n@njit(cache=True)\ndef g():\n    return {callee_value}\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path), str(Path(__file__).parents[2])])
    out = subprocess.run([sys.executable, "-c", "from pkg.caller import f; print(f())"],
                         env=env, capture_output=True, text=True, check=True)  # fmt: skip
    return int(out.stdout)


def test_unkeyed_cache_runs_the_old_callee(tmp_path):
    """The hazard itself: numba's default cache keeps the caller compiled against the old g."""
    _package(tmp_path, keyed=False)
    assert _run_f(tmp_path, 1) == 1
    assert _run_f(tmp_path, 2) == 1


def test_source_keyed_cache_runs_the_new_callee(tmp_path):
    _package(tmp_path, keyed=True)
    assert _run_f(tmp_path, 1) == 1
    assert _run_f(tmp_path, 2) == 2
    assert _run_f(tmp_path, 1) == 1  # the first version's cache is still valid and used


def test_dem_kernels_use_a_directory_keyed_by_their_sources(tmp_path):
    package = Path(__file__).parents[2] / "dem" / "kernels"
    if not os.environ.get("NUMBA_CACHE_DIR"):
        assert numba.config.CACHE_DIR == str(source_keyed_cache_dir(package))
    copy = tmp_path / "kernels"
    copy.mkdir()
    for source in package.glob("*.py"):
        (copy / source.name).write_bytes(source.read_bytes())
    assert source_keyed_cache_dir(copy).name == source_keyed_cache_dir(package).name
    (copy / "polygon.py").write_text((copy / "polygon.py").read_text() + "\n# edited\n")
    assert source_keyed_cache_dir(copy).name != source_keyed_cache_dir(package).name


def test_compile_kernels_writes_the_cache_of_every_solver_kernel_module(tmp_path):
    """dem.warmup, run in a process with an empty cache, leaves an on-disk index for the
    kernels of both static laws, the stiffness, and the explicit DEM's contact forces and
    integration, for workers started later to load."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    code = "from dem.warmup import compile_kernels; compile_kernels()"
    subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, check=True)
    cached = {p.name.split(".")[0] for p in tmp_path.rglob("*.nbi")}
    for module in ("interface_law", "fibre_law", "stiffness", "contact_force", "integrate"):
        assert module in cached, (module, sorted(cached))
