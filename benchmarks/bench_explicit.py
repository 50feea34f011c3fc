"""Cost of the explicit TIS solver: per node per step, and the full 5 x 5 run.

1. Step cost on the 5 x 5, 2.5 degree panel in its relaxed state for several node spacings,
   serial and parallel contact loops: wall and process-CPU time per step, per node and per
   contact entry (the machine is shared: the CPU/wall ratio says how much of it we had).
2. The full 5 x 5, 2.5 degree run (relaxation + indentation past the peak until the central
   block is out) at the discretisation ``tis-convergence`` calls converged
   (``validation.cases.tis.CONVERGED``), with its wall time and cost per node per step.

Usage::

    python benchmarks/bench_explicit.py            # step costs + the full converged run
    python benchmarks/bench_explicit.py --quick    # step costs + a coarse full run

Target of issue 5: the full converged 5 x 5 run under 10 minutes wall time on 2 cores (the
seed's C++ code: about 50 CPU hours). Wall-clock on a shared machine: compare ratios within a run.
"""

from __future__ import annotations

import argparse
import time

from dem.explicit import ExplicitModel, ExplicitSettings, RelaxationSettings
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM
from validation.cases.tis import CONVERGED, QUICK, run_panel


def step_cost(spacing_mm: float, parallel: bool, n_steps: int = 400) -> dict:
    """Time per step of the relaxed 5 x 5 panel with the indenter in contact."""
    scene = tis_panel(5, 2.5)
    settings = ExplicitSettings(
        k_n=tis_panel_k_def(5), node_spacing=spacing_mm * MM, parallel=parallel
    )
    model = ExplicitModel(scene, settings, scene.meta["central_block"], 1.25 * MM)
    model.relax(RelaxationSettings(min_steps=200))
    model.advance(10)  # compile
    wall0, cpu0 = time.perf_counter(), time.process_time()
    model.advance(n_steps)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    nodes = model.nodes.n_nodes + len(model.indenter.block)
    return {
        "spacing_mm": spacing_mm,
        "parallel": parallel,
        "nodes": nodes,
        "entries": model.n_entries,
        "wall_ms_per_step": wall / n_steps * 1e3,
        "ns_per_node_step": wall / n_steps / nodes * 1e9,
        "cpu_ns_per_node_step": cpu / n_steps / nodes * 1e9,
        "cpu_over_wall": cpu / wall,
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="coarse full run")
    args = parser.parse_args()
    print("step cost, 5x5 theta=2.5 (wall and process CPU):")
    for spacing in (1.0, 0.5, 0.25):
        for parallel in (False, True):
            r = step_cost(spacing, parallel)
            print(
                f"  h={r['spacing_mm']:.2f} mm parallel={r['parallel']!s:5}: {r['nodes']:6d} "
                f"nodes {r['entries']:6d} entries  {r['wall_ms_per_step']:.3f} ms/step  "
                f"{r['ns_per_node_step']:.1f} ns/node/step (CPU {r['cpu_ns_per_node_step']:.1f}, "
                f"CPU/wall {r['cpu_over_wall']:.2f})"
            )
    disc = QUICK if args.quick else CONVERGED
    print(f"full 5x5 theta=2.5 run at {disc}:")
    wall0, cpu0 = time.perf_counter(), time.process_time()
    res, _ = run_panel(5, 2.5, tis_panel_k_def(5), disc)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    info = res.info
    steps = info["steps_indentation"] + info["steps_relaxation"]
    print(
        f"  wall {wall:.1f} s (CPU {cpu:.1f} s), {steps} steps "
        f"({info['steps_relaxation']} relaxation), dt {info['dt']:.3e} s, "
        f"{info['n_nodes']} nodes, {info['cost_per_node_step_s'] * 1e9:.1f} ns/node/step "
        f"(indentation loop)"
    )
    print(
        f"  peak load {res.peak_load:.2f} N at {res.deflection_at_peak / MM:.3f} mm, "
        f"ultimate deflection {res.ultimate_deflection / MM:.3f} mm, "
        f"loading energy {res.loading_energy / MM:.1f} N mm"
    )
    print(f"  target: under 600 s wall -> {'met' if wall < 600 else 'NOT met'}")


if __name__ == "__main__":
    main()
