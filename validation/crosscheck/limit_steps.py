"""Limit-analysis steps: the dead-load check and the bounds of one interface model."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import limit
from dem.scene import Scene, proportional_to_weight
from limit import LimitAnalysisError, LimitSettings, bounds_and_estimates
from limit.solve import MSG_UNBOUNDED
from validation.crosscheck.steps import (
    Context,
    StepResult,
    finite_or_none,
    has_live_load,
    skip_without_collapse,
)


def _probe(scene: Scene) -> Scene:
    """The scene with a live load on its free blocks, if it has none (weight along +x)."""
    if has_live_load(scene):
        return scene
    live = proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0))
    live[scene.supports.fixed] = 0.0
    return scene.with_loads(live=live)


@dataclass(frozen=True)
class DeadLoadCheck:
    """Does the scene stand under its dead load? (a statically admissible field at lambda 0)

    Uses :func:`limit.stands` where the library has it; otherwise the associated programme
    with the scene's live load (or a probe, each free block's weight along +x): a solution or
    an unbounded multiplier means the dead load is carried, an infeasible programme that it
    is not.
    """

    settings: LimitSettings
    name: str = "dead-load"
    method: str = "dead-load check (limit analysis, vertex model)"

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        stands = getattr(limit, "stands", None)
        if stands is not None:
            res = stands(scene, self.settings)
            values = {"stands": bool(res.stands), "certificate": _cert(res.certificate)}
            return StepResult(
                self.name, self.method, "ok", "", res.wall_s, self.settings.to_dict(), values, res
            )
        try:
            res = limit.limit_analysis(_probe(scene), self.settings)
        except LimitAnalysisError as exc:
            text = str(exc)
            if text.startswith(MSG_UNBOUNDED):
                return self._result(True, "the live load is carried by arching (unbounded)")
            if "fall down by" in text or "falls down by" in text:
                return self._result(False, text)
            raise
        return self._result(True, "", _cert(res.certificate), res)

    def _result(self, stands: bool, reason: str, certificate=None, payload=None) -> StepResult:
        values = {"stands": stands, "certificate": certificate}
        return StepResult(
            self.name, self.method, "ok", reason, 0.0, self.settings.to_dict(), values, payload
        )


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
    max_iter: int = 30

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
        settings = {**self.settings.to_dict(), "max_iter": self.max_iter}
        try:
            b = bounds_and_estimates(scene, self.settings, max_iter=self.max_iter)
        except LimitAnalysisError as exc:
            if not str(exc).startswith(MSG_UNBOUNDED):
                raise
            values = {"upper": math.inf, "unbounded": True}
            return StepResult(self.name, self.method, "ok", str(exc), 0.0, settings, values)
        it = b.iterative
        values = {
            "upper": b.upper,
            "reduced_mu": finite_or_none(b.reduced_mu),
            "iterative": None if it is None else it.lam,
            "iterative_converged": None if it is None else it.converged,
            "iterative_admissible": None if it is None else it.admissible,
            "lower": finite_or_none(b.lower),
            "lower_note": b.lower_note,
            "status": b.associated.status,
            "certificate_worst": b.associated.certificate.worst(),
            "part_wall_s": b.wall_s,
            "moving_blocks": np.flatnonzero(
                np.abs(b.associated.velocities).max(axis=1)
                > 1e-6 * np.abs(b.associated.velocities).max()
            ).tolist(),
        }
        return StepResult(self.name, self.method, "ok", "", 0.0, settings, values, b)
