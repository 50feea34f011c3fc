"""Static DEM to collapse against closed forms (rigid blocks, Coulomb friction, no tension)."""

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dem.scene import Scene, Supports, proportional_to_weight
from dem.scenes import voussoir_arch
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import StaticSettings, StaticSolverError, solve_collapse
from limit import LimitSettings

MODELS = ("resultant", "fibre")
# The rigid-block collapse loads below are limits of elastic joints: the fibre law (its outer
# springs on the edges) reaches them once all but the edge springs are open; the resultant law
# integrates the stress of the whole joint, whose compressed strip narrows only as
# theta^(-1/2) when the block rocks, so its path approaches the limit from below and ends
# once what may still rise is below plateau_rise (1e-3) of lambda. Both must stay below it,
# within 0.1 %, and the limit must lie within the stated error bar.
BELOW = 1e-3


def _near_limit(result, limit):
    """``lambda_max`` at most ``limit`` (up to the residual tolerance), within ``BELOW``, and
    the limit inside ``lambda_estimate``'s bar."""
    lam = result.lambda_max
    assert limit * (1 - BELOW) <= lam <= limit * (1 + 1e-4), (lam, limit)
    assert result.lambda_estimate.contains(limit), (result.lambda_estimate, limit)


def _box(x0, x1, y0, y1, z0, z1):
    return np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])


def _stack(widths_heights, mu, direction=(1.0, 0.0, 0.0), depth=0.3):
    """Blocks stacked on a fixed base, centred on x = 0; live load = weight along direction."""
    blocks = [_box(-1.0, 1.0, -1.0, 1.0, -0.2, 0.0)]
    z = 0.0
    for b, h in widths_heights:
        blocks.append(_box(-b / 2, b / 2, -depth / 2, depth / 2, z, z + h))
        z += h
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=mu)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, direction))


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("mu", [0.3, 0.7])
def test_single_block_collapses_at_min_of_mu_and_b_over_h(model, mu):
    # closed form: sliding at lambda = mu, overturning about the base edge at lambda = b / h
    b, h = 0.2, 0.5
    result = solve_collapse(_stack([(b, h)], mu), StaticSettings(interface_model=model))
    _near_limit(result, min(mu, b / h))
    assert result.termination == "plateau"
    mech = result.mechanism[1]
    if mu < b / h:  # pure sliding along the load, no rotation
        np.testing.assert_allclose(mech[:3], [1.0, 0.0, 0.0], atol=1e-3)
        np.testing.assert_allclose(mech[3:], 0.0, atol=1e-2)
    else:  # rocking: rotation about +y for a load along +x
        assert mech[4] > 0


@pytest.mark.parametrize("model", MODELS)
def test_single_block_out_of_plane_direction(model):
    # same block loaded along y: overturning about the long base edge, lambda = depth / h
    depth, h = 0.12, 0.4
    scene = _stack([(0.3, h)], 0.7, direction=(0.0, 1.0, 0.0), depth=depth)
    result = solve_collapse(scene, StaticSettings(interface_model=model))
    _near_limit(result, depth / h)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("mu", [0.2, 0.9])
def test_two_block_stack(model, mu):
    # closed forms for two equal blocks b x h: sliding of the top or of both (lambda = mu),
    # rocking of the whole stack about the base edge (b / 2h), of the top block (b / h)
    b, h = 0.2, 0.3
    result = solve_collapse(_stack([(b, h), (b, h)], mu), StaticSettings(interface_model=model))
    _near_limit(result, min(mu, b / (2 * h), b / h))


def test_free_standing_wall_overturns_at_s_over_h():
    # a running-bond wall on a rigid base, out-of-plane load = weight: whole-wall rocking
    # about the base edge, lambda = s / H (any upper part of height h < H needs s / h)
    scene = running_bond_wall(3, 4, 81, 210, 70, 20, 0.7, live="weight")
    for model in MODELS:
        result = solve_collapse(scene, StaticSettings(interface_model=model))
        _near_limit(result, 70 / (4 * 81))


def test_symmetric_wall_has_symmetric_mechanism():
    # a wall with both end columns fixed is symmetric about x = L/2 (running bond with an
    # even number of blocks is mirror symmetric course by course): the out-of-plane
    # displacements of mirror blocks at collapse match (to 1 % of the largest; the last
    # increment alone may pick one of two mirror mechanisms, so the total field is compared).
    # Between two fixed columns the joints' rocking lift is confined and the wall arches
    # without bound (test_static_collapse): a compressive strength bounds it.
    scene = running_bond_wall(4, 4, 81, 210, 70, 20, 0.7, fixed_columns=("left", "right"))
    result = solve_collapse(
        scene, StaticSettings(interface_model="resultant", compressive_strength=2e5)
    )
    c = scene.assembly.centroid
    length = 4 * 0.210
    uy = result.displacements[:, 1]
    free = np.flatnonzero(~scene.supports.fixed)
    for i in free:
        mirror = np.flatnonzero(
            (np.abs(c[:, 0] - (length - c[i, 0])) < 1e-9) & (np.abs(c[:, 2] - c[i, 2]) < 1e-9)
        )
        assert len(mirror) == 1
        np.testing.assert_allclose(uy[i], uy[mirror[0]], atol=1e-2 * np.abs(uy).max())


def test_stiffness_halved_load_step_same_collapse():
    # the collapse multiplier does not depend on the load step (stability, rtol 1 %)
    scene = _stack([(0.2, 0.3), (0.2, 0.3)], 0.9)
    lam = [
        solve_collapse(scene, StaticSettings(load_step=step)).lambda_max
        for step in (0.005, 0.01, 0.02)
    ]
    np.testing.assert_allclose(lam, lam[1], rtol=1e-2)


def test_wall_with_fixed_column_reaches_its_mechanism_whatever_the_step():
    # seed 001's model of a return wall (end block of every course fixed), small: 3 x 6
    # Restrepo blocks, resultant law. The collapse multiplier must not depend on the load
    # step (rtol 1 %), the path must end on a plateau, and lambda must lie below the
    # associated bound of the same joint model (Radenkovic: zero-dilatancy friction cannot
    # carry more). Before the return mapping kept yielded joints yielding at the start of a
    # step, Newton cycled and the path stalled at 0.18-0.20 depending on the step (a false
    # plateau on the noise of loosely converged steps).
    from limit.problems import LimitSettings
    from limit.solve import limit_analysis

    scene = running_bond_wall(
        3, 6, 28.24, 79.78, 39.68, 26.8, 0.7, fixed_columns=("left",), live="weight"
    )
    results = [
        solve_collapse(scene, StaticSettings(load_step=step, on_failure="return"))
        for step in (0.005, 0.01, 0.02)
    ]
    lam = [r.lambda_max for r in results]
    assert all(r.termination == "plateau" for r in results)
    np.testing.assert_allclose(lam, lam[1], rtol=1e-2)
    upper = limit_analysis(scene, LimitSettings(interface_model="resultant")).lam
    assert lam[1] <= upper


def test_path_followed_past_a_stall_of_the_fixed_control():
    # seed 001 S15 with return walls of blocks, resultant law: with a tangent floor of 1e-6
    # the fixed control c stalled at 0.1726 (step cut to 1e-4 of the first, lambda still
    # rising) with seed 001's rocking rule; the path-direction control had to carry it to the
    # plateau. With the joints that open progressively neither run stalls (issue 11): the
    # default floor ends where lambda may rise by less than 0.1 %; the floor of 1e-6 creeps
    # on in short steps and may end at max_steps, still rising, which is then no collapse
    # and says how much more lambda may rise. Both must agree within 1 % and within their
    # bars, below the associated bound of the scene.
    from dem.scenes.seed001_walls import SPECIMENS
    from limit.problems import LimitSettings
    from limit.solve import limit_analysis

    scene = SPECIMENS["restrepo-S15"].build(return_walls="blocks")
    floored, direct = (
        solve_collapse(scene, StaticSettings(mu=0.7, on_failure="return", **kw))
        for kw in (dict(tangent_floor=1e-6), dict(load_step=0.02))
    )
    assert direct.termination == "plateau"
    assert floored.termination in ("plateau", "max_steps")
    assert floored.collapsed == (floored.termination == "plateau")
    np.testing.assert_allclose(floored.lambda_max, direct.lambda_max, rtol=1e-2)
    assert floored.lambda_estimate.overlaps(direct.lambda_estimate)
    upper = limit_analysis(scene, LimitSettings()).lam
    assert max(floored.lambda_max, direct.lambda_max) <= upper


def test_unsupported_block_is_named():
    # a block floating apart from the base: singular stiffness before any load
    blocks = [
        _box(-1, 1, -1, 1, -0.2, 0.0),
        _box(-0.1, 0.1, -0.1, 0.1, 0.0, 0.2),
        _box(3.0, 3.2, -0.1, 0.1, 0.0, 0.2),
    ]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.5)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1, 0, 0)))
    with pytest.raises(StaticSolverError, match="blocks \\[2\\]") as info:
        solve_collapse(scene)
    assert info.value.blocks == [2]


def test_no_support_at_all_is_an_error():
    scene = _stack([(0.2, 0.3)], 0.5)
    free = scene.with_supports(Supports.none(scene.n_blocks))
    with pytest.raises(StaticSolverError, match="reach no support"):
        solve_collapse(free)


def test_bad_inputs():
    scene = _stack([(0.2, 0.3)], 0.5)
    with pytest.raises(ValueError, match="interface_model"):
        StaticSettings(interface_model="springs")
    with pytest.raises(ValueError, match="kn"):
        StaticSettings(kn=-1.0)
    with pytest.raises(ValueError, match="live load is zero"):
        solve_collapse(scene.with_loads(live=-scene.loads.live_wrench))
    no_mu = Scene.from_convex_blocks(
        [b.vertices for b in scene.assembly.blocks], 2000.0, fixed=[0]
    ).with_loads(live=scene.loads.live_wrench)
    with pytest.raises(ValueError, match="friction coefficient"):
        solve_collapse(no_mu)
    with pytest.raises(TypeError, match="Scene"):
        solve_collapse("not a scene")
    with pytest.raises(TypeError, match="StaticSettings, got LimitSettings"):
        solve_collapse(scene, LimitSettings())


def test_dead_load_mechanism_is_reported():
    # a block on a 45 degree slope with mu = 0.5 slides under its own weight
    s = 1 / np.sqrt(2)
    base = np.array(
        [
            [0, -1, 0],
            [0, 1, 0],
            [2, -1, 0],
            [2, 1, 0],
            [2, -1, -2],
            [2, 1, -2],
            [0, -1, -2],
            [0, 1, -2.0],
        ]
    )
    base[:, 2] += base[:, 0]  # top face rises along x at 45 degrees
    base[base[:, 2] < -1.5, 2] = -2.0
    cube = np.array([[x, y, z] for x in (0.8, 1.0) for y in (-0.1, 0.1) for z in (0.0, 0.2)])
    # rotate the cube onto the slope around (0.9, 0, 0.9)
    rot = np.array([[s, 0, -s], [0, 1, 0], [s, 0, s]])
    cube = (cube - [0.9, 0, 0.0]) @ rot.T + [0.9, 0.0, 0.9]
    scene = Scene.from_convex_blocks([base, cube], 2000.0, fixed=[0], mu=0.5)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (0, 1, 0)))
    with pytest.raises(StaticSolverError, match="dead load"):
        solve_collapse(scene)


@pytest.mark.parametrize("model", MODELS)
def test_joints_too_stiff_to_tell_contact_from_touching_are_refused(model):
    """The dead load closes the base joint by ``W / (kn A)`` (closed form). Where that is within
    1000 touching gaps (1e-12 of the model's 2 m extent) the run is refused, naming kn; before,
    a block on the ground slid at lambda = 4e-7 instead of mu (kn = 5e15 Pa/m). A kn 1e5 times
    below the refused one gives mu."""
    mu, b, h = 0.3, 0.2, 0.5
    scene = _stack([(b, h)], mu)
    closure = 2000.0 * 9.81 * h  # W / A [Pa], times 1 / kn
    kn_refused = closure / (500 * 1e-12 * 2.0)  # a closure of 500 touching gaps
    with pytest.raises(ValueError, match=r"closes the joints by 1\.0+e-09 m .* too stiff"):
        solve_collapse(scene, StaticSettings(interface_model=model, kn=kn_refused, kt=kn_refused))
    kn = kn_refused * 1e-5
    result = solve_collapse(scene, StaticSettings(interface_model=model, kn=kn, kt=kn / 2.4))
    _near_limit(result, mu)


@pytest.mark.parametrize("model", MODELS)
def test_a_block_on_a_slope_tips_at_the_closed_form(model):
    """A 0.4 x 1 m block on a slope of 20 degrees, pushed downhill by its weight, tips at
    lambda = tan(atan(b / h) - theta) = 0.031451 (closed form). The resultant law approaches
    it slowly (its compressed strip narrows as the rotation^(-1/2)): the path must go on to
    within 0.5 % (it ended 12.5 % low when a slow rise in short steps counted as flat), and
    the stated error bar must hold the closed form."""
    theta, b, h = math.radians(20.0), 0.4, 1.0
    rot = Rotation.from_rotvec([0.0, theta, 0.0]).as_matrix()
    ground = _box(-0.8, 0.8, -0.8, 0.8, -0.3, 0.0) @ rot.T
    block = _box(-b / 2, b / 2, -b / 2, b / 2, 0.0, h) @ rot.T
    scene = Scene.from_convex_blocks([ground, block], 2000.0, fixed=[0], mu=0.9)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    tips = math.tan(math.atan(b / h) - theta)
    result = solve_collapse(scene, StaticSettings(interface_model=model))
    assert result.collapsed
    np.testing.assert_allclose(result.lambda_max, tips, rtol=5e-3)
    assert result.lambda_estimate.contains(tips), result.lambda_estimate
    assert result.lambda_estimate.error <= 5e-3 * tips


@pytest.mark.parametrize("model", MODELS)
def test_a_voussoir_arch_collapses_at_its_rigid_block_limit(model):
    """A semicircular arch of 12 voussoirs (span 2 m, ring 0.2 m) pushed sideways by its
    weight: four hinges, at the multiplier of rigid-block limit analysis (an independent
    method; no joint slides at mu = 0.6, so the associated bound is exact), within 0.1 %,
    and inside the stated error bar."""
    from limit import limit_analysis

    scene = voussoir_arch(2.0, 0.2, 12)
    rigid = limit_analysis(scene, LimitSettings()).lam
    result = solve_collapse(scene, StaticSettings(interface_model=model))
    assert result.collapsed
    np.testing.assert_allclose(result.lambda_max, rigid, rtol=1e-3)
    assert result.lambda_estimate.contains(rigid), result.lambda_estimate


@pytest.mark.parametrize("budget", ["none", "cheap", "full"])
def test_error_budget_of_lambda(budget):
    """``error``: none gives an unknown bar; cheap the free sources (end of path, load
    step, residual) at no cost; full also a run at twice the load step, its wall time
    reported as the cost, and a load-step bar at least the change it measured."""
    scene = _stack([(0.2, 0.5)], 0.7)
    result = solve_collapse(scene, StaticSettings(), error=budget)
    est = result.lambda_estimate
    assert est.value == result.lambda_max
    if budget == "none":
        assert math.isinf(est.error) and est.cost_s == 0.0
        return
    assert {"end of path", "load step", "residual"} <= set(est.sources)
    assert est.contains(0.4)  # rocking at b / h (closed form)
    if budget == "cheap":
        assert est.cost_s == 0.0
    else:
        assert est.cost_s > 0.0
        coarse = solve_collapse(scene, StaticSettings(load_step=0.02), error="none")
        assert est.sources["load step"] >= abs(coarse.lambda_max - result.lambda_max)


@pytest.mark.parametrize("budget", ["cheap", "full"])
def test_a_bar_past_a_peak_measures_the_step_sequence(budget):
    """A mortared block that cracks (tensile strength 10 kPa) loses a fifth of its load after
    the peak (softening): where such a peak lies depends on the steps that reach it, so even
    the cheap budget reruns at a load step 1.001 times as long, and the bar's "step
    sequence" source is twice the change of the peak (full: also the load-step rerun); a
    plateau end stays free (test_error_budget_of_lambda)."""
    scene = _stack([(0.2, 0.5)], 0.7)
    settings = StaticSettings(interface_model="resultant", tensile_strength=1e4)
    result = solve_collapse(scene, settings, error=budget)
    assert result.termination == "softening"
    probe = solve_collapse(scene, replace(settings, load_step=0.01001), error="none")
    est = result.lambda_estimate
    assert est.cost_s > 0.0
    assert est.sources["step sequence"] >= 2.0 * abs(probe.lambda_max - result.lambda_max)
    assert est.contains(probe.lambda_max)
    if budget == "full":
        coarse = solve_collapse(scene, replace(settings, load_step=0.02), error="none")
        assert est.sources["load step"] >= abs(coarse.lambda_max - result.lambda_max)


def test_a_bad_error_budget_is_refused():
    with pytest.raises(ValueError, match="error budget"):
        solve_collapse(_stack([(0.2, 0.5)], 0.7), error="some")


@pytest.mark.parametrize("model", MODELS)
def test_a_block_on_a_frictionless_floor_collapses_at_zero(model):
    """Closed form lambda = mu = 0: the path stays flat at 0 from its first step (the fibre law
    ran to max_steps, its initial slope being noise); a collapse at lambda within 1e-8."""
    result = solve_collapse(_stack([(0.4, 1.0)], 0.0), StaticSettings(interface_model=model))
    assert result.collapsed and abs(result.lambda_max) < 1e-8
