"""Cost of the contact nodes: node and entry counts, seeding, a step and a neighbour-list rebuild.

For the relaxed seed 000 panels (3 x 3 and 5 x 5 at 5 degrees, node spacing 0.5 mm, the
discretisation ``tis-convergence`` calls converged): the nodes seeded (surface and indenter),
the contact entries at rest, the set-up time, and the wall and process-CPU time of a step and
of a rebuild (neighbour list plus the overlap check). Run it on two commits, one after the
other on the same machine, to compare them (the machine is shared: compare ratios).

Usage::

    python benchmarks/bench_contact_nodes.py
"""

from __future__ import annotations

import time

from dem.explicit import ExplicitModel, ExplicitSettings, RelaxationSettings
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM

PANELS = [(3, 5.0), (5, 5.0)]
SPACING_MM = 0.5
STEPS, REBUILDS = 2000, 50


def clock(fn, n: int) -> tuple[float, float]:
    """Wall and process-CPU seconds per call."""
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for _ in range(n):
        fn()
    return (time.perf_counter() - wall0) / n, (time.process_time() - cpu0) / n


def main() -> None:
    for n, theta in PANELS:
        scene = tis_panel(n, theta)
        settings = ExplicitSettings(k_n=tis_panel_k_def(n), node_spacing=SPACING_MM * MM,
                                    parallel=False)  # fmt: skip
        wall0 = time.perf_counter()
        model = ExplicitModel(scene, settings, scene.meta["central_block"], 1.25 * MM)
        setup = time.perf_counter() - wall0
        model.relax(RelaxationSettings(min_steps=200))
        model.advance(10)  # compile
        step = [t / STEPS for t in clock(lambda model=model: model.advance(STEPS), 1)]
        rebuild = clock(model.rebuild, REBUILDS)
        nodes = model.nodes.n_nodes + len(model.indenter.block)
        print(f"{n}x{n} theta={theta:g}: {nodes} nodes ({model.nodes.n_nodes} surface), "
              f"{model.n_entries} entries at rest, set-up {setup:.2f} s; step "
              f"{step[0] * 1e6:.1f} us (CPU {step[1] * 1e6:.1f}), rebuild "
              f"{rebuild[0] * 1e3:.2f} ms (CPU {rebuild[1] * 1e3:.2f})")  # fmt: skip


if __name__ == "__main__":
    main()
