"""DEM steps: the static solver to collapse with one interface law, and the explicit
lateral (tilting) driver where the library has it."""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace

import dem.explicit
from dem.scene import Scene
from dem.static import StaticSettings, solve_collapse
from validation.crosscheck.steps import Context, StepResult, skip_without_collapse

COLLAPSE_ENDS = ("plateau", "softening", "snap_back")
"""Terminations of :func:`dem.static.solve_collapse` that are a collapse."""


def _returning(settings: StaticSettings) -> StaticSettings:
    """The settings with ``on_failure`` that returns the path instead of raising."""
    for value in ("return", "stop"):  # the name changed with issue 11
        try:
            return replace(settings, on_failure=value)
        except ValueError:
            continue
    return settings


def collapsed(result) -> bool:
    """Whether a static DEM result ended in a collapse (not max_steps, not non-convergence)."""
    flag = getattr(result, "collapsed", None)
    return bool(flag) if flag is not None else result.termination in COLLAPSE_ENDS


@dataclass(frozen=True)
class StaticCollapse:
    """:func:`dem.static.solve_collapse` with one interface law, returning the path even when
    it does not converge, so that a result that did not collapse is reported as such."""

    settings: StaticSettings

    @property
    def name(self) -> str:
        return f"dem-{self.settings.interface_model}"

    @property
    def method(self) -> str:
        return f"static DEM to collapse ({self.settings.interface_model} law)"

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        skipped = skip_without_collapse(self, scene, ctx)
        if skipped is not None:
            return skipped
        settings = _returning(self.settings)
        res = solve_collapse(scene, settings)
        values = {
            "lambda_max": res.lambda_max,
            "termination": res.termination,
            "collapsed": collapsed(res),
            "n_steps": res.n_steps,
            "n_iterations": res.n_iterations,
            "failure": res.failure,
        }
        reason = "" if values["collapsed"] else f"ended by {res.termination}: not a collapse"
        return StepResult(
            self.name, self.method, "ok", reason, res.wall_s, asdict(settings), values, res
        )


@dataclass(frozen=True)
class ExplicitLateral:
    """The explicit lateral (tilting) driver, ``dem.explicit.simulate_lateral``: the bracket
    ``lambda_stable <= lambda_c <= lambda_moving``. Skipped where the library lacks it."""

    name: str = "explicit"
    method: str = "explicit DEM, lateral load ramp"

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        skipped = skip_without_collapse(self, scene, ctx)
        if skipped is not None:
            return skipped
        simulate = getattr(dem.explicit, "simulate_lateral", None)
        if simulate is None:
            return StepResult(
                self.name,
                self.method,
                "skipped",
                "dem.explicit.simulate_lateral is not in this build",
            )
        res = simulate(scene)
        values = {
            "collapsed": bool(res.collapsed),
            "lambda_stable": res.lambda_stable,
            "lambda_moving": res.lambda_moving,
            "moving_blocks": list(map(int, res.moving_blocks)),
        }
        return StepResult(self.name, self.method, "ok", "", res.wall_s, {}, values, res)
