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
  at rest and its rigid-limit continuation lie below the upper bound, and it agrees with the
  static DEM;
- every block of the DEM collapse state is in equilibrium (FEM residual).

Every number is compared with its error bar (:class:`~dem.estimate.Estimate`, from the
method that made it, :func:`validation.crosscheck.steps.estimate_of`). An inequality
``a <= b`` holds when ``a - error_a <= b + error_b``; where a bar is not estimated, with the
slack ``rtol`` (solver tolerances), and the line says so. Two results agree when their
intervals overlap; where a bar is not estimated, agreement cannot be judged and the line does
not apply. A difference that is a modelling choice is named and measured on the scene, never
hidden in a tolerance: the two interface models (the resultant law's seed 001 Eq. A5 domain
against the exact one of the fibres) by the gap between their associated upper bounds, and
the explicit DEM's finite joint stiffness (against rigid blocks) by its continuation in joint
stiffness towards the rigid limit (``values["estimates"]["lambda_rigid"]`` of the explicit
step).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

from dem.estimate import Estimate
from validation.crosscheck.limit_steps import WHY_NONE
from validation.crosscheck.steps import Context, StepResult, estimate_of

MODEL_OF_LAW = {"fibre": "vertex", "resultant": "resultant"}
"""The limit-analysis interface model that matches each DEM interface law."""
PASS, FAIL, NA = "pass", "fail", "n/a"
EXPLICIT_BELOW = (
    "; the explicit DEM follows large displacements with the material's joint stiffness, the "
    "static DEM small ones with rigid blocks: a structure that deforms before it collapses (an "
    "arch, a vault) carries less in the explicit run, the more so the softer its joints; the "
    "continuation in joint stiffness towards the rigid limit measures that model difference"
)
"""What a failed agreement adds when the explicit run collapsed below the static DEM and no
rigid-limit continuation measured the stiffness effect."""


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
    value_error, bound_error : float or None
        Half-widths of the error bars of ``value`` and ``bound`` (``inf``: not estimated).
    """

    name: str
    status: str
    value: float | None = None
    bound: float | None = None
    detail: str = ""
    step: str = ""
    value_error: float | None = None
    bound_error: float | None = None

    def to_dict(self) -> dict:
        return asdict(self)


def _check(name: str, ok: bool | None, a: Estimate | None, b: Estimate | None, detail: str):
    """A line comparing ``a`` with ``b`` (None: does not apply)."""
    status = NA if ok is None else PASS if ok else FAIL
    return Check(
        name,
        status,
        None if a is None else a.value,
        None if b is None else b.value,
        detail,
        value_error=None if a is None else a.error,
        bound_error=None if b is None else b.error,
    )


def _tagged(checks: list[Check], step: str) -> list[Check]:
    return [replace(c, step=step) for c in checks]


def _known(*estimates: Estimate) -> bool:
    return all(math.isfinite(e.error) for e in estimates)


def at_most(a: Estimate, b: Estimate, rtol: float, unit: float = 1.0) -> tuple[bool, str]:
    """``a <= b`` by the error bars (``a.lo <= b.hi``); where a bar is unknown, ``a <= b``
    up to ``rtol`` relative to ``|b|`` (and ``rtol * unit`` near zero, with ``unit`` the limit
    programme's scale of lambda). Returns the answer and how it was decided."""
    if not math.isfinite(b.value):
        return True, ""
    if _known(a, b):
        return a.lo <= b.hi, ""
    ok = a.value <= b.value + rtol * max(abs(b.value), unit)
    return ok, f"a bar is not estimated: compared with the slack rtol = {rtol:g}"


def overlap(a: Estimate, b: Estimate) -> bool | None:
    """Whether two results agree (their intervals overlap); None when a bar is unknown."""
    return a.overlaps(b) if _known(a, b) else None


def _unit(lim) -> float:
    """The scale of lambda of a limit step (1 when it has none)."""
    return 1.0 if lim is None else float(lim.values.get("lam_unit", 1.0))


def _join(*parts: str) -> str:
    return "; ".join(p for p in parts if p)


def dead_load_checks(ctx: Context) -> list[Check]:
    """The scene stands: :func:`limit.stands`' certified decision (its carried fraction of the
    dead load, with the solver's bar, reaches the cap 1 to within ``limit.deadload.STANDS_TOL``)."""
    res = ctx.ok("dead-load")
    if res is None:
        step = ctx.results.get("dead-load")
        return [Check("stands under its dead load", NA, detail=step.reason if step else "not run")]
    v = res.values
    detail = res.reason
    if not v["stands"] and v["blocks"]:
        detail += f" Blocks {v['blocks'][:20]} and interfaces {v['interfaces'][:20]} move most."
    carried = estimate_of(res, "load_factor")
    cap = Estimate(1.0, {"exact": 0.0})
    return [_check("stands under its dead load", bool(v["stands"]), carried, cap, detail)]


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
    upper, lower, unit = estimate_of(res, "upper"), estimate_of(res, "lower"), _unit(res)
    out = []
    if lower is None:
        out.append(_check(f"lower <= upper ({model})", None, None, upper, v["lower_note"]))
    else:
        ok, how = at_most(lower, upper, rtol, unit)
        out.append(_check(f"lower <= upper ({model})", ok, lower, upper, how))
    for label, key in (("estimate mu*", "reduced_mu"), ("estimate (b)", "iterative")):
        name, est = f"{label} within bounds ({model})", estimate_of(res, key)
        if est is None:
            why = v.get(WHY_NONE[key])
            out.append(Check(name, NA, detail=why or "not computed"))
        elif key == "iterative" and not v["iterative_admissible"]:
            detail = "last iterate not admissible: not bounded by the upper bound"
            out.append(_check(name, None, est, upper, detail))
        else:
            ok, how = at_most(est, upper, rtol, unit)
            if lower is not None:
                ok_low, how_low = at_most(lower, est, rtol, unit)
                ok, how = ok and ok_low, how or how_low
            where = "no lower bound" if lower is None else f"lower {lower.format()}"
            out.append(_check(name, ok, est, upper, _join(where, how)))
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
    lam = estimate_of(res, "lambda_max")
    lim = ctx.ok(f"limit-{model}")
    upper = None if lim is None else estimate_of(lim, "upper")
    name = f"DEM {law} law collapsed"
    detail = f"termination: {v['termination']}"
    if lim is not None and upper is None:
        # no mechanism exists (associated upper bound unbounded): none is expected, and a
        # run without one is no collapse to check
        detail += f"; the limit analysis ({model}) finds no mechanism, so none is expected"
        return [_check(name, None, lam if v["collapsed"] else None, None, detail)]
    out = [_check(name, bool(v["collapsed"]), lam, None, detail)]
    if upper is None or lam is None:
        return out
    ok, how = at_most(lam, upper, rtol, _unit(lim))
    ratio = f"lambda_DEM / upper = {lam.value / upper.value:.4f}" if upper.value else ""
    out.append(_check(f"DEM {law} <= upper ({model})", ok, lam, upper, _join(ratio, how)))
    lower = estimate_of(lim, "lower")
    if lower is not None:
        ok, how = at_most(lower, lam, rtol, _unit(lim))
        out.append(_check(f"lower ({model}) <= DEM {law}", ok, lam, lower, how))
    return out


def interface_model_difference(ctx: Context) -> Estimate | None:
    """Upper bound of the vertex model minus that of the resultant model on this scene, with
    both bars: how much the resultant law's Eq. A5 domain moves the collapse multiplier against
    the exact domain of the fibres (None when a limit step is missing or unbounded)."""
    vertex = estimate_of(ctx.ok("limit-vertex"), "upper")
    resultant = estimate_of(ctx.ok("limit-resultant"), "upper")
    if vertex is None or resultant is None:
        return None
    sources = {f"vertex {k}": w for k, w in vertex.sources.items()}
    sources.update({f"resultant {k}": w for k, w in resultant.sources.items()})
    return Estimate(vertex.value - resultant.value, sources)


def agreement_check(ctx: Context) -> list[Check]:
    """The two DEM laws agree: their intervals overlap, directly or once the difference of the
    interface models measured on this scene (:func:`interface_model_difference`) is added to
    the resultant law's value."""
    fib, res = ctx.ok("dem-fibre"), ctx.ok("dem-resultant")
    if fib is None or res is None:
        return []
    name = "the two DEM laws agree"
    if not (fib.values["collapsed"] or res.values["collapsed"]):
        # both ended without a collapse (e.g. no mechanism exists): they agree that none came
        # within the run, and their last multipliers are no collapse loads to compare
        detail = (
            f"neither law collapsed (fibre: {fib.values['termination']}, resultant: "
            f"{res.values['termination']}): no collapse multipliers to compare"
        )
        return [Check(name, NA, detail=detail)]
    a, b = estimate_of(fib, "lambda_max"), estimate_of(res, "lambda_max")
    if a is None or b is None:
        return [Check(name, NA, detail="no finite pair of multipliers")]
    pair = f"fibre {a.format()}, resultant {b.format()}"
    direct = overlap(a, b)
    if direct is None:
        why = "a DEM law gives no error bar: agreement cannot be judged"
        return [_check(name, None, a, b, _join(pair, why))]
    if direct:
        return [_check(name, True, a, b, _join(pair, "the intervals overlap"))]
    model = interface_model_difference(ctx)
    if model is not None:
        shifted = Estimate(b.value + model.value, {**b.sources, **model.sources})
        if overlap(a, shifted):
            why = (
                f"the interface models differ by {model.format()} on this scene (upper bound "
                "of the vertex model minus that of the resultant model: seed 001 Eq. A5 domain "
                "against the exact one); with it the intervals overlap"
            )
            return [_check(name, True, a, shifted, _join(pair, why))]
    return [_check(name, False, a, b, _join(pair, *_disagreement(ctx, fib, res, model)))]


def _disagreement(ctx: Context, fib: StepResult, res: StepResult, model) -> list[str]:
    """Why the two DEM laws differ beyond their bars and the interface models' difference."""
    why = []
    for step in (fib, res):
        if not step.values["collapsed"]:
            why.append(f"{step.name} ended by {step.values['termination']}, not a collapse")
    for law, step in (("fibre", fib), ("resultant", res)):
        upper = estimate_of(ctx.ok(f"limit-{MODEL_OF_LAW[law]}"), "upper")
        if upper is not None and upper.value > 0:
            lam = step.values["lambda_max"]
            why.append(f"{law} {lam:.6g} = {lam / upper.value:.0%} of its upper bound")
    vertex = estimate_of(ctx.ok("limit-vertex"), "upper")
    if model is not None and vertex is not None and vertex.value:
        share = model.value / vertex.value
        why.append(
            f"the interface models differ by {model.format()} only ({share:.1%} of the vertex "
            "model's upper bound): the rest "
            "comes from the DEM path (possible causes: non-associated friction makes the "
            "collapse depend on the elastic path; the resultant law's friction domain (seed 001 "
            "Eq. A5 on the reduced rectangle) is not the springs' one)"
        )
    return why


def explicit_checks(ctx: Context, rtol: float) -> list[Check]:
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
    # the line shows the collapse multiplier at the material stiffness with its bar
    collapse = explicit_estimate(exp) if v["collapsed"] else None
    out = [_check("explicit run collapsed", confirmed, collapse, None, detail)]
    upper = estimate_of(lim, "upper")
    rest = estimate_of(exp, "lambda_stable")
    if upper is not None and rest is not None:
        ok, how = at_most(rest, upper, rtol, _unit(lim))
        name = "explicit lambda_stable <= upper (vertex)"
        resisting = "" if ok else v.get("resisting", "")
        out.append(_check(name, ok, rest, upper, _join(bracket, how, resisting)))
    rigid = estimate_of(exp, "lambda_rigid")
    if upper is not None and rigid is not None and confirmed:
        # rigid blocks with Coulomb friction: the associated multiplier bounds the collapse
        ok, how = at_most(rigid, upper, rtol, _unit(lim))
        detail = _join(f"rigid limit of the explicit run {rigid.format()}", how)
        out.append(_check("explicit rigid limit <= upper (vertex)", ok, rigid, upper, detail))
    return out + _explicit_vs_static(ctx, exp, confirmed)


def explicit_estimate(exp: StepResult) -> Estimate | None:
    """The explicit DEM's collapse multiplier at the material joint stiffness: the step's own
    estimate (``lambda_c``) when it gives one, else the bracket ``(stable, moving]`` whose
    other error sources (time step, loading rate, node spacing) are not estimated."""
    given = estimate_of(exp, "lambda_c")
    if given is not None:
        return given
    stable, moving = exp.values["lambda_stable"], exp.values["lambda_moving"]
    if moving is None:
        return None
    half = 0.5 * (moving - stable)
    sources = {"load-step bracket": half, "time step, rate, node spacing": math.inf}
    return Estimate(stable + half, sources, notes="the explicit bracket")


def _explicit_vs_static(ctx: Context, exp: StepResult, confirmed: bool) -> list[Check]:
    """The explicit DEM agrees with the static DEM: the rigid-limit continuation of the
    explicit run (rigid blocks, as the static DEM's model) overlaps the static multiplier; the
    finite-stiffness difference is named and measured. Without a continuation the value at the
    material stiffness is compared, and a gap is put to the finite stiffness in words."""
    out = []
    material, rigid = explicit_estimate(exp), estimate_of(exp, "lambda_rigid")
    for law in MODEL_OF_LAW:
        dem = ctx.ok(f"dem-{law}")
        lam = estimate_of(dem, "lambda_max")
        if dem is None or not dem.values["collapsed"] or material is None or lam is None:
            continue
        name = f"explicit DEM agrees with the static DEM {law}"
        if not confirmed:
            detail = (
                f"static DEM {lam.format()}; the explicit motion is not confirmed (line "
                "'explicit run collapsed'): its bracket is no agreement"
            )
            out.append(_check(name, None, material, lam, detail))
        elif rigid is not None:
            out.append(_rigid_line(name, material, rigid, lam))
        else:
            ok = overlap(material, lam)
            detail = f"explicit, material stiffness {material.format()}; static {lam.format()}"
            if ok is None:
                detail += "; the explicit DEM's error is not estimated: agreement cannot be judged"
            if ok is not True and material.value < lam.lo:
                detail += EXPLICIT_BELOW
            out.append(_check(name, ok, material, lam, detail))
    return out


def _rigid_line(name: str, material: Estimate, rigid: Estimate, lam: Estimate) -> Check:
    ok = overlap(rigid, lam)
    shift = rigid.value - material.value
    detail = (
        f"rigid limit of the explicit run {rigid.format()} against the static DEM "
        f"{lam.format()}; at the material joint stiffness {material.format()}: finite "
        f"stiffness (a model difference, measured by the continuation on this scene) lowers it "
        f"by {shift:.4g} ({shift / rigid.value:.1%} of the rigid limit)"
    )
    if ok is None:
        detail += "; a bar is not estimated: agreement cannot be judged"
    return _check(name, ok, rigid, lam, detail)


def fem_checks(ctx: Context) -> list[Check]:
    """Every free block of the DEM state is in equilibrium: its relative load imbalance, with
    the round-off bound of its computation as the bar, is at most the FEM check's tolerance."""
    fem = ctx.ok("fem")
    if fem is None:
        return []
    v = fem.values
    if v["max_residual"] is None:
        return [Check("FEM residual small", NA, detail="no free block solved")]
    worst = Estimate(v["max_residual"], {"round-off": v["max_residual_round_off"]})
    tol = Estimate(v["residual_tolerance"], {"exact": 0.0})
    ok = worst.lo <= tol.value and not v["not_in_equilibrium"]
    detail = f"state {fem.settings['state']}, {v['n_solved']} blocks solved"
    if v["not_in_equilibrium"]:
        detail += f"; blocks out of equilibrium: {v['not_in_equilibrium']}"
    out = [_check("FEM residual small (DEM state in equilibrium)", ok, worst, tol, detail)]
    if v.get("not_meshed"):
        out.append(Check("FEM meshed every free block", FAIL, detail=fem.reason))
    return out


def verdict(ctx: Context, rtol: float = 1e-3) -> list[Check]:
    """Every consistency check of a finished cross-check, in report order.

    Parameters
    ----------
    ctx : Context
    rtol : float
        Relative slack of the inequalities whose error bars are not estimated (solver
        tolerances) [-]; where both bars are known they decide.
    """
    return [
        *_tagged(dead_load_checks(ctx), "dead-load"),
        *step_checks(ctx),
        *limit_checks(ctx, rtol),
        *dem_checks(ctx, rtol),
        *agreement_check(ctx),
        *_tagged(explicit_checks(ctx, rtol), "explicit"),
        *_tagged(fem_checks(ctx), "fem"),
    ]
