"""Append-only store of a sweep's results: ``manifest.json`` + ``results.jsonl``.

One JSON record per line, written by the client as each task finishes with a single
``os.write`` on an ``O_APPEND`` descriptor followed by ``fsync``. A process killed while writing
leaves at most one torn last line, which is cut off when the store is opened again, so that
task runs again. Later records of a key replace earlier ones (a retried failure).
"""

from __future__ import annotations

import fcntl
import json
import logging
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from validation.sweep.tasks import jsonable

logger = logging.getLogger(__name__)

MANIFEST = "manifest.json"
RESULTS = "results.jsonl"
LOCK = ".lock"


class SweepStoreError(RuntimeError):
    """The store belongs to another sweep, or another process is writing it."""


@dataclass
class ResultStore:
    """Records of one sweep in a directory.

    :meth:`open` takes the store's lock (``flock`` on ``.lock``, a file that is never moved)
    before it reads or replaces the manifest or moves records, so a second sweep started on
    the same directory fails at once and cannot set aside the records of a running one.

    Parameters
    ----------
    directory : path
        Created if missing.
    manifest : dict
        What identifies the sweep (task function, root seed, settings). A store whose manifest
        differs raises :class:`SweepStoreError` unless ``overwrite`` is set, so results of one
        study are never mixed into another.
    overwrite : bool
        Start afresh when the manifest differs (the old records and manifest are moved to
        ``superseded/N/`` in the store, not deleted).
    """

    directory: Path
    manifest: dict
    overwrite: bool = False

    def __post_init__(self):
        self.directory = Path(self.directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self._lock: int | None = None
        self._fd: int | None = None

    def _take_lock(self) -> None:
        fd = os.open(self.directory / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError as exc:
            os.close(fd)
            raise SweepStoreError(
                f"{self.directory} is being written by another process (a running sweep)"
            ) from exc
        self._lock = fd

    def _claim(self) -> None:
        """Write this sweep's manifest, after checking (or setting aside) the one there."""
        manifest = jsonable(self.manifest)
        path = self.directory / MANIFEST
        if path.exists():
            old = json.loads(path.read_text())
            if old != manifest:
                if not self.overwrite:
                    raise SweepStoreError(
                        f"{self.directory} holds another sweep (manifest differs: "
                        f"{_diff(old, manifest)}); pass a new directory or overwrite=True"
                    )
                kept = self._set_aside(old)
                logger.warning(
                    "%s: another sweep's records (manifest differs: %s) set aside in %s",
                    self.directory, _diff(old, manifest), kept,
                )  # fmt: skip
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
        os.replace(tmp, path)

    def _set_aside(self, old: dict) -> Path:
        """Move the records and manifest of a superseded sweep into ``superseded/N/`` of the
        store (never deleted: a study killed before a code change keeps its records)."""
        base = self.directory / "superseded"
        n = 1 + max((int(p.name) for p in base.glob("*") if p.name.isdigit()), default=0)
        kept = base / str(n)
        kept.mkdir(parents=True)
        if (self.directory / RESULTS).exists():
            os.replace(self.directory / RESULTS, kept / RESULTS)
        (kept / MANIFEST).write_text(json.dumps(old, indent=1, sort_keys=True) + "\n")
        return kept

    @property
    def results_path(self) -> Path:
        return self.directory / RESULTS

    def open(self) -> None:
        """Lock the store for this process, then check the manifest and cut a torn last line.

        Raises
        ------
        SweepStoreError
            Another process holds the lock, or the manifest differs (without ``overwrite``).
        """
        self._take_lock()
        try:
            self._claim()
            fd = os.open(self.results_path, os.O_RDWR | os.O_CREAT | os.O_APPEND, 0o644)
            _cut_torn_line(fd, self.results_path)
        except BaseException:
            self.close()
            raise
        self._fd = fd

    def close(self) -> None:
        """Close the records and release the lock."""
        for name in ("_fd", "_lock"):
            fd = getattr(self, name)
            if fd is not None:
                os.close(fd)  # closing the lock's descriptor releases it
                setattr(self, name, None)

    def append(self, record: dict) -> None:
        """Write one record durably (one line, one write, fsync)."""
        if self._fd is None:
            raise SweepStoreError("open() the store before appending")
        line = json.dumps(jsonable(record), allow_nan=False, sort_keys=True) + "\n"
        os.write(self._fd, line.encode())
        os.fsync(self._fd)

    def records(self) -> Iterator[dict]:
        """Every complete record, in the order written (one line at a time)."""
        yield from read_records(self.results_path)

    def finished(self, include_failed: bool = True) -> dict[str, dict[str, Any]]:
        """``key -> params`` of tasks already in the store (the last record of each key)."""
        out: dict[str, dict[str, Any]] = {}
        for rec in self.records():
            if include_failed or rec["status"] == "ok":
                out[rec["key"]] = rec["params"]
            else:
                out.pop(rec["key"], None)
        return out


def read_records(path: str | Path) -> Iterator[dict]:
    """Complete records of a ``results.jsonl`` (a torn last line is skipped)."""
    path = Path(path)
    if not path.exists():
        return
    with path.open() as fh:
        for line in fh:
            if not line.endswith("\n"):
                logger.warning("%s: torn last record skipped", path)
                return
            yield json.loads(line)


def latest_records(path: str | Path) -> list[dict]:
    """The last record of every key, ordered by task index."""
    last: dict[str, dict] = {}
    for rec in read_records(path):
        last[rec["key"]] = rec
    return sorted(last.values(), key=lambda r: (r.get("index", 0), r["key"]))


def _cut_torn_line(fd: int, path: Path) -> None:
    size = os.fstat(fd).st_size
    if size == 0:
        return
    data = os.pread(fd, size, 0)
    end = data.rfind(b"\n") + 1
    if end != size:
        logger.warning("%s: cutting a torn last record (%d bytes)", path, size - end)
        os.ftruncate(fd, end)


def _diff(old: dict, new: dict) -> str:
    keys = sorted(set(old) | set(new))
    changed = [k for k in keys if old.get(k) != new.get(k)]
    return ", ".join(f"{k}: {old.get(k)!r} -> {new.get(k)!r}" for k in changed[:3])
