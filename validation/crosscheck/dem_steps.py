"""DEM steps: the static solver to collapse with one interface law, and the explicit DEM
under a ramped live load."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

from dem.estimate import Estimate
from dem.explicit import RigidContinuation, simulate_lateral
from dem.explicit.lateral import DEVELOP_FACTOR, LiveLoadRamp
from dem.scene import Scene
from dem.static import StaticSettings, solve_collapse
from validation.crosscheck.steps import (
    Context,
    StepResult,
    finite_or_none,
    put_estimates,
    skip_without_collapse,
)


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
        settings = replace(self.settings, on_failure="return")
        res = solve_collapse(scene, settings)
        values = {
            "lambda_max": res.lambda_max,
            "termination": res.termination,
            "collapsed": bool(res.collapsed),
            "n_steps": res.n_steps,
            "n_iterations": res.n_iterations,
            "failure": res.failure,
        }
        # the solver's own bar of lambda_max (end of path, load step, residual)
        values = put_estimates(values, lambda_max=res.lambda_estimate)
        reason = "" if values["collapsed"] else f"ended by {res.termination}: not a collapse"
        return StepResult(
            self.name, self.method, "ok", reason, res.wall_s, asdict(settings), values, res
        )


@dataclass(frozen=True)
class ExplicitLateral:
    """The explicit DEM under the scene's live load raised in ramp-and-hold steps
    (:func:`dem.explicit.simulate_lateral` with a :class:`~dem.explicit.lateral.LiveLoadRamp`):
    the bracket ``lambda_stable < lambda_c <= lambda_moving``.

    The steps are scaled to the associated upper bound of the vertex model when it ran:
    first step ``step_fraction`` of it, up to ``max_fraction`` of it (the library's defaults
    otherwise).

    Attributes
    ----------
    step_fraction, max_fraction : float
        [-].
    refinements : int
        Halvings of the step after the first moving one.
    error : {"none", "cheap", "full"}
        What the multiplier's error bar measures (:func:`dem.explicit.simulate_lateral`):
        the bracket alone, plus the loading rate, plus the time step and node spacing.
    continuation : RigidContinuation or None
        Also extrapolate the multiplier to rigid joints (``lambda_rigid``), the model of the
        limit analysis and the static DEM; None: the material stiffness only.
    """

    step_fraction: float = 0.125
    max_fraction: float = 1.25
    refinements: int = 4
    error: str = "cheap"
    continuation: RigidContinuation | None = field(default_factory=RigidContinuation)
    name: str = "explicit"
    method: str = "explicit DEM, live load ramped and held"

    def driver(self, ctx: Context) -> LiveLoadRamp:
        lim = ctx.ok("limit-vertex")
        upper = None if lim is None else lim.values["upper"]
        if upper is None or not (math.isfinite(upper) and upper > 0):
            return LiveLoadRamp(refinements=self.refinements)
        return LiveLoadRamp(
            step=self.step_fraction * upper,
            max_lambda=self.max_fraction * upper,
            refinements=self.refinements,
        )

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        skipped = skip_without_collapse(self, scene, ctx)
        if skipped is not None:
            return skipped
        lim = ctx.ok("limit-vertex")
        if lim is not None and not math.isfinite(lim.values["upper"]):
            return StepResult(
                self.name,
                self.method,
                "skipped",
                "the limit analysis finds no mechanism: nothing to ramp towards",
            )
        driver = self.driver(ctx)
        res = simulate_lateral(scene, driver=driver, error=self.error,
                               continuation=self.continuation)  # fmt: skip
        values = {
            "collapsed": bool(res.collapsed),
            "mechanism_confirmed": bool(res.mechanism_confirmed),
            "arrested": bool(res.arrested),
            "lambda_stable": res.lambda_stable,
            "lambda_moving": finite_or_none(res.lambda_moving),
            "moving_blocks": [int(i) for i in res.moving_blocks],
            "detection_lambda": res.detection_lambda,
        }
        values.update(_estimates(res))
        reason = ""
        if res.collapsed and not res.mechanism_confirmed:
            reason = (
                f"the motion at lambda = {res.lambda_moving:.4g} is not confirmed: no block "
                f"moved {DEVELOP_FACTOR:g} displacement thresholds while it was followed, so it "
                "may still stop (lambda_moving was found by speed alone)"
            )
        if res.arrested:
            reason = (
                f"the mechanism formed at lambda = {res.lambda_moving:.4g} and stopped after a "
                "finite motion (blocks bearing on each other after finite rotations): the "
                "bracket is its onset, the collapse of the rigid-block methods in small "
                "displacements"
            )
        resisting = _resisting(res, lim)
        if resisting:
            values["resisting"] = resisting
            reason = f"{reason}; {resisting}" if reason else resisting
        settings = {"driver": res.driver, "solver": res.settings}
        return StepResult(self.name, self.method, "ok", reason, res.wall_s, settings, values, res)


def _estimates(res) -> dict:
    """The multiplier at the material stiffness (``lambda_c``) and its rigid limit
    (``lambda_rigid``) with their bars, the last load level at rest (``lambda_stable``: a
    multiplier the ramp applied, exact), and the continuation's levels, for the report."""
    at_rest = Estimate(res.lambda_stable, {"exact": 0.0}, notes="applied by the ramp, at rest")
    out: dict = {"estimates": {"lambda_stable": at_rest.to_dict()}}
    if res.estimate is not None:
        out["lambda_c"] = res.estimate.value
        if math.isfinite(res.estimate.error):  # error budget "none": no bar to judge by
            out["estimates"]["lambda_c"] = res.estimate.to_dict()
    if res.rigid is not None:
        out["lambda_rigid"] = res.rigid.value
        out["estimates"]["lambda_rigid"] = res.rigid.to_dict()
    if res.levels:
        out["stiffness_levels"] = res.levels
    return out


def _resisting(res, lim: StepResult | None) -> str:
    """Which contacts resisted when the explicit run was at rest above the upper bound of the
    vertex model (a load no rigid-block structure with these interfaces carries): the block
    pairs in contact then, those without a face interface first, with their gaps and forces
    (:func:`dem.explicit.diagnosis.pair_forces`); empty otherwise."""
    upper = None if lim is None else lim.values.get("upper")
    contacts = res.contacts_at_rest
    if upper is None or contacts is None or not res.lambda_stable > upper:
        return ""
    return (
        f"at rest at lambda = {res.lambda_stable:.4g}, above the upper bound {upper:.4g}: the "
        f"contacts that resisted (pairs without a face interface, which the limit analysis "
        f"does not have, first): {contacts.describe()}"
    )
