"""Checkpoint files of explicit runs: arrays in ``.npz`` plus JSON metadata, no pickles.

A checkpoint is a NumPy ``.npz`` archive read with ``allow_pickle=False``. It holds the arrays
of a run (the :class:`~dem.explicit.state.ExplicitState` and whatever the driver records) and
one entry ``__meta__``, a JSON string with the format tag :data:`FORMAT`, its version, the run's
key (a hash of scene and settings) and the driver's scalars. A file that is empty, truncated,
not an ``.npz`` archive, or an archive without our tag raises :class:`CheckpointError` naming
the file and what is wrong with it; it is never unpickled.
"""

from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path

import numpy as np

FORMAT = "blockmech.explicit.checkpoint"
VERSION = 2
_META = "__meta__"


class CheckpointError(RuntimeError):
    """A checkpoint file cannot be read (empty, truncated, not ours, or another version)."""

    def __init__(self, path: Path, problem: str):
        self.path = Path(path)
        super().__init__(
            f"checkpoint {self.path} {problem}; delete it (or pass another path) to start the "
            "run afresh"
        )


def write_checkpoint(path: str | Path, arrays: dict[str, np.ndarray], meta: dict) -> None:
    """Write arrays and metadata atomically (a temporary file renamed over ``path``).

    Parameters
    ----------
    path : path
        Target ``.npz`` file.
    arrays : dict of str to array
        Numeric or boolean arrays (object arrays are refused).
    meta : dict
        JSON-serialisable scalars and lists; ``format`` and ``version`` are added.
    """
    path = Path(path)
    for name, value in arrays.items():
        if np.asarray(value).dtype == object:
            raise TypeError(f"checkpoint array {name!r} has dtype object (would need a pickle)")
    payload = {name: np.asarray(value) for name, value in arrays.items()}
    payload[_META] = np.array(json.dumps({**meta, "format": FORMAT, "version": VERSION}))
    tmp = path.with_name(path.name + ".tmp.npz")
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(tmp, **payload)
    os.replace(tmp, path)


def read_checkpoint(path: str | Path) -> tuple[dict[str, np.ndarray], dict]:
    """Arrays and metadata of a checkpoint written by :func:`write_checkpoint`.

    Raises
    ------
    CheckpointError
        If the file is empty, truncated or corrupt, not an ``.npz`` archive, has no metadata
        of ours, or was written by another version of this format.
    """
    path = Path(path)
    if path.stat().st_size == 0:
        raise CheckpointError(path, "is empty (0 bytes)")
    try:
        with np.load(path, allow_pickle=False) as data:
            if _META not in data.files:
                raise CheckpointError(
                    path, f"is an .npz archive but not a checkpoint of ours (no {_META} entry)"
                )
            meta = json.loads(str(data[_META]))
            arrays = {name: data[name] for name in data.files if name != _META}
    except CheckpointError:
        raise
    except (zipfile.BadZipFile, EOFError, OSError, KeyError, ValueError) as exc:
        raise CheckpointError(
            path, f"is truncated or not an .npz archive ({type(exc).__name__})"
        ) from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise CheckpointError(path, f"is not a checkpoint of ours (format tag {FORMAT!r} missing)")
    if meta.get("version") != VERSION:
        raise CheckpointError(
            path, f"has format version {meta.get('version')}, this code reads {VERSION}"
        )
    return arrays, meta
