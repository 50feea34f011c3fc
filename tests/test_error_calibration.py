"""Calibration of the error bars: on a catalogue of closed forms, the true error lies within
the stated bar in at least 95 % of the cases, and the bar is at most 10 times the true error
wherever the true error is above the method's resolution (issue 28).

Each case gives the method's :class:`dem.estimate.Estimate`, the exact answer of the model it
claims to approximate, the exact answer's own uncertainty (0 for a closed form, half the last
digit of a published value) and the method's resolution (below it an error is round-off and
a bar cannot be compared with it). A bar that is "decorative" (large everywhere) fails the
ratio; a bar that is too small fails the coverage.

Catalogue (limit analysis, :mod:`limit.lambda_error`):

- blocks on the ground pushed by lambda times their weight: min(mu, b/h) (both interface
  models);
- stacks of n aligned blocks: the whole stack overturns at b/(n h), any part slides at mu;
- pure torsion of the seed 001 interface (vertex: mu N times the corner radius
  sqrt(0.15^2 + 0.1^2); resultant: c_T mu N);
- joints with tensile strength: mu (W + sigma_t A) / W, and a hanging block's pull-out;
- a flat block sliding under a load at theta with an inscribed friction polygon of k sides
  (``error="cheap"`` and ``"full"``: the polygon's error measured against the exact cones),
  exact mu;
- the Tresca load multiplier (seed 003, :attr:`limit.tresca.TrescaMultiplierResult.
  load_multiplier_estimate`): 2 x 2 unit cells under pure shear, s / tau, and a brick wall's
  bed joints, s, with Clarabel and HiGHS;
- the least thickness of a semicircular arch (Milankovitch 1907, t/r = 0.1075 given to four
  digits): the certified bisection of 20 and 40 voussoirs, extrapolated in the voussoir
  count (order 2, :func:`dem.estimate.richardson`), with the two bisection brackets.

Static DEM (:func:`dem.static.solve_collapse`, ``StaticResult.lambda_estimate``): the same
blocks and stacks, resultant and fibre laws.

FEM check (:func:`fem_check.error.solve_with_error`): the largest principal stress of a TIS
block under smooth interface tractions, P2, ``error="full"``, against a finer P2 solve.

Explicit DEM (:func:`dem.explicit.simulate_lateral`): stacks of one to three blocks tipping
at b / (n h) or sliding at mu, with rigid joints (``error="cheap"``: load step, detection,
loading rate) and with soft joints continued to rigid ones (``RigidContinuation``); the
peak load and deflection at peak of an indented 3 x 3 TIS panel (``error="cheap"``: curve
sampling, loading rate) against the run at a quarter of its speed.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest

from dem.estimate import Estimate, richardson
from dem.scene import Scene
from dem.scenes import stack
from dem.scenes.arch import HEYMAN_T_OVER_R, voussoir_arch
from limit import LimitSettings, geometric_safety_factor, limit_analysis
from tests.limit._scenes import block_on_ground, torsion_pair
from tests.limit.test_closed_forms import _sliding_block

LA_RESOLUTION = 1e-8
"""Resolution of a limit-analysis multiplier relative to max(1, |lambda|): ten times
Clarabel's tolerance (1e-9, :class:`limit.LimitSettings`)."""
COVERAGE = 0.95
BLOCKS = [(0.2, 0.5, 0.7), (0.4, 0.5, 0.3), (0.3, 0.4, 0.9), (0.5, 0.3, 0.4)]
"""(width, height, mu) of single blocks: tipping at b/h or sliding at mu."""
STACKS = [(2, 0.3, 0.4, 0.8), (3, 0.4, 0.25, 0.9), (3, 0.6, 0.2, 0.5)]
"""(n, width, height, mu) of aligned stacks: tipping at b/(n h) or sliding at mu."""
RATIO = 10.0


@dataclass(frozen=True)
class Case:
    """One calibration case: ``run()`` gives the Estimate; ``exact`` the model's answer,
    known to ``exact_error``; errors below ``resolution`` are round-off."""

    name: str
    run: Callable[[], Estimate]
    exact: float
    exact_error: float = 0.0
    resolution: float = 0.0


@dataclass(frozen=True)
class Outcome:
    case: Case
    estimate: Estimate

    @property
    def true_error(self) -> float:
        return abs(self.estimate.value - self.case.exact)

    @property
    def covered(self) -> bool:
        return bool(self.true_error <= self.estimate.error + self.case.exact_error)

    @property
    def above_resolution(self) -> bool:
        return self.true_error > self.case.resolution + self.case.exact_error

    @property
    def ratio(self) -> float:
        return self.estimate.error / self.true_error if self.true_error > 0 else math.inf


def _la(scene: Scene, settings: LimitSettings | None = None, error="cheap") -> Estimate:
    return limit_analysis(scene, settings, error=error).lambda_estimate


def _la_case(name, scene_fn, exact, settings=None, error="cheap") -> Case:
    resolution = LA_RESOLUTION * max(1.0, abs(exact))
    return Case(name, lambda: _la(scene_fn(), settings, error), exact, 0.0, resolution)


def _tensile_slide(sigma_t: float, mu: float) -> tuple[Scene, float]:
    scene = block_on_ground(1.0, 1.0, 0.2, mu)
    weight = scene.assembly.mass[1] * 9.81
    return scene, mu * (1 + sigma_t * 1.0 / weight)


def _c_t(l1: float, l2: float) -> float:
    """Mean distance of a rectangle's points to its centroid (seed 001 Eq. 11-12)."""
    d = math.hypot(l1, l2)
    return (
        d + l1**2 / (2 * l2) * math.log((l2 + d) / l1) + l2**2 / (2 * l1) * math.log((l1 + d) / l2)
    ) / 6


def limit_cases() -> list[Case]:
    cases = []
    for model in ("vertex", "resultant"):
        s = LimitSettings(interface_model=model)
        for w, h, mu in BLOCKS:
            cases.append(
                _la_case(
                    f"block {w}x{h} mu {mu} [{model}]",
                    lambda w=w, h=h, mu=mu: block_on_ground(w, 0.3, h, mu),
                    min(mu, w / h),
                    s,
                )
            )
        for n, b, h, mu in STACKS:
            cases.append(
                _la_case(
                    f"stack of {n}, {b}x{h}, mu {mu} [{model}]",
                    lambda n=n, b=b, h=h, mu=mu: stack(n, b, 0.3, h, mu=mu),
                    min(mu, b / (n * h)),
                    s,
                )
            )
        sigma_t = 2.0e3
        scene, exact = _tensile_slide(sigma_t, 0.5)
        st = s.with_(tensile_strength=sigma_t)
        cases.append(_la_case(f"tensile slide [{model}]", lambda sc=scene: sc, exact, st))
    cases.append(
        _la_case("pure torsion [vertex]", torsion_pair, 0.7 * 240.0 * math.hypot(0.15, 0.1), None)
    )
    cases.append(
        _la_case(
            "pure torsion [resultant]",
            torsion_pair,
            _c_t(0.3, 0.2) * 0.7 * 240.0,
            LimitSettings(interface_model="resultant"),
        )
    )
    mu = 0.5
    for theta_deg in (10.0, 22.5, 40.0):
        for k in (4, 8):
            for budget in ("cheap", "full"):
                cases.append(
                    _la_case(
                        f"sliding at {theta_deg} deg, {k}-gon, {budget}",
                        lambda t=theta_deg: _sliding_block(math.radians(t), mu),
                        mu,
                        LimitSettings(friction_polygon=k),
                        error=budget,
                    )
                )
    return cases


def _tresca(packing, dead_sigma, live_sigma, s, solver) -> Estimate:
    from limit.tresca import TrescaSettings, max_load_multiplier
    from limit.voronoi_packing import uniform_stress_traction

    res = max_load_multiplier(
        packing,
        uniform_stress_traction(packing, dead_sigma),
        uniform_stress_traction(packing, live_sigma),
        s,
        TrescaSettings(solver=solver),
    )
    return res.load_multiplier_estimate


def tresca_cases() -> list[Case]:
    from limit.voronoi_packing import brick_wall_packing, voronoi_packing_from_seeds

    squares = voronoi_packing_from_seeds(
        np.array([[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [1.5, 1.5]]), 2.0, 2.0
    )
    wall = brick_wall_packing(n_courses=5, bricks_per_course=3, brick_length=0.2, brick_height=0.1)
    shear = np.array([[0.0, 1.0], [1.0, 0.0]])
    cases = []
    for solver in ("CLARABEL", "HIGHS"):
        for p, s, tau in [(1e5, 3e3, 1e4), (1.0, 0.03, 0.1), (2e4, 5e2, 3e3)]:
            cases.append(Case(
                f"Tresca 2x2 shear p {p:g} s {s:g} tau {tau:g} [{solver}]",
                lambda p=p, s=s, tau=tau, so=solver: _tresca(
                    squares, -p * np.eye(2), tau * shear, s, so
                ),
                s / tau, 0.0, LA_RESOLUTION * max(1.0, s / tau),
            ))  # fmt: skip
        cases.append(Case(
            f"Tresca brick wall bed joints [{solver}]",
            lambda so=solver: _tresca(wall, -np.eye(2), shear, 0.7, so),
            0.7, 0.0, LA_RESOLUTION,
        ))  # fmt: skip
    return cases


def _least_thickness(n: int) -> Estimate:
    """Certified bisection of the least t/r of an n-voussoir semicircular arch (r = 1 m)."""

    def build(t_over_r: float) -> Scene:
        return voussoir_arch(2.0, t_over_r, n, depth=0.2, mu=10.0, live_direction=None)

    res = geometric_safety_factor(build, 0.09, 0.12, rtol=1e-4)
    return res.critical_estimate


def _arch_extrapolated() -> Estimate:
    """Richardson in the voussoir count (h ~ 1/n, order 2: the thrust line touches a joint
    instead of its tangency point, a quadratic loss) of 20 and 40 voussoirs, plus both
    bisection brackets."""
    coarse, fine = _least_thickness(20), _least_thickness(40)
    extrapolated = richardson(coarse.value, fine.value, ratio=2.0, order=2.0)
    return extrapolated.with_source("bisection", coarse.error + fine.error)


def arch_cases() -> list[Case]:
    # the published value has four digits: it is known to half its last one
    return [Case("least t/r, semicircular arch", _arch_extrapolated, HEYMAN_T_OVER_R, 5e-5, 0.0)]


def _static(scene_fn, model: str) -> Estimate:
    from dem.static import StaticSettings, solve_collapse

    return solve_collapse(scene_fn(), StaticSettings(interface_model=model)).lambda_estimate


def static_cases() -> list[Case]:
    """Blocks and stacks of :func:`limit_cases` with both interface laws, the default
    (``"cheap"``) budget. Resolution: the residual tolerance of the solve (1e-6 of the loads,
    :class:`dem.static.StaticSettings`), relative to max(1, lambda)."""
    from dem.static import StaticSettings

    resolution = StaticSettings().tolerance
    cases = []
    for model in ("resultant", "fibre"):
        for w, h, mu in BLOCKS:
            cases.append(Case(
                f"static: block {w}x{h} mu {mu} [{model}]",
                lambda w=w, h=h, mu=mu, m=model: _static(
                    lambda: block_on_ground(w, 0.3, h, mu), m
                ),
                min(mu, w / h), 0.0, resolution * max(1.0, min(mu, w / h)),
            ))  # fmt: skip
        for n, b, h, mu in STACKS:
            cases.append(Case(
                f"static: stack of {n}, {b}x{h}, mu {mu} [{model}]",
                lambda n=n, b=b, h=h, mu=mu, m=model: _static(
                    lambda: stack(n, b, 0.3, h, mu=mu), m
                ),
                min(mu, b / (n * h)), 0.0, resolution,
            ))  # fmt: skip
    return cases


EXPLICIT_RESOLUTION = 1e-9
"""No explicit multiplier is nearer than its bracket's width to the answer by round-off: any
true error above this counts."""


def _explicit(n: int, b: float, h: float, mu: float, rigid_joints: bool) -> Estimate:
    """The explicit DEM's multiplier of ``stack(n, b, b, h)`` pushed by its weight: at rigid
    joints its material value with the ``"cheap"`` budget (load step, detection, loading
    rate); with the default (soft) joints its continuation to rigid joints."""
    from dem.explicit import RigidContinuation, masonry_settings, simulate_lateral
    from dem.explicit.lateral import LiveLoadRamp

    scene = stack(n, b, b, h, mu=mu)
    driver = LiveLoadRamp(step=0.05, max_lambda=1.0, refinements=4)
    if rigid_joints:
        settings = masonry_settings(scene, joint_stiffness=None)
        return simulate_lateral(scene, settings, driver, error="cheap").estimate
    res = simulate_lateral(scene, driver=driver, continuation=RigidContinuation(rtol=0.02))
    return res.rigid


JOINTS = {True: "rigid joints", False: "soft joints, rigid limit"}


def explicit_cases(fast: bool) -> list[Case]:
    """Blocks and columns tipping at b / (n h) or sliding at mu (rigid joints, cheap budget),
    and a soft column continued to rigid joints; ``fast``: one of each kind."""
    specs = [(1, 0.2, 0.5, 0.9, True), (3, 0.2, 0.4, 0.6, False)]
    if not fast:
        specs += [(2, 0.3, 0.4, 0.9, True), (3, 0.2, 0.4, 0.6, True), (1, 0.5, 0.2, 0.3, True),
                  (2, 0.4, 0.25, 0.5, True)]  # fmt: skip
    return [
        Case(
            f"explicit: stack of {n}, {b}x{h}, mu {mu}, " + JOINTS[rigid],
            lambda n=n, b=b, h=h, mu=mu, rigid=rigid: _explicit(n, b, h, mu, rigid),
            min(mu, b / (n * h)),
            0.0,
            EXPLICIT_RESOLUTION,
        )
        for n, b, h, mu, rigid in specs
    ]


FEM_H_MM = (1.4, 1.0)
"""Mesh sizes [mm] of the FEM peak estimates (``error="full"``: two coarser levels each)."""
FEM_REFERENCE_H_MM = (0.7, 0.5)
"""The reference: P2 at the finer size, known to its step from the coarser one [mm]."""


def _fem_peak(block, load, h_mm: float, budget: str = "full") -> Estimate:
    from fem_check.elastic import BlockSolver
    from fem_check.error import reference_solvers, solve_with_error
    from fem_check.mesh import MeshSettings
    from validation.cases.fem import MATERIAL

    solver = BlockSolver(MATERIAL, MeshSettings(size=h_mm * 1e-3), degree=2)
    refs = reference_solvers(solver, budget)
    return solve_with_error(solver, block, load, refs, budget)[1].max_principal


def fem_cases() -> list[Case]:
    """The largest principal stress of a TIS block under smooth interface tractions (P2, the
    case of ``benchmarks/bench_fem.py --speed-error``), ``error="full"`` at each of
    :data:`FEM_H_MM`, against the P2 value at the finest of :data:`FEM_REFERENCE_H_MM`,
    known to its step from the other one. Resolution: the sparse solves'
    (:data:`fem_check.error.ROUND_OFF` of the value)."""
    from fem_check.error import ROUND_OFF
    from validation.cases.fem import _smooth_tis_load, _tis_block

    block = _tis_block(2.5)
    load = _smooth_tis_load(block)
    coarse_ref, fine_ref = (_fem_peak(block, load, h, "none").value for h in FEM_REFERENCE_H_MM)
    return [
        Case(
            f"FEM TIS peak, P2, h = {h} mm, full",
            lambda h=h: _fem_peak(block, load, h),
            fine_ref,
            abs(fine_ref - coarse_ref),
            ROUND_OFF * abs(fine_ref),
        )
        for h in FEM_H_MM
    ]


@functools.cache
def _indentation(speed_mm_s: float, error: str):
    """The 3 x 3, 2.5 deg panel of seed 000 at node spacing 1.5 mm, indented at
    ``speed_mm_s`` until the load has fallen to 85 % after the peak."""
    from dem.explicit import ExplicitSettings, IndentationSettings, simulate_indentation
    from dem.scenes.tis_panel import tis_panel
    from dem.tis_stiffness import tis_panel_k_def
    from dem.units import MM

    settings = ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1.5 * MM)
    indentation = IndentationSettings(speed=speed_mm_s * MM, stop_below_peak_fraction=0.85)
    return simulate_indentation(tis_panel(3, 2.5), settings, indentation, error=error)


def indentation_cases() -> list[Case]:
    """The explicit indentation's peak load and deflection at peak at 50 mm/s with the
    ``"cheap"`` budget (curve sampling, loading rate) against the run at 12.5 mm/s, same
    node spacing and time step: the converged answer in the loading rate to within its own
    rate error, a quarter of the first run's at order 1 (taken as exact). The reference run
    is made when the catalogue is built."""
    reference = _indentation(12.5, "none")
    return [
        Case(
            f"explicit indentation 3x3 2.5 deg: {name}",
            lambda name=name: _indentation(50.0, "cheap").estimates[name],
            float(getattr(reference, name)),
            0.0,
            EXPLICIT_RESOLUTION * abs(float(getattr(reference, name))),
        )
        for name in ("peak_load", "deflection_at_peak")
    ]


def run_catalogue(cases: list[Case]) -> list[Outcome]:
    return [Outcome(c, c.run()) for c in cases]


def summary(outcomes: list[Outcome]) -> dict:
    """Counts of the calibration: cases, covered, and the bar / true ratios above resolution."""
    ratios = [o.ratio for o in outcomes if o.above_resolution]
    return {
        "cases": len(outcomes),
        "covered": int(sum(o.covered for o in outcomes)),
        "above_resolution": len(ratios),
        "ratio_min": min(ratios, default=math.nan),
        "ratio_max": max(ratios, default=math.nan),
        "not_covered": [o.case.name for o in outcomes if not o.covered],
        "too_wide": [o.case.name for o in outcomes if o.above_resolution and o.ratio > RATIO],
    }


def check(outcomes: list[Outcome]) -> None:
    s = summary(outcomes)
    assert s["covered"] >= COVERAGE * s["cases"], s
    assert not s["too_wide"], s


def test_limit_analysis_bars_are_calibrated():
    check(run_catalogue(limit_cases()))


def test_tresca_multiplier_bars_are_calibrated():
    check(run_catalogue(tresca_cases()))


def test_arch_least_thickness_bar_is_calibrated():
    check(run_catalogue(arch_cases()))


def test_static_dem_bars_are_calibrated():
    check(run_catalogue(static_cases()))


def test_explicit_bars_are_calibrated_fast_subset():
    check(run_catalogue(explicit_cases(fast=True)))


@pytest.mark.slow  # P2 solves down to 0.5 mm: about 5 min on a busy machine
def test_fem_tis_peak_bars_are_calibrated():
    check(run_catalogue(fem_cases()))


@pytest.mark.slow  # six explicit runs with their loading-rate reruns: ~40 s on a busy machine
def test_explicit_bars_are_calibrated():
    check(run_catalogue(explicit_cases(fast=False)))


@pytest.mark.slow  # three runs to the peak of a 3x3 panel, one at a quarter of the speed
def test_explicit_indentation_bars_are_calibrated():
    check(run_catalogue(indentation_cases()))


def test_the_calibration_can_fail():
    """A bar a thousand times too small is not covered, and one a thousand times too wide
    fails the ratio: the check is not decorative."""
    exact = 0.4
    tight = Case("tight", lambda: Estimate(0.41, {"x": 1e-5}), exact)
    wide = Case("wide", lambda: Estimate(0.41, {"x": 10.0}), exact)
    for case in (tight, wide):
        with pytest.raises(AssertionError):
            check(run_catalogue([case]))
    check(run_catalogue([Case("good", lambda: Estimate(0.41, {"x": 0.02}), exact)]))


if __name__ == "__main__":  # the counts for a report: python -m tests.test_error_calibration
    catalogue = (
        ("limit", limit_cases()),
        ("tresca", tresca_cases()),
        ("arch", arch_cases()),
        ("static", static_cases()),
        ("explicit", explicit_cases(fast=False)),
        ("fem", fem_cases()),
        ("indentation", indentation_cases()),
    )
    for name, cases in catalogue:
        outcomes = run_catalogue(cases)
        print(name, summary(outcomes))
        for o in outcomes:
            print(f"  {o.case.name}: true {o.true_error:.3g} bar {o.estimate.error:.3g}")
