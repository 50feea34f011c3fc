r"""Adaptive fibre grid: the fibre law's collapse multiplier refined until the grid no longer
moves it.

The fibre law (:class:`dem.static.settings.FibreLawSettings`) resolves partly open, crushed
and twisting joints only as finely as its grid of springs. :func:`refine_fibre_grid` runs the
analysis on grids whose cells halve, ``p -> 2 p - 1`` Gauss-Lobatto points per side (5, 9,
17, 33, ...; on other convex polygons the midpoint grid doubles the same way), until
``lambda_max`` changes by less than ``grid_tolerance`` of itself between the last two grids,
or ``max_points`` is reached.

The error source ``"fibre grid"`` is twice the last change, a stated bound rather than a
Richardson extrapolation: the error of a crushed or partly open zone is of first order in the
cell size but oscillates in sign as the edge of the zone passes between springs (a block
tipping on a crushed toe), so no order can be fitted and an extrapolation can land on the
wrong side. For a first-order error that does not oscillate (rocking on a polygon whose edges
carry no springs) the change between a grid and the one of half its cell is about the error
of the finer one; the factor 2 covers convergence rates down to ``log2(1.5)``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Protocol, TypeVar

from dem.static.settings import FibreLawSettings, StaticSettings

logger = logging.getLogger(__name__)

SOURCE = "fibre grid"
"""Name of the error source in the result's estimate."""

BOUND_FACTOR = 2.0
"""Half-width of the grid's error source in units of the last change of lambda (notes)."""


class _Run(Protocol):
    """What the refinement reads of a run (a :class:`dem.static.StaticResult`)."""

    lambda_max: float
    collapsed: bool


Run = TypeVar("Run", bound=_Run)


@dataclass(frozen=True)
class GridRefinement:
    """The grids an analysis ran on and how far the last refinement moved lambda.

    Attributes
    ----------
    points : tuple of int
        Gauss-Lobatto points per side of each grid, coarse to fine (the result is the last).
    lambdas : tuple of float
        ``lambda_max`` of each grid [-] (NaN where the run did not collapse).
    tolerance : float
        Relative change of lambda at which the refinement stops [-].
    converged : bool
        Whether the last change is within ``tolerance`` of the last lambda.
    """

    points: tuple[int, ...]
    lambdas: tuple[float, ...]
    tolerance: float
    converged: bool

    @property
    def change(self) -> float:
        """``|lambda_fine - lambda_coarse|`` of the last two grids; inf with one grid or a
        run that did not collapse."""
        if len(self.lambdas) < 2 or not all(map(math.isfinite, self.lambdas[-2:])):
            return math.inf
        return abs(self.lambdas[-1] - self.lambdas[-2])

    def error_sources(self) -> dict[str, float]:
        """``{"fibre grid": BOUND_FACTOR * change}``: the bound on the finest grid's error in
        ``lambda_max`` (module notes)."""
        return {SOURCE: BOUND_FACTOR * self.change}

    def describe(self) -> str:
        """The grids and their lambdas in words, e.g. ``"fibre grids 5, 9, 17 points:
        lambda_max 0.5657, 0.5433, no collapse"``."""
        lams = ", ".join(
            f"{lam:.6g}" if math.isfinite(lam) else "no collapse" for lam in self.lambdas
        )
        points = ", ".join(map(str, self.points))
        return f"fibre grids {points} points: lambda_max {lams}"

    def to_dict(self) -> dict:
        return {
            "points": list(self.points),
            "lambdas": list(self.lambdas),
            "tolerance": self.tolerance,
            "converged": self.converged,
            "change": self.change,
        }


def finer_points(points: int) -> int:
    """Points per side of the grid whose cells are half as long."""
    return 2 * points - 1


def refine_fibre_grid(
    settings: StaticSettings, solve: Callable[[StaticSettings], Run]
) -> tuple[Run, GridRefinement]:
    """Run ``solve`` on finer fibre grids until lambda settles (module notes).

    Parameters
    ----------
    settings : StaticSettings
        With the fibre law; its ``points`` is the first grid, ``grid_tolerance`` and
        ``max_points`` stop the refinement.
    solve : callable
        One analysis at fixed settings, returning its result whether it collapsed or not.

    Returns
    -------
    result : StaticResult
        The run on the finest grid.
    refinement : GridRefinement
    """
    law = settings.law_settings
    if not isinstance(law, FibreLawSettings) or law.grid_tolerance is None:
        raise ValueError("refine_fibre_grid needs the fibre law with a grid_tolerance")
    points, lambdas = [], []
    result, converged = None, False
    n = law.points
    while True:
        grid = replace(law, points=n, grid_tolerance=None)
        result = solve(replace(settings, law=grid, fibre_points=None, interface_model=None))
        points.append(n)
        lambdas.append(result.lambda_max if result.collapsed else math.nan)
        if not result.collapsed:
            break
        if len(lambdas) > 1:
            converged = abs(lambdas[-1] - lambdas[-2]) <= law.grid_tolerance * abs(lambdas[-1])
        if converged or finer_points(n) > law.max_points:
            break
        n = finer_points(n)
    refinement = GridRefinement(tuple(points), tuple(lambdas), law.grid_tolerance, converged)
    if not converged and result.collapsed:
        logger.warning(
            "fibre grid not converged: lambda moved by %.3g %% between %d and %d points "
            "(tolerance %.3g %%, max_points %d); that change is the grid's error bound",
            100 * refinement.change / abs(lambdas[-1]),
            points[-2] if len(points) > 1 else points[-1],
            points[-1],
            100 * law.grid_tolerance,
            law.max_points,
        )  # fmt: skip
    return result, refinement
