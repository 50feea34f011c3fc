"""Time to recover the stresses of all 49 blocks of a 5 x 5 TIS panel state (P2).

Meshing (gmsh, once per block shape), assembly (K, M, rigid modes, boundary facets),
factorisation (once per shape), load mapping (consistent point loads), solves and stress
recovery, for the 49 blocks of a 5 x 5 panel. The state is the DEM peak state
``validation/results/tis-peak-state.npz`` when it is balanced, else the synthetic statically
admissible state of ``validation.cases.fem`` (about the DEM's number of contact nodes).

Usage::

    python benchmarks/bench_fem.py              # h = 1.1 mm: about 5,900 dofs per full block
    python benchmarks/bench_fem.py --h-mm 1.6   # coarser
    python benchmarks/bench_fem.py --speed-error   # speed against error (figure data)

``--speed-error`` writes ``speed-error-fem.json`` (``--out``, default ``benchmarks/results/``,
committed with its commit and date) for ``paper_figures.fig_speed_error_methods``: the largest
principal stress of (1) a bar in pure bending with P1, h = 1 to 0.35 mm (estimated:
the P1/P2 bar of :mod:`fem_check.error`; true: the distance to Saint-Venant's exact ``A c``)
and (2) a TIS block under smooth interface tractions with P2, h = 2 to 0.7 mm (estimated: the
three-level bar of ``error="full"``; true: the distance to the P2 solve at 0.5 mm, the finest
run). Cost: the solve plus its error estimate [s]; errors (estimated and true) relative to
the value.

Target of issue 6: under 60 s on 2 cores including meshing. Wall-clock on a shared machine.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from dem.geometry.polyhedron import convex_block
from fem_check.elastic import BlockSolver
from fem_check.error import reference_solvers, solve_with_error
from fem_check.loads import BlockLoad, TractionPatch
from fem_check.mesh import MeshSettings
from fem_check.recovery import recover_nodal_stress, summarise
from validation.cases.fem import (
    MATERIAL,
    _dem_state_check,
    _smooth_tis_load,
    _tis_block,
    dem_tis_state,
    solve_assembly,
    synthetic_tis_state,
)
from validation.provenance import REPO, write_stamped
from validation.report import input_path

SPEED_ERROR_DIR = REPO / "benchmarks" / "results"
BEND_L, BEND_C, BEND_A = 6e-3, 1e-3, 1e9  # bar length, half height [m], sigma_xx = A y [Pa/m]
BEND_H_MM = (1.0, 0.7, 0.5, 0.35)
TIS_H_MM = (2.0, 1.4, 1.0, 0.7)
TIS_REFERENCE_H_MM = 0.5


def _bending_bar():
    """A bar ``[0, L] x [-c, c]^2`` with the linear end tractions of pure bending:
    sigma_xx = A y exactly (Saint-Venant), largest principal stress ``A c``."""
    c, length = BEND_C, BEND_L
    corners = [(x, y, z) for x in (0, length) for y in (-c, c) for z in (-c, c)]

    def cap(x):
        return np.array([(x, -c, -c), (x, c, -c), (x, c, c), (x, -c, c)], float)

    spin = np.array([0.0, 0.0, BEND_A])
    load = BlockLoad(patches=(
        TractionPatch(cap(length), np.zeros(3), -spin, np.array([length, 0.0, 0.0])),
        TractionPatch(cap(0.0), np.zeros(3), spin, np.zeros(3)),
    ))  # fmt: skip
    return convex_block(np.array(corners, float)), load


def _series(label, block, load, degree, h_mm, budget, exact=None) -> dict:
    out = {"label": label, "h_mm": list(h_mm), "cost_s": [], "estimated": [], "true": [],
           "value": []}  # fmt: skip
    for h in h_mm:
        solver = BlockSolver(MATERIAL, MeshSettings(size=h * 1e-3), degree=degree)
        t0 = time.perf_counter()
        _, est = solve_with_error(solver, block, load, reference_solvers(solver, budget), budget)
        out["cost_s"].append(time.perf_counter() - t0)
        e = est.max_principal
        out["value"].append(e.value)
        out["estimated"].append(e.error / abs(e.value) if np.isfinite(e.error) else None)
        out["true"].append(None if exact is None else abs(e.value - exact) / abs(e.value))
    return out


def speed_error() -> dict:
    """Cost, estimated and true relative error of the largest principal stress (notes)."""
    bar, bending = _bending_bar()
    p1 = _series("P1, bar in pure bending (P1/P2 bar)", bar, bending, 1, BEND_H_MM, "cheap",
                 BEND_A * BEND_C)  # fmt: skip
    block = _tis_block(2.5)
    load = _smooth_tis_load(block)
    ref_solver = BlockSolver(MATERIAL, MeshSettings(size=TIS_REFERENCE_H_MM * 1e-3), degree=2)
    reference = summarise(ref_solver.solve(block, load)).max_principal
    p2 = _series("P2, TIS block, smooth tractions (full: three levels)", block, load, 2,
                 TIS_H_MM, "full", reference)  # fmt: skip
    return {"method": "FEM check (scikit-fem)", "quantity": "largest principal stress",
            "tis_reference_h_mm": TIS_REFERENCE_H_MM, "series": [p1, p2]}  # fmt: skip


def write_speed_error(out: str | None) -> None:
    path = Path(out) if out else SPEED_ERROR_DIR / "speed-error-fem.json"
    data = write_stamped(path, speed_error)
    for s in data["series"]:
        print(s["label"])
        for h, c, e, t in zip(s["h_mm"], s["cost_s"], s["estimated"], s["true"], strict=True):
            print(f"  h {h:5.2f} mm {c:8.3f} s  estimated {e}  true {t}")
    print(f"wrote {path}")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--h-mm", type=float, default=1.1, help="mesh size [mm]")
    parser.add_argument("--degree", type=int, default=2)
    parser.add_argument("--speed-error", action="store_true", help="figure data (see notes)")
    parser.add_argument("--out", default=None, help="where --speed-error writes its JSON")
    args = parser.parse_args()
    if args.speed_error:
        write_speed_error(args.out)
        return

    start = time.perf_counter()
    path = input_path("tis-peak-state.npz")
    state = "synthetic admissible state"
    if path.exists():
        blocks, loads, fixed, _ = dem_tis_state(path)
        if _dem_state_check(blocks, loads, fixed)[2]:
            state = f"DEM state {path.name}"
    if state.startswith("synthetic"):
        blocks, loads, fixed = synthetic_tis_state()
    t_state = time.perf_counter() - start
    n_points = sum(len(ld.points) for ld in loads)

    start = time.perf_counter()
    sols, _, solver = solve_assembly(blocks, loads, fixed, args.degree, args.h_mm * 1e-3)
    t_solve = time.perf_counter() - start
    start = time.perf_counter()
    summaries = [summarise(s, recover_nodal_stress(s)) for s in sols]
    t_recover = time.perf_counter() - start
    total = t_solve + t_recover

    dofs = sorted(int(op.n_dofs) for op in solver.operators.values())
    print(
        f"state: {state}, {len(blocks)} blocks, {n_points} point forces (built in {t_state:.2f} s)"
    )
    print(f"P{args.degree}, h = {args.h_mm} mm, {len(dofs)} shapes, dofs per shape {dofs}")
    for stage, sec in solver.timings.items():
        print(f"  {stage:<10} {sec:7.2f} s")
    print(f"  {'recover':<10} {t_recover:7.2f} s")
    other = t_solve - sum(solver.timings.values())
    print(f"  {'other':<10} {other:7.2f} s  (equilibrium checks, support reactions)")
    print(f"total (meshing to recovered stresses): {total:.2f} s  (target < 60 s)")
    worst = int(np.argmax([q.max_principal for q in summaries]))
    print(f"most stressed block {worst}: {summaries[worst].max_principal / 1e6:.2f} MPa")


if __name__ == "__main__":
    main()
