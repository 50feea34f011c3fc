"""A number with its error bar, as every method of the toolkit reports its headline value.

An :class:`Estimate` is a value and the half-width of an interval that should contain the
converged answer of the method's own model (the answer at zero load step, infinite grid,
end of path, ...), broken down by source. The half-width is the sum of the sources'
half-widths: the sources are not independent in general (a coarser grid and a shorter path
push the same way), so they are added, not combined in quadrature. Two estimates agree when
their intervals overlap.

The error is estimated by the method itself from work it can do: a second run at a refined
discretisation (with Richardson extrapolation where the order is known), a certified duality
gap, a continuation. How much work is spent is the user's choice, :data:`ErrorBudget`.

A bar never omits a known source silently. A source the chosen budget does not pay for is
estimated another way where the method can (a priori from its known order and a level the
run has, or from a neighbouring level of a sweep: :func:`sweep_errors`), or is listed in
:attr:`Estimate.omitted`: the bar then covers the named sources only, says so wherever it is
printed (``± 0.80 (without time step, node spacing)``), is not :attr:`Estimate.complete`, and
a reference outside it is a ``"partial bar"``, not a numerical error
(:attr:`validation.report.Row.error_kind`). An unbounded source is ``inf``, never left out.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

ErrorBudget = Literal["none", "cheap", "full"]
"""How much a method spends on its error estimate: ``"none"`` reports the value alone (its
error is unknown, ``inf``), ``"cheap"`` uses what the run gives for free or one extra coarse
run, ``"full"`` the refinements the method needs for a bar it can defend."""

ERROR_BUDGETS: tuple[str, ...] = ("none", "cheap", "full")


HALVED_RERUN_FACTOR = 2.0
"""Factor on the change ``|s_x - s_{x/2}|`` between a run at parameter ``x`` (load rate, time
step, node spacing) and its rerun at ``x / 2`` that bounds the error of the run itself: with
an error ``~ x^p`` and ``p >= 1``, the run's error is ``|s_x - s_{x/2}| 2^p / (2^p - 1) <= 2
|s_x - s_{x/2}|``. The number reported is the run's (the rerun only measures the change), so
the factor is the coarser level's, not the finer one's (``1 / (2^p - 1) <= 1``)."""


def check_error_budget(budget: str) -> str:
    """Return ``budget`` if it is one of :data:`ERROR_BUDGETS`, else raise ``ValueError``."""
    if budget not in ERROR_BUDGETS:
        raise ValueError(f"error budget must be one of {ERROR_BUDGETS}, got {budget!r}")
    return budget


@dataclass(frozen=True)
class Estimate:
    """A value and the half-width of the interval that should hold the converged answer.

    Parameters
    ----------
    value
        The method's answer, in the unit of the quantity.
    sources
        Source name -> half-width (same unit, >= 0, ``inf`` for an unbounded source), e.g.
        ``{"load step": 1e-4, "end of path": 3e-4}``. No sources means an exact value.
    cost_s
        Wall time spent on the error estimate beyond the value itself [s].
    notes
        Anything a reader needs to read the bar (the order assumed, the levels used).
    omitted
        Known error sources the bar does not cover (the budget did not pay for them; module
        notes): the bar is then the part of the error the named sources give.
    """

    value: float
    sources: Mapping[str, float] = field(default_factory=dict)
    cost_s: float = 0.0
    notes: str = ""
    omitted: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        value = float(self.value)
        if math.isnan(value):
            raise ValueError("Estimate value is NaN")
        clean = {}
        for name, width in dict(self.sources).items():
            w = float(width)
            if math.isnan(w) or w < 0:
                raise ValueError(f"error source {name!r} has half-width {width!r} (must be >= 0)")
            clean[str(name)] = w
        if not math.isfinite(self.cost_s) or self.cost_s < 0:
            raise ValueError(f"cost_s must be finite and >= 0, got {self.cost_s!r}")
        object.__setattr__(self, "value", value)
        object.__setattr__(self, "sources", clean)
        object.__setattr__(self, "cost_s", float(self.cost_s))
        if isinstance(self.omitted, str):
            raise ValueError(f"omitted must be a sequence of source names, got {self.omitted!r}")
        object.__setattr__(self, "omitted", tuple(str(s) for s in self.omitted))

    @classmethod
    def unknown(cls, value: float, why: str = "not estimated") -> Estimate:
        """A value whose error was not estimated (an infinite bar, never a silent zero)."""
        return cls(value, {"not estimated": math.inf}, notes=why)

    @property
    def error(self) -> float:
        """Half-width of the interval: the sum of the sources' half-widths."""
        return float(sum(self.sources.values()))

    @property
    def complete(self) -> bool:
        """Whether the bar covers every known source: none :attr:`omitted`, none unbounded."""
        return not self.omitted and math.isfinite(self.error)

    @property
    def lo(self) -> float:
        return self.value - self.error

    @property
    def hi(self) -> float:
        return self.value + self.error

    def contains(self, x: float) -> bool:
        """Whether ``x`` lies in ``[value - error, value + error]``."""
        return self.lo <= float(x) <= self.hi

    def overlaps(self, other: Estimate) -> bool:
        """Whether the two intervals share a point (the agreement test of the cross-check)."""
        return self.lo <= other.hi and other.lo <= self.hi

    def with_source(self, name: str, width: float, cost_s: float = 0.0) -> Estimate:
        """A copy with one more (or a replaced) error source, and its cost added."""
        sources = dict(self.sources)
        sources[name] = width
        omitted = tuple(s for s in self.omitted if s != name)
        return Estimate(self.value, sources, self.cost_s + cost_s, self.notes, omitted)

    def format(self, unit: str = "") -> str:
        """``value ± error`` rounded to the digits the error supports, with ``unit``."""
        text = f"{format_estimate(self.value, self.error)} {unit}".rstrip()
        return text + omitted_suffix(self.omitted)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON types (an infinite half-width is the string ``"inf"``)."""
        return {
            "value": self.value,
            "error": _json_float(self.error),
            "sources": {k: _json_float(v) for k, v in self.sources.items()},
            "cost_s": self.cost_s,
            "notes": self.notes,
            "omitted": list(self.omitted),
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Estimate:
        return cls(
            float(data["value"]),
            {k: float(v) for k, v in data.get("sources", {}).items()},
            float(data.get("cost_s", 0.0)),
            str(data.get("notes", "")),
            tuple(data.get("omitted", ())),
        )


def omitted_suffix(omitted) -> str:
    """`` (without a, b)`` after a printed bar that omits sources, empty otherwise."""
    return f" (without {', '.join(omitted)})" if omitted else ""


def _json_float(x: float) -> float | str:
    return x if math.isfinite(x) else str(x)


FINE_RELATIVE = 1e-6
"""Below this relative half-width a value is printed to 7 significant digits."""


def format_estimate(value: float, error: float, sig_error: int = 2) -> str:
    """``value ± error`` with the error to ``sig_error`` significant digits and the value to
    the same decimal place; an exact value keeps 6 significant digits, an unknown error
    (``inf``) shows ``± ?`` after 4 significant digits, and an error below
    :data:`FINE_RELATIVE` of the value shows the value to 7 significant digits and the error
    in scientific notation (a certified gap of 1e-11 does not make a reader count 12 zeros), as
    does a small error of a value that is exactly 0."""
    if not math.isfinite(value):
        return str(value)
    if math.isinf(error):
        return f"{value:.4g} ± ?"
    if error <= 0:
        return f"{value:.6g}"
    if error < FINE_RELATIVE * abs(value):
        return f"{value:.7g} ± {error:.{sig_error - 1}e}"
    exponent = math.floor(math.log10(error)) - (sig_error - 1)
    decimals = max(0, -exponent)
    if value == 0 and error < 1e-4:  # a residual at 0: no column of zeros
        return f"0 ± {error:.{sig_error - 1}e}"
    if abs(value) >= 1e6 or (value != 0 and abs(value) < 1e-4):
        scale = math.floor(math.log10(abs(value))) if value != 0 else 0
        digits = max(1, scale - exponent + 1)
        return f"{value:.{digits - 1}e} ± {error:.{sig_error - 1}e}"
    return f"{round(value, -exponent):.{decimals}f} ± {round(error, -exponent):.{decimals}f}"


def richardson(coarse: float, fine: float, ratio: float, order: float) -> Estimate:
    """Richardson extrapolation of two levels whose step differs by ``ratio`` (> 1) with
    error ~ h**order: the extrapolated value, with the distance from the fine level as its
    half-width (the fine level lies in the interval, so the bar holds even where the order is
    not yet asymptotic)."""
    if ratio <= 1 or order <= 0:
        raise ValueError(f"richardson needs ratio > 1 and order > 0, got {ratio}, {order}")
    factor = ratio**order - 1.0
    extrapolated = fine + (fine - coarse) / factor
    return Estimate(
        extrapolated,
        {"discretisation": abs(extrapolated - fine)},
        notes=f"Richardson, ratio {ratio:g}, order {order:g}",
    )


def sweep_errors(
    steps: Sequence[float], values: Sequence[float], order: float, exact_last: bool = False
) -> list[float]:
    """Half-width of the error of each level of a refinement sweep against its limit.

    ``steps`` run coarse to fine (each > the next > 0, the parameter whose error goes as
    ``step**order``), ``values`` are the results there. The finest level's error is the
    Richardson bound of its last pair, ``|s_f - s_c| / (r**order - 1)`` with ``r`` their step
    ratio (0 where ``exact_last``: the finest level is the model itself, e.g. no mass
    scaling); every coarser level adds its distance to the next finer one to that level's
    error (the triangle inequality). So a coarse level's bar uses every finer level of the
    sweep, and holds even where the differences grow on refinement (a pre-asymptotic sweep),
    as long as the finest pair is asymptotic at ``order`` or better: pass the smallest order
    the discretisation can have. A non-finite value makes its level and every coarser one
    unbounded."""
    h = [float(s) for s in steps]
    s = [float(v) for v in values]
    if len(h) != len(s) or len(h) < 2:
        raise ValueError(f"a sweep needs >= 2 levels with one value each, got {len(h)}, {len(s)}")
    if order <= 0 or any(not (a > b > 0) for a, b in zip(h, h[1:], strict=False)):
        raise ValueError(f"sweep steps must decrease and stay > 0, order > 0: {h}, {order}")
    r = h[-2] / h[-1]
    errors = [0.0 if exact_last else abs(s[-1] - s[-2]) / (r**order - 1.0)]
    for i in range(len(s) - 2, -1, -1):
        errors.insert(0, abs(s[i] - s[i + 1]) + errors[0])
    return [e if math.isfinite(e) else math.inf for e in errors]
