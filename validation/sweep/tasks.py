"""Tasks of a sweep: one parameter set, a stable key and its own random seed.

Seeds come from :class:`numpy.random.SeedSequence`: the root seed of the study spawns one child
per task, so task ``i`` gets the same independent stream whether the sweep runs serially, on a
cluster, in another order, or is resumed after a kill.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Task:
    """One run of a sweep.

    Attributes
    ----------
    key : str
        Unique within the sweep; the store uses it to skip finished tasks on resume.
    params : dict
        JSON-able parameters handed to the task function.
    seed : int
        Seed for ``numpy.random.default_rng`` inside the task (0 <= seed < 2**64).
    index : int
        Position of the task in the sweep (for ordered tables).
    """

    key: str
    params: dict[str, Any] = field(default_factory=dict)
    seed: int = 0
    index: int = 0

    def __post_init__(self):
        if not isinstance(self.key, str) or not self.key or "\n" in self.key:
            raise ValueError(f"task key must be a non-empty one-line string, got {self.key!r}")
        if not isinstance(self.seed, int) or not 0 <= self.seed < 2**64:
            raise ValueError(
                f"task {self.key}: seed must be an int in [0, 2**64), not {self.seed!r}"
            )
        try:
            json.dumps(self.params, allow_nan=False)
        except (TypeError, ValueError) as exc:
            raise ValueError(
                f"task {self.key}: params must be JSON-able with finite floats ({exc})"
            ) from exc


def task_seeds(root_seed: int, n: int) -> list[int]:
    """``n`` independent 64-bit seeds spawned from ``root_seed``.

    Parameters
    ----------
    root_seed : int
        Seed of the whole study (>= 0).
    n : int
        Number of tasks.

    Returns
    -------
    list of int
        Seed ``i`` depends only on ``root_seed`` and ``i`` (``SeedSequence(root).spawn``).
    """
    if not isinstance(root_seed, int | np.integer) or root_seed < 0:
        raise ValueError(f"root_seed must be a non-negative integer, got {root_seed!r}")
    children = np.random.SeedSequence(int(root_seed)).spawn(int(n))
    return [int(c.generate_state(1, dtype=np.uint64)[0]) for c in children]


def make_tasks(
    params: Iterable[Mapping[str, Any]], root_seed: int, prefix: str = "task"
) -> Iterator[Task]:
    """Tasks ``prefix-00000, prefix-00001, ...`` from parameter sets, seeded from ``root_seed``.

    The parameter sets are read lazily (a generator of a million sets is fine); task ``i``
    gets child ``i`` of ``SeedSequence(root_seed)``.
    """
    root = np.random.SeedSequence(int(root_seed))
    for i, p in enumerate(params):
        # spawn_key (i,) is exactly what SeedSequence.spawn gives the i-th child
        child = np.random.SeedSequence(root.entropy, spawn_key=(*root.spawn_key, i))
        seed = int(child.generate_state(1, dtype=np.uint64)[0])
        yield Task(key=f"{prefix}-{i:05d}", params=dict(p), seed=seed, index=i)


def jsonable(value: Any) -> Any:
    """Plain JSON types; NaN and inf become the strings ``"nan"``, ``"inf"``, ``"-inf"``."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
        return jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return value
