"""The results manifest: which result files a folder holds and the commit they come from.

``MANIFEST.json`` in a results folder names one commit (that of the ``python -m validation
all`` run that wrote the folder, or, rebuilt from the files, the commit most of them share) and
lists every case's ``CASE.json`` with its own commit, clean flag, date and wall time, and the
commits of the sweep records beside it (``CASE-runs.jsonl``). :func:`check_manifest` says
which results are not from the manifest's commit, were written from a dirty tree, are quick
runs in the full folder, or are missing.
"""

from __future__ import annotations

import collections
import json
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from validation.provenance import now
from validation.report import _write_atomic

MANIFEST = "MANIFEST.json"


def _case_entry(path: Path) -> dict[str, Any]:
    data = json.loads(path.read_text())
    runs = [p for p in data.get("side_products", {}) if p.endswith("-runs.jsonl")]
    return {
        "file": path.name,
        "git_commit": data.get("git_commit", "unknown"),
        "git_clean": data.get("git_clean", _clean_of_old(data)),
        "date": data.get("date"),
        "wall_s": data.get("wall_s"),
        "quick": data.get("quick"),
        "sweep_record_commits": _record_commits([path.parent / p for p in runs]),
    }


def _clean_of_old(data: dict) -> bool | None:
    """Files written before ``git_clean`` held ``git_dirty``."""
    dirty = data.get("git_dirty")
    return None if dirty is None else not dirty


def _record_commits(paths: Iterable[Path]) -> dict[str, int]:
    """Commit -> number of sweep records stamped with it (``"unknown"`` for unstamped ones)."""
    count: collections.Counter[str] = collections.Counter()
    for path in paths:
        if not path.exists():
            continue
        for line in path.read_text().splitlines():
            if line.strip():
                count[json.loads(line).get("git_commit", "unknown")] += 1
    return dict(count)


def result_files(directory: Path) -> list[Path]:
    """The ``CASE.json`` files of a results folder (not the manifest, not side products)."""
    out = []
    for path in sorted(Path(directory).glob("*.json")):
        if path.name == MANIFEST:
            continue
        try:
            data = json.loads(path.read_text())
        except json.JSONDecodeError:
            continue
        if isinstance(data, dict) and "rows" in data and data.get("case") == path.stem:
            out.append(path)
    return out


def build_manifest(directory: Path, commit: str | None = None) -> dict[str, Any]:
    """The manifest of ``directory``; ``commit`` defaults to the commit most results share."""
    cases = {p.stem: _case_entry(p) for p in result_files(directory)}
    if commit is None:
        counts = collections.Counter(c["git_commit"] for c in cases.values())
        commit = counts.most_common(1)[0][0] if counts else "unknown"
    return {"git_commit": commit, "date": now(), "cases": cases}


def write_manifest(directory: Path, commit: str | None = None) -> Path:
    """Write ``directory/MANIFEST.json`` (:func:`build_manifest`) and return its path."""
    path = Path(directory) / MANIFEST
    _write_atomic(path, json.dumps(build_manifest(directory, commit), indent=1) + "\n")
    return path


def previous_wall_times(directory: Path) -> dict[str, float]:
    """Case -> wall time [s] of its last run as the manifest of ``directory`` lists it (empty
    without a manifest): the expected cost of each case, to start the longest first."""
    path = Path(directory) / MANIFEST
    if not path.exists():
        return {}
    cases = json.loads(path.read_text()).get("cases", {})
    return {c: float(e["wall_s"]) for c, e in cases.items() if e.get("wall_s") is not None}


def check_manifest(directory: Path, expected: Iterable[str] = (), full: bool = True) -> list[str]:
    """What is not from the manifest's commit: one line per problem, empty when none.

    Parameters
    ----------
    directory : path
        A results folder with ``MANIFEST.json``.
    expected : iterable of str
        Cases that should be there (the registered ones).
    full : bool
        The folder holds full runs: a quick result in it is a problem.
    """
    path = Path(directory) / MANIFEST
    if not path.exists():
        return [f"{path} is missing: run `python -m validation manifest --write`"]
    manifest = json.loads(path.read_text())
    commit = manifest["git_commit"]
    listed = manifest["cases"]
    now_there = {p.stem: _case_entry(p) for p in result_files(directory)}
    problems = [f"{c}: no results file" for c in expected if c not in now_there]
    for case, entry in now_there.items():
        problems += _entry_problems(case, entry, listed.get(case), commit, full)
    return problems


def _entry_problems(case: str, entry: dict, listed: dict | None, commit: str, full: bool):
    out = []
    if listed is None:
        out.append(f"{case}: not in the manifest")
    elif listed["date"] != entry["date"] or listed["git_commit"] != entry["git_commit"]:
        out.append(f"{case}: rewritten since the manifest was written ({entry['date']})")
    if entry["git_commit"] != commit:
        out.append(f"{case}: from commit {entry['git_commit'][:12]}, not {commit[:12]}")
    if entry["git_clean"] is not True:
        state = "a dirty" if entry["git_clean"] is False else "an unknown"
        out.append(f"{case}: written from {state} tree")
    if full and entry["quick"]:
        out.append(f"{case}: a quick run in the full results")
    others = {c: n for c, n in entry["sweep_record_commits"].items() if c != commit}
    if others:
        text = ", ".join(f"{n} from {c[:12]}" for c, n in others.items())
        out.append(f"{case}: sweep records not from {commit[:12]}: {text}")
    return out
