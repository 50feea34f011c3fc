r"""Geometric safety factor: bisection on a geometry parameter with the dead-load check.

Heyman's geometric factor of safety of a masonry structure is the ratio of its actual
thickness to the least thickness at which it can still stand under its own weight (for an
arch, the thickness whose thrust line just fits). Here the user supplies ``build(t) -> Scene``
for a geometry parameter ``t`` (a thickness, a width, a slope) and a bracket ``[lo, hi]``
at whose ends the scene stands at one end and falls at the other; the critical value is found
by bisection with :func:`limit.deadload.stands`, each side certified: the standing side by an
admissible equilibrium, the falling side by a dual bound below one.

The outcomes are told apart by type, never by text: a scene that falls is a ``False`` of
:func:`stands` (its :class:`~limit.errors.DeadLoadInfeasibleError` counterpart), a numerical
failure is a :class:`~limit.errors.NumericalFailureError` and stops the bisection with the
parameter value in its message, and an invalid geometry is the builder's ``ValueError``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from dem.estimate import Estimate
from dem.scene import Scene
from limit.deadload import StandsResult, stands
from limit.errors import NumericalFailureError
from limit.problems import LimitSettings, checked_settings

__all__ = ["GeometricSafetyResult", "geometric_safety_factor"]


@dataclass(frozen=True)
class GeometricSafetyResult:
    """Outcome of :func:`geometric_safety_factor`.

    Attributes
    ----------
    critical : float
        The parameter value between standing and falling (midpoint of the final bracket).
    stands_above : bool
        The scene stands for values above ``critical`` (a thickness) or below it (a slope).
    bracket : (float, float)
        ``(falls_at, stands_at)``: the last values proven to fall and to stand,
        ``|stands_at - falls_at| <= rtol * |critical|``.
    factor : float or None
        For ``actual``: ``actual / critical`` when it stands above, ``critical / actual``
        when it stands below (above one: safe). None without ``actual``.
    standing, falling : StandsResult
        The certified checks at the two ends of the final bracket.
    history : list of (float, bool)
        Every parameter value checked and whether it stood, in order.
    wall_s : float
        [s].
    """

    critical: float
    stands_above: bool
    bracket: tuple[float, float]
    factor: float | None
    standing: StandsResult
    falling: StandsResult
    history: list = field(default_factory=list)
    wall_s: float = 0.0

    @property
    def critical_estimate(self) -> Estimate:
        """``critical`` with the half-width of the certified bracket (source
        ``"bisection"``): the critical value of this scene family lies between the last
        value proven to fall and the last proven to stand."""
        half = 0.5 * abs(self.bracket[1] - self.bracket[0])
        return Estimate(self.critical, {"bisection": half}, notes="certified bisection bracket")


def _check(build: Callable[[float], Scene], t: float, settings: LimitSettings) -> StandsResult:
    try:
        return stands(build(t), settings)
    except NumericalFailureError as exc:
        raise NumericalFailureError(f"dead-load check at parameter {t:.6g}: {exc}") from exc


def _narrow(a: float, b: float, rtol: float) -> bool:
    """The bracket ``[a, b]`` is narrower than ``rtol`` times its midpoint (or ``rtol`` near
    zero)."""
    return abs(b - a) <= rtol * max(abs(0.5 * (a + b)), rtol)


def geometric_safety_factor(
    build: Callable[[float], Scene],
    lo: float,
    hi: float,
    *,
    actual: float | None = None,
    settings: LimitSettings | None = None,
    rtol: float = 1e-3,
    max_steps: int = 60,
) -> GeometricSafetyResult:
    """Critical value of a geometry parameter by bisection, and the geometric safety factor.

    Parameters
    ----------
    build : callable
        ``build(t) -> Scene`` for the parameter ``t`` (its unit is the caller's).
    lo, hi : float
        Bracket, ``lo < hi``: the scene must stand at one end and fall at the other.
    actual : float, optional
        The design value of the parameter; gives ``factor``.
    settings : LimitSettings, optional
        Interface model and strengths of the dead-load check.
    rtol : float
        Stop when the bracket is narrower than ``rtol * |critical|`` (or ``rtol`` near 0).
    max_steps : int
        Largest number of bisection steps.

    Raises
    ------
    ValueError
        A bad bracket, a scene that stands (or falls) at both ends, or a bracket still wider
        than ``rtol`` after ``max_steps`` steps.
    NumericalFailureError
        A dead-load check without a certified answer (the parameter value is named).
    """
    _check_bracket(lo, hi, rtol, max_steps)
    settings = checked_settings(settings)
    t0 = time.perf_counter()
    at_lo, at_hi = _check(build, lo, settings), _check(build, hi, settings)
    history = [(lo, at_lo.stands), (hi, at_hi.stands)]
    if at_lo.stands == at_hi.stands:
        state = "stands" if at_lo.stands else "falls"
        raise ValueError(
            f"the scene {state} at both ends of the bracket [{lo:g}, {hi:g}]: widen it so that "
            "it stands at one end and falls at the other"
        )
    stands_above = at_hi.stands
    ends = ((lo, at_lo), (hi, at_hi)) if stands_above else ((hi, at_hi), (lo, at_lo))
    (t_fall, fall), (t_stand, stand) = _bisect(build, settings, *ends, rtol, max_steps, history)
    critical = 0.5 * (t_fall + t_stand)
    factor = None
    if actual is not None:
        factor = actual / critical if stands_above else critical / actual
    return GeometricSafetyResult(
        critical=critical,
        stands_above=stands_above,
        bracket=(t_fall, t_stand),
        factor=factor,
        standing=stand,
        falling=fall,
        history=history,
        wall_s=time.perf_counter() - t0,
    )


def _check_bracket(lo: float, hi: float, rtol: float, max_steps: int) -> None:
    """Raise a ``ValueError`` naming a bad bracket, ``rtol`` or ``max_steps``."""
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"the bracket needs finite lo < hi, got lo={lo!r}, hi={hi!r}")
    if not 0 < rtol < 1:
        raise ValueError(f"rtol must lie in (0, 1), got {rtol}")
    if isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 1:
        raise ValueError(f"max_steps must be an integer >= 1, got {max_steps!r}")


def _bisect(
    build: Callable[[float], Scene],
    settings: LimitSettings,
    falling: tuple[float, StandsResult],
    standing: tuple[float, StandsResult],
    rtol: float,
    max_steps: int,
    history: list,
) -> tuple[tuple[float, StandsResult], tuple[float, StandsResult]]:
    """Halve the bracket between ``falling`` and ``standing`` (each ``(t, check)``) until it is
    narrower than ``rtol``; append every check to ``history``; return the final two ends.

    Raises a ``ValueError`` if ``max_steps`` steps leave the bracket wider than ``rtol``.
    """
    (t_fall, fall), (t_stand, stand) = falling, standing
    for _ in range(max_steps):
        if _narrow(t_fall, t_stand, rtol):
            break
        mid = 0.5 * (t_fall + t_stand)
        check = _check(build, mid, settings)
        history.append((mid, check.stands))
        if check.stands:
            t_stand, stand = mid, check
        else:
            t_fall, fall = mid, check
    if not _narrow(t_fall, t_stand, rtol):
        raise ValueError(
            f"max_steps = {max_steps} bisection steps narrowed the bracket only to "
            f"[{min(t_fall, t_stand):.6g}, {max(t_fall, t_stand):.6g}], wider than rtol = "
            f"{rtol:g} times the critical value: raise max_steps or rtol"
        )
    return (t_fall, fall), (t_stand, stand)
