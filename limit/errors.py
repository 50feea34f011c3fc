"""Exceptions raised by the limit-analysis solvers."""

from __future__ import annotations


class LimitAnalysisError(RuntimeError):
    """A limit-analysis problem has no certified optimum.

    Raised when the solver reports a status other than ``optimal`` or ``optimal_inaccurate``
    (e.g. ``infeasible``, ``unbounded``, ``solver_error``), or when the returned point fails
    its feasibility certificate.
    """
