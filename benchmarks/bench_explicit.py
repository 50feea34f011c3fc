"""Cost of the explicit solver: per node per step, the converged 5 x 5 run, the seed's resolution.

Costs per node and step count every node of the model (surface nodes and indenter nodes), not
only the nodes tested in a step. The machine is shared: wall and process-CPU times are both
printed (CPU / wall says how much of the cores we had) with the load average, and serial and
parallel are compared within one run.

1. Step cost on the relaxed 5 x 5, 2.5 degree panel for several node spacings, with the serial
   and the parallel node loop: a whole step (separated entries skipped while they cannot
   touch), and the node loop over every entry in four variants that give its profile
   (``PARTS``): every entry skipped (bookkeeping and the pairs' frames), signed distance only,
   plus the normal force and the sums, and everything (friction included). Then the serial /
   parallel ratio of the step's wall time, with the thread count and threading layer.
2. The full 5 x 5, 2.5 degree run (relaxation + indentation until the central block is out) at
   the discretisation ``tis-convergence`` calls converged (``validation.cases.tis.CONVERGED``),
   with its wall time and cost per node per step (issue 12 target: 15 ns). ``--reference FILE``
   checks that a change of the code leaves the results alone: the first run writes the curve
   (P, delta, block poses, energies) to ``FILE``, later runs compare theirs with it exactly.
3. The seed's resolution, node spacing 0.06 mm (about half a million nodes): set-up time, the
   measured cost of a step, and the run time projected from it and the step count of the run
   of item 2 (the number of steps does not depend on the node spacing: the time step follows
   the total stiffness, which the tributary areas keep). ``--seed-full`` runs it instead of
   projecting (target: 10 minutes on 2 cores; seed 000: about 50 CPU hours).

Usage::

    python benchmarks/bench_explicit.py               # 1, 2 and 3 (projected)
    python benchmarks/bench_explicit.py --quick       # 1, a coarse 2, and 3 (projected)
    python benchmarks/bench_explicit.py --seed-full   # 1, 2 and the full run of 3
    python benchmarks/bench_explicit.py --reference /tmp/curve.npz   # on main, then on a branch
"""

from __future__ import annotations

import argparse
import os
import time

import numba
import numpy as np

from dem.explicit import ExplicitModel, ExplicitSettings, RelaxationSettings
from dem.kernels.contact_force import node_contacts, node_contacts_parallel
from dem.kernels.integrate import quat_to_rot
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM
from validation.cases.tis import CONVERGED, QUICK, run_panel

SEED_SPACING_MM = 0.06
SEED_STEPS = 50
"""Steps timed at the seed's resolution."""


def relaxed_panel(spacing_mm: float, parallel: bool) -> ExplicitModel:
    scene = tis_panel(5, 2.5)
    settings = ExplicitSettings(
        k_n=tis_panel_k_def(5), node_spacing=spacing_mm * MM, parallel=parallel
    )
    model = ExplicitModel(scene, settings, scene.meta["central_block"], 1.25 * MM)
    model.relax(RelaxationSettings(min_steps=200))
    model.advance(10)  # compile
    return model


def clock(fn, n: int) -> tuple[float, float]:
    """Wall and process-CPU seconds per call."""
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for _ in range(n):
        fn()
    return (time.perf_counter() - wall0) / n, (time.process_time() - cpu0) / n


def step_cost(model: ExplicitModel, n_steps: int) -> dict:
    """Per-step cost of the whole step and of parts of its node loop (see ``PARTS``)."""
    st, sc = model.state, model.scratch
    quat_to_rot(st.motion.quat, sc.rot)
    kernel = node_contacts_parallel if model.parallel else node_contacts

    def loop(contacts, law, reset):
        def run():
            reset(sc)
            constants = (model.surface, model.bodies, model.shapes, law)
            kernel(constants, (contacts, st.motion), 1e-9, sc, model.pairs, False)

        return run

    contacts = st.contacts._replace(shear=st.contacts.shear.copy())
    parts = {"step": clock(lambda: model.advance(n_steps), 1)}
    parts["step"] = tuple(x / n_steps for x in parts["step"])
    shares = entry_shares(model)
    for name, (weight, k_t, gap) in PARTS.items():
        c = contacts if weight else contacts._replace(weight=np.zeros_like(contacts.weight))
        law = model.law if k_t else model.law._replace(k_t=0.0)
        run = loop(c, law, lambda s, gap=gap: s.skip_gap.fill(gap))
        run()  # compile
        parts[name] = clock(run, n_steps)
    return {"nodes": model.nodes.n_nodes + len(model.indenter.block),
            "entries": model.n_entries, "parts": parts, "shares": shares}  # fmt: skip


def entry_shares(model: ExplicitModel) -> tuple[float, float]:
    """Shares of the entries skipped (separated, cannot touch yet) and in contact at the last
    step; the rest were evaluated and found separated."""
    sc, weight = model.scratch, model.state.contacts.weight
    skipped = sc.skip_gap > 0.0
    touching = ~skipped & (sc.out_depth > 0.0) & (weight != 0.0)
    return float(skipped.mean()), float(touching.mean())


PARTS = {
    "skipped": (True, True, 1.0),
    "distance": (False, True, 0.0),
    "normal": (True, False, 0.0),
    "contacts": (True, True, 0.0),
}
"""Node loop variants timed (weights kept, friction kept, skip gap set before each pass):
every entry skipped (the loop's bookkeeping and the pairs' frames), every entry evaluated with
zero weights (signed distance only), without friction (signed distance, normal force and
sums) and the whole loop (every entry evaluated: no skipping)."""


def print_step_costs(spacings) -> None:
    print("1. step cost, relaxed 5x5 theta=2.5 (ns per node and step, all nodes counted; "
          "'step' is a whole step with the skipping of separated entries, the parts are node "
          "loops over every entry):")  # fmt: skip
    for spacing in spacings:
        walls = {}
        for parallel in (False, True):
            model = relaxed_panel(spacing, parallel)
            r = step_cost(model, n_steps=max(20, int(2e6 / model.nodes.n_nodes)))
            text = ", ".join(
                f"{name} {w / r['nodes'] * 1e9:.1f} (CPU {c / r['nodes'] * 1e9:.1f})"
                for name, (w, c) in r["parts"].items()
            )
            w, c = r["parts"]["step"]
            walls[parallel] = w
            skipped, touching = r["shares"]
            print(f"  h={spacing:.2f} mm parallel={parallel!s:5} {r['nodes']:7d} nodes "
                  f"{r['entries']:7d} entries ({skipped:.0%} skipped, {touching:.0%} in "
                  f"contact), {len(model.pairs.a)} pairs: {text}; "
                  f"CPU/wall {c / w:.2f}")  # fmt: skip
        ratio = walls[False] / walls[True]
        print(f"  h={spacing:.2f} mm: serial / parallel step wall time {ratio:.2f} "
              f"({numba.get_num_threads()} threads, layer {numba.threading_layer()})")  # fmt: skip


def full_run(disc: dict, reference: str | None) -> dict:
    print(f"2. full 5x5 theta=2.5 run at {disc}:")
    res, steps = _timed_run(disc)
    if reference is not None:
        compare_curve(res, reference)
    return {"steps": steps}


def _timed_run(disc: dict, parallel: bool | None = False):
    """The full 5 x 5, 2.5 degree run at ``disc``, its times printed; (result, steps)."""
    wall0, cpu0 = time.perf_counter(), time.process_time()
    res, _ = run_panel(5, 2.5, tis_panel_k_def(5), disc, parallel=parallel)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    info = res.info
    steps = info["steps_indentation"] + info["steps_relaxation"]
    print(
        f"  wall {wall:.1f} s (CPU {cpu:.1f} s), {steps} steps ({info['steps_relaxation']} "
        f"relaxation), dt {info['dt']:.3e} s, {info['n_nodes']} nodes, "
        f"{info['cost_per_node_step_s'] * 1e9:.1f} ns/node/step wall in the indentation loop "
        f"and {info['cpu_per_node_step_s'] * 1e9:.1f} process CPU (target 15; all nodes "
        f"counted)"
    )
    print(
        f"  peak load {res.peak_load:.2f} N at {res.deflection_at_peak / MM:.3f} mm; ended at "
        f"{res.delta[-1] / MM:.3f} mm ({info.get('stopped_by') or 'its own end criteria'})"
    )
    return res, steps


def compare_curve(res, path: str) -> None:
    """Write the run's records to ``path``, or compare them exactly with the ones there."""
    curve = {name: getattr(res, name) for name in CURVE}
    if not os.path.exists(path):
        np.savez(path, **curve)
        print(f"  curve written to {path} (the reference for later runs)")
        return
    ref = np.load(path)
    differ = [name for name in CURVE if not np.array_equal(ref[name], curve[name])]
    if differ:
        print(f"  curve DIFFERS from {path} in {', '.join(differ)}")
    else:
        print(f"  curve identical to {path}, bit for bit ({', '.join(CURVE)})")


CURVE = ("delta", "load", "block_pos", "block_quat", "kinetic", "elastic")
"""Records of the full run compared with ``--reference``."""


def seed_resolution(steps: int, full: bool) -> None:
    print(f"3. seed resolution, node spacing {SEED_SPACING_MM} mm:")
    scene = tis_panel(5, 2.5)
    if full:
        print("  full run, parallel node loop (target 600 s wall on 2 cores):")
        _timed_run(dict(CONVERGED, node_spacing_mm=SEED_SPACING_MM), parallel=True)
        return
    for parallel in (False, True):
        wall0 = time.perf_counter()
        settings = ExplicitSettings(k_n=tis_panel_k_def(5), node_spacing=SEED_SPACING_MM * MM,
                                    parallel=parallel)  # fmt: skip
        model = ExplicitModel(scene, settings, scene.meta["central_block"], 1.25 * MM)
        setup = time.perf_counter() - wall0
        nodes = model.nodes.n_nodes + len(model.indenter.block)
        model.advance(5)  # compile
        wall, cpu = clock(lambda model=model: model.advance(SEED_STEPS), 1)
        per_step, cpu_step = wall / SEED_STEPS, cpu / SEED_STEPS
        print(
            f"  parallel={parallel!s:5} set-up {setup:.1f} s, {nodes} nodes, "
            f"{model.n_entries} entries: {per_step * 1e3:.1f} ms/step wall "
            f"({cpu / wall:.2f} CPU/wall), {per_step / nodes * 1e9:.1f} ns/node/step wall, "
            f"{cpu_step / nodes * 1e9:.1f} CPU; projected run of {steps} steps: "
            f"{setup + per_step * steps:.0f} s wall at this load, {cpu_step * steps:.0f} CPU s "
            f"(target 600 s wall on 2 cores; a projection, not a run)"
        )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="coarse full run")
    parser.add_argument("--seed-full", action="store_true", help="run the seed resolution")
    parser.add_argument("--reference", help="npz of the full run's curve: write, or compare")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()} on {os.cpu_count()} cores (shared machine)")
    print_step_costs((1.0, 0.5, 0.25))
    run = full_run(QUICK if args.quick else CONVERGED, args.reference)
    seed_resolution(run["steps"], args.seed_full)
    print(f"load average at the end {os.getloadavg()}")


if __name__ == "__main__":
    main()
