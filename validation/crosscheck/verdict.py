"""The consistency verdict of a cross-check, line by line.

What must hold between the methods (each line says which theorem or check it rests on):

- the scene stands under its dead load (else no collapse multiplier exists);
- per interface model, ``lower <= estimates <= upper``: the frictionless associated
  multiplier bounds the zero-dilatancy one from below and the associated one bounds it from
  above (Radenkovic), and both estimates are associated-admissible force fields;
- per DEM law, the run ended in a collapse (a plateau, softening or snap-back, not
  ``max_steps`` or non-convergence), and ``lower <= lambda_DEM <= upper`` of the matching
  model (fibre law ~ vertex model, resultant law ~ resultant model);
- the two DEM laws agree, or the report says why not;
- the explicit run collapsed, its motion confirmed (it grew when followed), its last state
  at rest lies below the upper bound, and its bracket holds the static DEM multiplier (an
  unconfirmed motion makes no bracket);
- every block of the DEM collapse state is in equilibrium (FEM residual).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

from validation.crosscheck.limit_steps import WHY_NONE
from validation.crosscheck.steps import Context

MODEL_OF_LAW = {"fibre": "vertex", "resultant": "resultant"}
"""The limit-analysis interface model that matches each DEM interface law."""
PASS, FAIL, NA = "pass", "fail", "n/a"
EXPLICIT_BELOW = (
    "; the explicit DEM follows large displacements with the material's joint stiffness, the "
    "static DEM small ones: a structure that deforms before it collapses (an arch, a vault) "
    "carries less in the explicit run, the more so the softer its joints (rerun "
    "dem.explicit.simulate_lateral with a stiffer k_n: the bracket should rise towards the "
    "static value)"
)
"""What a failed bracket check adds when the explicit run collapsed below the static DEM (the
README's cross-check section gives a barrel vault's numbers)."""


@dataclass(frozen=True)
class Check:
    """One line of the verdict.

    Attributes
    ----------
    name : str
    status : {"pass", "fail", "n/a"}
    value : float or None
        The quantity checked.
    bound : float or None
        What it is compared with.
    detail : str
        Why it passes, fails or does not apply.
    step : str
        The step whose result is checked (empty for checks across steps).
    """

    name: str
    status: str
    value: float | None = None
    bound: float | None = None
    detail: str = ""
    step: str = ""

    def to_dict(self) -> dict:
        return asdict(self)


def _tagged(checks: list[Check], step: str) -> list[Check]:
    return [replace(c, step=step) for c in checks]


def _le(a: float, b: float, rtol: float, unit: float = 1.0) -> bool:
    """``a <= b`` up to ``rtol`` relative to ``|b|`` (and ``rtol * unit`` near zero, with
    ``unit`` the limit programme's scale of lambda: the multiplier at which the live load
    equals the weight)."""
    return a <= b + rtol * max(abs(b), unit) if math.isfinite(b) else True


def _unit(lim) -> float:
    """The scale of lambda of a limit step (1 when it has none)."""
    return 1.0 if lim is None else float(lim.values.get("lam_unit", 1.0))


def dead_load_checks(ctx: Context) -> list[Check]:
    res = ctx.ok("dead-load")
    if res is None:
        step = ctx.results.get("dead-load")
        return [Check("stands under its dead load", NA, detail=step.reason if step else "not run")]
    v = res.values
    detail = res.reason
    if not v["stands"] and v["blocks"]:
        detail += f" Blocks {v['blocks'][:20]} and interfaces {v['interfaces'][:20]} move most."
    return [
        Check(
            "stands under its dead load",
            PASS if v["stands"] else FAIL,
            v["load_factor"],
            1.0,
            detail,
        )
    ]


def step_checks(ctx: Context) -> list[Check]:
    """A failed method is a line of the verdict: a result that is missing is not consistent."""
    return [
        Check(f"{name} ran", FAIL, detail=res.reason, step=name)
        for name, res in ctx.results.items()
        if res.status == "failed"
    ]


def limit_checks(ctx: Context, rtol: float) -> list[Check]:
    out = []
    for model in ("vertex", "resultant"):
        out += _tagged(_model_checks(ctx, model, rtol), f"limit-{model}")
    return out


def _model_checks(ctx: Context, model: str, rtol: float) -> list[Check]:
    res = ctx.ok(f"limit-{model}")
    if res is None:
        return []
    v = res.values
    if v.get("unbounded"):
        detail = (
            "no collapse mechanism: the live load is carried for every multiplier (arching "
            "against rigid supports)"
        )
        return [Check(f"finite upper bound ({model})", NA, detail=detail)]
    upper, lower, unit = v["upper"], v["lower"], _unit(res)
    out = []
    if lower is None:
        out.append(Check(f"lower <= upper ({model})", NA, None, upper, v["lower_note"]))
    else:
        ok = _le(lower, upper, rtol, unit)
        out.append(Check(f"lower <= upper ({model})", PASS if ok else FAIL, lower, upper))
    for label, key in (("estimate mu*", "reduced_mu"), ("estimate (b)", "iterative")):
        name, est = f"{label} within bounds ({model})", v[key]
        if est is None:
            why = v.get(WHY_NONE[key])
            out.append(Check(name, NA, detail=why or "not computed"))
        elif key == "iterative" and not v["iterative_admissible"]:
            detail = "last iterate not admissible: not bounded by the upper bound"
            out.append(Check(name, NA, est, upper, detail))
        else:
            ok = _le(est, upper, rtol, unit) and (lower is None or _le(lower, est, rtol, unit))
            detail = f"lower {lower:.6g}" if lower is not None else "no lower bound"
            out.append(Check(name, PASS if ok else FAIL, est, upper, detail))
    return out


def dem_checks(ctx: Context, rtol: float) -> list[Check]:
    out = []
    for law in MODEL_OF_LAW:
        out += _tagged(_law_checks(ctx, law, rtol), f"dem-{law}")
    return out


def _law_checks(ctx: Context, law: str, rtol: float) -> list[Check]:
    res = ctx.ok(f"dem-{law}")
    if res is None:
        return []
    model = MODEL_OF_LAW[law]
    v = res.values
    lam = v["lambda_max"]
    lim = ctx.ok(f"limit-{model}")
    upper = None if lim is None else lim.values["upper"]
    name = f"DEM {law} law collapsed"
    detail = f"termination: {v['termination']}"
    if upper is not None and not math.isfinite(upper):
        # no mechanism exists (associated upper bound unbounded): none is expected, and a
        # run without one is no collapse to check
        detail += f"; the limit analysis ({model}) finds no mechanism, so none is expected"
        return [Check(name, NA, lam if v["collapsed"] else None, upper, detail)]
    out = [Check(name, PASS if v["collapsed"] else FAIL, lam, None, detail)]
    if upper is None:
        return out
    ok = _le(lam, upper, rtol, _unit(lim))
    ratio = f"lambda_DEM / upper = {lam / upper:.4f}" if upper else ""
    out.append(Check(f"DEM {law} <= upper ({model})", PASS if ok else FAIL, lam, upper, ratio))
    lower = lim.values["lower"]
    if lower is not None:
        ok = _le(lower, lam, rtol, _unit(lim))
        out.append(Check(f"lower ({model}) <= DEM {law}", PASS if ok else FAIL, lam, lower))
    return out


def agreement_check(ctx: Context, agree_rtol: float) -> list[Check]:
    fib, res = ctx.ok("dem-fibre"), ctx.ok("dem-resultant")
    if fib is None or res is None:
        return []
    a, b = fib.values["lambda_max"], res.values["lambda_max"]
    name = "the two DEM laws agree"
    if not (fib.values["collapsed"] or res.values["collapsed"]):
        # both ended without a collapse (e.g. no mechanism exists): they agree that none came
        # within the run, and their last multipliers are no collapse loads to compare
        detail = (
            f"neither law collapsed (fibre: {fib.values['termination']}, resultant: "
            f"{res.values['termination']}): no collapse multipliers to compare"
        )
        return [Check(name, NA, None, agree_rtol, detail)]
    if not (math.isfinite(a) and math.isfinite(b)):
        return [Check(name, NA, None, agree_rtol, f"fibre {a}, resultant {b}: no finite pair")]
    diff = abs(a - b) / max(abs(a), abs(b), 1e-300)
    if diff <= agree_rtol:
        return [Check(name, PASS, diff, agree_rtol, f"fibre {a:.6g}, resultant {b:.6g}")]
    why = []
    for step in (fib, res):
        if not step.values["collapsed"]:
            why.append(f"{step.name} ended by {step.values['termination']}, not a collapse")
    uppers = {}
    for law, step in (("fibre", fib), ("resultant", res)):
        lim = ctx.ok(f"limit-{MODEL_OF_LAW[law]}")
        if lim is not None and math.isfinite(lim.values["upper"]) and lim.values["upper"] > 0:
            uppers[law] = lim.values["upper"]
            lam = step.values["lambda_max"]
            why.append(f"{law} {lam:.6g} = {lam / uppers[law]:.0%} of its upper bound")
    if len(uppers) == 2:
        gap = abs(uppers["fibre"] - uppers["resultant"]) / max(uppers.values())
        if diff <= gap + agree_rtol:
            why.append(
                f"the upper bounds of the two interface models differ as much "
                f"({100 * gap:.1f} %): the models differ, not the solvers"
            )
        else:
            why.append(
                f"the upper bounds differ by {100 * gap:.1f} % only: the rest comes from "
                "the DEM path (possible causes: non-associated friction makes the collapse "
                "depend on the elastic path; the resultant law's friction domain (seed 001 "
                "Eq. A5 on the reduced rectangle) is not the springs' one)"
            )
    detail = "; ".join(why) or f"fibre {a:.6g}, resultant {b:.6g}"
    return [Check(name, FAIL, diff, agree_rtol, detail)]


def explicit_checks(ctx: Context, rtol: float, agree_rtol: float) -> list[Check]:
    """The explicit run found a collapse whose motion grew when followed (a motion that was
    not confirmed may still stop: it is no collapse), and its last stable multiplier is below
    the upper bound (a state at rest with Coulomb contacts is statically admissible)."""
    exp, lim = ctx.ok("explicit"), ctx.ok("limit-vertex")
    if exp is None:
        return []
    v = exp.values
    stable, moving = v["lambda_stable"], v["lambda_moving"]
    confirmed = v["collapsed"] and v["mechanism_confirmed"]
    bracket = f"bracket ({stable:.4g}, {moving if moving is None else f'{moving:.4g}'}]"
    detail = bracket
    if v["collapsed"] and not confirmed:
        detail += (
            f"; the motion at {moving:.4g} is not confirmed: it did not grow when followed and "
            "may still stop, so it is no collapse"
        )
    out = [Check("explicit run collapsed", PASS if confirmed else FAIL, moving, None, detail)]
    if lim is not None and math.isfinite(lim.values["upper"]):
        upper = lim.values["upper"]
        ok = _le(stable, upper, rtol, _unit(lim))
        out.append(
            Check(
                "explicit lambda_stable <= upper (vertex)",
                PASS if ok else FAIL,
                stable,
                upper,
                bracket,
            )
        )
    return out + _explicit_vs_static(ctx, stable, moving, confirmed, agree_rtol)


def _explicit_vs_static(
    ctx: Context, stable, moving, confirmed: bool, agree_rtol: float
) -> list[Check]:
    """The static DEM's collapse multiplier lies in the explicit bracket, widened by
    ``agree_rtol`` (two DEM models of the same joints); a bracket whose upper end is a motion
    that was not confirmed is no agreement, and the line does not apply."""
    out = []
    for law in MODEL_OF_LAW:
        dem = ctx.ok(f"dem-{law}")
        if dem is None or not dem.values["collapsed"] or moving is None:
            continue
        lam = dem.values["lambda_max"]
        name = f"explicit bracket holds the static DEM {law}"
        if not confirmed:
            detail = (
                f"static DEM {lam:.4g}; the explicit motion at {moving:.4g} is not confirmed "
                "(line 'explicit run collapsed'): its bracket is no agreement"
            )
            out.append(Check(name, NA, lam, moving, detail))
            continue
        ok = stable * (1 - agree_rtol) <= lam <= moving * (1 + agree_rtol)
        detail = (
            f"static DEM {lam:.4g} against the bracket ({stable:.4g}, {moving:.4g}] widened by "
            f"{agree_rtol:.0%} on each side"
        )
        if lam > moving * (1 + agree_rtol):
            detail += EXPLICIT_BELOW
        out.append(Check(name, PASS if ok else FAIL, lam, moving, detail))
    return out


def fem_checks(ctx: Context) -> list[Check]:
    fem = ctx.ok("fem")
    if fem is None:
        return []
    v = fem.values
    worst, tol = v["max_residual"], v["residual_tolerance"]
    if worst is None:
        return [Check("FEM residual small", NA, detail="no free block solved")]
    ok = worst <= tol and not v["not_in_equilibrium"]
    detail = f"state {fem.settings['state']}, {v['n_solved']} blocks solved"
    if v["not_in_equilibrium"]:
        detail += f"; blocks out of equilibrium: {v['not_in_equilibrium']}"
    out = [
        Check(
            "FEM residual small (DEM state in equilibrium)",
            PASS if ok else FAIL,
            worst,
            tol,
            detail,
        )
    ]
    if v.get("not_meshed"):
        out.append(Check("FEM meshed every free block", FAIL, detail=fem.reason))
    return out


def verdict(ctx: Context, rtol: float = 1e-3, agree_rtol: float = 0.05) -> list[Check]:
    """Every consistency check of a finished cross-check, in report order.

    Parameters
    ----------
    ctx : Context
    rtol : float
        Relative slack of the inequalities (solver tolerances and plateau noise) [-].
    agree_rtol : float
        Largest relative difference of the two DEM laws called agreement [-].
    """
    return [
        *_tagged(dead_load_checks(ctx), "dead-load"),
        *step_checks(ctx),
        *limit_checks(ctx, rtol),
        *dem_checks(ctx, rtol),
        *agreement_check(ctx, agree_rtol),
        *_tagged(explicit_checks(ctx, rtol, agree_rtol), "explicit"),
        *_tagged(fem_checks(ctx), "fem"),
    ]
