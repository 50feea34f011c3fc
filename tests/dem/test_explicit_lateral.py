"""Lateral-load driver against closed forms: rocking at b/h, sliding at mu, a two-block stack.

A rigid block of width ``b`` (along the tilt) and height ``h`` on a fixed base, under its weight
and a lateral force ``lambda`` times its weight (a table tilted by ``theta``, ``lambda =
tan theta``), stays at rest while ``lambda < min(mu, b / h)``: it slides at ``mu`` (the
friction cone) and rocks at ``b / h`` (the resultant reaches the downhill edge). A stack of two
equal blocks of height ``h`` rocks as a whole at ``b / (2 h)`` (its centroid at ``h``, the top
block alone only at ``b / h``) and slides at ``mu`` (same ``mu`` on both joints).

The driver brackets the threshold: ``lambda_stable < lambda* <= lambda_moving`` within the
bracket width ``step / 2^refinements``, and a slowly moving block may be judged at rest by at
most ``detection_lambda`` above ``lambda*`` (see :mod:`dem.explicit.lateral`).
"""

import itertools

import numpy as np
import pytest

from dem.explicit import (
    ExplicitSettings,
    LiveLoadRamp,
    MotionCriteria,
    SimulationError,
    TiltingTable,
    masonry_settings,
    simulate_lateral,
)
from dem.scene import Scene, proportional_to_weight

DENSITY = 2000.0
THICKNESS = 0.2  # [m], along x (out of the tilt plane)


def box(lo, hi):
    return np.array(list(itertools.product(*zip(lo, hi, strict=True))), dtype=float)


def stack_on_ground(b, h, mu, n_blocks=1):
    """``n_blocks`` equal blocks ``b`` (along y) by ``h`` stacked on a fixed base."""
    ground = box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0))
    blocks = [box((0.0, 0.0, k * h), (THICKNESS, b, (k + 1) * h)) for k in range(n_blocks)]
    return Scene.from_convex_blocks(blocks + [ground], DENSITY, fixed=[n_blocks], mu=mu)


def assert_brackets(result, expected, driver):
    assert result.collapsed and result.mechanism_confirmed
    width = driver.step / 2**driver.refinements
    assert result.lambda_moving - result.lambda_stable <= width + 1e-12
    assert result.lambda_stable - result.detection_lambda <= expected <= result.lambda_moving
    assert result.detection_lambda < 2e-3  # the thresholds as stated are tight


@pytest.mark.parametrize(
    ("b", "h", "mu", "mechanism"),
    [(0.1, 0.25, 0.7, "rocking"), (0.3, 0.1, 0.3, "sliding")],
)
def test_single_block_tilting_table(b, h, mu, mechanism):
    """Tilting table: the bracket holds min(mu, b/h) (rocking 0.4; sliding 0.3)."""
    driver = TiltingTable(step=0.05, refinements=4)
    result = simulate_lateral(stack_on_ground(b, h, mu), driver=driver)
    expected = min(mu, b / h)
    assert (b / h < mu) == (mechanism == "rocking")
    assert_brackets(result, expected, driver)
    np.testing.assert_array_equal(result.moving_blocks, [0])
    # every recorded step agrees with the bracket
    stable = result.record_stable
    assert np.all(result.record_lambda[stable] <= result.lambda_stable)
    assert np.all(result.record_lambda[~stable] >= result.lambda_moving)


def test_two_block_stack_rocks_as_a_whole():
    """Two blocks 0.1 x 0.125 m: the stack rocks at b / (2h) = 0.4 < mu = 0.7 < b / h = 0.8,
    both blocks move."""
    driver = TiltingTable(step=0.05, refinements=4)
    result = simulate_lateral(stack_on_ground(0.1, 0.125, 0.7, n_blocks=2), driver=driver)
    assert_brackets(result, 0.4, driver)
    np.testing.assert_array_equal(result.moving_blocks, [0, 1])


def test_live_load_ramp_matches_tilting_closed_form():
    """A live load equal to the weight along +y, ramped and held: sliding at mu = 0.3."""
    scene = stack_on_ground(0.3, 0.1, 0.3)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (0.0, 1.0, 0.0)))
    driver = LiveLoadRamp(step=0.05, refinements=4)
    result = simulate_lateral(scene, driver=driver)
    assert_brackets(result, 0.3, driver)


def test_no_collapse_below_max_lambda_is_not_a_collapse():
    """A squat block (b/h = 3, mu = 0.7) tilted up to 0.5 only: not collapsed, NaN moving."""
    driver = TiltingTable(step=0.25, max_lambda=0.5)
    result = simulate_lateral(stack_on_ground(0.3, 0.1, 0.7), driver=driver)
    assert not result.collapsed
    assert np.isnan(result.lambda_moving)
    assert result.lambda_stable == pytest.approx(0.5)
    assert len(result.moving_blocks) == 0


def test_floating_block_is_named():
    """A block hanging in the air (block 1, 0.5 m above the other) is refused by name."""
    ground = box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0))
    scene = Scene.from_convex_blocks(
        [box((0, 0, 0), (0.2, 0.2, 0.2)), box((0, 0, 0.7), (0.2, 0.2, 0.9)), ground],
        DENSITY,
        fixed=[2],
        mu=0.5,
    )
    with pytest.raises(SimulationError, match=r"1 blocks .* no support.*\[1\]"):
        simulate_lateral(scene)


def test_scene_without_live_load_refused_by_live_ramp():
    with pytest.raises(ValueError, match="no live load"):
        simulate_lateral(stack_on_ground(0.3, 0.1, 0.3), driver=LiveLoadRamp())


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"step": 0.0}, "step"),
        ({"hold": -1.0}, "hold"),
        ({"max_hold": 0.5}, "max_hold"),
        ({"refinements": -1}, "refinements"),
        ({"direction": (0.0, 0.0, 1.0)}, "direction"),
        ({"start": 1.0}, "start"),
        ({"start": -0.1}, "start"),
    ],
)
def test_nonsense_driver_settings_refused(kwargs, name):
    with pytest.raises(ValueError, match=name):
        TiltingTable(**kwargs)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"speed_fraction": 2.0}, "speed_fraction"),
        ({"onset_fraction": 0.0}, "onset_fraction"),
        ({"onset_ratio": 1.0}, "onset_ratio"),
        ({"onset_ratio": float("nan")}, "onset_ratio"),
    ],
)
def test_nonsense_motion_criteria_refused(kwargs, name):
    with pytest.raises(ValueError, match=name):
        MotionCriteria(**kwargs)


def test_masonry_settings_kn_from_material():
    """k_n = E / L: a block of height 0.25 on a fixed base, E = 1 GPa -> 4 GPa/m (rigid
    joints), in series with a joint of 4 GPa/m -> 2 GPa/m; nodes on the edges (vertex
    layout), spacing the smallest block side over 4."""
    scene = stack_on_ground(0.1, 0.25, 0.7)
    np.testing.assert_allclose(masonry_settings(scene, 1e9, None).k_n, 1e9 / 0.25, rtol=1e-12)
    settings = masonry_settings(scene, young=1e9, joint_stiffness=4e9)
    np.testing.assert_allclose(settings.k_n, 2e9, rtol=1e-12)
    assert settings.node_layout == "vertex"
    np.testing.assert_allclose(settings.node_spacing, 0.1 / 4, rtol=1e-12)
    assert isinstance(settings, ExplicitSettings)


def test_kn_from_material_refuses_bad_input():
    from dem.explicit import k_n_from_material

    with pytest.raises(ValueError, match="young"):
        k_n_from_material(stack_on_ground(0.1, 0.25, 0.7), young=-1.0)
    lone = Scene.from_convex_blocks([box((0, 0, 0), (0.1, 0.1, 0.1))], DENSITY, mu=0.5)
    with pytest.raises(ValueError, match="no face-to-face interface"):
        k_n_from_material(lone)


def test_tilting_table_turns_gravity():
    """At lambda = tan(theta) the weight keeps its magnitude m g and leans by theta towards the
    tilt direction: horizontal / vertical = lambda; the live-load ramp adds lambda m g."""
    scene = stack_on_ground(0.1, 0.25, 0.7)
    weight = scene.assembly.mass[0] * 9.81
    w = TiltingTable(direction=(0.0, 1.0, 0.0)).wrench(scene, 0.75)
    np.testing.assert_allclose(np.linalg.norm(w[0, :3]), weight, rtol=1e-12)
    np.testing.assert_allclose(w[0, 1] / -w[0, 2], 0.75, rtol=1e-12)
    live = scene.with_loads(live=proportional_to_weight(scene.assembly, (0.0, 1.0, 0.0)))
    r = LiveLoadRamp().wrench(live, 0.75)
    np.testing.assert_allclose(r[0, :3], [0.0, 0.75 * weight, -weight], rtol=1e-12)
