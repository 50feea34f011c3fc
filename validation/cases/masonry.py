"""Static DEM to collapse against seed 001 Tables 1-3 (Baraldi & Cecchi).

Three cases:

- ``masonry-orduna``: Table 1, the two dry-joint panels of Orduna & Lourenco (2005b);
- ``masonry-restrepo``: Table 2, the Restrepo-Velez et al. (2014) tilting-table specimens, with
  the return walls as the seed models them (a fixed column) and built as blocks;
- ``masonry-chee-liang``: Table 3, the mortared walls of Chee Liang (1996) under pressure.

Each row is one collapse analysis (interface model x support variant) with the seed's DEM
value and the reference values of the table. Each run also leaves an ``.npz`` (pushover,
mechanism, interface states) and the scene as JSON under ``validation/results/masonry/`` for
the figures. The ``masonry-orduna`` case writes ``validation/results/masonry-collapse-state.npz``
(3 x 13 panel, resultant model) for the FEM check.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from dem.scenes.seed001_walls import (
    CHEE_LIANG_NAMES,
    RESTREPO_NAMES,
    SPECIMENS,
    SeedSpecimen,
)
from dem.static import StaticResult, StaticSettings, StaticSolverError, solve_collapse
from dem.units import MPA, N_MM3
from validation.report import RESULTS_DIR, Row

logger = logging.getLogger(__name__)

RUN_DIR = RESULTS_DIR / "masonry"
COLLAPSE_STATE = RESULTS_DIR / "masonry-collapse-state.npz"
SEED_TABLE2_MEAN_ERROR = 0.096  # the seed's own DEM over Table 2 (mean |DEM - exp| / exp)


def _settings(spec: SeedSpecimen, model: str, quick: bool) -> StaticSettings:
    joint = spec.joint
    kw: dict = {"interface_model": model, "mu": joint.mu, "on_failure": "return"}
    if joint.tensile_strength_mpa > 0:
        kw["tensile_strength"] = joint.tensile_strength_mpa * MPA
    if joint.kn_n_mm3 is not None:
        kw["kn"] = joint.kn_n_mm3 * N_MM3
    if joint.kt_n_mm3 is not None:
        kw["kt"] = joint.kt_n_mm3 * N_MM3
    if spec.table == "Table 3":
        # the bottom edge is a simple support: a dry hinge on the foundation
        kw["tension_at_supports"] = False
        kw["load_step"] = 0.2 if quick else 0.05
        # brittle peaks: keep the control increments within 30 first increments
        kw["max_step_factor"] = 30.0
        if model == "fibre":
            kw["fibre_points"] = 3 if quick else 4
    if quick:
        kw["max_steps"] = 150
    return StaticSettings(**kw)


def _save_run(tag: str, scene, result: StaticResult) -> str:
    RUN_DIR.mkdir(parents=True, exist_ok=True)
    scene_path = RUN_DIR / f"{tag}.scene.json"
    scene.to_json(scene_path)
    np.savez_compressed(
        RUN_DIR / f"{tag}.npz",
        pushover_lambda=result.pushover_lambda,
        pushover_control=result.pushover_control,
        pushover_monitor=result.pushover_monitor,
        monitor=np.array(result.monitor),
        lambda_max=result.lambda_max,
        mechanism=result.mechanism,
        displacements=result.displacements,
        interface_state=result.interface_state,
        interface_state_at_peak=result.interface_state_at_peak,
        interface_forces=result.interface_forces,
        block_a=result.block_a,
        block_b=result.block_b,
        scene_json=str(scene_path.relative_to(RESULTS_DIR.parent.parent)),
    )
    return str(scene_path)


def _row(
    spec: SeedSpecimen, model: str, variant: str, quick: bool, scale: float = 1.0
) -> tuple[Row, StaticResult | None, object]:
    """One analysis; ``scale`` converts lambda to the table's unit (Pa -> kN/m^2)."""
    if variant.startswith("blocks_") and spec.builder == "restrepo_specimen":
        # sensitivity to the assumed return-wall length: "blocks_6" = 6 blocks long
        scene = spec.build(return_walls="blocks", return_blocks=int(variant.split("_")[1]))
    elif spec.builder in ("restrepo_specimen", "orduna_panel") and variant != "none":
        scene = spec.build(return_walls=variant)
    else:
        scene = spec.build()
    settings = _settings(spec, model, quick)
    start = time.perf_counter()
    result: StaticResult | None = None
    error = ""
    try:
        result = solve_collapse(scene, settings)
    except StaticSolverError as exc:
        error = str(exc)
        logger.warning("%s %s %s: %s", spec.key, model, variant, exc)
    wall = time.perf_counter() - start
    # a run that did not collapse has no collapse multiplier: never reported as one
    collapsed = result is not None and result.collapsed
    ours = result.lambda_max * scale if collapsed else None
    extra = {
        "model": model,
        "supports_variant": variant,
        "seed_dem": spec.seed_dem,
        "seed_rel_error": abs(spec.seed_dem - spec.reference) / spec.reference,
        **{f"ref_{k}": v for k, v in spec.references.items()},
        "n_blocks": scene.n_blocks,
        "termination": "error" if result is None else result.termination,
        "collapsed": collapsed,
        "lambda_reached": None if result is None else result.lambda_max * scale,
        "failure": error if result is None else result.failure,
        "n_steps": None if result is None else result.n_steps,
    }
    tag = f"{spec.key}_{model}_{variant}"
    if result is not None:
        _save_run(tag, scene, result)
    row = Row(
        quantity=f"{spec.key} {spec.quantity} ({model}, {variant})",
        ours=ours,
        reference=spec.reference,
        source=spec.source,
        wall_s=wall,
        settings={
            "static": {k: v for k, v in settings.__dict__.items() if not k.startswith("_")},
            "assumptions": spec.assumptions,
            "supports": spec.supports,
            "run": f"validation/results/masonry/{tag}.npz",
        },
        extra=extra,
    )
    return row, result, scene


def _mean_errors(rows: list[Row]) -> dict[tuple[str, str], tuple[float, int]]:
    out: dict[tuple[str, str], list[float]] = {}
    for r in rows:
        if r.rel_error is not None:
            out.setdefault((r.extra["model"], r.extra["supports_variant"]), []).append(r.rel_error)
    return {k: (float(np.mean(v)), len(v)) for k, v in out.items()}


def _summary(rows: list[Row], seed_errors: list[float]) -> str:
    lines = ["| interface model | supports | mean rel. error | specimens |", "|---|---|---|---|"]
    for (model, variant), (err, n) in sorted(_mean_errors(rows).items()):
        lines.append(f"| {model} | {variant} | {err:.3f} | {n} |")
    lines.append(
        f"| seed 001 DEM | as in the seed | {np.mean(seed_errors):.3f} | {len(seed_errors)} |"
    )
    return "\n".join(lines)


# ----------------------------------------------------------------------------------------------
# Table 1
# ----------------------------------------------------------------------------------------------


ORDUNA_VARIANTS = (
    ("resultant", "translations"),
    ("fibre", "translations"),
    ("resultant", "blocks"),
    ("fibre", "blocks"),
)


def run_orduna(quick: bool = True):
    """Seed 001 Table 1: lambda_max of the 3 x 13 and 6 x 13 dry panels, both interface laws."""
    rows = []
    for key in ("orduna-3x13", "orduna-6x13"):
        spec = SPECIMENS[key]
        for model, variant in ORDUNA_VARIANTS:
            row, result, scene = _row(spec, model, variant, quick)
            lo, hi = sorted((spec.seed_dem, spec.references["fem"], spec.references["limit"]))[::2]
            row.extra["within_seed_spread"] = (
                None if row.ours is None else bool(lo <= row.ours <= hi)
            )
            rows.append(row)
            if (
                key == "orduna-3x13"
                and (model, variant) == ("resultant", "translations")
                and result is not None
            ):
                _write_collapse_state(scene, result)
    notes = (
        "Seed 001 Table 1 (Orduna & Lourenco 2005b). Reference = FEM; `ref_limit` = limit "
        "analysis; spread of the seed = [min, max] of DEM, FEM, limit. Supports as the seed "
        "states: translations of the end blocks of every course fixed, rotations free, on a "
        "fixed foundation.\n\n"
        "Known difference: with small-displacement kinematics the fibre model's rocking "
        "dilatancy is confined by the immovable column(s), which clamps the neighbouring blocks "
        "(arching): its collapse load is far above the references. The resultant model has no "
        "dilatancy (its hinges rotate about the joint centroid): the free part overturns about "
        "its base, sliding along the restrained column(s), at a load a little above the "
        "free-standing overturning s/H = 0.066 (the path reaches that plateau for any load "
        "step since the return-mapping fix of the masonry-restrepo findings; the 6 x 13 panel "
        "stalled at 0.063 before it).\n\n"
        "Variant `blocks` (ours): the restraint built as return walls of blocks in corner "
        "bond, 2 blocks long (assumed), as a real return wall would hold the panel; the "
        "return-wall blocks are b/2 = 105 mm thick."
    )
    return rows, notes


def _write_collapse_state(scene, result: StaticResult) -> None:
    RESULTS_DIR.mkdir(parents=True, exist_ok=True)
    scene_path = RESULTS_DIR / "masonry-collapse-state.scene.json"
    scene.to_json(scene_path)
    np.savez(
        COLLAPSE_STATE,
        interface_block_a=result.block_a.astype(np.int64),
        interface_block_b=result.block_b.astype(np.int64),
        resultants=result.interface_forces,
        lambda_max=result.lambda_max,
        scene_json=str(scene_path.relative_to(RESULTS_DIR.parent.parent)),
    )


# ----------------------------------------------------------------------------------------------
# Table 2
# ----------------------------------------------------------------------------------------------

QUICK_RESTREPO = ("S15", "S13")
VARIANTS = (
    ("fibre", "blocks"),
    ("resultant", "fixed_column"),
    ("fibre", "fixed_column"),
    ("resultant", "blocks"),
)


def run_restrepo(quick: bool = True):
    """Seed 001 Table 2: every specimen, both interface laws, both return-wall models."""
    names = QUICK_RESTREPO if quick else RESTREPO_NAMES
    rows = []
    for name in names:
        spec = SPECIMENS[f"restrepo-{name}"]
        if spec.supports == "base+beams":
            variants = (("fibre", "none"), ("resultant", "none"))
        else:
            variants = VARIANTS + ((("fibre", "blocks_6"),) if not quick else ())
        for model, variant in variants:
            row, _, _ = _row(spec, model, variant, quick)
            rows.append(row)
    seed_errors = [
        abs(SPECIMENS[f"restrepo-{n}"].seed_dem / SPECIMENS[f"restrepo-{n}"].reference - 1)
        for n in names
    ]
    notes = (
        "Seed 001 Table 2 (Restrepo-Velez et al. 2014): reference = experiment. Variants: "
        "`fixed_column` = the seed's model (end block of every course fixed); `blocks` = the "
        "return walls built as blocks in corner bond (3 blocks long behind the wall, assumed). "
        "S32 has no return wall; its top is held by the beams (assumed: free, it overturns "
        "at 0.084). Opening sizes of S23/S34 are assumed (see settings). `blocks_6` (full "
        "runs only): return walls 6 blocks long, the sensitivity to that assumption.\n\n"
        "Findings. (1) resultant law (the seed's) + fixed column: the early 'collapse' of "
        "earlier runs (S11 at 0.024, S5 at 0.070) was a solver defect, not physics. The "
        "return mapping took joints sitting exactly on their limit (the committed state after "
        "a plastic return) as elastic at the start of the next step (about two thirds of the "
        "yielded joints of S11), Newton cycled between states, the step shrank to 1e-9 m, and "
        "the plateau test fired on the lambda noise of loosely converged steps while the path "
        "was still rising at half its initial slope (load control from a stalled state found "
        "equilibria about 25 % higher). Fixed by deciding yielding to within 1e-9 of the limit, a "
        "tangent floor of 1e-4 (1e-9 left blocks held by yielded joints nearly free in the "
        "iteration matrix), a secant predictor and no loosely converged steps: every "
        "fixed-column specimen now ends on a plateau in 1-5 s, S11 at 0.0758 for load steps "
        "0.005, 0.01, 0.02 (spread 0.05 %). The "
        "mechanism is the overturning of the whole free wall about its base, sliding along the "
        "column(s): the resultant law rotates its hinges about the joint centroid, without "
        "uplift, so the fixed blocks that overlap the wall cannot lock it, and lambda stays a "
        "little above the free wall's s/H = 0.067 (0.076-0.113 for every specimen). The seed's "
        "DEM, with the same law and supports, reports 0.10-0.35 and diagonal cracks (Figs. "
        "15-16); we cannot reproduce that and do not know what in its solver carries the "
        "difference. (2) return walls built as blocks: the closest variant for both laws "
        "(resultant law: S11-S15 within 11 %); the two-sided specimens are capped by the "
        "assumed 3-block return walls, which "
        "overturn themselves (limit analysis: 0.217 for S5 against 0.349 measured; the fibre "
        "law with 6-block return walls comes to 0.297). With the resultant law, the "
        "load-weighted control of S15, S6, S1-S2-S3 and S5 stalls near the peak (steps cut to "
        "1e-4 of the first while lambda still rose at 1.5-5 % of the initial slope); the "
        "solver then follows the path along its last increment: S15, S6 and S5 end on "
        "plateaus 0.6 %, 0.9 % and 8.5 % above where they stalled (0.1914, 0.1590, 0.1822), "
        "S1-S2-S3 still rises at 4.6 % of the initial slope when it reaches max_steps "
        "(0.1677, was 0.1657). The fibre law's S34 passes its peak in a snap-back. Where the "
        "paths stall, frictional equilibrium is not unique and the path taken depends on the "
        "iteration: S15 ends at 0.19265 / 0.19253 / 0.19263 / 0.19262 for tangent floors "
        "1e-3 / 1e-4 / 1e-5 / 1e-6 (spread 0.06 %; 1e-6 stalled at 0.1726 before the "
        "path-direction control), S1-S2-S3 at 0.1738 (max_steps) / 0.1677 (max_steps) / "
        "0.1743 (plateau) for 1e-3 / 1e-4 / 1e-5 (spread 4 %). (3) fibre law "
        "+ fixed column: the "
        "rocking dilatancy (uplift about block edges) is confined by the immovable column(s): "
        "the blocks are clamped and arching grows without bound with two columns (lambda >> "
        "1). (4) resultant law over openings without lintels: the blocks above an opening "
        "have no support without dilatancy (arching), a mechanism under the dead load.\n\n"
        "Mean relative error per variant over the specimens run "
        f"(the seed's own DEM over all of Table 2: {SEED_TABLE2_MEAN_ERROR}):\n\n"
        + _summary(rows, seed_errors)
    )
    return rows, notes


# ----------------------------------------------------------------------------------------------
# Table 3
# ----------------------------------------------------------------------------------------------

QUICK_CHEE_LIANG = ("14-15",)


def run_chee_liang(quick: bool = True):
    """Seed 001 Table 3: ultimate pressure of the mortared walls, both interface laws."""
    names = QUICK_CHEE_LIANG if quick else CHEE_LIANG_NAMES
    rows = []
    for name in names:
        spec = SPECIMENS[f"chee-liang-{name}"]
        for model in ("fibre", "resultant"):
            row, _, _ = _row(spec, model, "simply_supported", quick, scale=1e-3)
            tests = sorted(spec.references.values())
            lo, hi = min(tests + [spec.seed_dem]), max(tests + [spec.seed_dem])
            row.extra["within_seed_spread"] = (
                None if row.ours is None else bool(lo <= row.ours <= hi)
            )
            rows.append(row)
    notes = (
        "Seed 001 Table 3 (Chee Liang 1996): reference = mean of the two tests of each wall "
        "pair (`ref_test_1`, `ref_test_2`); p in kN/m^2 = lambda / 1000. Joint law of the "
        "seed: k_n = 25, k_t = 105 N/mm^3, mu = 0.57, tensile strength 0.35 MPa, cohesion "
        "mu * sigma_t. Assumed: unit weight 18 kN/m^3, block pitch brick + 10 mm joint, the "
        "bottom course on a fixed foundation through a dry (no-tension) joint; out-of-plane "
        "translation restrained along the supported edges.\n\n"
        "The resultant law's rocking limit (f_t - N) l_c assumes a uniform tensile block over "
        "the whole joint (seed Eq. 9): for a mortared joint at N = 0 it is 3 times the elastic "
        "cracking moment, so it overestimates the cracking pressure; the fibre model cracks "
        "fibre by fibre.\n\n"
        "The fibre law's values are converged in the number of fibres (points per side 3 / 4 / "
        "5, measured: 9-13 at 21.86 / 18.74 / 18.53, 14-15 at 14.75 / 16.25 / 16.12 kN/m^2), so "
        "its distance from the tests is the model's: each fibre is elastic-brittle in tension "
        "(no softening), while the resultant law keeps its full bending capacity once it "
        "yields (perfectly plastic). The tests lie between the two laws for 14-15 and 10-11, "
        "above both for 8-12 and 9-13, and below both for 2-3 and 4-5; no single joint law "
        "with the seed's parameters brackets the scatter of the walls."
    )
    return rows, notes


CASES = {
    "masonry-orduna": run_orduna,
    "masonry-restrepo": run_restrepo,
    "masonry-chee-liang": run_chee_liang,
}
