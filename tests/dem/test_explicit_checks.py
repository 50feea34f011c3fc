"""Checks of the explicit solver's inputs and results: balance after relaxation, mu = inf in
the settings, the tilting table's direction."""

import dataclasses
import math

import numpy as np
import pytest
import scipy.optimize

from dem.explicit import (
    ExplicitModel,
    ExplicitSettings,
    RelaxationSettings,
    SimulationError,
    TiltingTable,
    simulate_lateral,
)
from dem.scene import Scene, proportional_to_weight

G = 9.81
HEAVY_MASS = 2.0  # [kg]
HEAVY_SIDE = 0.05  # [m]


def box(x0, y0, z0, sx, sy, sz):
    return np.array(
        [[x0 + i * sx, y0 + j * sy, z0 + k * sz] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    )


GROUND = box(-0.05, -0.05, -0.01, 0.1, 0.1, 0.01)


def heavy_on_light_plate():
    """Fixed ground (block 0), a light plate (1) and on it a block 400 times denser (2)."""
    plate = box(-0.03, -0.03, 0.0, 0.06, 0.06, 0.005)
    heavy = box(-0.025, -0.025, 0.005, HEAVY_SIDE, HEAVY_SIDE, HEAVY_SIDE)
    rho = HEAVY_MASS / HEAVY_SIDE**3
    return Scene.from_convex_blocks([GROUND, plate, heavy], [rho / 400, rho / 400, rho],
                                    fixed=[0], mu=0.5)  # fmt: skip


def test_heavy_block_on_light_plate_is_out_of_balance_when_relaxation_stops_at_rest():
    """The light plate sets omega_max, the damping over-damps the heavy block: it creeps slowly
    enough for the kinetic energy to pass while the ground carries too little. Closed form: the
    ground carries the total weight; what it misses is the heavy block's net force."""
    scene = heavy_on_light_plate()
    settings = ExplicitSettings(k_n=1e12, node_spacing=0.01)
    short = RelaxationSettings(max_steps=8000)  # at rest from about 7200 steps on
    with pytest.raises(SimulationError, match="block 2 out of balance.*local_damping=0.7"):
        ExplicitModel(scene, settings).relax(short)
    model = ExplicitModel(scene, settings)
    info = model.relax(RelaxationSettings(max_steps=8000, require_convergence=False))
    assert info["kinetic"] <= info["tolerance"]
    force, *_ = model.contact_wrenches()
    weight = scene.assembly.mass[1:].sum() * G
    missing = weight + force[0, 2]  # the ground's reaction is -force[0]
    assert missing > 0.01 * HEAVY_MASS * G
    assert info["unbalanced_block"] == 2
    np.testing.assert_allclose(info["unbalanced_ratio"], missing / (HEAVY_MASS * G), rtol=1e-3)


@pytest.mark.parametrize("relaxation", [
    RelaxationSettings(),  # goes on past rest until the block has settled
    RelaxationSettings(ke_speed=1e-7),
    RelaxationSettings(global_damping=0.0, local_damping=0.7),
], ids=["default", "slower", "local"])  # fmt: skip
def test_heavy_block_on_light_plate_settles(relaxation):
    """Relaxation ends only once the ground carries the weight within ``unbalanced_tol``."""
    scene = heavy_on_light_plate()
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e12, node_spacing=0.01))
    info = model.relax(relaxation)
    force, *_ = model.contact_wrenches()
    weight = scene.assembly.mass[1:].sum() * G
    assert info["unbalanced_ratio"] < 1e-2
    assert abs(weight + force[0, 2]) <= info["unbalanced_ratio"] * HEAVY_MASS * G * (1 + 1e-3)


def test_out_of_balance_at_rest_without_viscous_damping_is_not_blamed_on_it():
    """A block on a slope 2 degrees steeper than its friction angle, relaxed with local damping
    only and a loose kinetic-energy tolerance: at ``max_steps`` it is at rest yet sliding, out
    of balance by ``sin a - mu cos a`` of its weight (closed form), and the error does not
    blame a viscous damping that did not act."""
    mu = 0.3
    angle = math.atan(mu) + math.radians(2.0)
    ground, block = box(-0.05, -0.05, -0.01, 0.1, 0.1, 0.01), box(0.0, 0.0, 0.0, 0.01, 0.01, 0.003)
    scene = Scene.from_convex_blocks([ground, block], 2500.0, fixed=[0], mu=mu, g=0.0)
    weight = scene.assembly.mass[1] * G
    dead = np.zeros((2, 6))
    dead[1, 0], dead[1, 2] = weight * math.sin(angle), -weight * math.cos(angle)
    scene = scene.with_loads(dead=dead)
    relaxation = RelaxationSettings(global_damping=0.0, local_damping=0.7, ke_speed=1e-2,
                                    max_steps=2000)  # fmt: skip
    settings = ExplicitSettings(k_n=1e10, node_spacing=0.0025)
    with pytest.raises(SimulationError, match="no viscous damping") as caught:
        ExplicitModel(scene, settings).relax(relaxation)
    assert "viscous damping holds" not in str(caught.value)
    model = ExplicitModel(scene, settings)
    info = model.relax(dataclasses.replace(relaxation, require_convergence=False))
    assert info["kinetic"] <= info["tolerance"]
    np.testing.assert_allclose(
        info["unbalanced_ratio"], math.sin(angle) - mu * math.cos(angle), rtol=0.05
    )


def test_a_wedge_with_gaps_drops_into_its_seat():
    """A wedge between two fixed blocks whose faces lean theta from the vertical, a normal gap g
    on each side: relaxed with local damping only, it drops g / sin(theta) (closed form) and
    is then in balance."""
    theta, gap, a, h, d = math.radians(10.0), 1e-4, 0.02, 0.02, 0.02
    t, shift = math.tan(theta), gap / math.cos(theta)

    def prism(x_bottom, x_top):  # (x at z = 0, x at z = h) of the left and right sides
        return np.array([[x, y, z] for (x, z) in ((x_bottom[0], 0), (x_bottom[1], 0),
                         (x_top[0], h), (x_top[1], h)) for y in (0.0, d)])  # fmt: skip

    wedge = prism((-a, a), (-a - h * t, a + h * t))
    left = prism((-3 * a, -a - shift), (-3 * a, -a - h * t - shift))
    right = prism((a + shift, 3 * a), (a + h * t + shift, 3 * a))
    scene = Scene.from_convex_blocks([left, right, wedge], 2500.0, fixed=[0, 1], mu=0.5)
    k_n = 1e11
    model = ExplicitModel(scene, ExplicitSettings(k_n=k_n, node_spacing=0.004, margin=1e-3))
    z0 = model.state.motion.pos[2, 2]
    model.relax(RelaxationSettings(global_damping=0.0, local_damping=0.7, max_steps=400000))
    drop = z0 - model.state.motion.pos[2, 2]
    # the penalty layer adds the normal pressure over k_n, turned vertical by 1 / sin(theta)
    weight = scene.assembly.mass[2] * G
    squeeze = weight / (2 * math.sin(theta) * d * h / math.cos(theta)) / k_n / math.sin(theta)
    np.testing.assert_allclose(drop, gap / math.sin(theta) + squeeze, rtol=2e-2)
    assert np.all(model.unbalanced() < 1e-2)


def test_block_resting_on_ground_is_in_balance():
    """One block on the ground: the relaxation passes the balance check and the ground carries
    its weight within the reported ratio."""
    scene = Scene.from_convex_blocks([GROUND, box(0.0, 0.0, 0.0, 0.02, 0.02, 0.02)], 2500.0,
                                     fixed=[0], mu=0.5)  # fmt: skip
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=0.005))
    info = model.relax(RelaxationSettings())
    weight = scene.assembly.mass[1] * G
    force, *_ = model.contact_wrenches()
    assert info["unbalanced_ratio"] < 1e-2
    assert abs(force[0, 2] + weight) <= info["unbalanced_ratio"] * weight * (1 + 1e-6)


def test_unbalanced_tol_refuses_nonsense():
    with pytest.raises(ValueError, match="unbalanced_tol"):
        RelaxationSettings(unbalanced_tol=0.0)


@pytest.mark.parametrize("value", [-0.1, 1.0, math.nan])
def test_relaxation_local_damping_refuses_nonsense(value):
    with pytest.raises(ValueError, match=r"local_damping must be in \[0, 1\)"):
        RelaxationSettings(local_damping=value)


SLOPE = math.radians(60.0)


def incline_motion(scene_mu, settings_mu, angle=SLOPE, n_steps=4000):
    """A flat block on ground tilted by ``angle`` (gravity turned), its centroid after
    ``n_steps`` steps."""
    top = box(0.0, 0.0, 0.0, 0.01, 0.01, 0.003)  # b / h = 3.3 > tan(60 deg): does not tip
    scene = Scene.from_convex_blocks([GROUND, top], 2500.0, fixed=[0], mu=scene_mu, g=0.0)
    dead = np.zeros((2, 6))
    mass = scene.assembly.mass[1]
    dead[1, 0], dead[1, 2] = mass * G * math.sin(angle), -mass * G * math.cos(angle)
    settings = ExplicitSettings(k_n=1e10, node_spacing=0.0025, global_damping=0.0,
                                mu=settings_mu)  # fmt: skip
    model = ExplicitModel(scene.with_loads(dead=dead), settings)
    model.advance(n_steps)
    return model.pos[1].copy()


def test_settings_mu_inf_is_scene_mu_inf():
    """``ExplicitSettings(mu=inf)`` is no sliding, as ``mu = inf`` in the scene: the same motion
    bit for bit; on a 60 degree slope the block sticks (elastic creep only), with mu = 0.3 it
    slides."""
    from_settings = incline_motion(0.3, math.inf)
    from_scene = incline_motion(math.inf, None)
    np.testing.assert_array_equal(from_settings, from_scene)
    start = box(0.0, 0.0, 0.0, 0.01, 0.01, 0.003).mean(axis=0)
    assert abs(from_settings[0] - start[0]) < 1e-6
    assert incline_motion(0.3, None)[0] - start[0] > 1e-4
    with pytest.raises(ValueError, match="mu"):
        ExplicitSettings(k_n=1e10, mu=math.nan)


def table_scene(live_direction=None):
    block = box(0.0, 0.0, 0.0, 0.02, 0.02, 0.02)
    scene = Scene.from_convex_blocks([GROUND, block], 2500.0, fixed=[0], mu=0.5)
    if live_direction is None:
        return scene
    return scene.with_loads(live=proportional_to_weight(scene.assembly, live_direction))


def test_tilting_table_refuses_a_vertical_live_load():
    """A live load with no horizontal component gives no tilt direction: refused, not +y."""
    vertical = table_scene((0.0, 0.0, -1.0))
    with pytest.raises(ValueError, match="horizontal"):
        TiltingTable().wrench(vertical, 0.5)
    with pytest.raises(ValueError, match="horizontal"):  # before any relaxation
        simulate_lateral(vertical, driver=TiltingTable())
    # a direction given, or a live load with a horizontal part, or none at all (+y) is fine
    w = TiltingTable(direction=(1.0, 0.0, 0.0)).wrench(table_scene((0.0, 0.0, -1.0)), 0.5)
    assert w[1, 0] > 0 and w[1, 1] == 0
    w = TiltingTable().wrench(table_scene((-1.0, 0.0, -1.0)), 0.5)
    np.testing.assert_allclose(w[1, 0] / w[1, 2], 0.5, rtol=1e-12)  # leans along -x
    w = TiltingTable().wrench(table_scene(), 0.5)
    np.testing.assert_allclose(w[1, 1] / -w[1, 2], 0.5, rtol=1e-12)


def _amplification(h: float, a: float) -> np.ndarray:
    """One symplectic Euler step of ``x'' = -omega^2 x - (a / dt) x'`` on ``(x, dt v)``."""
    return np.array([[1 - h * h, 1 - a], [-h * h, 1 - a]])


def test_a_global_damping_that_makes_the_step_unstable_is_refused():
    """The damping force is explicit: the top mode's step is stable while the spectral radius of
    its amplification matrix (computed here) is at most 1. A damping ratio 5 % under that limit
    relaxes a block on the ground into balance; 5 % above, the settings are refused."""
    scene = Scene.from_convex_blocks([GROUND, box(0.0, 0.0, 0.0, 0.02, 0.02, 0.02)], 2500.0,
                                     fixed=[0], mu=0.5)  # fmt: skip
    settings = ExplicitSettings(k_n=1e10, node_spacing=0.005)
    model = ExplicitModel(scene, settings)
    w, dt = model.omega_max, model.dt
    h, dashpot = w * dt, model.beta * w * w * dt

    def radius(ratio):
        return max(abs(np.linalg.eigvals(_amplification(h, 2 * ratio * w * dt + dashpot))))

    limit = scipy.optimize.brentq(lambda r: radius(r) - 1.0 - 1e-12, 0.0, 10.0)
    assert radius(0.95 * limit) <= 1.0 < radius(1.05 * limit)
    info = model.relax(RelaxationSettings(global_damping=0.95 * limit))
    assert info["unbalanced_ratio"] < 1e-2
    with pytest.raises(ValueError, match="RelaxationSettings.global_damping.*unstable"):
        model.relax(RelaxationSettings(global_damping=1.05 * limit))
    with pytest.raises(ValueError, match="ExplicitSettings.global_damping.*unstable"):
        ExplicitModel(scene, dataclasses.replace(settings, global_damping=1.05 * limit))
