"""``crosscheck(scene)``: every method on one scene, a consistency verdict and a report."""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from dem.scene import Scene
from dem.static import StaticSettings
from limit import LimitSettings
from validation.crosscheck.dem_steps import ExplicitLateral, StaticCollapse
from validation.crosscheck.fem_step import FemCheck
from validation.crosscheck.limit_steps import DeadLoadCheck, LimitBounds
from validation.crosscheck.pictures import PictureOptions
from validation.crosscheck.steps import Context, Step, StepResult, run_step
from validation.crosscheck.verdict import FAIL, Check, verdict

logger = logging.getLogger(__name__)

METHODS = ("dead", "limit", "dem", "explicit", "fem")
"""Groups of steps, in the order they run: dead-load check, limit analysis (both interface
models), static DEM (both laws), explicit lateral driver, FEM check of the DEM state."""


@dataclass(frozen=True)
class CrosscheckSettings:
    """What a cross-check runs and with which settings.

    Attributes
    ----------
    methods : tuple of str
        A subset of :data:`METHODS`.
    limit : LimitSettings
        Base settings of the limit analysis (the interface model is set per step).
    static : StaticSettings
        Base settings of the static DEM (the interface law is set per step).
    explicit : ExplicitLateral
        The explicit step with its load steps.
    fem : FemCheck
        The FEM step with its mesh and material.
    max_updates : int or None
        Capacity updates of the fixed-capacity estimate (b); None: the library's default.
    rtol : float
        Relative slack of the verdict's inequalities where an error bar is not estimated
        [-]; agreement is decided by the methods' error bars (:mod:`.verdict`).
    pictures : bool or PictureOptions
        Draw the PNG pictures (the VTU files are always written); a
        :class:`~validation.crosscheck.pictures.PictureOptions` says what they show.
    """

    methods: tuple[str, ...] = METHODS
    limit: LimitSettings = field(default_factory=LimitSettings)
    static: StaticSettings = field(default_factory=StaticSettings)
    explicit: ExplicitLateral = field(default_factory=ExplicitLateral)
    fem: FemCheck = field(default_factory=FemCheck)
    max_updates: int | None = None
    rtol: float = 1e-3
    pictures: bool | PictureOptions = True

    def __post_init__(self):
        unknown = set(self.methods) - set(METHODS)
        if unknown:
            raise ValueError(f"unknown methods {sorted(unknown)}; choose from {METHODS}")
        m = self.max_updates
        if m is not None and (isinstance(m, bool) or int(m) != m or m < 1):
            raise ValueError(f"max_updates must be None or an integer >= 1, got {m!r}")
        if not 0 <= self.rtol < 1:
            raise ValueError(f"rtol must lie in [0, 1), got {self.rtol!r}")

    @classmethod
    def quick(cls, **kw) -> CrosscheckSettings:
        """Smaller settings for a first look: 10 updates of estimate (b), coarse FEM mesh, a
        wider explicit bracket (3 halvings of the step) without its error estimate or rigid
        limit."""
        return cls(
            max_updates=10,
            fem=FemCheck(mesh_fraction=0.4),
            explicit=ExplicitLateral(refinements=3, error="none", continuation=None),
            **kw,
        )

    def steps(self) -> list[Step]:
        """The step objects of the chosen methods, in order."""
        groups: dict[str, list[Step]] = {
            "dead": [DeadLoadCheck(self.limit.with_(interface_model="vertex"))],
            "limit": [
                LimitBounds(self.limit.with_(interface_model=m), self.max_updates)
                for m in ("vertex", "resultant")
            ],
            "dem": [
                StaticCollapse(replace(self.static, interface_model=law))
                for law in ("fibre", "resultant")
            ],
            "explicit": [self.explicit],
            "fem": [self.fem],
        }
        return [s for m in METHODS if m in self.methods for s in groups[m]]


@dataclass
class CrosscheckResult:
    """Everything a cross-check found.

    Attributes
    ----------
    scene : dict
        Summary of the scene (blocks, interfaces, weight, live-load resultant, extent).
    steps : list of StepResult
    checks : list of Check
    files : dict
        Written files by key (``report_md``, ``scene``, ``mechanism``, ...).
    wall_s : float
        [s].
    warnings : list of str
        Warnings the steps raised (each message once), repeated in the report.
    """

    scene: dict
    steps: list[StepResult]
    checks: list[Check]
    files: dict = field(default_factory=dict)
    wall_s: float = 0.0
    warnings: list[str] = field(default_factory=list)

    @property
    def consistent(self) -> bool:
        """No check failed (checks that do not apply do not count)."""
        return all(c.status != FAIL for c in self.checks)

    def step(self, name: str) -> StepResult:
        for s in self.steps:
            if s.name == name:
                return s
        raise KeyError(f"no step {name!r}; steps: {[s.name for s in self.steps]}")


def weight_direction(scene: Scene, rtol: float = 1e-9) -> list[float] | None:
    """The unit direction ``d`` if the live load is every free block's weight along ``d``
    (then lambda is an acceleration in g), else None."""
    free = ~scene.supports.fixed
    live = scene.loads.live_wrench[free]
    weight = scene.assembly.mass[free] * float(np.linalg.norm(scene.loads.gravity))
    total = live[:, :3].sum(0)
    if not np.any(total) or np.any(live[:, 3:]):
        return None
    d = total / np.linalg.norm(total)
    if not np.allclose(live[:, :3], weight[:, None] * d, rtol=rtol, atol=rtol * weight.max()):
        return None
    return d.tolist()


def scene_summary(scene: Scene) -> dict:
    """Size, weight and live load of a scene, for the report's header."""
    a = scene.assembly
    free = ~scene.supports.fixed
    lo = np.min([b.vertices.min(0) for b in a.blocks], axis=0)
    hi = np.max([b.vertices.max(0) for b in a.blocks], axis=0)
    weight = a.mass * float(np.linalg.norm(scene.loads.gravity))
    return {
        "name": scene.name,
        "n_blocks": a.n_blocks,
        "n_free": int(free.sum()),
        "n_fixed": int((~free).sum()),
        "n_restrained_dofs": int(scene.supports.restrained.sum()),
        "n_interfaces": a.interfaces().n_interfaces,
        "edge_contacts": a.interfaces().edge_contacts.tolist(),
        "weight_free_N": float(weight[free].sum()),
        "live_resultant_N": scene.loads.live_wrench[free, :3].sum(0).tolist(),
        "live_weight_direction": weight_direction(scene),
        "extra_dead_N": scene.loads.dead_wrench[:, :3].sum(0).tolist(),
        "extent_m": (hi - lo).tolist(),
        "mu": None if a.mu is None else [float(a.mu.min()), float(a.mu.max())],
        "meta": scene.meta,
    }


Progress = Callable[[str, Step, StepResult | None], None]


def crosscheck(
    scene: Scene,
    settings: CrosscheckSettings | None = None,
    out_dir: str | Path | None = None,
    progress: Progress | None = None,
) -> CrosscheckResult:
    """Run every chosen method on a scene, check them against each other and write a report.

    Parameters
    ----------
    scene : Scene
    settings : CrosscheckSettings, optional
    out_dir : path, optional
        Where ``report.md``, ``report.json``, the VTU files and the pictures go; None writes
        nothing.
    progress : callable, optional
        ``progress(event, step, result)`` with ``event`` ``"start"`` (result None) or
        ``"end"``, for a console.

    Returns
    -------
    CrosscheckResult
    """
    from validation.crosscheck.files import write_report

    settings = settings or CrosscheckSettings()
    start = time.perf_counter()
    ctx = Context(settings)
    with warnings.catch_warnings(record=True) as seen:
        for step in settings.steps():
            if progress:
                progress("start", step, None)
            res = run_step(step, scene, ctx)
            logger.info("%s: %s %s (%.1f s)", step.name, res.status, res.reason, res.wall_s)
            if progress:
                progress("end", step, res)
    for w in seen:  # shown or logged as they would have been, and kept for the report
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    checks = verdict(ctx, settings.rtol)
    result = CrosscheckResult(scene_summary(scene), list(ctx.results.values()), checks)
    result.warnings = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in seen))
    if out_dir is not None:
        result.files = write_report(scene, ctx, result, Path(out_dir), settings.pictures)
    result.wall_s = time.perf_counter() - start
    return result
