"""Rigid-block limit analysis: static programmes, certificates, bounds and estimates."""

from limit.deadload import StandsResult, stands
from limit.errors import (
    DeadLoadInfeasibleError,
    InconsistentBoundsError,
    LimitAnalysisError,
    NoMechanismError,
    NumericalFailureError,
)
from limit.estimates import Bounds, bounds_and_estimates, iterative_estimate
from limit.problems import LimitSettings, build_static_problem
from limit.safety import GeometricSafetyResult, geometric_safety_factor
from limit.solve import LimitResult, kinematic_analysis, limit_analysis, solve_static

__all__ = [
    "Bounds",
    "DeadLoadInfeasibleError",
    "GeometricSafetyResult",
    "InconsistentBoundsError",
    "LimitAnalysisError",
    "LimitResult",
    "LimitSettings",
    "NoMechanismError",
    "NumericalFailureError",
    "StandsResult",
    "bounds_and_estimates",
    "build_static_problem",
    "geometric_safety_factor",
    "iterative_estimate",
    "kinematic_analysis",
    "limit_analysis",
    "solve_static",
    "stands",
]
