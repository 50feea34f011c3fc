"""Cross-check any scene with every method: one call, one report (see :func:`crosscheck`)."""

from validation.crosscheck.run import (
    METHODS,
    CrosscheckResult,
    CrosscheckSettings,
    crosscheck,
    scene_summary,
)
from validation.crosscheck.steps import Context, Step, StepResult
from validation.crosscheck.verdict import Check

__all__ = [
    "METHODS",
    "Check",
    "Context",
    "CrosscheckResult",
    "CrosscheckSettings",
    "Step",
    "StepResult",
    "crosscheck",
    "scene_summary",
]
