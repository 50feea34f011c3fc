"""Time to recover the stresses of all 49 blocks of a 5 x 5 TIS panel state (P2).

Meshing (gmsh, once per block shape), assembly (K, M, rigid modes, boundary facets),
factorisation (once per shape), load mapping (consistent point loads), solves and stress
recovery, for the 49 blocks of a 5 x 5 panel. The state is the DEM peak state
``validation/results/tis-peak-state.npz`` when it is balanced, else the synthetic statically
admissible state of ``validation.cases.fem`` (about the DEM's number of contact nodes).

Usage::

    python benchmarks/bench_fem.py              # h = 1.1 mm: about 5,900 dofs per full block
    python benchmarks/bench_fem.py --h-mm 1.6   # coarser

Target of issue 6: under 60 s on 2 cores including meshing. Wall-clock on a shared machine.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from fem_check.recovery import recover_nodal_stress, summarise
from validation.cases.fem import (
    RESULTS_DIR,
    _dem_state_check,
    dem_tis_state,
    solve_assembly,
    synthetic_tis_state,
)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--h-mm", type=float, default=1.1, help="mesh size [mm]")
    parser.add_argument("--degree", type=int, default=2)
    args = parser.parse_args()

    start = time.perf_counter()
    path = RESULTS_DIR / "tis-peak-state.npz"
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
