"""Speed and round-off robustness of the static DEM (seed 001 masonry).

Run ``python benchmarks/bench_static.py [--quick] [--table2] [--kernels] [--walls S15,S13]``.
Prints

1. ``--table2``: every Table 2 wall (Restrepo-Velez specimens) to collapse with both interface
   laws and both return-wall models: wall time against the target of 10 s, lambda, termination
   (a run that did not collapse, or raised a StaticSolverError, prints its termination,
   never a lambda), the certificate of a plateau (``dem.static.certificate``), steps and Newton
   iterations (the load-independent measure of the work) and how many of them went into
   Newton solves that failed; ``--save FILE`` writes the rows as
   JSON, ``--baseline FILE`` (such a JSON of an earlier run) adds to each row its time and
   iterations relative to that run and the change of lambda, and prints the totals;
2. ``--kernels``: the same runs (with the validation case's settings) repeated in
   subprocesses under the OpenBLAS kernels ``OPENBLAS_CORETYPE = Haswell, SkylakeX,
   Sandybridge`` (the CPU must support each: AVX2, AVX-512, AVX), and the spread of lambda
   across them (target 1 %); ``python -m validation run masonry-restrepo-kernels`` records it;
3. by default: S11 to collapse for each law and return-wall model, lambda_max of S11 with the
   load step halved and doubled (1 %), and a scaling table from 100 to 10,000 blocks
   (free-standing running-bond walls): set-up, one evaluation of the interface law plus the
   stiffness assembly, one sparse factorisation, and a full collapse run up to
   ``--collapse-max`` blocks; times per block in microseconds;
4. ``--in-plane [SIZES]``: in-plane running-bond walls of about 1,000, 3,000 and 10,000
   blocks (Restrepo-Velez blocks on a fixed foundation, mu 0.7, live load = each block's
   weight along +x), each run to collapse (or ``--in-plane-steps`` steps) with the static DEM
   (resultant law) and solved by the associated limit analysis (resultant model, an upper
   bound) in fresh subprocesses: blocks, dofs, wall time, steps, iterations and the failed
   share, the time per iteration split into law, assembly, factorisation, solves and the rest
   (cProfile), lambda with its bar by both methods and whether the DEM's lies below the upper
   bound within the two bars, the subprocess's peak resident memory, and the growth exponents
   of the time per iteration (against dofs) and of the total time (against blocks);
   ``--lu superlu,pardiso`` runs the static DEM once per sparse LU (``BLOCKMECH_SPARSE_LU``)
   and prints the whole-run ratios and the change of lambda between them.

Times are wall-clock on a shared machine: compare ratios within one run.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import logging
import math
import os
import pstats
import resource
import subprocess
import sys
import time
from pathlib import Path

from dem.estimate import format_estimate
from dem.scene import Scene
from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import (
    RESTREPO_BLOCK_MM,
    RESTREPO_MU,
    RESTREPO_NAMES,
    RESTREPO_UNIT_WEIGHT,
    SPECIMENS,
    restrepo_specimen,
)
from dem.static import StaticSettings, StaticSolverError, newton, solve_collapse
from dem.static.dead_load import solve_dead_load
from dem.static.model import Model
from dem.static.newton import Corrector, factor
from dem.static.pardiso import PardisoLU
from limit.problems import LimitSettings, build_static_problem
from limit.solve import solve_static

TARGET_S = 10.0
LAWS = ("resultant", "fibre")
VARIANTS = ("fixed_column", "blocks")
IN_PLANE_SIZES = {100: (8, 12), 1000: (24, 40), 3000: (50, 60), 10000: (70, 140)}
"""Blocks (about) -> (blocks per even course, courses) of the in-plane walls: 981, 3,031 and
9,871 blocks with the foundation."""
IN_PLANE_TARGET_S = {100: None, 1000: None, 3000: 15.0, 10000: 60.0}


def run_wall(name: str, model: str, variant: str) -> dict:
    """One Table 2 wall to collapse: lambda (None if no collapse), termination, wall time."""
    spec = SPECIMENS[f"restrepo-{name}"]
    scene = spec.build() if spec.supports == "base+beams" else spec.build(return_walls=variant)
    settings = StaticSettings(interface_model=model, mu=spec.joint.mu, on_failure="return")
    start = time.perf_counter()
    row = {"name": name, "model": model, "variant": variant}
    try:
        result = solve_collapse(scene, settings)
    except StaticSolverError as exc:  # e.g. no equilibrium under the dead load
        logging.getLogger(__name__).warning("%s %s %s: %s", name, model, variant, exc)
        return {
            **row,
            "lam": None,
            "termination": "error",
            "steps": 0,
            "iterations": 0,
            "failed_iterations": 0,
            "wall_s": time.perf_counter() - start,
        }
    return {
        **row,
        "lam": result.lambda_max if result.collapsed else None,
        "lam_error": result.lambda_estimate.error if result.collapsed else None,
        "termination": result.termination,
        "certificate": result.certificate,
        "steps": result.n_steps,
        "iterations": result.n_iterations,
        "failed_iterations": result.n_failed_iterations,
        "wall_s": time.perf_counter() - start,
    }


def table2_runs(names) -> list[tuple[str, str, str]]:
    runs = []
    for name in names:
        beams = SPECIMENS[f"restrepo-{name}"].supports == "base+beams"
        for variant in ("none",) if beams else VARIANTS:
            runs += [(name, model, variant) for model in LAWS]
    return runs


def _line(r: dict) -> str:
    lam = "no collapse" if r["lam"] is None else f"{r['lam']:.4f}"
    share = r.get("failed_iterations", 0) / max(r["iterations"], 1)
    ok = "OK" if r["wall_s"] <= TARGET_S else "over target"
    return (
        f"{r['name']:9s} {r['model']:9s} {r['variant']:12s} lambda {lam:>11s} "
        f"{r['termination']:10s} {r.get('certificate', ''):12s} steps {r['steps']:4d} "
        f"iterations {r['iterations']:5d} "
        f"(failed {r.get('failed_iterations', 0):5d}, {share:4.0%}) {r['wall_s']:7.2f} s  {ok}"
    )


def _key(r: dict) -> str:
    return f"{r['name']} {r['model']} {r['variant']}"


def _ratios(r: dict, before: dict | None) -> str:
    """Time and iterations of ``r`` over those of the same run in ``before``, and the change
    of lambda."""
    if before is None:
        return "  (not in baseline)"
    time_ratio = r["wall_s"] / max(before["wall_s"], 1e-9)
    iter_ratio = r["iterations"] / max(before["iterations"], 1)
    if r["lam"] is None or before["lam"] is None:
        dlam = "lambda: " + ("same termination" if r["lam"] is before["lam"] else "changed")
    else:
        dlam = f"lambda {before['lam']:.4f} -> {r['lam'] / before['lam'] - 1:+.2%}"
        bar = r.get("lam_error")
        if bar is not None:
            inside = abs(r["lam"] - before["lam"]) <= bar
            dlam += f" ({'within' if inside else 'OUTSIDE'} its bar +- {bar:.2g})"
    return f"  time {time_ratio:4.2f}x  iterations {iter_ratio:4.2f}x  {dlam}"


def table2(names, save: Path | None = None, baseline: Path | None = None) -> None:
    """Every Table 2 run of ``names``; saves the rows to ``save`` (JSON) and prints the ratio
    of time and iterations to those of the same run in the JSON ``baseline``."""
    print("== every Table 2 wall to collapse (target <= 10 s per wall) ==")
    before = {}
    if baseline is not None:
        before = {_key(r): r for r in json.loads(baseline.read_text())}
    solve_collapse(
        restrepo_specimen("S15", "fixed_column"), StaticSettings(max_steps=2, on_failure="return")
    )
    rows = []
    for run in table2_runs(names):
        r = run_wall(*run)
        rows.append(r)
        extra = _ratios(r, before.get(_key(r))) if baseline is not None else ""
        print(_line(r) + extra, flush=True)
        if save is not None:
            save.write_text(json.dumps(rows, indent=1))
    total = sum(r["iterations"] for r in rows)
    failed = sum(r["failed_iterations"] for r in rows)
    print(
        f"failed share over {len(rows)} runs: {failed} of {total} iterations "
        f"({failed / max(total, 1):.0%})"
    )
    if before:
        _totals(rows, before)


def _totals(rows: list[dict], before: dict) -> None:
    common = [r for r in rows if _key(r) in before]
    if not common:
        return
    t0 = sum(before[_key(r)]["wall_s"] for r in common)
    t1 = sum(r["wall_s"] for r in common)
    i0 = sum(before[_key(r)]["iterations"] for r in common)
    i1 = sum(r["iterations"] for r in common)
    print(
        f"total of {len(common)} runs: time {t0:.1f} s -> {t1:.1f} s ({t1 / t0:.2f}x), "
        f"iterations {i0} -> {i1} ({i1 / max(i0, 1):.2f}x)"
    )


def kernels(names) -> None:
    """The spread of lambda across OpenBLAS kernels: the ``masonry-restrepo-kernels`` case's
    subprocess per kernel (:mod:`validation.cases.masonry`), on the walls ``names``."""
    from validation.cases.masonry import KERNELS, _run_under_kernels

    print(f"== lambda under the OpenBLAS kernels {', '.join(KERNELS)} (target 1 %) ==")
    for run in table2_runs(names):
        out = _run_under_kernels(*run, quick=False)
        lams = [r["lam"] for r in out]
        terms = "/".join(r["termination"] for r in out)
        if all(lam is not None for lam in lams):
            spread = (max(lams) - min(lams)) / min(lams)
            values = " / ".join(f"{lam:.5f}" for lam in lams)
            verdict = "OK" if spread <= 0.01 else "over target"
            print(f"{' '.join(run):34s} {values}  spread {spread:.2%}  {terms}  {verdict}")
        else:
            print(f"{' '.join(run):34s} not every run collapsed: {terms}")


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
        for model in LAWS:
            settings = StaticSettings(interface_model=model)
            start = time.perf_counter()
            m = Model(scene, settings)
            setup = time.perf_counter() - start
            dead, _ = solve_dead_load(Corrector(m, settings))
            floor = settings.law_settings.tangent_floor
            reps = 3
            start = time.perf_counter()
            for _ in range(reps):
                D = m.evaluate(dead.u, floor).law.D
                m.stiffness(D)
            law = (time.perf_counter() - start) / reps
            A = m.stiffness(D, m.w)
            start = time.perf_counter()
            for _ in range(reps):
                factor(A)
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


def in_plane_wall(n_per_course: int, n_courses: int) -> Scene:
    """A running-bond wall of Restrepo-Velez blocks on a fixed foundation, mu 0.7, with the
    live load = each free block's weight along +x (in its plane)."""
    return running_bond_wall(
        n_per_course, n_courses, *RESTREPO_BLOCK_MM, RESTREPO_UNIT_WEIGHT, mu=RESTREPO_MU,
        live="in_plane", name=f"in_plane_{n_per_course}x{n_courses}",
    )  # fmt: skip


PROFILED = {
    "law": Model.evaluate,
    "assembly": Model.stiffness,
    "factorisation": factor,
    "solves": ("~", "<method 'solve' of 'SuperLU' objects>"),
    "pardiso solves": PardisoLU.solve,
}
"""Parts of a Newton iteration -> function (or cProfile's (file, name) of a built-in) whose
cumulative time cProfile gives: the interface law with ``H U`` and ``H^T f`` (every trial of
the line search), the assembly of ``K`` or the bordered matrix, the sparse LU, and the
triangular solves (GMRES's included) of SuperLU or PARDISO."""


def _profile_key(part) -> tuple:
    """cProfile's (file, line, name) of a function, or (file suffix, name) of a built-in."""
    if isinstance(part, tuple):
        return part
    code = part.__code__
    return code.co_filename, code.co_firstlineno, code.co_name


def _profiled_parts(stats: pstats.Stats) -> dict[str, float]:
    """Cumulative seconds of each part of :data:`PROFILED` in ``stats``."""
    keys = {part: _profile_key(fn) for part, fn in PROFILED.items()}
    out = dict.fromkeys(PROFILED, 0.0)
    for (path, line, func), (_, _, _, cumulative, _) in stats.stats.items():
        for part, key in keys.items():
            exact = len(key) == 3 and (path, line, func) == key
            if exact or (len(key) == 2 and func == key[1] and path.endswith(key[0])):
                out[part] += cumulative
    return out


def _warm_up(method: str) -> None:
    """One tiny in-plane wall by ``method``: numba's cached kernels and the solvers'
    imports are loaded before the timed run."""
    scene = in_plane_wall(4, 4)
    if method == "static":
        solve_collapse(scene, StaticSettings(max_steps=2, on_failure="return"))
    else:
        solve_static(build_static_problem(scene, LimitSettings(interface_model="resultant")))


def _static_row(scene: Scene, max_steps: int | None) -> dict:
    """The resultant law to collapse (or ``max_steps``) under cProfile: the result and the
    seconds of each part of :data:`PROFILED`."""
    extra = {} if max_steps is None else {"max_steps": max_steps}
    settings = StaticSettings(interface_model="resultant", on_failure="return", **extra)
    profile = cProfile.Profile()
    profile.enable()
    res = solve_collapse(scene, settings)
    profile.disable()
    return {
        "lam": res.lambda_max,
        "lam_error": res.lambda_estimate.error,
        "collapsed": res.collapsed,
        "termination": res.termination,
        "steps": res.n_steps,
        "iterations": res.n_iterations,
        "failed_iterations": res.n_failed_iterations,
        "parts_s": _profiled_parts(pstats.Stats(profile)),
    }


def run_in_plane(size: int, method: str, max_steps: int | None = None) -> dict:
    """One in-plane wall by ``method`` ("static": the resultant law to collapse or
    ``max_steps``; "limit": the associated static programme, resultant model, an upper bound
    with its bar from the solver's certificate), timed after a warm-up from the built scene;
    with this process's peak resident memory before and after [MiB]."""
    scene = in_plane_wall(*IN_PLANE_SIZES[size])
    scene.assembly.interfaces()
    _warm_up(method)
    row = {
        "size": size,
        "blocks": scene.n_blocks,
        "dofs": int(scene.supports.free_dofs.sum()),
        "method": method,
        "lu": newton.BACKEND.name,
        "base_mib": _peak_mib(),
    }
    start = time.perf_counter()
    if method == "static":
        row |= _static_row(scene, max_steps)
    else:
        problem = build_static_problem(scene, LimitSettings(interface_model="resultant"))
        res = solve_static(problem)
        est = res.lambda_estimate
        row |= {"lam": res.lam, "lam_error": est.error, "termination": res.status}
    row["wall_s"] = time.perf_counter() - start
    row["peak_mib"] = _peak_mib()
    return row


def _peak_mib() -> float:
    """Peak resident memory of this process so far [MiB] (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _subprocess_row(size: int, method: str, max_steps: int | None, lu: str = "auto") -> dict:
    cmd = [sys.executable, __file__, "--in-plane-one", f"{size}:{method}:{max_steps or 0}"]
    env = os.environ | {newton.LU_ENV: lu}
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, env=env).stdout
    return json.loads(out.strip().splitlines()[-1])


def _static_line(st: dict) -> str:
    """Blocks, dofs, the path's work and the time of one iteration split into its parts."""
    n_it = max(st["iterations"], 1)
    parts = st["parts_s"]
    other = st["wall_s"] - sum(parts.values())
    split = " ".join(f"{k} {1e3 * v / n_it:.1f}" for k, v in (parts | {"other": other}).items())
    target = IN_PLANE_TARGET_S[st["size"]]
    verdict = "" if target is None else (" OK" if st["wall_s"] <= target else " over target")
    return (
        f"{st['blocks']:6d} blocks {st['dofs']:6d} dofs | {st['lu']:>7s} "
        f"{st['wall_s']:7.1f} s{verdict}"
        f" lambda {format_estimate(st['lam'], st['lam_error'])} {st['termination']} steps "
        f"{st['steps']} iterations {st['iterations']} (failed {st['failed_iterations']}, "
        f"{st['failed_iterations'] / n_it:.0%}) {1e3 * st['wall_s'] / n_it:.1f} ms/iteration "
        f"[ms: {split}] peak {st['peak_mib']:.0f} MiB (before {st['base_mib']:.0f})"
    )


def _limit_line(st: dict, li: dict) -> str:
    """The limit analysis and whether the static DEM lies below its upper bound within the
    two bars."""
    holds = st["lam"] - st["lam_error"] <= li["lam"] + li["lam_error"]
    return (
        f"{'':20s}| limit  {li['wall_s']:7.1f} s lambda "
        f"{format_estimate(li['lam'], li['lam_error'])} (upper bound) {li['termination']} "
        f"peak {li['peak_mib']:.0f} MiB | DEM <= upper bound: "
        f"{'holds' if holds else 'VIOLATED'} (DEM/limit {st['lam'] / li['lam']:.4f})"
    )


def _growth(st: dict, last: dict) -> str:
    """Exponents of the time per iteration and of the total time against the size."""
    per = [r["wall_s"] / max(r["iterations"], 1) for r in (last, st)]
    k_it = math.log(per[1] / per[0]) / math.log(st["dofs"] / last["dofs"])
    k_all = math.log(st["wall_s"] / last["wall_s"]) / math.log(st["blocks"] / last["blocks"])
    return (
        f"{'':20s}| since {last['blocks']} blocks: time per iteration ~ n^{k_it:.2f}, "
        f"total time ~ n^{k_all:.2f}"
    )


def _lu_ratio(first: dict, other: dict) -> str:
    """Whole-run time of ``first`` over ``other`` (two sparse LUs on one wall) and the
    change of lambda between them."""
    return (
        f"{'':20s}| {first['lu']} / {other['lu']}: whole run "
        f"{first['wall_s'] / other['wall_s']:.2f}x"
        f", iterations {first['iterations']} / {other['iterations']}, lambda change "
        f"{abs(other['lam'] - first['lam']):.2e} ({other['lam']!r})"
    )


def in_plane(sizes, max_steps: int | None = None, limit: bool = True, lus=("auto",)) -> None:
    """Every in-plane wall of ``sizes`` with the static DEM, once per sparse LU of ``lus``
    (``dem.static.newton.select_backend``), and (``limit``) the limit analysis, each in a
    fresh subprocess (so its peak memory is its own); the static path to collapse, or
    ``max_steps`` steps (which measures the cost per iteration of the larger walls in a
    bounded time)."""
    print("== in-plane running-bond walls, live load = weight along +x ==")
    cap = "to collapse" if max_steps is None else f"at most {max_steps} steps"
    print(f"static DEM (resultant law) {cap}, under cProfile; load average at start: "
          f"{' '.join(f'{x:.1f}' for x in _load())}")  # fmt: skip
    last = None
    for size in sizes:
        rows = [_subprocess_row(size, "static", max_steps, lu) for lu in lus]
        for st in rows:
            print(_static_line(st), flush=True)
        for other in rows[1:]:
            print(_lu_ratio(rows[0], other), flush=True)
        st = rows[-1]
        if last is not None:
            print(_growth(st, last), flush=True)
        if limit:
            print(_limit_line(st, _subprocess_row(size, "limit", None)), flush=True)
        print(f"{'':20s}| load average {_load()[0]:.1f}", flush=True)
        last = st


def _load() -> tuple[float, float, float]:
    return os.getloadavg()


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer variants and sizes")
    parser.add_argument("--collapse-max", type=int, default=2000)
    parser.add_argument("--table2", action="store_true", help="every Table 2 wall, both laws")
    parser.add_argument("--kernels", action="store_true", help="spread across OpenBLAS kernels")
    parser.add_argument("--walls", default=",".join(RESTREPO_NAMES), help="Table 2 walls")
    parser.add_argument("--save", type=Path, help="--table2: write the rows to this JSON file")
    parser.add_argument(
        "--baseline",
        type=Path,
        help="--table2: JSON of an earlier run (--save); print time, iterations and lambda "
        "against it per wall",
    )
    parser.add_argument(
        "--in-plane",
        nargs="?",
        const="1000,3000,10000",
        help="in-plane walls of about these many blocks (1000, 3000, 10000)",
    )
    parser.add_argument(
        "--in-plane-steps", type=int, help="--in-plane: stop each static path after so many steps"
    )
    parser.add_argument("--no-limit", action="store_true", help="--in-plane: the static DEM alone")
    parser.add_argument(
        "--lu",
        default="auto",
        help="--in-plane: sparse LUs to run the static DEM with, e.g. superlu,pardiso (ratios "
        "against the first)",
    )
    parser.add_argument("--in-plane-one", help=argparse.SUPPRESS)  # SIZE:METHOD:STEPS
    args = parser.parse_args(argv)
    if args.in_plane_one:
        size, method, steps = args.in_plane_one.split(":")
        print(json.dumps(run_in_plane(int(size), method, int(steps) or None)))
        return
    if args.in_plane:
        sizes = [int(x) for x in args.in_plane.split(",")]
        in_plane(sizes, args.in_plane_steps, limit=not args.no_limit, lus=args.lu.split(","))
        return
    names = args.walls.split(",")
    if args.table2:
        table2(names, args.save, args.baseline)
    if args.kernels:
        kernels(names)
    if args.table2 or args.kernels:
        return
    print("== S11 to collapse (target < 10 s) ==")
    for model in LAWS:
        for variant in VARIANTS:
            print(_line(run_wall("S11", model, variant)), flush=True)
    stability(args.quick)
    sizes = (100, 300, 1000) if args.quick else (100, 300, 1000, 3000, 10000)
    scaling(sizes, args.collapse_max)


if __name__ == "__main__":
    main()
