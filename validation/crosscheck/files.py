"""``report.md`` and ``report.json`` of a cross-check, with its VTU files and pictures."""

from __future__ import annotations

import datetime
import json
import math
from pathlib import Path

from dem.estimate import Estimate, format_estimate
from dem.geometry.interfaces import pair_list
from dem.scene import Scene
from validation.crosscheck.html_report import write_html_report
from validation.crosscheck.limit_steps import WHY_NONE
from validation.crosscheck.pictures import (
    PictureOptions,
    draw_pictures,
    write_mechanism_view,
    write_vtus,
)
from validation.crosscheck.pushover import zero_lower_note
from validation.crosscheck.steps import Context
from validation.report import _fmt, _git_commit, _jsonable, _versions

BLOCK_ROWS = 20
"""Blocks listed in the FEM table of ``report.md``."""

MULTIPLIERS = (
    ("limit-vertex", "upper", "upper bound, associated (vertex model)"),
    ("limit-vertex", "reduced_mu", "estimate (a) mu* (vertex model)"),
    ("limit-vertex", "iterative", "estimate (b) fixed capacities (vertex model)"),
    ("limit-vertex", "lower", "lower bound, frictionless (vertex model)"),
    ("limit-resultant", "upper", "upper bound, associated (resultant model)"),
    ("limit-resultant", "reduced_mu", "estimate (a) mu* (resultant model)"),
    ("limit-resultant", "iterative", "estimate (b) fixed capacities (resultant model)"),
    ("limit-resultant", "lower", "lower bound, frictionless (resultant model)"),
    ("dem-fibre", "lambda_max", "static DEM, fibre law"),
    ("dem-resultant", "lambda_max", "static DEM, resultant law"),
    ("explicit", "lambda_stable", "explicit DEM, last stable lambda"),
    ("explicit", "lambda_moving", "explicit DEM, first moving lambda"),
)


def write_report(
    scene: Scene, ctx: Context, result, out: Path, pictures: bool | PictureOptions
) -> dict:
    """Write every file of a cross-check into ``out`` and return their paths by key
    (``pictures``: False for none, True or a :class:`PictureOptions` to draw them)."""
    out.mkdir(parents=True, exist_ok=True)
    files = write_vtus(scene, ctx, out)
    view, why_not = None, "no pictures were asked for (--no-pictures)"
    if pictures:
        options = pictures if isinstance(pictures, PictureOptions) else PictureOptions()
        drawn = draw_pictures(scene, ctx, out, files, options)
        files.update({f"{k}_png": v for k, v in drawn.items()})
        view, why_not = write_mechanism_view(scene, ctx, out / "mechanism_3d.html", options)
        if view is not None:
            files["mechanism_3d"] = str(view)
    files["report_json"] = str(out / "report.json")
    files["report_md"] = str(out / "report.md")
    files["report_html"] = str(out / "report.html")
    payload = {
        "scene": result.scene,
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "git_commit": _git_commit(),
        "versions": _versions(),
        "consistent": result.consistent,
        "checks": [c.to_dict() for c in result.checks],
        "steps": [s.to_dict() for s in result.steps],
        "files": {k: Path(v).name for k, v in files.items()},
    }
    Path(files["report_json"]).write_text(json.dumps(_jsonable(payload), indent=1) + "\n")
    text = markdown(result, files, payload) + "\n"
    Path(files["report_md"]).write_text(text)
    write_html_report(text, Path(files["report_html"]), view, why_not)
    return files


def _table(header: list[str], rows: list[list]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
    return lines


def _cell(value) -> str:
    """A table cell: an estimate as ``value ± error`` rounded to the digits its error
    supports (:func:`dem.estimate.format_estimate`), a bare float to 4 significant digits
    (no error known: more would claim digits nobody checked)."""
    if isinstance(value, Estimate):
        return value.format()
    if isinstance(value, dict) and {"value", "error"} <= value.keys():
        return format_estimate(float(value["value"]), float(value["error"]))
    if isinstance(value, float):
        return f"{value:.4g}"
    return _fmt(value)


def _with_bar(value, error):
    """A checked value with its method's error bar where it has one (a dict for
    :func:`_cell`), else the bare value."""
    if value is None or error is None:
        return value
    return {"value": value, "error": error}


def _multipliers(result) -> list[list]:
    steps = {s.name: s for s in result.steps}
    rows = []
    for name, key, label in MULTIPLIERS:
        step = steps.get(name)
        if step is None or not step.ok or key not in step.values:
            continue
        note = step.values.get("termination", "")
        if key in WHY_NONE and step.values[key] is None:
            note = step.values.get(WHY_NONE[key], "")
        if key == "lower" and step.values[key] == 0.0:
            note = zero_lower_note(result.scene["live_resultant_N"])
        if key == "iterative" and step.values.get("iterative") is not None:
            note = (
                f"converged {step.values['iterative_converged']}, "
                f"admissible {step.values['iterative_admissible']}"
            )
        value = step.values.get("estimates", {}).get(key) or step.values[key]
        rows.append([label, value, note])
    return rows


def markdown(result, files: dict, payload: dict) -> str:
    """The human report: scene, verdict, multipliers, FEM, steps, files, settings."""
    lines = [
        *_scene_lines(result, payload),
        "",
        "## In short",
        "",
        *in_short(result),
        "",
        "## Verdict",
        "",
        *_verdict_table(result),
        "",
        "## Load multipliers",
        "",
        *_table(["quantity", "lambda", "note"], _multipliers(result)),
        "",
        *_fem_lines(result),
        "## Steps",
        "",
        *_table(
            ["step", "method", "status", "wall [s]", "reason"],
            [[x.name, x.method, x.status, x.wall_s, x.reason] for x in result.steps],
        ),
        "",
        "## Files",
        "",
        *[f"- `{Path(v).name}` ({k})" for k, v in files.items()],
        "",
        *[f"![{k}]({Path(v).name})" for k, v in files.items() if k.endswith("_png")],
        "",
        "## Settings of every step",
        "",
        *[f"- {x.name}: `{json.dumps(_jsonable(x.settings))}`" for x in result.steps],
    ]
    return "\n".join(lines)


def _scene_lines(result, payload: dict) -> list[str]:
    """Title, commit, verdict and the scene in one paragraph, with its edge contacts and
    warnings."""
    s = result.scene
    verdict = "consistent" if result.consistent else "INCONSISTENT (see the failed lines)"
    return [
        f"# Cross-check of `{s['name']}`",
        "",
        f"commit `{payload['git_commit'][:12]}`, {payload['date']}; verdict: **{verdict}**",
        "",
        f"{s['n_blocks']} blocks ({s['n_free']} free, {s['n_fixed']} fixed, "
        f"{s['n_restrained_dofs']} restrained dofs), {s['n_interfaces']} interfaces; weight of "
        f"the free blocks {s['weight_free_N'] / 1e3:.4g} kN; live load per unit lambda "
        f"{[round(v / 1e3, 4) for v in s['live_resultant_N']]} kN; extent "
        f"{[round(v, 4) for v in s['extent_m']]} m; friction {s['mu']}.",
        *_edge_contacts(s.get("edge_contacts", [])),
        *_warnings(s.get("meta", {}).get("warnings", []) + list(result.warnings)),
    ]


def _verdict_table(result) -> list[str]:
    """One row per check: its status, value and bound (with error bars) and detail."""
    return _table(
        ["check", "result", "value", "bound", "detail"],
        [
            [c.name, c.status, _with_bar(c.value, c.value_error),
             _with_bar(c.bound, c.bound_error), c.detail]
            for c in result.checks
        ],
    )  # fmt: skip


def _fem_lines(result) -> list[str]:
    """The section on block stresses at the DEM collapse state, or nothing if the FEM step
    did not run (or failed)."""
    fem = next((x for x in result.steps if x.name == "fem" and x.ok), None)
    if fem is None:
        return []
    title = ["## Block stresses at the DEM collapse state (FEM)", ""]
    if not fem.values["n_solved"]:
        return [
            *title,
            f"No block was solved at the state {fem.settings['state']} (lambda = "
            f"{fem.settings['lambda']:.4g}): {_none_solved(fem)}.",
            "",
        ]
    v = fem.values
    listed = _most_stressed(v["blocks"], v["residual_tolerance"])
    return [
        *title,
        f"State {fem.settings['state']} at lambda = {fem.settings['lambda']:.4g}; largest "
        f"tension {_stress(v, 'max_tension_Pa')} MPa (block {v['max_tension_block']}), largest "
        f"compression {_stress(v, 'max_compression_Pa')} MPa (block "
        f"{v['max_compression_block']}); largest equilibrium residual "
        f"{_cell(v['max_residual'])} (tolerance {v['residual_tolerance']:g}). "
        f"E = {fem.settings['young'] / 1e9:g} GPa is "
        "a placeholder: the stresses of a statically determinate block do not depend on it.",
        "",
        *_table(
            ["block", "residual", "max principal [MPa]", "min principal [MPa]"],
            [[b["block"], b["residual"], _mpa(b.get("max_principal")),
              _mpa(b.get("min_principal"))] for b in listed],
        ),
        "",
        f"The {min(len(v['blocks']), BLOCK_ROWS)} most stressed or least balanced blocks of "
        f"{len(v['blocks'])}; every block is in `report.json`.",
        "",
    ]  # fmt: skip


def _none_solved(fem) -> str:
    """Why the FEM step solved no block."""
    v = fem.values
    why = [fem.reason] if fem.reason else []
    if v["not_in_equilibrium"]:
        why.append(
            f"blocks {v['not_in_equilibrium']} are out of equilibrium (residual above "
            f"{v['residual_tolerance']:g}): not solved"
        )
    return "; ".join(why) or "the scene has no free block"


def _value(result, step: str, key: str):
    found = [s for s in result.steps if s.name == step and s.ok]
    return found[0].values.get(key) if found else None


def in_short(result) -> list[str]:
    """The few sentences an engineer reads first: stands, bounds, DEM, mechanism, stresses."""
    out = []
    stands = _value(result, "dead-load", "stands")
    if stands is not None:
        out.append(f"- Under its dead load the structure {'stands' if stands else 'FALLS'}.")
    upper, lower = _value(result, "limit-vertex", "upper"), _value(result, "limit-vertex", "lower")
    if upper is not None and not math.isfinite(upper):
        out.append(
            "- Rigid blocks with Coulomb joints: no collapse mechanism, the live load is "
            "carried for every multiplier (limit analysis, unbounded)."
        )
    elif upper is not None:
        if lower == 0.0:
            why = zero_lower_note(result.scene["live_resultant_N"])
            span = f"at most {upper:.4g} (proven upper bound; the lower bound {why})"
        elif lower is not None:
            span = f"between {lower:.4g} and {upper:.4g} (proven bounds)"
        else:
            note = _value(result, "limit-vertex", "lower_note")
            span = f"at most {upper:.4g} (proven upper bound; {note})"
        out.append(
            f"- Rigid blocks with Coulomb joints (vertex model): collapse multiplier {span}."
        )
    dem = [
        (
            law,
            _value(result, f"dem-{law}", "lambda_max"),
            _value(result, f"dem-{law}", "termination"),
        )
        for law in ("fibre", "resultant")
    ]
    dem = [f"{law} law {lam:.4g} ({end})" for law, lam, end in dem if lam is not None]
    if dem:
        out.append(f"- Static DEM: {', '.join(dem)}.")
    stable, moving = (
        _value(result, "explicit", "lambda_stable"),
        _value(result, "explicit", "lambda_moving"),
    )
    if stable is not None:
        if moving is None:
            end = "no motion found."
        elif _value(result, "explicit", "mechanism_confirmed"):
            end = f"moving at {moving:.4g}."
        else:
            end = (
                f"moving at {moving:.4g}, not confirmed (the motion did not grow when followed "
                "and may still stop)."
            )
        out.append(f"- Explicit DEM: at rest up to lambda = {stable:.4g}, {end}")
    d = result.scene.get("live_weight_direction")
    if d is not None:
        out.append(
            f"- The live load is each block's weight along {[round(c, 3) for c in d]}: "
            "lambda is the uniform acceleration in g the structure carries along it (for a "
            "horizontal direction, an equivalent static seismic coefficient)."
        )
    moving = _value(result, "limit-vertex", "moving_blocks")
    if moving:
        more = f" and {len(moving) - 20} more" if len(moving) > 20 else ""
        out.append(f"- Mechanism (limit analysis): blocks {moving[:20]}{more} move.")
    tension = _value(result, "fem", "max_tension_Pa")
    if tension is not None:
        comp = _value(result, "fem", "max_compression_Pa")
        out.append(
            f"- At the DEM state of lambda_max the largest tension in a block is "
            f"{tension / 1e6:.3g} MPa and the largest compression {-comp / 1e6:.3g} MPa."
        )
    failed = sum(c.status == "fail" for c in result.checks)
    out.append(
        f"- The methods are {'consistent' if not failed else 'NOT consistent'} "
        f"({failed} failed check{'s' if failed != 1 else ''}; see the verdict)."
    )
    return out


def _most_stressed(blocks: list[dict], tol: float) -> list[dict]:
    """The ``BLOCK_ROWS`` blocks out of equilibrium (residual above ``tol``) or with the
    largest stress magnitude, in block order."""

    def key(b: dict) -> tuple:
        stress = max(abs(b.get("max_principal") or 0.0), abs(b.get("min_principal") or 0.0))
        return (b["residual"] > tol, stress)

    ranked = sorted(blocks, key=key, reverse=True)[:BLOCK_ROWS]
    return sorted(ranked, key=lambda b: b["block"])


def _stress(values: dict, key: str) -> str:
    """A stress of a step's values in MPa, with its error bar where the step has one."""
    found = values.get("estimates", {}).get(key)
    if isinstance(found, dict) and {"value", "error"} <= found.keys():
        return format_estimate(float(found["value"]) / 1e6, float(found["error"]) / 1e6)
    return _cell(_mpa(values[key]))


def _mpa(value) -> float | None:
    return None if value is None else value / 1e6


def _edge_contacts(pairs: list) -> list[str]:
    """A line on the block pairs that touch only along an edge or at a corner, if any."""
    if not pairs:
        return []
    return [
        "",
        f"{len(pairs)} pair{'s' if len(pairs) > 1 else ''} of blocks "
        f"touch{'es' if len(pairs) == 1 else ''} only along an edge or at a corner "
        f"({pair_list(pairs, 10)}): the static DEM and the limit analysis carry no force there "
        "(face interfaces only); the explicit DEM's nodes do.",
    ]


def _warnings(messages: list[str]) -> list[str]:
    """The warnings of reading the scene and of the run, which did not stop it."""
    if not messages:
        return []
    return ["", "## Warnings", "", *[f"- {m}" for m in messages]]
