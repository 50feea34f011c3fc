"""Rigid-block limit analysis: static programmes, certificates, bounds and estimates."""

from limit.deadload import StandsResult, stands
from limit.errors import (
    DeadLoadInfeasibleError,
    LimitAnalysisError,
    NoMechanismError,
    NumericalFailureError,
)
from limit.estimates import Bounds, bounds_and_estimates, iterative_estimate
from limit.problems import LimitSettings, build_static_problem
from limit.solve import LimitResult, kinematic_analysis, limit_analysis, solve_static

__all__ = [
    "Bounds",
    "DeadLoadInfeasibleError",
    "LimitAnalysisError",
    "LimitResult",
    "LimitSettings",
    "NoMechanismError",
    "NumericalFailureError",
    "StandsResult",
    "bounds_and_estimates",
    "build_static_problem",
    "iterative_estimate",
    "kinematic_analysis",
    "limit_analysis",
    "solve_static",
    "stands",
]
