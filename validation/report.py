"""Rows of a validation table and their JSON + markdown files (the contract of DESIGN.md).

Writes are atomic and together: a case runs inside :func:`staged`, which gives it a private
staging directory (:func:`output_dir`) for its side products (``.npz``, scenes, mechanisms);
:func:`write_results` writes the table there, and only when the case has finished are the
files moved into place with ``os.replace``, the side products first and ``CASE.json`` last
(it lists each side product with its SHA-256, so a reader can check that they belong
together). A case that fails, or a run that is killed, leaves the previous results whole.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import datetime
import hashlib
import json
import math
import os
import platform
import shutil
import subprocess
import uuid
from collections.abc import Iterator
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any

RESULTS_DIR = Path(__file__).parent / "results"
STAGING_PREFIX = ".staging-"
"""Staging directories ``RESULTS_DIR/.staging-CASE-PID`` (git-ignored)."""
_REPO = Path(__file__).parent.parent
_GENERATED = ("validation/results", "paper_figures/out")
"""Paths whose changes do not make the tree dirty (the runs' own outputs)."""

_STAGING: contextvars.ContextVar[Path | None] = contextvars.ContextVar("staging", default=None)
_PACKAGES = ("numpy", "scipy", "numba", "scikit-fem", "gmsh", "meshio", "cvxpy", "clarabel")


def is_published(source: str) -> bool:
    """A reference from a seed's table or reported experiment (its difference is a model
    error), as opposed to a numerical reference (closed form, exact count, another method)."""
    s = source.lower()
    return s.startswith("seed ") and ("table" in s or "experiment" in s)


@dataclass
class Row:
    """One line of a validation table.

    Parameters
    ----------
    quantity
        What is compared, with its unit, e.g. ``"block volume 5x5 theta=2.5 [mm^3]"``.
    ours
        Our value (None when a method does not apply to the row).
    reference
        The independent value (closed form, seed table, other method), or None.
    source
        Where ``reference`` comes from, e.g. ``"seed 001 Table 1"`` or ``"closed form"``.
    wall_s
        Wall time of the computation that produced ``ours`` [s].
    settings
        Anything needed to reproduce the row (solver settings, discretisation, seed).
    extra
        Further columns (other methods' values, flags such as ``within_bounds``).
    """

    quantity: str
    ours: float | None
    reference: float | None = None
    source: str = ""
    wall_s: float | None = None
    settings: dict[str, Any] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def rel_error(self) -> float | None:
        """|ours - reference| / |reference|, or the absolute error when the reference is 0."""
        if self.ours is None or self.reference is None:
            return None
        diff = abs(float(self.ours) - float(self.reference))
        scale = abs(float(self.reference))
        return diff / scale if scale > 0 else diff

    def to_dict(self) -> dict[str, Any]:
        out = dataclasses.asdict(self)
        out["reference"] = {"value": self.reference, "source": self.source}
        del out["source"]
        out["rel_error"] = self.rel_error
        return out


def output_dir() -> Path:
    """Where a running case writes its side products: its staging directory inside
    :func:`staged`, else ``RESULTS_DIR``."""
    return _STAGING.get() or RESULTS_DIR


def _git_dirty() -> tuple[bool | None, list[str]]:
    """Whether the working tree differs from the commit (outside :data:`_GENERATED`), and the
    first changed paths; ``(None, [])`` when git cannot tell."""
    try:
        out = subprocess.run(
            ["git", "status", "--porcelain", "--", ".", *[f":!{g}" for g in _GENERATED]],
            cwd=_REPO,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        return None, []
    paths = [line[3:] for line in out.splitlines() if line.strip()]
    return bool(paths), paths[:20]


def _git_commit() -> str:
    try:
        return subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=Path(__file__).parent,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for name in _PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def _jsonable(value: Any) -> Any:
    """Plain JSON types; NaN and inf become strings so that the file stays valid JSON."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if hasattr(value, "tolist"):
        return _jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return value


def _fmt(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, (int, float)):
        return f"{value:.6g}"
    return str(value)


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def _write_atomic(path: Path, text: str) -> None:
    """Write through a temporary file in the same directory, then ``os.replace``. The file
    gets the mode of any other written file (0666 less the umask), not mkstemp's 0600."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.parent / f".{path.name}.{os.getpid()}.{uuid.uuid4().hex}.tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def staged(case: str, out_dir: Path | None = None) -> Iterator[Path]:
    """Run a case's writes in a staging directory and move them into ``out_dir`` only when
    the block ends without an exception (module notes). Stale staging directories of the
    same case (a killed run) are removed first."""
    out_dir = Path(RESULTS_DIR if out_dir is None else out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    for stale in out_dir.glob(f"{STAGING_PREFIX}{case}-*"):
        shutil.rmtree(stale, ignore_errors=True)
    stage = out_dir / f"{STAGING_PREFIX}{case}-{os.getpid()}"
    stage.mkdir()
    token = _STAGING.set(stage)
    try:
        yield stage
        _commit(stage, out_dir, case)
    finally:
        _STAGING.reset(token)
        shutil.rmtree(stage, ignore_errors=True)


def _commit(stage: Path, out_dir: Path, case: str) -> None:
    """Move every staged file into ``out_dir``: side products, then ``CASE.md``, then
    ``CASE.json``."""
    last = [stage / f"{case}.md", stage / f"{case}.json"]
    files = [p for p in sorted(stage.rglob("*")) if p.is_file() and p not in last]
    for src in [*files, *(p for p in last if p.exists())]:
        dest = out_dir / src.relative_to(stage)
        dest.parent.mkdir(parents=True, exist_ok=True)
        os.replace(src, dest)


def write_results(
    case: str,
    rows: list[Row],
    *,
    quick: bool,
    wall_s: float,
    notes: str = "",
    out_dir: Path | None = None,
) -> tuple[Path, Path]:
    """Write ``CASE.json`` and ``CASE.md`` (each atomically) and return their paths.

    ``out_dir`` defaults to :func:`output_dir` (the staging directory of a running case). The
    JSON lists the side products already written there with their SHA-256, and records the
    commit and whether the working tree was dirty (``git_dirty``, ``git_dirty_files``).
    """
    out_dir = output_dir() if out_dir is None else Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    own = {f"{case}.json", f"{case}.md"}
    side = (
        {
            str(p.relative_to(out_dir)): _sha256(p)
            for p in sorted(out_dir.rglob("*"))
            if p.is_file() and p.name not in own and not p.name.startswith(".")
        }
        if _STAGING.get() == out_dir
        else {}
    )
    dirty, dirty_files = _git_dirty()
    payload = {
        "case": case,
        "quick": quick,
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "git_commit": _git_commit(),
        "git_dirty": dirty,
        "git_dirty_files": dirty_files,
        "versions": _versions(),
        "wall_s": wall_s,
        "notes": notes,
        "side_products": side,
        "rows": [r.to_dict() for r in rows],
    }
    json_path = out_dir / f"{case}.json"

    extra_keys: list[str] = []
    for r in rows:
        extra_keys += [k for k in r.extra if k not in extra_keys]
    header = ["quantity", "ours", "reference", "source", "rel_error", "wall_s", *extra_keys]
    flag = {True: " (dirty tree)", False: "", None: " (tree state unknown)"}[dirty]
    lines = [
        f"# {case}{' (quick)' if quick else ''}",
        "",
        f"commit `{payload['git_commit'][:12]}`{flag}, {payload['date']}, total {wall_s:.2f} s",
        "",
    ]
    if notes:
        lines += [notes, ""]
    lines += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        cells = [r.quantity, r.ours, r.reference, r.source, r.rel_error, r.wall_s]
        cells += [r.extra.get(k) for k in extra_keys]
        lines.append("| " + " | ".join(_fmt(c) for c in cells) + " |")
    md_path = out_dir / f"{case}.md"
    _write_atomic(md_path, "\n".join(lines) + "\n")
    _write_atomic(json_path, json.dumps(_jsonable(payload), indent=1) + "\n")
    return json_path, md_path
