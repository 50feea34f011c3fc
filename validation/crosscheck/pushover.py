"""The pushover picture of a cross-check: the static DEM paths against the limit-analysis
bounds (a band per interface model) and the explicit DEM's bracket.

The paths are drawn up to their collapse region (a few times the displacement at which each
first reaches :data:`NEAR_PEAK` of its largest lambda), so that one law's long plateau does
not squash the others; ``tail=True`` draws them whole.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from validation.crosscheck.steps import Context

NEAR_PEAK = 0.95
"""Fraction of a path's largest lambda that marks its collapse region [-]."""
REGION = 2.0
"""The picture shows this many times the displacement at which a path reaches the collapse
region [-]."""


def zero_lower_note(live: list[float], gravity: list[float] | None = None) -> str:
    """Why a proven lower bound is 0: it is the frictionless (Radenkovic) bound, and joints
    without friction carry no shear, which this live load (resultant ``live`` [N]) needs;
    named a lateral load when it has no component along gravity (default -z)."""
    g = np.asarray(gravity if gravity is not None else (0.0, 0.0, -1.0), dtype=float)
    live_arr = np.asarray(live, dtype=float)
    along = abs(float(live_arr @ g)) / (np.linalg.norm(g) * (np.linalg.norm(live_arr) or 1.0))
    kind = "a lateral load" if along < 1e-9 else "this live load"
    return (
        "0 is the frictionless (Radenkovic) lower bound: joints without friction carry no "
        f"shear, and {kind} needs shear at every lambda > 0"
    )


COLOURS = {"vertex": "tab:red", "resultant": "tab:green"}
WIDTH = {"vertex": 4.0, "resultant": 1.5}
"""Line widths of the models' bounds: the resultant's thin line stays visible on the
vertex's where the two bounds coincide."""


def collapse_region_end(control: np.ndarray, lam: np.ndarray) -> float:
    """Displacement up to which a path is drawn: :data:`REGION` times the first one at
    which lambda reaches :data:`NEAR_PEAK` of its largest value (the whole path if that
    is shorter) [the unit of ``control``]."""
    control, lam = np.asarray(control, dtype=float), np.asarray(lam, dtype=float)
    if len(lam) == 0 or lam.max() <= 0:
        return float(np.max(control, initial=0.0))
    first = int(np.argmax(lam >= NEAR_PEAK * lam.max()))
    return float(min(REGION * control[first], control.max()))


def _bounds(ax, ctx: Context) -> list[float]:
    """A band from the lower to the upper bound per interface model, its estimates dashed."""
    drawn = []
    for model, colour in COLOURS.items():
        res = ctx.ok(f"limit-{model}")
        if res is None:
            continue
        if not math.isfinite(res.values["upper"]):
            label = f"{model} model: no collapse mechanism (the upper bound is unbounded)"
            ax.plot([], [], color=colour, lw=WIDTH[model], label=label)
            continue
        v = res.values
        upper, lower = v["upper"], v.get("lower")
        if lower is None:
            why = v.get("lower_note") or "no lower bound computed"
            label = f"{model} model: upper bound {upper:.4g} ({why})"
        elif lower == 0.0:  # a band from 0 would cover the picture and say nothing more
            label = f"{model} model: upper bound {upper:.4g}, lower bound 0 (frictionless)"
        else:
            label = f"{model} model: proven bounds [{lower:.4g}, {upper:.4g}]"
            ax.axhspan(lower, upper, color=colour, alpha=0.12, lw=0)
        ax.axhline(upper, color=colour, lw=WIDTH[model], alpha=0.8, label=label)
        estimates = [(k, v.get(k)) for k in ("reduced_mu", "iterative") if v.get(k) is not None]
        for _, value in estimates:
            ax.axhline(value, color=colour, lw=WIDTH[model] * 0.7, ls="--", alpha=0.8)
        if estimates:
            names = {"reduced_mu": "(a) mu*", "iterative": "(b) fixed capacities"}
            text = ", ".join(f"{names[k]} {x:.4g}" for k, x in estimates)
            ax.plot([], [], color=colour, ls="--", label=f"{model} model: estimates {text}")
        drawn += [upper] + [x for _, x in estimates]
    return drawn


def _bracket(ax, ctx: Context) -> list[float]:
    """The explicit DEM's bracket lambda_stable < lambda_c <= lambda_moving, hatched."""
    exp = ctx.ok("explicit")
    if exp is None:
        return []
    stable, moving = exp.values["lambda_stable"], exp.values["lambda_moving"]
    if moving is None:
        label = f"explicit DEM: at rest up to {stable:.4g}, no motion found"
        ax.axhline(stable, color="black", ls=":", lw=1.5, label=label)
        return [stable]
    confirmed = "" if exp.values["mechanism_confirmed"] else " (motion not confirmed)"
    label = f"explicit DEM bracket ({stable:.4g}, {moving:.4g}]{confirmed}"
    ax.axhspan(
        stable, moving, facecolor="none", edgecolor="black", hatch="///", lw=1.0, label=label
    )
    return [stable, moving]


def render_pushover(ctx: Context, png: Path, tail: bool = False) -> Path | None:
    """pushover.png: DEM paths, bounds and bracket; None if there is nothing to draw."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves = [(n, ctx.ok(n)) for n in ("dem-fibre", "dem-resultant") if ctx.ok(n) is not None]
    limits = [ctx.ok(f"limit-{m}") for m in COLOURS]
    if not curves and not any(limits):
        return None
    fig, ax = plt.subplots(figsize=(8, 6.5))
    levels, ends, longest = [], [], 0.0
    for name, res in curves:
        c, lam = res.payload.pushover
        x = np.asarray(c) * 1e3
        law, end = name.split("-", 1)[1], res.values["termination"]
        ax.plot(x, lam, marker=".", ms=3, lw=1.5, label=f"static DEM, {law} law (ended by {end})")
        levels.append(float(np.max(lam, initial=0.0)))
        ends.append(collapse_region_end(x, lam))
        longest = max(longest, float(np.max(x, initial=0.0)))
    levels += _bounds(ax, ctx) + _bracket(ax, ctx)
    top = max([v for v in levels if math.isfinite(v)], default=1.0) or 1.0
    ax.set_ylim(0.0, 1.12 * top)
    shown = "whole paths"
    if curves and not tail and max(ends) < longest:
        ax.set_xlim(-0.02 * max(ends), max(ends) * 1.02)
        shown = f"paths up to their collapse region (they go on to {longest:.3g} mm)"
    ax.set_xlabel(f"control displacement (live-load weighted mean) [mm]\n{shown}")
    ax.set_ylabel("load multiplier lambda [-]")
    parts = ["static DEM pushover"] if curves else []
    parts += ["limit-analysis bounds"] if any(limits) else []
    parts += ["the explicit DEM bracket"] if ctx.ok("explicit") is not None else []
    ax.set_title(", ".join(parts[:-1]) + (" and " if len(parts) > 1 else "") + parts[-1])
    ax.grid(alpha=0.3)
    fig.legend(loc="lower center", ncol=1, fontsize=8, frameon=False)
    n_entries = len(ax.get_legend_handles_labels()[0])
    fig.tight_layout(rect=(0, 0.035 * n_entries + 0.02, 1, 1))
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return png
