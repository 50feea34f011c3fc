"""The indentation's headline numbers with their error bars.

Each number of the curve summary (:func:`dem.explicit.results.curve_summary`: peak load,
deflection at peak, loading energy, ultimate deflection) becomes an
:class:`~dem.estimate.Estimate` of the converged answer of the model (quasi-static loading,
zero time step, zero node spacing, continuous curve), with sources the method measures itself:

- "curve sampling" (free): the curve is recorded every ``record_interval`` of travel ``h``, as
  the mean load over each interval. For a curve that varies smoothly over one interval, the
  peak of the continuous curve lies within one interval of the recorded one and rises above
  it by at most the change of the recorded load over one interval on either side; the
  ultimate deflection is known to one interval, the loading energy to the area of one
  interval at the load there. A peak that was not reached (the load never fell after it) is
  a lower bound only: every number gets an unbounded source;
- "loading rate" (``"cheap"``): the run repeated at half the indenter speed;
- "time step" and "node spacing" (``"full"``): the run repeated at half the time step, and at
  half the node spacing.

A rerun's source is :data:`dem.estimate.HALVED_RERUN_FACTOR` (2) times the change of the
number: the bound of the run's own error for a convergence order of at least 1. A rerun that
does not reach the peak, or gives a non-finite number, makes that source unbounded; so does,
for the loading energy, a rerun whose block did not get out (its work stops at the end of the
rerun, not at an ultimate deflection, so the two numbers are not the same quantity).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from dem.estimate import HALVED_RERUN_FACTOR, ErrorBudget, Estimate, check_error_budget

logger = logging.getLogger(__name__)

QUANTITIES = ("peak_load", "deflection_at_peak", "loading_energy", "ultimate_deflection")
"""The numbers of an indentation run that carry an estimate (attributes of the result)."""

RERUNS = {
    "loading rate": ({}, {"speed": 0.5}),
    "time step": ({"dt_safety": 0.5}, {}),
    "node spacing": ({"node_spacing": 0.5}, {}),
}
"""Error sources measured by a second run: name -> (factors on solver settings, factors on
indentation settings)."""

BUDGET_SOURCES = {"none": (), "cheap": ("loading rate",),
                  "full": ("loading rate", "time step", "node spacing")}  # fmt: skip
"""The reruns each error budget pays for (:data:`dem.estimate.ErrorBudget`)."""


def curve_sampling(result, record_interval: float) -> dict[str, float]:
    """Half-width of each of :data:`QUANTITIES` from the sampling of the curve (module notes),
    in its unit ([N], [m], [J], [m]); ``inf`` for every one when the peak was not reached, and
    for the ultimate deflection and the loading energy when the block did not get out."""
    if not result.peak_reached:
        return dict.fromkeys(QUANTITIES, math.inf)
    load = np.asarray(result.load)
    k = int(np.argmax(load))
    neighbours = load[max(0, k - 1) : k + 2]
    widths = {
        "peak_load": float(np.max(np.abs(neighbours - load[k]))),
        "deflection_at_peak": float(record_interval),
        "ultimate_deflection": float(record_interval),
    }
    if math.isfinite(result.ultimate_deflection):
        end = int(np.searchsorted(result.delta, result.ultimate_deflection))
        widths["loading_energy"] = float(record_interval * abs(load[min(end, len(load) - 1)]))
    else:
        widths["loading_energy"] = widths["ultimate_deflection"] = math.inf
    return widths


def indentation_estimates(
    run: Callable, settings, indentation, result, budget: ErrorBudget
) -> dict[str, Estimate]:
    """The estimates of :data:`QUANTITIES` of ``result`` under the error ``budget``.

    Parameters
    ----------
    run : callable
        ``run(settings, indentation) -> IndentationResult``: the same scene and relaxation,
        no checkpoint.
    settings, indentation : ExplicitSettings, IndentationSettings
        Those of ``result``.
    result : IndentationResult
    budget : {"none", "cheap", "full"}
        ``"none"``: every value with an unknown bar; otherwise the curve sampling plus the
        reruns of :data:`BUDGET_SOURCES`, the reruns of ``"full"`` it does not pay for listed
        in :attr:`~dem.estimate.Estimate.omitted`.

    Returns
    -------
    dict
        Quantity name -> :class:`~dem.estimate.Estimate` (SI units) of every quantity with a
        value (no ultimate deflection when the block did not get out); the cost of the reruns
        is in every estimate's ``cost_s``.
    """
    check_error_budget(budget)
    values = {name: float(getattr(result, name)) for name in QUANTITIES}
    if budget == "none":
        return {name: Estimate.unknown(v, "error budget 'none'")
                for name, v in values.items() if not math.isnan(v)}  # fmt: skip
    sources = {name: {} for name in QUANTITIES}
    for name, width in curve_sampling(result, indentation.record_interval).items():
        sources[name]["curve sampling"] = width
    cost = 0.0
    for source in BUDGET_SOURCES[budget]:
        wall0 = time.perf_counter()
        other = _rerun(run, settings, indentation, source)
        cost += time.perf_counter() - wall0
        if not other.peak_reached:
            logger.warning("the %s rerun did not reach the peak: that source is unbounded",
                           source)  # fmt: skip
        stop = getattr(other, "info", {}).get("stopped_by", "")
        if stop and not math.isfinite(other.ultimate_deflection):
            logger.warning("the %s rerun stopped before its block got out, so its sources of "
                           "the ultimate deflection and the loading energy are unbounded: %s",
                           source, stop)  # fmt: skip
        for name in QUANTITIES:
            width = HALVED_RERUN_FACTOR * abs(_rerun_value(other, name) - values[name])
            sources[name][source] = width if math.isfinite(width) else math.inf
    notes = f"reruns at half the parameter: {', '.join(BUDGET_SOURCES[budget])}"
    omitted = tuple(s for s in BUDGET_SOURCES["full"] if s not in BUDGET_SOURCES[budget])
    return {name: Estimate(values[name], sources[name], cost, notes, omitted)
            for name in QUANTITIES if not math.isnan(values[name])}  # fmt: skip


def _rerun_value(other, name: str) -> float:
    """The rerun's number ``name``, NaN where it is not the same quantity as the run's: no
    peak reached, or a loading energy without an ultimate deflection (module notes)."""
    if not other.peak_reached:
        return math.nan
    if name == "loading_energy" and not math.isfinite(other.ultimate_deflection):
        return math.nan
    return float(getattr(other, name))


def _rerun(run: Callable, settings, indentation, source: str):
    """The run with the change of ``source`` (:data:`RERUNS`)."""
    on_settings, on_indentation = RERUNS[source]
    changed = replace(settings, **{k: getattr(settings, k) * f for k, f in on_settings.items()})
    moved = replace(
        indentation, **{k: getattr(indentation, k) * f for k, f in on_indentation.items()}
    )
    return run(changed, moved)
