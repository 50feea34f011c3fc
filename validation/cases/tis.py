"""Cases `tis-panels`, `tis-convergence`, `tis-friction`: explicit indentation of seed 000's panels.

All runs: the ``n x n`` panel of :func:`dem.scenes.tis_panel.tis_panel` (50 x 50 x 3.18 mm,
boundary blocks fixed, density 2500 kg/m^3, mu = 0.23), relaxed under gravity, then indented at
the central block by a rigid frictionless sphere (radius 1.25 mm) at constant speed;
``k_n = k_def = M E / L`` (Eq. (3), ``M = n + 1``, ``E`` implied by the seed's 2.25 GPa/mm for
the 5 x 5 panel) for the perfect panels and ``k_imp`` (Eq. (4), ``k_gaps = 0.65 GPa/mm``) for the
gap-calibrated ones. See :mod:`dem.explicit` for the definitions of peak load, deflection at
peak, ultimate deflection and loading energy.

Besides the JSON/markdown tables the cases write, for the figures, ``tis-panels-curves.npz``,
``tis-friction-curves.npz`` and ``tis-convergence-curves.npz``, and from the 5 x 5, 2.5 degree
perfect panel the contact state at peak load ``tis-peak-state.npz`` (FEM post-processing).
"""

from __future__ import annotations

import logging
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from dem.estimate import Estimate, sweep_errors
from dem.explicit import (
    ExplicitSettings,
    IndentationResult,
    IndentationSettings,
    RelaxationSettings,
    simulate_indentation,
)
from dem.scene import Assembly, Scene
from dem.scenes.tis_panel import MU_SEED_000, tis_panel
from dem.tis_stiffness import (
    K_GAPS_SEED_000,
    MU_STD_SEED_000,
    draw_block_friction,
    k_series,
    tis_panel_k_def,
)
from dem.units import GPA, MM
from validation.cases.bars import per_unit
from validation.report import Row, output_dir
from validation.sweep.stats import mean_ci

logger = logging.getLogger(__name__)

THICKNESS_MM = 3.18
PANELS = [(n, theta) for theta in (2.5, 5.0, 7.5) for n in (3, 5, 7)]
# seed 000 Table 1 (LS-DEM with k_def over experiment) and Table 2 (experiment over calibrated
# LS-DEM): their product is P_perfect / P_calibrated without the experiments.
TABLE1_PEAK = {3: 7.1, 5: 3.7, 7: 3.4}
TABLE1_ENERGY = {3: 6.2, 5: 5.6, 7: 6.0}
TABLE2_PEAK = {(7, 2.5): 0.85, (5, 2.5): 1.36, (3, 2.5): 1.66, (7, 5.0): 0.88, (5, 5.0): 1.40,
               (3, 5.0): 1.74, (7, 7.5): 1.24, (5, 7.5): 1.21, (3, 7.5): 1.58}  # fmt: skip
TABLE2_ENERGY = {(7, 2.5): 1.02, (5, 2.5): 1.42, (3, 2.5): 1.44, (7, 5.0): 1.25, (5, 5.0): 1.84,
                 (3, 5.0): 2.13, (7, 7.5): 1.92, (5, 7.5): 1.37, (3, 7.5): 2.22}  # fmt: skip

# The discretisation that tis-convergence calls converged (peak load within 1 % of the finest
# node spacing, loading rate and mass scaling with no visible effect on the curve).
CONVERGED = {"node_spacing_mm": 0.5, "speed_mm_s": 50.0, "mass_scaling": 1.0, "dt_safety": 0.5}
QUICK = {"node_spacing_mm": 1.5, "speed_mm_s": 50.0, "mass_scaling": 1.0, "dt_safety": 0.5}
BUDGET = {True: "cheap", False: "full"}
"""Error budget of the panel and friction runs by ``quick`` (:func:`simulate_indentation`):
quick runs rerun at half the speed only; full runs also at half the time step and half the
node spacing."""


def _checkpoint_dir() -> Path:
    path = Path(os.environ.get("TIS_CHECKPOINT_DIR", Path(tempfile.gettempdir()) / "tis-ckpt"))
    path.mkdir(parents=True, exist_ok=True)
    return path


def _enable_progress() -> None:
    """Show the solver's progress lines on stderr when nobody configured logging."""
    log = logging.getLogger("dem.explicit")
    if not log.handlers and not logging.getLogger().handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("%(asctime)s %(message)s", "%H:%M:%S"))
        log.addHandler(handler)
        log.setLevel(logging.INFO)


def run_panel(
    n: int,
    theta_deg: float,
    k_n: float,
    disc: dict,
    *,
    block_mu: np.ndarray | None = None,
    mu: float | None = None,
    stop_below_peak_fraction: float | None = None,
    max_deflection_mm: float = 6.0,
    checkpoint: str | None = None,
    relaxation: RelaxationSettings | None = None,
    parallel: bool | None = False,
    error: str = "none",
) -> tuple[IndentationResult, Scene]:
    """One relaxation + indentation run of a seed 000 panel (``parallel``: as
    :class:`dem.explicit.ExplicitSettings`; ``error``: the error budget of
    :func:`dem.explicit.simulate_indentation`)."""
    scene = tis_panel(n, theta_deg, thickness_mm=THICKNESS_MM)
    if block_mu is not None:
        asm = scene.assembly
        scene = Scene(Assembly(asm.blocks, asm.density, block_mu), scene.supports, scene.loads,
                      scene.name, scene.meta)  # fmt: skip
    settings = ExplicitSettings(
        k_n=k_n,
        node_spacing=disc["node_spacing_mm"] * MM,
        mass_scaling=disc["mass_scaling"],
        dt_safety=disc["dt_safety"],
        mu=mu,
        parallel=parallel,
    )
    indentation = IndentationSettings(
        speed=disc["speed_mm_s"] * MM,
        max_deflection=max_deflection_mm * MM,
        stop_below_peak_fraction=stop_below_peak_fraction,
    )
    path = None if checkpoint is None else _checkpoint_dir() / f"{checkpoint}.npz"
    result = simulate_indentation(scene, settings, indentation, relaxation, checkpoint=path,
                                  error=error)  # fmt: skip
    if path is not None:
        # checkpoints only serve to resume a killed run: a finished one is not reused later
        path.unlink(missing_ok=True)
    return result, scene


def mechanism(result: IndentationResult, scene: Scene) -> dict:
    """Failure mechanism at the end of the run: drops of the loaded block and of the others.

    ``central_out``: the loaded block has dropped by more than half the panel thickness while
    no other block has dropped by more than 30 % of that (it slides out of the panel, seed 000
    Fig. 5b); ``final_load_ratio``: the last recorded load over the peak.
    """
    c = result.info["loaded_block"]
    drop = -(result.block_pos[-1, :, 2] - result.block_pos[0, :, 2]) / MM
    others = np.delete(drop, c)
    return {
        "central_drop_mm": float(drop[c]),
        "other_max_drop_mm": float(others.max()),
        "central_out": bool(drop[c] > 0.5 * THICKNESS_MM and others.max() < 0.3 * drop[c]),
        "final_load_ratio": float(result.load[-1] / result.peak_load),
    }


def energy_check(res: IndentationResult) -> float:
    """Largest (kinetic + penalty energy) / (indenter work) over the run: at most 1 when no
    energy is created (friction and damping dissipate the rest)."""
    ok = res.work > 0.01 * res.work.max()
    if not np.any(ok):
        return float("nan")
    return float(np.max((res.kinetic[ok] + res.elastic[ok]) / res.work[ok]))


def _curve_rows(label: str, res: IndentationResult, settings: dict, extra: dict) -> list[Row]:
    """Peak load, deflection at peak, loading energy and ultimate deflection of one run, each
    with the run's own error bar (``res.estimates``; the peak row's ``error_cost_s`` is the
    wall time of its reruns [s]); no ultimate deflection and no loading energy when the run
    stopped before the block was out (blocks passing through each other further than their
    contact represents, :mod:`dem.explicit.unmodelled`), :func:`loading_energy`."""
    wall = res.info["wall_s"]
    est = res.estimates
    extra = {**extra, "energy_over_work_max": energy_check(res),
             "error_cost_s": est["peak_load"].cost_s}  # fmt: skip
    ultimate = est.get("ultimate_deflection")
    energy = loading_energy(res)

    def row(quantity: str, ours, more: dict | None = None) -> Row:
        return Row(f"{label}: {quantity}", ours, None, "", wall, settings, more or {})

    return [
        row("peak load [N]", est["peak_load"], extra),
        row("deflection at peak [mm]", per_unit(est["deflection_at_peak"], MM)),
        row(
            "loading energy [N mm]",
            None if energy is None else per_unit(energy, MM),
            {} if energy is not None else _no_energy(res),
        ),
        row(
            "ultimate deflection [mm]",
            None if ultimate is None else per_unit(ultimate, MM),
            {"stopped_by": res.info.get("stopped_by", "")},
        ),  # fmt: skip
    ]


def loading_energy(res: IndentationResult) -> Estimate | None:
    """The loading energy with its bar, or None when the block did not get out: the work then
    stops at the end of the run, which is a lower bound of the loading energy, not its value
    (no ultimate deflection to integrate to)."""
    if "ultimate_deflection" not in res.estimates:
        return None
    return res.estimates["loading_energy"]


def _no_energy(res: IndentationResult) -> dict:
    return {
        "note": "no loading energy: the block did not get out, so the work up to the end of "
        "the run (work_to_end_nmm) is a lower bound of it",
        "work_to_end_nmm": float(res.loading_energy / MM),
    }


def ratio(num: Estimate, den: Estimate) -> Estimate:
    """``num / den`` with the bar of the interval quotient ``[num] / [den]`` (exact, not first
    order), shared out over the sources of both in proportion to their first-order parts
    (``"numerator: <source>"``, ``"denominator: <source>"``); unbounded sources stay
    unbounded, and the bar is unbounded when ``[den]`` holds zero. The sources either part
    omits are omitted from the quotient's bar too."""
    r = num.value / den.value
    cost = num.cost_s + den.cost_s
    omitted = tuple(dict.fromkeys((*num.omitted, *den.omitted)))
    first = {f"numerator: {k}": w / abs(den.value) for k, w in num.sources.items()}
    first.update({f"denominator: {k}": abs(r) * w / abs(den.value)
                  for k, w in den.sources.items()})  # fmt: skip
    if not (math.isfinite(num.error) and math.isfinite(den.error)):
        return Estimate(r, first, cost, omitted=omitted)
    if den.lo <= 0.0 <= den.hi:
        return Estimate(r, {"denominator interval holds zero": math.inf}, cost, omitted=omitted)
    ends = [a / b for a in (num.lo, num.hi) for b in (den.lo, den.hi)]
    width = max(max(ends) - r, r - min(ends))
    total = sum(first.values())
    if total == 0.0:
        return Estimate(r, first, cost, omitted=omitted)
    return Estimate(r, {k: w / total * width for k, w in first.items()}, cost, omitted=omitted)


def mean_of_runs(estimates: list[Estimate]) -> Estimate:
    """The mean of the runs' values as an estimate of the population mean: the half-width of
    its Student t 95 % interval (``"sampling"``) plus, per source, the mean of the runs'
    half-widths (the runs' errors move the mean by at most that much); the sources any run
    omits are omitted from the mean's bar."""
    values = np.array([e.value for e in estimates])
    mean, half = mean_ci(values)
    sources = {"sampling": half}
    for name in sorted({k for e in estimates for k in e.sources}):
        sources[name] = float(np.mean([e.sources.get(name, 0.0) for e in estimates]))
    omitted = tuple(dict.fromkeys(s for e in estimates for s in e.omitted))
    return Estimate(mean, sources, sum(e.cost_s for e in estimates),
                    f"mean of {len(values)} runs, Student t 95 %", omitted)  # fmt: skip


def _store_curves(store: dict, key: str, res: IndentationResult, scene: Scene) -> None:
    store[f"{key}/delta"] = res.delta
    store[f"{key}/load"] = res.load
    picks = np.unique(
        np.concatenate(
            [
                np.linspace(0, len(res.delta) - 1, 7).astype(int),
                [int(np.argmax(res.load))],
            ]  # fmt: skip
        )
    )
    store[f"{key}/pose_delta"] = res.delta[picks]
    store[f"{key}/pose_pos"] = res.block_pos[picks]
    store[f"{key}/pose_quat"] = res.block_quat[picks]
    store[f"{key}/ref_centroid"] = scene.assembly.centroid
    arrays = scene.assembly.arrays
    store[f"{key}/vertices"] = arrays.vertices
    store[f"{key}/vert_ptr"] = arrays.vert_ptr
    store[f"{key}/fixed"] = scene.supports.fixed
    store[f"{key}/summary"] = np.array(
        [res.peak_load, res.deflection_at_peak, res.ultimate_deflection, res.loading_energy]
    )
    snaps = res.snapshots
    store[f"{key}/snap_delta"] = np.array([s["delta"] for s in snaps])
    store[f"{key}/snap_is_peak"] = np.array([s["kind"] == "peak" for s in snaps])
    store[f"{key}/snap_ptr"] = np.concatenate([[0], np.cumsum([len(s["pairs"]) for s in snaps])])
    store[f"{key}/snap_pairs"] = np.concatenate([s["pairs"] for s in snaps] or [np.zeros((0, 2))])
    store[f"{key}/snap_force"] = np.concatenate([s["force"] for s in snaps] or [np.zeros((0, 3))])
    store[f"{key}/snap_point"] = np.concatenate([s["point"] for s in snaps] or [np.zeros((0, 3))])


def _disc_settings(disc: dict, k_n: float) -> dict:
    return {**disc, "k_n_gpa_mm": k_n / (GPA / MM), "tip_radius_mm": 1.25}


# -- tis-panels ---------------------------------------------------------------------------------
def run_panels(quick: bool) -> tuple[list[Row], str]:
    """All nine panels, perfect and gap-calibrated stiffness, plus stability cases."""
    _enable_progress()
    disc = QUICK if quick else CONVERGED
    panels = [(3, 2.5), (5, 2.5)] if quick else PANELS
    calibrated_panels = [(3, 2.5)] if quick else PANELS
    store: dict = {}
    rows, results = _panel_runs(panels, calibrated_panels, disc, quick, store)
    rows += _calibration_ratio_rows(results, disc)
    rows += _trend_rows(panels, results)
    rows += _stability_rows(quick, disc, store)
    np.savez(output_dir() / "tis-panels-curves.npz", **store)
    return rows, _panels_notes(disc, quick)


def _panel_runs(panels, calibrated_panels, disc: dict, quick: bool, store: dict):
    """Every panel run, perfect and (where listed) calibrated: their curve rows and results
    by ``(n, theta, model)``; the 5 x 5, 2.5 deg perfect panel's peak state is written for
    the FEM case."""
    rows: list[Row] = []
    results: dict = {}
    for n, theta in panels:
        models = ["perfect"] + (["calibrated"] if (n, theta) in calibrated_panels else [])
        for model in models:
            k_def = tis_panel_k_def(n)
            k_n = k_def if model == "perfect" else k_series(k_def, K_GAPS_SEED_000)
            tag = "quick" if quick else "full"
            res, scene = run_panel(n, theta, k_n, disc, error=BUDGET[quick],
                                   checkpoint=f"panel-{n}-{theta}-{model}-{tag}")  # fmt: skip
            results[(n, theta, model)] = res
            label = f"{n}x{n} theta={theta:g} {model}"
            mech = mechanism(res, scene)
            extra = {**mech, "n_nodes": res.info["n_nodes"], "dt_s": res.info["dt"]}
            rows += _curve_rows(label, res, _disc_settings(disc, k_n), extra)
            _store_curves(store, f"{n}x{n}_{theta:g}_{model}", res, scene)
            if (n, theta, model) == (5, 2.5, "perfect"):
                np.savez(output_dir() / "tis-peak-state.npz", **res.peak_state)
    return rows, results


def _calibration_ratio_rows(results: dict, disc: dict) -> list[Row]:
    """Calibrated over perfect peak load and energy, against the ratios the seed's Tables 1
    and 2 imply and the exact homogeneity prediction ``k_imp / k_def``."""
    rows: list[Row] = []
    for (n, theta, model), res in results.items():
        if model != "calibrated":
            continue
        perf = results[(n, theta, "perfect")]
        k_def = tis_panel_k_def(n)
        k_ratio = k_series(k_def, K_GAPS_SEED_000) / k_def
        settings = _disc_settings(disc, k_def)
        ref_p = ref_e = None
        if theta == 2.5:
            ref_p = 1.0 / (TABLE1_PEAK[n] * TABLE2_PEAK[(n, theta)])
            ref_e = 1.0 / (TABLE1_ENERGY[n] * TABLE2_ENERGY[(n, theta)])
        rows.append(Row(
            f"{n}x{n} theta={theta:g}: P_calibrated / P_perfect",
            ratio(res.estimates["peak_load"], perf.estimates["peak_load"]),
            ref_p, "seed 000 1/(Table 1 x Table 2)" if ref_p else "", None, settings,
            {"k_imp_over_k_def": k_ratio,
             "rel_to_k_ratio": res.peak_load / perf.peak_load / k_ratio - 1.0},
        ))  # fmt: skip
        energies = loading_energy(res), loading_energy(perf)
        missing = {"note": "no loading energy in one of the runs (the block did not get out)"}
        rows.append(Row(
            f"{n}x{n} theta={theta:g}: LE_calibrated / LE_perfect",
            None if None in energies else ratio(*energies), ref_e,
            "seed 000 1/(Table 1 x Table 2)" if ref_e else "", None, settings,
            {"k_imp_over_k_def": k_ratio, **(missing if None in energies else {})},
        ))  # fmt: skip
    return rows


def _trend_rows(panels, results: dict) -> list[Row]:
    """Peak load against block size at each theta (seed 000 Sec. 5.1.3: load and energy grow
    with size) and against theta at each size."""
    rows: list[Row] = []
    for theta in sorted({t for _, t in panels}):
        sizes = [n for n, t in panels if t == theta]
        if len(sizes) < 2:
            continue
        runs = [results[(n, theta, "perfect")] for n in sizes]
        peaks = [res.peak_load for res in runs]
        energies = [res.loading_energy for res in runs]
        rows.append(Row(
            f"theta={theta:g} perfect: P_max ratio {sizes[0]}x{sizes[0]} / {sizes[-1]}x{sizes[-1]}",
            ratio(runs[0].estimates["peak_load"], runs[-1].estimates["peak_load"]), None, "",
            None, {},
            {"decreasing_with_n": bool(np.all(np.diff(peaks) < 0)),
             "energy_decreasing_with_n": bool(np.all(np.diff(energies) < 0))},
        ))  # fmt: skip
    for n in sorted({n for n, _ in panels}):
        thetas = [t for m, t in panels if m == n]
        if len(thetas) < 2:
            continue
        runs = [results[(n, t, "perfect")] for t in thetas]
        peaks = [res.peak_load for res in runs]
        rows.append(Row(
            f"{n}x{n} perfect: P_max ratio theta={thetas[-1]:g} / theta={thetas[0]:g}",
            ratio(runs[-1].estimates["peak_load"], runs[0].estimates["peak_load"]), None, "",
            None, {},
            {"increasing_with_theta": bool(np.all(np.diff(peaks) > 0))},
        ))  # fmt: skip
    return rows


def _panels_notes(disc: dict, quick: bool) -> str:
    return (
        "Explicit LS-DEM-style runs (dem.explicit). k_def = (n+1) E / L with E = 18.75 GPa, "
        "implied by the seed's 2.25 GPa/mm for the 5x5 panel; k_imp by Eq. (4) with k_gaps = "
        "0.65 GPa/mm. delta is the indenter travel from first touch (it includes the sphere's "
        "penalty indentation). Ultimate deflection: P below 10 % of the peak for 0.3 mm of "
        "travel. Discretisation: "
        + ", ".join(f"{k}={v}" for k, v in disc.items())
        + (" (quick: coarse, not converged)." if quick else " (converged per tis-convergence).")
        + f" Error bars: each run's own ({_budget_note(quick)}); ratios carry the interval "
        "quotient of their two runs' bars; a peak the run did not reach (the load never fell "
        "after it) is a lower bound, `± ?`."
        + " P_calibrated/P_perfect: the quasi-static problem is homogeneous in k_n (rigid "
        "blocks, penalty contact, Coulomb friction with k_t proportional to k_n, weight "
        "negligible), so the ratio must equal k_imp/k_def; the seed's Tables 1 and 2 imply "
        "different ratios for the 3x3 and 7x7 panels, which no choice of k_def per panel can "
        "give with one k_gaps."
    )


def _budget_note(quick: bool) -> str:
    reruns = "half the speed" + ("" if quick else ", half the time step, half the node spacing")
    return (
        f"error budget '{BUDGET[quick]}': the sampling of the curve (one record of travel) "
        f"plus twice the change of each number in a rerun at {reruns} "
        "(dem.explicit.indentation_error)"
    )


def _stability_rows(quick: bool, disc: dict, store: dict) -> list[Row]:
    """Hard cases: theta = 0, theta = 10 deg, E ten times larger, 7x7 with per-block mu."""
    rows = []
    n = 3 if quick else 5
    k_def = tis_panel_k_def(n)
    budget = BUDGET[quick]
    ref, _ = run_panel(n, 2.5, k_def, disc, stop_below_peak_fraction=0.85, error=budget)
    # no interlock: the blocks never come to rest under gravity; relax briefly and go on
    falling = RelaxationSettings(max_steps=2000, require_convergence=False)
    flat, scene = run_panel(n, 0.0, k_def, disc, max_deflection_mm=4.0, relaxation=falling,
                            error=budget)  # fmt: skip
    mech = mechanism(flat, scene)
    if not flat.peak_reached:  # the largest load so far is no peak (a lower bound only)
        mech = {**mech, "largest_load_ratio": float(flat.peak_load / ref.peak_load),
                "note": "no peak: the load never fell after its largest value, so there is no "
                "P_max to bound; largest_load_ratio is the largest load over the travel / "
                "P_max(theta=2.5)"}  # fmt: skip
    rows.append(Row(
        f"{n}x{n} theta=0 (no interlock): P_max / P_max(theta=2.5)",
        ratio(flat.estimates["peak_load"], ref.estimates["peak_load"])
        if flat.peak_reached else None,
        0.0, "no interlock: the central block slides out at near-zero load (the indenter pushes "
        "only against the damping) while the panel stays exactly symmetric; unstable (an "
        "indenter 1 nm off the axis lets two neighbours slide down with it and jam it, about "
        "220 N), and depths of round-off size carry no friction, so round-off does not decide "
        "it (dem.kernels.contact_force)", flat.info["wall_s"], _disc_settings(disc, k_def), mech,
    ))  # fmt: skip
    _store_curves(store, f"{n}x{n}_0_perfect", flat, scene)
    stiff, _ = run_panel(n, 2.5, 10 * k_def, disc, stop_below_peak_fraction=0.85, error=budget)
    rows.append(Row(
        f"{n}x{n} theta=2.5: P_max(10 E) / P_max(E)",
        ratio(stiff.estimates["peak_load"], ref.estimates["peak_load"]), 10.0,
        "closed form: P proportional to k_n", stiff.info["wall_s"],
        _disc_settings(disc, 10 * k_def), {"dt_s": stiff.info["dt"]},
    ))  # fmt: skip
    if not quick:
        steep, scene = run_panel(5, 10.0, k_def, disc, error=budget)
        rows += _curve_rows("5x5 theta=10 perfect", steep, _disc_settings(disc, k_def),
                            mechanism(steep, scene))  # fmt: skip
        _store_curves(store, "5x5_10_perfect", steep, scene)
        mu7 = draw_block_friction(81, MU_SEED_000, MU_STD_SEED_000, seed=7)
        k7 = tis_panel_k_def(7)
        rough, scene = run_panel(7, 2.5, k7, disc, block_mu=mu7, error=budget)
        rows += _curve_rows("7x7 theta=2.5 perfect, per-block mu (seed 7)", rough,
                            _disc_settings(disc, k7), mechanism(rough, scene))  # fmt: skip
        _store_curves(store, "7x7_2.5_rough", rough, scene)
    return rows


# -- tis-convergence ------------------------------------------------------------------------------
CONVERGENCE_SWEEPS = {
    True: {
        "node_spacing_mm": [2.0, 1.5, 1.0],
        "speed_mm_s": [100.0, 50.0, 25.0],
        "mass_scaling": [16.0, 4.0, 1.0],
        "dt_safety": [0.5, 0.25],
    },
    False: {
        "node_spacing_mm": [1.5, 1.0, 0.7, 0.5, 0.35, 0.25],
        "speed_mm_s": [200.0, 100.0, 50.0, 25.0, 12.5],
        "mass_scaling": [100.0, 10.0, 1.0],
        "dt_safety": [0.5, 0.25],
    },
}
"""Values of each discretisation parameter, coarse to fine, of ``tis-convergence`` (by
``quick``)."""
SWEEP_ORDER = {"node_spacing_mm": 1.0, "speed_mm_s": 1.0, "mass_scaling": 0.5, "dt_safety": 1.0}
"""The smallest convergence order of the peak load in each parameter (:func:`sweep_errors`):
1, that of a consistent discretisation, and 1/2 in the mass scaling ``s``, which enters the
dynamics as ``v sqrt(s)`` only."""
EXACT_MASS_SCALING = 1.0
"""No mass scaling: the model itself, whose sweep level has no error of its own."""


class _PeakRuns:
    """Runs of the 5x5, 2.5 deg panel to 85 % past the peak, cached by discretisation."""

    def __init__(self, k_n: float):
        self.k_n = k_n
        self.cache: dict = {}

    def __call__(self, disc: dict):
        key = tuple(sorted(disc.items()))
        if key not in self.cache:
            start = time.perf_counter()
            # scaled masses relax with a damping force sqrt(mass_scaling) times larger: the
            # sweep measures what that does, so the relaxation is not refused
            scaled = RelaxationSettings(unbalanced_tol=math.inf)
            res, _ = run_panel(5, 2.5, self.k_n, disc, stop_below_peak_fraction=0.85,
                               relaxation=scaled if disc["mass_scaling"] > 1 else None)  # fmt: skip
            self.cache[key] = (res, time.perf_counter() - start)
        return self.cache[key]


def run_convergence(quick: bool) -> tuple[list[Row], str]:
    """Node spacing, time step, loading rate and mass scaling for the 5x5, 2.5 degree panel."""
    _enable_progress()
    k_n = tis_panel_k_def(5)
    base = dict(QUICK if quick else CONVERGED)
    sweeps = CONVERGENCE_SWEEPS[quick]
    store: dict = {}
    rows, base_bars, finest_spacing = _sweep_rows(sweeps, base, _PeakRuns(k_n), store)
    rows.append(_converged_row(base, k_n, base_bars, finest_spacing, sweeps, quick, store))
    np.savez(output_dir() / "tis-convergence-curves.npz", **store)
    notes = (
        "5x5 panel, theta = 2.5 deg, k_n = 2.25 GPa/mm. Each sweep varies one parameter around "
        f"the base {base} and runs until the load has dropped to 85 % of the peak; its error is "
        "against the finest run of the same sweep. curve_rel_diff: largest |P - P_finest| over "
        "the common deflection range before the peak, relative to the finest peak. Error bars "
        "(dem.estimate.sweep_errors): the finest run of a sweep is off by the Richardson bound "
        f"of its last pair at the smallest order {SWEEP_ORDER} (0 without mass scaling: the "
        "model), each coarser run by its distance to the next finer run plus that run's error; "
        "a peak's bar adds to its own parameter's error the error of the base value of every "
        "other parameter (from its sweep), so every bar names all four sources; the converged "
        "row's bar is the sum of the base errors. Mass scaling "
        "s and speed v enter the dynamics through v sqrt(s) only (time scaling), so the two "
        "sweeps test the same inertia effect. The converged row is the full run at the base "
        "discretisation (relaxation + indentation until the central block is out)."
        + (" Quick mode: coarse, the base is not converged." if quick else "")
    )
    return rows, notes


def _sweep_rows(sweeps: dict, base: dict, peak_run: _PeakRuns, store: dict):
    """One row per run of every sweep; the base discretisation's error per sweep
    (:func:`_level_errors`) and the finest node-spacing run."""
    rows: list[Row] = []
    runs_of = {p: [(v, *peak_run({**base, p: v})) for v in vals] for p, vals in sweeps.items()}
    errors = {p: _level_errors(p, sweeps[p], [r.peak_load for _, r, _ in runs])
              for p, runs in runs_of.items()}  # fmt: skip
    base_bars = {f"{p} (base {base[p]:g})": errors[p][sweeps[p].index(base[p])] for p in sweeps}
    finest_spacing = runs_of["node_spacing_mm"][-1][1]
    for param, runs in runs_of.items():
        # the finest run: smallest spacing / speed / mass scaling / time step
        ref_res = runs[-1][1]
        others = {k: w for k, w in base_bars.items() if not k.startswith(f"{param} ")}
        for i, (value, res, wall) in enumerate(runs):
            err = abs(res.peak_load - ref_res.peak_load) / ref_res.peak_load
            curve_err = _curve_difference(res, ref_res)
            ours = Estimate(res.peak_load, {f"{param} ({value:g})": errors[param][i], **others},
                            notes="dem.estimate.sweep_errors")  # fmt: skip
            rows.append(Row(
                f"peak load, {param}={value:g} [N]", ours,
                ref_res.peak_load,
                f"finest run of this sweep ({param}={sweeps[param][-1]:g})", wall,
                {**base, param: value},
                {"curve_rel_diff": curve_err, "n_nodes": res.info["n_nodes"],
                 "steps": res.info["steps_indentation"], "dt_s": res.info["dt"],
                 "cost_per_node_step_ns": res.info["cost_per_node_step_s"] * 1e9,
                 "error_vs_finest": err},
            ))  # fmt: skip
            store[f"{param}={value:g}/delta"] = res.delta
            store[f"{param}={value:g}/load"] = res.load
            store[f"{param}={value:g}/wall_s"] = np.array(wall)
            store[f"{param}={value:g}/rel_error"] = np.array(err)
    return rows, base_bars, finest_spacing


def _converged_row(base, k_n, base_bars, finest_spacing, sweeps, quick, store) -> Row:
    """The full run at the base discretisation (relaxation + indentation until the block is
    out), with the sweeps' base bars, against the finest node-spacing run."""
    start = time.perf_counter()
    full, scene = run_panel(5, 2.5, k_n, base)
    wall = time.perf_counter() - start
    info = full.info
    store["converged/delta"] = full.delta
    store["converged/load"] = full.load
    converged = Estimate(full.peak_load, base_bars, notes="dem.estimate.sweep_errors, base levels")
    return Row(
        "converged: 5x5 theta=2.5 full run, peak load [N]", converged,
        finest_spacing.peak_load,
        f"finest node spacing run ({sweeps['node_spacing_mm'][-1]:g} mm)", wall,
        {**base, "k_n_gpa_mm": k_n / (GPA / MM)},
        {"steps": info["steps_indentation"] + info["steps_relaxation"], "n_nodes": info["n_nodes"],
         "cost_per_node_step_ns": info["cost_per_node_step_s"] * 1e9,
         "ultimate_deflection_mm": full.ultimate_deflection / MM, **mechanism(full, scene),
         "within_1pct": bool(abs(full.peak_load / finest_spacing.peak_load - 1) <= 0.01),
         "energy_over_work_max": energy_check(full), "quick_not_converged": quick},
    )  # fmt: skip


def _level_errors(param: str, values: list, peaks: list) -> list[float]:
    """The error of the peak at each level of one sweep (coarse to fine) against the limit of
    that parameter (:func:`dem.estimate.sweep_errors` at :data:`SWEEP_ORDER`)."""
    exact_last = param == "mass_scaling" and values[-1] == EXACT_MASS_SCALING
    return sweep_errors(values, peaks, SWEEP_ORDER[param], exact_last)


def _curve_difference(res: IndentationResult, ref: IndentationResult) -> float:
    upto = min(res.deflection_at_peak, ref.deflection_at_peak)
    grid = np.linspace(0, upto, 50)[1:]
    if len(grid) == 0 or upto <= 0:
        return float("nan")
    diff = np.interp(grid, res.delta, res.load) - np.interp(grid, ref.delta, ref.load)
    return float(np.abs(diff).max() / ref.peak_load)


# -- tis-friction ---------------------------------------------------------------------------------
def run_friction(quick: bool) -> tuple[list[Row], str]:
    """mu = 0.23, 0.21, 0.19 and realisations of per-block mu ~ N(0.23, 0.06) (Fig. 9)."""
    _enable_progress()
    n, theta = 5, 5.0
    disc = QUICK if quick else CONVERGED
    k_n = k_series(tis_panel_k_def(n), K_GAPS_SEED_000)
    n_real = 3 if quick else 8
    rows: list[Row] = []
    store: dict = {}
    tag = "quick" if quick else "full"
    det = {}
    for mu in (0.23, 0.21, 0.19):
        res, scene = run_panel(n, theta, k_n, disc, mu=mu, checkpoint=f"fric-{mu}-{tag}",
                               error=BUDGET[quick])  # fmt: skip
        det[mu] = res
        rows += _curve_rows(f"5x5 theta=5 calibrated, mu={mu:g}", res, _disc_settings(disc, k_n),
                            {"mu": mu, **mechanism(res, scene)})  # fmt: skip
        _store_curves(store, f"mu={mu:g}", res, scene)
    for mu in (0.21, 0.19):
        rows.append(Row(
            f"P_max(mu={mu:g}) / P_max(mu=0.23)",
            ratio(det[mu].estimates["peak_load"], det[0.23].estimates["peak_load"]), None,
            "seed 000 Fig. 9a: lower with smaller mu", None, {},
            {"lower": bool(det[mu].peak_load < det[0.23].peak_load)},
        ))  # fmt: skip
    peaks, energies, estimates = [], [], []
    n_blocks = (n + 2) ** 2
    for seed in range(n_real):
        mu_blocks = draw_block_friction(n_blocks, MU_SEED_000, MU_STD_SEED_000, seed=seed)
        res, scene = run_panel(n, theta, k_n, disc, block_mu=mu_blocks, error=BUDGET[quick],
                               checkpoint=f"fric-real{seed}-{tag}")  # fmt: skip
        peaks.append(res.peak_load)
        energies.append(res.loading_energy)
        estimates.append(res.estimates["peak_load"])
        rows += _curve_rows(f"5x5 theta=5 calibrated, mu ~ N(0.23, 0.06) seed {seed}", res,
                            {**_disc_settings(disc, k_n), "rng_seed": seed},
                            {"mu_mean_free": float(mu_blocks[~scene.supports.fixed].mean()),
                             **mechanism(res, scene)})  # fmt: skip
        _store_curves(store, f"real{seed}", res, scene)
    rows.append(Row(
        f"mean P_max of {n_real} realisations / P_max(mu=0.23)",
        ratio(mean_of_runs(estimates), det[0.23].estimates["peak_load"]), None,
        "seed 000 Fig. 9b: the average realisation lies below the deterministic curve", None,
        {"n_realisations": n_real},
        {"std_over_mean": float(np.std(peaks) / np.mean(peaks)),
         "mean_energy_ratio": float(np.mean(energies)) / det[0.23].loading_energy},
    ))  # fmt: skip
    np.savez(output_dir() / "tis-friction-curves.npz", **store)
    notes = (
        "Panel of seed 000 Fig. 9 taken as the 5x5, theta = 5 deg calibration panel with "
        "k_imp (k_gaps = 0.65 GPa/mm); per-block mu drawn with numpy default_rng(seed) from "
        "N(0.23, 0.06) (clipped at 0) for every block; a pair's mu is the mean of its two "
        "blocks' values (ExplicitSettings.mu_rule). Discretisation: "
        + ", ".join(f"{k}={v}" for k, v in disc.items())
        + (" (quick: coarse, not converged)." if quick else ".")
        + f" Error bars: each run's own ({_budget_note(quick)}); the ratios carry the interval "
        "quotient of their two runs' bars; the mean over the realisations adds the Student t 95 % "
        "interval of the population mean to the mean of the runs' bars (tis.mean_of_runs)."
    )
    return rows, notes


CASES = {"tis-panels": run_panels, "tis-convergence": run_convergence, "tis-friction": run_friction}
