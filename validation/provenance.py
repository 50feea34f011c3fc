"""Where a result comes from: the commit, whether the tree was clean, the date, the versions.

Every results file (``CASE.json``) and every record of a sweep carries :func:`stamp`, so that
the results manifest (:mod:`validation.manifest`) can say which results are not from one
commit.
"""

from __future__ import annotations

import datetime
import json
import platform
import subprocess
import time
from collections.abc import Callable
from importlib import metadata
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
GENERATED = ("validation/results", "validation/results-quick", "paper_figures/out")
"""Paths whose changes do not make the tree dirty (the runs' own outputs)."""
PACKAGES = ("numpy", "scipy", "numba", "scikit-fem", "gmsh", "meshio", "cvxpy", "clarabel")


def git_dirty(repo: Path = REPO) -> tuple[bool | None, list[str]]:
    """Whether the working tree differs from the commit (outside :data:`GENERATED`), and the
    first changed paths; ``(None, [])`` when git cannot tell."""
    try:
        out = subprocess.run(
            ["git", "status", "--porcelain", "--", ".", *[f":!{g}" for g in GENERATED]],
            cwd=repo,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        return None, []
    paths = [line[3:] for line in out.splitlines() if line.strip()]
    return bool(paths), paths[:20]


def git_commit(repo: Path = REPO) -> str:
    """The checked-out commit, or ``"unknown"`` outside a git checkout."""
    try:
        return subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=repo, capture_output=True, text=True, check=True
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def versions() -> dict[str, str]:
    """Python and the numerical packages' versions."""
    out = {"python": platform.python_version()}
    for name in PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def now() -> str:
    """The UTC date and time to the second, ISO 8601."""
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")


def stamp() -> dict[str, Any]:
    """``git_commit``, ``git_clean`` (None when git cannot tell), ``git_dirty_files`` and
    ``date`` of a result written now."""
    dirty, files = git_dirty()
    return {
        "git_commit": git_commit(),
        "git_clean": None if dirty is None else not dirty,
        "git_dirty_files": files,
        "date": now(),
    }


def write_stamped(path: Path, make: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    """Run ``make``, stamp its record (:func:`stamp`, plus its ``wall_s`` [s]) and write it
    as JSON to ``path`` (folders made); return the record."""
    t0 = time.perf_counter()
    data = make()
    data = {**stamp(), "wall_s": time.perf_counter() - t0, **data}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=1))
    return data
