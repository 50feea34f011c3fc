"""Time of the static limit analysis against the number of blocks.

Running-bond walls (Restrepo-Velez blocks, 21 courses or square-ish) fixed on their left
column under out-of-plane load proportional to weight; for each size: interface detection
(dem.geometry), programme assembly, cvxpy compilation, Clarabel, certificate, total.

Usage::

    python benchmarks/bench_limit.py            # up to about 3,000 blocks
    python benchmarks/bench_limit.py --huge     # adds a 9,900-block wall (minutes)
    python benchmarks/bench_limit.py --quick    # up to about 1,000 blocks
    python benchmarks/bench_limit.py --models vertex resultant --json out.json
    python benchmarks/bench_limit.py --speed-error   # speed against error (figure data)

``--speed-error`` writes ``speed-error-limit.json`` (``--out``, default ``benchmarks/results/``,
committed with its commit and date) for ``paper_figures.fig_speed_error_methods``: on a
263-block wall, the inscribed friction polygons of 4 to 32 sides (estimated error: the
outer-polygon bracket of ``error="cheap"``; true error: the distance to the exact cones) and
Clarabel's tolerance from 1e-4 to 1e-10 with the exact cones (estimated: ``lambda_estimate``;
true: the distance to the solve at 1e-11). Errors (estimated and true) are relative to the
returned lambda.

Speed targets of issue 4: a Table 2 wall (about 300 blocks) in under 1 s, 10,000 blocks in
under 60 s on 2 cores. Times are wall-clock on a shared machine: compare ratios within a run.

Measured 2026-11-21 (2 cores, the other core busy with a DEM run; vertex model, Clarabel
0.11.1 with QDLDL, tol 1e-9): 263 blocks 0.23 s, 981 blocks 2.3 s, 3,031 blocks 19.5 s, 9,871
blocks (29,260 interfaces, 117,040 cones) 56-60 s of Clarabel and 59-62 s for assembly +
compilation + Clarabel + certificate (plus 6.3 s to build the wall and find its interfaces),
lambda = 0.02565. 22-65 interior-point iterations; the time per iteration follows the fill of
the KKT factorisation (~n^1.5, a planar block graph). Changes that took the 10,000-block wall
from 206 s (session 1, loaded machine) to about 60 s: the p >= 0 rows implied by the cones
left out (-13 %), Clarabel's iterative refinement off for the vertex model unless a solve is
inaccurate (-15 %), and the torsion coefficients vectorised (assembly 3.4 s -> 0.4 s). Tried
and rejected: ``faer`` (1 or 2 threads: 1.3-3x slower than QDLDL here), the kinematic
(velocity) form (no faster: the same block graph is factorised), per-block force scaling (fewer
iterations but Clarabel stops early, 1e-3 off in lambda), SCS (thousands of iterations), looser
tolerances (1e-7: 21 instead of 22 iterations). A supernodal LDL^T with nested dissection
(Pardiso, MOSEK, CHOLMOD) would be the next step; the Clarabel wheel has none.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

from dem.scenes.running_bond_wall import running_bond_wall
from limit.problems import LimitSettings, build_static_problem
from limit.solve import limit_analysis, solve_static
from validation.provenance import REPO, write_stamped

SIZES_FULL = ((6, 13), (12, 21), (24, 40), (50, 60))
SIZE_HUGE = (70, 140)
SIZES_QUICK = ((6, 13), (12, 21), (24, 40))


def bench_one(n_per_course: int, n_courses: int, model: str, certify: bool = True) -> dict:
    """Timings [s] of one wall."""
    t0 = time.perf_counter()
    scene = running_bond_wall(
        n_per_course, n_courses, 28.24, 79.78, 39.68, 26.8, mu=0.7, fixed_columns=("left",)
    )
    interfaces = scene.assembly.interfaces()
    t1 = time.perf_counter()
    sp_ = build_static_problem(scene, LimitSettings(interface_model=model))
    t2 = time.perf_counter()
    res = solve_static(sp_, certify=certify)
    t3 = time.perf_counter()
    return {
        "model": model,
        "n_blocks": scene.n_blocks,
        "n_interfaces": interfaces.n_interfaces,
        "n_cones": sp_.n_cones,
        "geometry_s": t1 - t0,
        "assembly_s": t2 - t1,
        "compile_s": res.compile_s,
        "clarabel_s": res.solve_s,
        "solve_and_certify_s": t3 - t2,
        "limit_total_s": t3 - t1,
        "lam": res.lam,
        "status": res.status,
        "certificate_worst": res.certificate.worst() if certify else None,
    }


SPEED_ERROR_DIR = REPO / "benchmarks" / "results"
SPEED_ERROR_WALL = (12, 21)
POLYGON_SIDES = (4, 8, 16, 32)
TOLERANCES = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)


def _timed(scene, settings, error: str = "cheap") -> tuple[float, object]:
    t0 = time.perf_counter()
    res = limit_analysis(scene, settings, error=error)
    return time.perf_counter() - t0, res


def speed_error() -> dict:
    """Cost, estimated and true relative error of lambda along two refinements (module
    notes)."""
    scene = running_bond_wall(
        *SPEED_ERROR_WALL, 28.24, 79.78, 39.68, 26.8, mu=0.7, fixed_columns=("left",)
    )
    base = LimitSettings(dead_load_check=False)
    exact = limit_analysis(scene, base.with_(tol=1e-11, cert_tol=1e-4)).lam
    series = []
    polygon = {"label": "inscribed friction polygon, 4-32 sides (cheap bracket)",
               "cost_s": [], "estimated": [], "true": [], "sides": list(POLYGON_SIDES)}  # fmt: skip
    for k in POLYGON_SIDES:
        cost, res = _timed(scene, base.with_(friction_polygon=k))
        polygon["cost_s"].append(cost)
        polygon["estimated"].append(res.lambda_estimate.error / abs(res.lam))
        polygon["true"].append(abs(res.lam - exact) / abs(res.lam))
    series.append(polygon)
    tol = {"label": "Clarabel tolerance 1e-4 to 1e-10 (exact cones)",
           "cost_s": [], "estimated": [], "true": [], "tol": list(TOLERANCES)}  # fmt: skip
    for t in TOLERANCES:
        cost, res = _timed(scene, base.with_(tol=t, cert_tol=5e-2))
        tol["cost_s"].append(cost)
        tol["estimated"].append(res.lambda_estimate.error / abs(res.lam))
        tol["true"].append(abs(res.lam - exact) / abs(res.lam))
    series.append(tol)
    n_blocks = scene.n_blocks
    return {"method": "limit analysis (cvxpy + Clarabel)", "scene": f"{n_blocks}-block wall",
            "lambda_exact": exact, "series": series}  # fmt: skip


def write_speed_error(out: str | None) -> None:
    path = Path(out) if out else SPEED_ERROR_DIR / "speed-error-limit.json"
    data = write_stamped(path, speed_error)
    for s in data["series"]:
        print(s["label"])
        for c, e, t in zip(s["cost_s"], s["estimated"], s["true"], strict=True):
            print(f"  {c:8.3f} s  estimated {e:9.2e}  true {t:9.2e}")
    print(f"wrote {path}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--huge", action="store_true", help="add a 9,900-block wall")
    parser.add_argument("--models", nargs="+", default=["vertex", "resultant"])
    parser.add_argument("--json", default=None)
    parser.add_argument("--speed-error", action="store_true", help="figure data (see notes)")
    parser.add_argument("--out", default=None, help="where --speed-error writes its JSON")
    args = parser.parse_args(argv)
    warnings.filterwarnings("ignore")
    if args.speed_error:
        write_speed_error(args.out)
        return 0
    sizes = SIZES_QUICK if args.quick else SIZES_FULL
    if args.huge:
        sizes = (*sizes, SIZE_HUGE)
    out = []
    header = (
        f"{'model':9s} {'blocks':>7s} {'ifaces':>7s} {'geom':>7s} {'assemble':>8s} "
        f"{'compile':>8s} {'clarabel':>8s} {'limit':>8s} {'lambda':>9s}"
    )
    print(header)
    for n, nc in sizes:
        for model in args.models:
            r = bench_one(n, nc, model)
            out.append(r)
            print(
                f"{model:9s} {r['n_blocks']:7d} {r['n_interfaces']:7d} {r['geometry_s']:7.2f} "
                f"{r['assembly_s']:8.2f} {r['compile_s']:8.2f} {r['clarabel_s']:8.2f} "
                f"{r['limit_total_s']:8.2f} {r['lam']:9.5f}",
                flush=True,
            )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
