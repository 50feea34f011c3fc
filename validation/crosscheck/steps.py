"""One protocol for every method of the cross-check: ``run(scene, ctx) -> StepResult``.

A step says what it ran (``status = "ok"``), what it did not need to run and why
(``"skipped"``), or what went wrong (``"failed"``, with the error's message); it records its
wall time and the settings that reproduce it. Later steps read earlier results from the
context (the FEM check reads the DEM collapse state; the verdict reads everything).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from dem.estimate import Estimate
from dem.scene import Scene

logger = logging.getLogger(__name__)

STATUSES = ("ok", "skipped", "failed")


@dataclass
class StepResult:
    """Outcome of one step.

    Attributes
    ----------
    name : str
        Step id, e.g. ``"limit-vertex"``, ``"dem-fibre"``.
    method : str
        What it is in words, e.g. ``"limit analysis (vertex model)"``.
    status : {"ok", "skipped", "failed"}
    reason : str
        Why it was skipped or failed, or a remark on an ok result.
    wall_s : float
        [s].
    settings : dict
        Everything needed to reproduce the step.
    values : dict
        JSON-able results (multipliers, terminations, stresses). ``values["estimates"]``
        maps a headline value's key to its :class:`~dem.estimate.Estimate` as a dict (value,
        error, sources), where the method estimated its error (:func:`estimate_of`).
    payload : object
        The method's own result object (not written to JSON).
    """

    name: str
    method: str
    status: str
    reason: str = ""
    wall_s: float = 0.0
    settings: dict = field(default_factory=dict)
    values: dict = field(default_factory=dict)
    payload: Any = None

    def __post_init__(self):
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {self.status!r}")

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "method": self.method,
            "status": self.status,
            "reason": self.reason,
            "wall_s": self.wall_s,
            "settings": self.settings,
            "values": self.values,
        }


@dataclass
class Context:
    """What the steps share: the cross-check settings and the results so far."""

    settings: Any
    results: dict[str, StepResult] = field(default_factory=dict)

    def ok(self, name: str) -> StepResult | None:
        """The result of step ``name`` if it ran successfully, else None."""
        res = self.results.get(name)
        return res if res is not None and res.ok else None


class Step(Protocol):
    """A method of the cross-check."""

    name: str
    method: str

    def run(self, scene: Scene, ctx: Context) -> StepResult: ...


def has_live_load(scene: Scene) -> bool:
    """Whether the live pattern acts on a free dof (else there is no collapse to look for)."""
    return bool(np.any(scene.loads.live_wrench[scene.supports.free_dofs] != 0))


def skip_without_collapse(step: Step, scene: Scene, ctx: Context) -> StepResult | None:
    """A skipped result when a collapse analysis has nothing to do, else None."""
    if not has_live_load(scene):
        return StepResult(step.name, step.method, "skipped", "no live load: no collapse analysis")
    dead = ctx.ok("dead-load")
    if dead is not None and dead.values.get("stands") is False:
        return StepResult(
            step.name, step.method, "skipped", "the scene falls under its dead load alone"
        )
    return None


def run_step(step: Step, scene: Scene, ctx: Context) -> StepResult:
    """Run a step, timing it and turning an exception into a ``failed`` result."""
    start = time.perf_counter()
    try:
        res = step.run(scene, ctx)
    except Exception as exc:  # a failing method must not hide the others
        logger.info("step %s failed", step.name, exc_info=True)
        res = StepResult(step.name, step.method, "failed", f"{type(exc).__name__}: {exc}")
    if not res.wall_s:
        res.wall_s = time.perf_counter() - start
    ctx.results[step.name] = res
    return res


def finite_or_none(value) -> float | None:
    """A float for JSON, None for a missing value; inf is kept (an unbounded multiplier)."""
    if value is None:
        return None
    value = float(value)
    return None if math.isnan(value) else value


def put_estimates(values: dict, **estimates: Estimate | None) -> dict:
    """``values`` with ``values["estimates"][key]`` set for every estimate given (None skipped)."""
    out = dict(values.get("estimates", {}))
    out.update({k: e.to_dict() for k, e in estimates.items() if e is not None})
    return {**values, "estimates": out}


def estimate_of(res: StepResult | None, key: str) -> Estimate | None:
    """Value ``key`` of a step with its error bar: the method's estimate when it gave one,
    else the bare value with an unknown bar (``inf``); None when the step or value is missing
    or not finite."""
    if res is None:
        return None
    given = res.values.get("estimates", {}).get(key)
    if given is not None:
        return Estimate.from_dict(given)
    value = res.values.get(key)
    if value is None or not math.isfinite(float(value)):
        return None
    return Estimate.unknown(float(value), f"{res.name} gives no error bar for {key}")
