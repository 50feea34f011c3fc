"""Limit analysis of scenes built by hand from convex blocks, against closed forms."""

import math

import numpy as np
import pytest

import limit
from dem import Scene
from dem.scene import proportional_to_weight
from limit import LimitSettings
from tests.limit._scenes import GROUND, box


def _uphill_pushed_block(tan_theta: float, mu: float) -> tuple[Scene, float]:
    """A 0.2 m cube on a ground tilted by ``theta`` (downhill towards -x), pushed uphill
    along the slope by lambda times its weight. Returns the scene and ``theta`` [rad]."""
    theta = math.atan(tan_theta)
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    blk = box((-0.1, -0.1, 0.0), (0.1, 0.1, 0.2))
    scene = Scene.from_convex_blocks([GROUND @ rot.T, blk @ rot.T], 2000.0, fixed=[0], mu=mu)
    uphill = rot @ np.array([1.0, 0.0, 0.0])
    return scene.with_loads(live=proportional_to_weight(scene.assembly, uphill)), theta


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_reduced_friction_estimate_of_a_block_that_slides_down_with_mu_star(model):
    """tan(theta) = 0.55 lies between mu* = 0.6 / sqrt(1.36) = 0.514 and mu = 0.6: the block
    stands, and slides uphill at lambda = sin(theta) + mu cos(theta) (closed form). With
    mu* it slides down by itself, so the associated problem with mu* has no collapse
    multiplier: its admissible multipliers are [0.031, 0.933], and the largest one was
    returned as estimate (a) before."""
    scene, theta = _uphill_pushed_block(0.55, 0.6)
    b = limit.bounds_and_estimates(scene, LimitSettings(interface_model=model))
    assert b.upper == pytest.approx(math.sin(theta) + 0.6 * math.cos(theta), rel=1e-6)
    assert b.reduced_mu is None
    assert "dead load" in b.reduced_note


def test_reduced_friction_estimate_of_a_block_that_stands_with_mu_star():
    """tan(theta) = 0.4 < mu* = 0.514: estimate (a) is the closed form with mu*."""
    scene, theta = _uphill_pushed_block(0.4, 0.6)
    b = limit.bounds_and_estimates(scene)
    mu_star = 0.6 / math.sqrt(1.36)
    assert b.reduced_mu == pytest.approx(math.sin(theta) + mu_star * math.cos(theta), rel=1e-6)


def test_frictionless_lower_bound_of_a_propped_block_without_the_dead_load_check():
    """Without friction the block on the slope stands only while pushed uphill by exactly
    sin(theta) times its weight, so there is no frictionless lower bound. The cross-check
    switches ``dead_load_check`` off once the scene is known to stand with mu; the
    frictionless programme must still be checked (it returned sin(theta) = 0.482 before)."""
    scene, _ = _uphill_pushed_block(0.55, 0.6)
    b = limit.bounds_and_estimates(scene, LimitSettings(dead_load_check=False))
    assert b.lower is None
    assert "cannot carry its dead load" in b.lower_note


@pytest.mark.parametrize("mu", [0.5, 0.0])
def test_kinematic_form_refuses_a_block_that_slides_down_by_itself(mu):
    """mu < tan(theta) = 0.55: the block slides down unless pushed uphill by at least
    sin(theta) - mu cos(theta) times its weight, so no multiplier is a collapse multiplier.
    The static form refuses it; the kinematic form returned the top of the propped interval,
    sin(theta) + mu cos(theta) (0.920 for mu = 0.5, 0.482 for mu = 0)."""
    scene, _ = _uphill_pushed_block(0.55, 0.6)
    settings = LimitSettings(mu=mu)
    with pytest.raises(limit.DeadLoadInfeasibleError):
        limit.limit_analysis(scene, settings)
    with pytest.raises(limit.DeadLoadInfeasibleError):
        limit.kinematic_analysis(scene, settings)


def _leaning_plank() -> Scene:
    """A 1 m plank leaning at 60 degrees between a fixed floor and a fixed wall: its lower
    edge rests on the floor and its upper edge on the wall face, both line contacts."""
    wall = box((0.0, -1.0, 0.0), (0.2, 1.0, 2.0))
    a = math.radians(60.0)
    c, s = math.cos(a), math.sin(a)
    # plank axis (-c, 0, s) up from its foot, thickness along the normal (s, 0, c)
    foot = np.array([-c * 1.0 - 0.05 * s, 0.0, 0.0])
    axis, normal = np.array([c, 0.0, s]), np.array([-s, 0.0, c])
    corners = [
        foot + u * axis + v * normal + (0.0, y, 0.0)
        for u in (0.0, 1.0)
        for v in (0.0, 0.05)
        for y in (-0.2, 0.2)
    ]
    plank = np.array(corners)
    plank[:, 0] -= plank[:, 0].max()  # touch the wall face x = 0
    plank[:, 2] -= plank[:, 2].min()  # and the floor z = 0
    floor = box((-2.0, -1.0, -0.2), (0.0, 1.0, 0.0))
    return Scene.from_convex_blocks([floor, wall, plank], 2000.0, fixed=[0, 1], mu=0.6)


def test_a_block_held_by_edge_contacts_only_is_reported_as_such():
    """Line contacts carry nothing in the interface model (interfaces are coplanar faces):
    the plank has no interface, so it falls. The error must say that it touches no block
    on a face, not that it touches no block (it touches two)."""
    scene = _leaning_plank()
    faces = scene.assembly.interfaces()
    assert 2 not in set(faces.block_a) | set(faces.block_b)
    result = limit.stands(scene)
    assert not result.stands and result.blocks == (2,)
    assert "edge" in result.reason and "face" in result.reason


def _arch(t_over_r: float, n: int = 20) -> Scene:
    """A semicircular arch of ``n`` wedge voussoirs with radial joints, centre-line radius
    1 m, thickness ``t_over_r`` m, 0.2 m deep, on two fixed springer blocks (mu = 10: no
    sliding)."""
    ri, ro = 1.0 - t_over_r / 2, 1.0 + t_over_r / 2
    blocks = [box((x - 0.2, -0.1, -0.2), (x + 0.2, 0.1, 0.0)) for x in (1.0, -1.0)]
    phi = np.linspace(0.0, math.pi, n + 1)
    for a0, a1 in zip(phi[:-1], phi[1:], strict=True):
        blocks.append(
            np.array(
                [
                    (r * math.cos(a), y, r * math.sin(a))
                    for a in (a0, a1)
                    for r in (ri, ro)
                    for y in (-0.1, 0.1)
                ]
            )
        )
    return Scene.from_convex_blocks(blocks, 2000.0, fixed=[0, 1], mu=10.0)


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_least_thickness_of_a_semicircular_arch(model):
    """Heyman's least thickness of a semicircular arch under its own weight is
    t/R = 0.1075 for continuous hinges (Milankovitch); with 20 voussoirs the hinges may sit
    only at joints, so it is slightly smaller (0.10734 measured; 0.10743 with 40, 0.10745
    with 80 voussoirs)."""
    res = limit.geometric_safety_factor(
        _arch, 0.09, 0.12, actual=0.12, rtol=1e-4, settings=LimitSettings(interface_model=model)
    )
    assert res.stands_above
    assert 0.105 < res.critical < 0.1075
    assert res.critical == pytest.approx(0.10734, rel=2e-4)


def test_a_bisection_cut_short_by_max_steps_is_refused():
    """Three bisection steps narrow [0.09, 0.12] to 0.00375, wider than rtol * t* = 1e-4:
    the bracket the result promises (``<= rtol |critical|``) does not hold, so no critical
    value is returned (it was, 0.1069, off by 0.4 %)."""
    with pytest.raises(ValueError, match="max_steps"):
        limit.geometric_safety_factor(_arch, 0.09, 0.12, rtol=1e-3, max_steps=3)


def test_the_crosscheck_says_why_estimate_a_is_missing(tmp_path):
    """The report's note beside a missing estimate (a) gives the reason, as for the lower
    bound (it was empty)."""
    from validation.crosscheck import CrosscheckSettings, crosscheck

    scene, _ = _uphill_pushed_block(0.55, 0.6)
    result = crosscheck(scene, CrosscheckSettings.quick(methods=("dead", "limit")), tmp_path)
    for model in ("vertex", "resultant"):
        values = result.step(f"limit-{model}").values
        assert values["reduced_mu"] is None and values["lower"] is None
        assert "cannot carry its dead load" in values["reduced_note"]
    report = (tmp_path / "report.md").read_text()
    row = next(x for x in report.splitlines() if x.startswith("| estimate (a) mu* (vertex"))
    assert "cannot carry its dead load" in row


@pytest.mark.parametrize("angle_deg", [0.0, 30.0, 135.0, 300.0])
@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_a_tetrahedron_tips_about_a_base_edge(model, angle_deg):
    """A tetrahedron on its right-triangle face (legs 0.3 m, apex 0.25 m above the base
    centroid), no sliding, pushed horizontally along ``d`` by lambda times its weight. It
    rocks about the base edge that minimises ``dist(c, edge) / (z_c n.d)`` over the edges
    whose outward normal ``n`` has ``n.d > 0`` (a tangent line through a corner is never
    better: the ratio is monotone between the two edge normals); ``c`` is the centroid."""
    tet = np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.3, 0.0], [0.1, 0.1, 0.25]])
    c = tet.mean(axis=0)
    a = math.radians(angle_deg)
    d = np.array([math.cos(a), math.sin(a), 0.0])
    expected = math.inf
    for p, q in ((0, 1), (1, 2), (2, 0)):
        edge = tet[q, :2] - tet[p, :2]
        n = np.array([edge[1], -edge[0]]) / np.linalg.norm(edge)  # outward (counter-clockwise)
        if n @ d[:2] > 0:
            expected = min(expected, n @ (tet[p, :2] - c[:2]) / (c[2] * (n @ d[:2])))
    scene = Scene.from_convex_blocks([GROUND, tet], 2000.0, fixed=[0], mu=math.inf)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, d))
    lam = limit.limit_analysis(scene, LimitSettings(interface_model=model)).lam
    assert lam == pytest.approx(expected, rel=1e-6)


@pytest.fixture
def tripled_estimate_on_a_huge_push(monkeypatch) -> Scene:
    """A 1 x 1 x 0.2 m block pushed by a live load of 1e10 N (upper bound 0.6 W / 1e10), with
    estimate (b) made three times its true value."""
    import limit.estimates as est

    real = est.iterative_estimate

    def wrong(*args, **kw):
        it = real(*args, **kw)
        it.lam = 3.0 * kw["start"].lam
        return it

    monkeypatch.setattr(est, "iterative_estimate", wrong)
    blk = box((-0.5, -0.5, 0.0), (0.5, 0.5, 0.2))
    scene = Scene.from_convex_blocks([GROUND, blk], 2000.0, fixed=[0], mu=0.6)
    live = np.zeros((2, 6))
    live[1, 0] = 1e10
    return scene.with_loads(live=live)


def test_an_estimate_above_the_upper_bound_is_caught_whatever_the_load_unit(
    tripled_estimate_on_a_huge_push,
):
    """The ordering check had an absolute allowance of 1e-6 in lambda: with the live load
    given as a 1e10 N push (upper bound 0.6 W / 1e10 = 2.4e-7), an estimate (b) three times
    the upper bound passed. The allowance is now relative to the multiplier at which the
    live load equals the weight."""
    scene = tripled_estimate_on_a_huge_push
    weight = scene.assembly.mass[1] * 9.81
    b = limit.bounds_and_estimates(scene, strict=False)
    assert b.upper == pytest.approx(0.6 * weight / 1e10, rel=1e-6)
    assert not b.consistent
    assert b.issues[0].startswith("estimate (b)")


def test_the_crosscheck_verdict_catches_an_estimate_above_the_bound_in_any_load_unit(
    tripled_estimate_on_a_huge_push, tmp_path
):
    """The verdict allowed an absolute 1e-3 in lambda: with a 1e10 N live push (upper bound
    2.4e-7) an estimate (b) three times the upper bound was a 'pass'."""
    from validation.crosscheck import CrosscheckSettings, crosscheck

    scene = tripled_estimate_on_a_huge_push
    result = crosscheck(scene, CrosscheckSettings.quick(methods=("limit",)), tmp_path)
    check = next(c for c in result.checks if c.name == "estimate (b) within bounds (vertex)")
    assert check.status == "fail"
    assert not result.consistent


def test_an_accurate_result_after_a_retry_comes_without_a_warning(monkeypatch):
    """A 0.2 x 0.6 m block pushed sideways with mu = 0.1 (resultant model), its first solve
    stopped by Clarabel after 3 iterations with loose reduced tolerances (AlmostSolved, which
    cvxpy reports as optimal_inaccurate with its 'Solution may be inaccurate' warning), the
    short-step retry optimal (lambda = mu, closed form). cvxpy's warning of the first attempt
    must not reach the user with that accurate result; the only warning is the toolkit's
    own, for an inaccurate return."""
    import warnings

    from limit import clarabel

    real = clarabel.run_clarabel
    stopped = {"max_iter": 3, **{f"reduced_tol_{k}": 1e3 for k in ("gap_abs", "gap_rel")}}
    stopped |= {"reduced_tol_feas": 1e3, "reduced_tol_ktratio": 1e3}

    def first_stopped(problem, settings, attempt=clarabel.REFINED):
        if attempt.label == "refined":
            settings = settings.with_(clarabel={**settings.clarabel, **stopped})
        return real(problem, settings, attempt)

    monkeypatch.setattr(clarabel, "run_clarabel", first_stopped)
    ground = box((-2.0, -1.0, -0.2), (2.0, 1.0, 0.0))
    blk = box((-0.1, -0.1, 0.0), (0.1, 0.1, 0.6))
    scene = Scene.from_convex_blocks([ground, blk], 2000.0, fixed=[0], mu=0.6)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = limit.limit_analysis(scene, LimitSettings(mu=0.1, interface_model="resultant"))
    assert res.attempts == [("refined", "optimal_inaccurate"), ("short steps", "optimal")]
    assert res.lam == pytest.approx(0.1, rel=1e-6)
    assert [str(w.message) for w in caught] == []


def _chip_on_a_block(tan_theta: float, chip_density: float) -> Scene:
    """A 0.2 m cube (the chip, mu = 0.25 beneath it) on a free 1 m cube on a fixed ground,
    all tilted by ``theta`` (the big cube's joint has mu = 1); densities 2000 and
    ``chip_density`` kg/m^3. The chip slides iff tan(theta) > 0.25."""
    theta = math.atan(tan_theta)
    c, s = math.cos(theta), math.sin(theta)
    rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    big = box((-0.5, -0.5, 0.0), (0.5, 0.5, 1.0))
    chip = box((-0.1, -0.1, 1.0), (0.1, 0.1, 1.2))
    return Scene.from_convex_blocks(
        [GROUND @ rot.T, big @ rot.T, chip @ rot.T],
        [2000.0, 2000.0, chip_density],
        fixed=[0],
        mu=[1.0, 1.0, 0.25],
    )


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_a_light_block_is_never_certified_on_a_wrong_answer(model):
    """The certificate measured every residual against the total weight W: a chip of 8e-8 W
    that slides (tan 0.27 > mu 0.25) was certified as standing, its friction exceeded by
    0.4 % of its own weight (2e-10 W). Now each interface's strength and each block's
    equilibrium are also checked against the loads of its own blocks: the right answer, or
    a NumericalFailureError, never a certified wrong one."""
    assert not limit.stands(_chip_on_a_block(0.27, 2000.0)).stands  # 8e-3 W: resolved
    light = _chip_on_a_block(0.27, 0.02)
    assert light.assembly.mass[2] / light.assembly.mass[1:].sum() < 1e-7
    try:
        result = limit.stands(light, LimitSettings(interface_model=model))
    except limit.NumericalFailureError as exc:
        assert "loads of its own blocks" in str(exc)
    else:
        assert not result.stands


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_the_multiplier_of_a_light_block_is_right_or_refused(model):
    """A 0.2 x 0.2 x 0.6 m block of density 2e-3 kg/m^3 (2.4e-8 of the structure's weight) on
    a 1 m cube, pushed sideways by lambda times its own weight: it slides at lambda = mu =
    0.25. The certificate relative to the total weight passed 0.2623 (vertex) and 0.2300
    (resultant)."""
    big = box((-0.5, -0.5, 0.0), (0.5, 0.5, 1.0))
    chip = box((-0.1, -0.1, 1.0), (0.1, 0.1, 1.6))
    scene = Scene.from_convex_blocks(
        [GROUND, big, chip], [2000.0, 2000.0, 2e-3], fixed=[0], mu=0.25
    )
    live = np.zeros((3, 6))
    live[2, 0] = scene.assembly.mass[2] * 9.81
    scene = scene.with_loads(live=live)
    try:
        lam = limit.limit_analysis(scene, LimitSettings(interface_model=model)).lam
    except limit.NumericalFailureError as exc:
        assert "loads of its own blocks" in str(exc)
    else:
        assert lam == pytest.approx(0.25, rel=2e-3)
