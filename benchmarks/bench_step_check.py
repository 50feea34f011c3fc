"""Time-step check at the neighbour-list rebuilds: how far the present entries' highest
frequency moves from the start's over TIS runs, and what the check costs.

For each run (TIS panels at theta 5 degrees, perfect and gap-calibrated stiffness, at the
quick or the converged discretisation of :mod:`validation.cases.tis`) every rebuild is
timed, and besides the check the run makes (per-block bound, exact eigenvalue only where the
bound is above the stable frequency) the exact highest frequency of the present entries is
computed and timed too (the probe's own time is taken off the run's wall time). Printed per
run: the largest and smallest omega(present) / omega(start), the largest bound / exact, the
run's wall time, and the mean costs of the rebuild itself, of the bound (per check: one per
rebuild in a run, and one at each start of stepping) and of the exact eigenvalue (per
rebuild), with their shares of the run.

The machine is shared: compare times only as ratios within one run.

Usage::

    python benchmarks/bench_step_check.py --quick          # 3 x 3 and 5 x 5, quick
    python benchmarks/bench_step_check.py --sizes 3 5 7    # converged (0.5 mm)
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from dem.explicit import model as model_module
from dem.explicit import step_check
from dem.explicit.timestep import highest_frequency
from dem.tis_stiffness import K_GAPS_SEED_000, k_series, tis_panel_k_def
from validation.cases.tis import CONVERGED, QUICK, run_panel

THETA = 5.0


class Probe:
    """Times the rebuilds and the check's bound; computes the exact frequency at each."""

    def __init__(self):
        self.reset()
        self.rebuild = model_module.ExplicitModel.rebuild
        self.bound = step_check.frequency_bound

    def reset(self):
        self.rebuild_s, self.bound_s, self.exact_s, self.probe_s = [], [], [], []
        self.ratio, self.bound_ratio = [], []

    def install(self):
        probe = self

        def bound(*args):
            t0 = time.perf_counter()
            out = probe.bound(*args)
            probe.bound_s.append(time.perf_counter() - t0)
            return out

        def rebuild(model):
            t0 = time.perf_counter()
            probe.rebuild(model)
            probe.rebuild_s.append(time.perf_counter() - t0)
            if not hasattr(model, "step_check"):
                return  # the first rebuild, before the time step is chosen
            t0 = time.perf_counter()
            rot = model.rotations()
            system = model._contact_stiffness(rot)
            t1 = time.perf_counter()
            exact = highest_frequency(system)
            probe.exact_s.append(time.perf_counter() - t1)
            probe.ratio.append(exact / model.omega_max)
            probe.bound_ratio.append(probe.bound(system).max() / exact)
            probe.probe_s.append(time.perf_counter() - t0)

        step_check.frequency_bound = bound
        model_module.ExplicitModel.rebuild = rebuild


def run(n: int, kind: str, disc: dict, probe: Probe) -> None:
    probe.reset()
    k_def = tis_panel_k_def(n)
    k_n = k_def if kind == "perfect" else k_series(k_def, K_GAPS_SEED_000)
    wall0 = time.perf_counter()
    res, _ = run_panel(n, THETA, k_n, disc)
    wall = time.perf_counter() - wall0 - sum(probe.probe_s)  # the run without the probe
    ratio = np.array(probe.ratio)
    rebuild, bound, exact = (np.array(x) for x in (probe.rebuild_s, probe.bound_s, probe.exact_s))
    check = res.info["step_check"]
    print(
        f"{n}x{n} theta={THETA:g} {kind} {disc['node_spacing_mm']} mm: {len(ratio)} rebuilds, "
        f"omega/omega_start max {ratio.max():.4f} min {ratio.min():.4f}; bound/exact max "
        f"{max(probe.bound_ratio):.3f} ({len(bound)} checks); run's record {check}; "
        f"wall {wall:.1f} s; means: "
        f"rebuild {rebuild.mean() * 1e3:.2f} ms, bound {bound.mean() * 1e3:.2f} ms "
        f"({bound.mean() / rebuild.mean():.3f} of a rebuild, {bound.sum() / wall:.4f} of the "
        f"run), exact {exact.mean() * 1e3:.2f} ms ({exact.mean() / rebuild.mean():.3f} of a "
        f"rebuild, {exact.sum() / wall:.4f} of the run); load {os.getloadavg()[0]:.1f}",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--sizes", type=int, nargs="+", default=[3, 5])
    parser.add_argument("--kinds", nargs="+", default=["perfect", "calibrated"])
    args = parser.parse_args()
    probe = Probe()
    probe.install()
    disc = QUICK if args.quick else CONVERGED
    for n in args.sizes:
        for kind in args.kinds:
            run(n, kind, disc, probe)


if __name__ == "__main__":
    main()
