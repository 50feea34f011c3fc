"""Exceptions raised by the limit analysis, one type per structural outcome.

A caller (a bisection on a geometry parameter, a sweep) tells the outcomes apart by type:

- :class:`DeadLoadInfeasibleError`: no equilibrium under the dead load alone, the structure
  falls down by itself; it names the blocks and interfaces of the mechanism that proves it;
- :class:`NoMechanismError`: the live load is carried for every multiplier (unbounded);
- :class:`NumericalFailureError`: the solver could not give an answer that passes its
  certificate (a numerical failure, not a structural statement).

All three derive from :class:`LimitAnalysisError`, so ``except LimitAnalysisError`` still
catches every outcome without a certified optimum.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = [
    "LimitAnalysisError",
    "DeadLoadInfeasibleError",
    "NoMechanismError",
    "NumericalFailureError",
    "InconsistentBoundsError",
]


class LimitAnalysisError(RuntimeError):
    """A limit-analysis problem has no certified optimum (base of the outcomes below)."""


class DeadLoadInfeasibleError(LimitAnalysisError):
    """The structure falls down under its dead load alone (the static programme is infeasible).

    Attributes
    ----------
    blocks : tuple of int
        Blocks that move most in the collapse mechanism under the dead load (the dual, Farkas
        certificate of infeasibility), fastest first; empty when no mechanism was computed.
    interfaces : tuple of int
        Interfaces with the largest relative motion in that mechanism, largest first.
    """

    def __init__(self, message: str, blocks: Sequence[int] = (), interfaces: Sequence[int] = ()):
        super().__init__(message)
        self.blocks = tuple(int(i) for i in blocks)
        self.interfaces = tuple(int(k) for k in interfaces)


class NoMechanismError(LimitAnalysisError):
    """The live load is carried for every multiplier: no collapse mechanism (unbounded)."""


class NumericalFailureError(LimitAnalysisError):
    """The solver gave no answer that passes its certificate, even after the retries."""


class InconsistentBoundsError(NumericalFailureError):
    """Bounds and estimates that break the theorems' ordering (an estimate above the proven
    upper bound, a lower bound above an estimate).

    Attributes
    ----------
    bounds : limit.estimates.Bounds
        The inconsistent result, with its ``issues``, for inspection.
    """

    def __init__(self, message: str, bounds=None):
        super().__init__(message)
        self.bounds = bounds
