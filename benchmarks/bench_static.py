"""Speed of the static DEM (seed 001 masonry): one Table 2 specimen, and scaling in size.

Run ``python benchmarks/bench_static.py [--quick]``. Prints

1. the wall time of one Restrepo-Velez specimen (S11, about 300 blocks) to collapse for each
   interface law and return-wall model, against the target of 10 s on 2 cores;
2. the stability target: lambda_max of S11 with the load step halved and doubled (1 %);
3. a scaling table from 100 to 10,000 blocks (free-standing running-bond walls, resultant and
   fibre laws): set-up (interfaces, H blocks), one evaluation of the interface law plus the
   stiffness assembly, one sparse factorisation of the tangent, and a full collapse run up to
   ``--collapse-max`` blocks; times per block in microseconds.

Times are wall-clock on a shared machine: compare ratios within one run.
"""

from __future__ import annotations

import argparse
import math
import time

from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import SPECIMENS, restrepo_specimen
from dem.static import StaticSettings, _factor, _Model, _newton_dead, solve_collapse

TARGET_S = 10.0


def specimen(quick: bool) -> None:
    print("== one Table 2 specimen to collapse (target < 10 s) ==")
    variants = [("fibre", "blocks"), ("resultant", "fixed_column")]
    if not quick:
        variants += [("fibre", "fixed_column"), ("resultant", "blocks")]
    spec = SPECIMENS["restrepo-S11"]
    for model, variant in variants:
        scene = restrepo_specimen("S11", variant)
        settings = StaticSettings(interface_model=model, on_failure="return")
        solve_collapse(scene, StaticSettings(interface_model=model, max_steps=2))  # compile
        start = time.perf_counter()
        result = solve_collapse(scene, settings)
        wall = time.perf_counter() - start
        print(
            f"S11 {model:9s} {variant:12s} blocks {scene.n_blocks:4d}  lambda_max "
            f"{result.lambda_max:.4f} (test {spec.reference})  steps {result.n_steps:4d} "
            f"iterations {result.n_iterations:5d}  {wall:6.2f} s  "
            f"{'OK' if wall < TARGET_S else 'over target'}"
        )


def stability(quick: bool) -> None:
    print("== lambda_max of S11 with the load step halved and doubled (target 1 %) ==")
    variants = [("resultant", "fixed_column")]
    if not quick:
        variants += [("fibre", "blocks"), ("resultant", "blocks")]
    for model, variant in variants:
        scene = restrepo_specimen("S11", variant)
        lam = {}
        for step in (0.005, 0.01, 0.02):
            settings = StaticSettings(interface_model=model, load_step=step, on_failure="return")
            lam[step] = solve_collapse(scene, settings).lambda_max
        spread = max(abs(lam[s] / lam[0.01] - 1) for s in (0.005, 0.02))
        values = "  ".join(f"{s}: {v:.5f}" for s, v in lam.items())
        print(
            f"S11 {model:9s} {variant:12s} {values}  largest change {spread:.2%}  "
            f"{'OK' if spread < 0.01 else 'over target'}"
        )


def scaling(sizes, collapse_max: int) -> None:
    print("== scaling: free-standing running-bond walls, live load = weight out of plane ==")
    header = (
        f"{'blocks':>7s} {'dofs':>7s} {'model':>9s} {'setup s':>8s} {'law+K ms':>9s} "
        f"{'LU ms':>8s} {'collapse s':>10s} {'us/block/iter':>13s} {'lambda':>8s}"
    )
    print(header)
    for target in sizes:
        n = max(2, int(round(math.sqrt(target / 2))))
        courses = max(2, int(round(target / n)))
        scene = running_bond_wall(n, courses, 81, 210, 70, 20, 0.7, live="weight")
        for model in ("resultant", "fibre"):
            settings = StaticSettings(interface_model=model)
            start = time.perf_counter()
            m = _Model(scene, settings)
            setup = time.perf_counter() - start
            u, _, _ = _newton_dead(m, settings)
            reps = 3
            start = time.perf_counter()
            for _ in range(reps):
                _, D, _, _, _ = m.evaluate(m.full(u))
                m.stiffness(D)
            law = (time.perf_counter() - start) / reps
            A = m.stiffness(D, bordered=True)
            start = time.perf_counter()
            for _ in range(reps):
                _factor(A)
            lu = (time.perf_counter() - start) / reps
            coll, lam, per = float("nan"), float("nan"), float("nan")
            if scene.n_blocks <= collapse_max:
                start = time.perf_counter()
                res = solve_collapse(scene, settings)
                coll = time.perf_counter() - start
                lam = res.lambda_max
                per = coll / max(res.n_iterations, 1) / scene.n_blocks * 1e6
            print(
                f"{scene.n_blocks:7d} {m.n_free:7d} {model:>9s} {setup:8.2f} {law * 1e3:9.1f} "
                f"{lu * 1e3:8.1f} {coll:10.2f} {per:13.1f} {lam:8.4f}"
            )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer variants and sizes")
    parser.add_argument("--collapse-max", type=int, default=2000)
    args = parser.parse_args(argv)
    specimen(args.quick)
    stability(args.quick)
    sizes = (100, 300, 1000) if args.quick else (100, 300, 1000, 3000, 10000)
    scaling(sizes, args.collapse_max)


if __name__ == "__main__":
    main()
