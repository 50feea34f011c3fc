"""Rigid-block limit analysis: static programmes, certificates, bounds and estimates."""

from limit.errors import LimitAnalysisError
from limit.problems import LimitSettings, build_static_problem
from limit.solve import LimitResult, limit_analysis, solve_static

__all__ = [
    "LimitAnalysisError",
    "LimitResult",
    "LimitSettings",
    "build_static_problem",
    "limit_analysis",
    "solve_static",
]
