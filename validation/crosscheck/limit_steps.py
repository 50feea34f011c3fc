"""Limit-analysis steps: the dead-load check and the bounds of one interface model."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dem.estimate import Estimate
from dem.scene import Scene
from limit import LimitSettings, NoMechanismError, bounds_and_estimates, stands
from limit.lambda_error import solver_estimate
from validation.crosscheck.steps import (
    Context,
    StepResult,
    finite_or_none,
    put_estimates,
    skip_without_collapse,
)

WHY_NONE = {"lower": "lower_note", "reduced_mu": "reduced_note", "iterative": "iterative_note"}
"""The value of a bounds step that says why a bound or an estimate is missing."""


@dataclass(frozen=True)
class DeadLoadCheck:
    """Does the scene stand under its dead load? (:func:`limit.stands`: a certified yes, or no
    with the blocks and interfaces of the dead-load mechanism)."""

    settings: LimitSettings
    name: str = "dead-load"
    method: str = "dead-load check (limit analysis, vertex model)"

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        res = stands(scene, self.settings)
        values = {
            "stands": bool(res.stands),
            "load_factor": res.load_factor,
            "certificate": _cert(res.certificate),
            "blocks": list(res.blocks),
            "interfaces": list(res.interfaces),
        }
        values = put_estimates(values, load_factor=load_factor_estimate(res))
        return StepResult(
            self.name,
            self.method,
            "ok",
            res.reason,
            res.wall_s,
            self.settings.to_dict(),
            values,
            res,
        )


def load_factor_estimate(res) -> Estimate:
    """The carried fraction of the dead load (:class:`limit.deadload.StandsResult`) with the
    solver error of its programme (:func:`limit.lambda_error.solver_estimate`: duality gap and
    feasibility shift of the certificate); exact where it was decided without a solve
    (nothing loaded: 1, a block without any support: 0)."""
    if res.certificate is None:
        why = "decided without a solve (nothing loaded, or a block without support)"
        return Estimate(res.load_factor, {"exact": 0.0}, notes=why)
    return solver_estimate(res.load_factor, res.certificate)


def _cert(certificate) -> dict | None:
    if certificate is None:
        return None
    return {
        k: finite_or_none(v)
        for k, v in certificate.to_dict().items()
        if isinstance(v, (int, float))
    }


@dataclass(frozen=True)
class LimitBounds:
    """Associated upper bound, the two non-associated estimates, the lower bound and the
    mechanism of one interface model (:func:`limit.bounds_and_estimates`)."""

    settings: LimitSettings
    max_updates: int | None = None

    @property
    def name(self) -> str:
        return f"limit-{self.settings.interface_model}"

    @property
    def method(self) -> str:
        return f"limit analysis ({self.settings.interface_model} model)"

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        skipped = skip_without_collapse(self, scene, ctx)
        if skipped is not None:
            return skipped
        limit_settings = self.settings
        dead = ctx.ok("dead-load")
        if dead is not None and dead.values["stands"] and dead.settings == limit_settings.to_dict():
            # the dead-load step already proved it under the same settings: not twice
            limit_settings = limit_settings.with_(dead_load_check=False)
        settings = {**limit_settings.to_dict(), "max_updates": self.max_updates}
        try:
            b = bounds_and_estimates(
                scene, limit_settings, max_updates=self.max_updates, strict=False
            )
        except NoMechanismError as exc:
            values = {"upper": math.inf, "unbounded": True}
            return StepResult(self.name, self.method, "ok", str(exc), 0.0, settings, values)
        it = b.iterative
        values = {
            "upper": b.upper,
            "reduced_mu": finite_or_none(b.reduced_mu),
            "reduced_note": b.reduced_note,
            "lam_unit": b.lam_unit,
            "iterative": None if it is None else it.lam,
            "iterative_converged": None if it is None else it.converged,
            "iterative_admissible": None if it is None else it.admissible,
            "iterative_note": None if it is None else it.note,
            "lower": finite_or_none(b.lower),
            "lower_note": b.lower_note,
            "status": b.associated.status,
            "certificate_worst": b.associated.certificate.worst(),
            "part_wall_s": b.wall_s,
            "ordering_issues": list(b.issues),
            "moving_blocks": np.flatnonzero(
                np.abs(b.associated.velocities).max(axis=1)
                > 1e-6 * np.abs(b.associated.velocities).max()
            ).tolist(),
        }
        values = put_estimates(
            values,
            upper=b.upper_estimate,
            lower=None if values["lower"] is None else b.lower_estimate,
            reduced_mu=b.reduced_mu_estimate,
            iterative=None if it is None else it.estimate,
        )
        return StepResult(self.name, self.method, "ok", "", 0.0, settings, values, b)
