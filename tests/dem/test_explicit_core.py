"""Closed-form checks of the explicit solver core (contact, friction, integration)."""

import math

import numpy as np
import pytest

from dem.explicit import ExplicitModel, ExplicitSettings, RelaxationSettings, SimulationError
from dem.scene import Scene

SIDE = 0.01  # cube side [m]
DENSITY = 2500.0


def cube(x, y, z, side=SIDE, sx=None, sy=None, sz=None):
    sx, sy, sz = sx or side, sy or side, sz or side
    return np.array(
        [[x + i * sx, y + j * sy, z + k * sz] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    )


def chain_scene(n_blocks, stress):
    blocks = [cube(i * SIDE, 0.0, 0.0) for i in range(n_blocks)]
    scene = Scene.from_convex_blocks(blocks, DENSITY, fixed=[0], mu=0.3, g=0.0)
    dead = np.zeros((n_blocks, 6))
    dead[-1, 0] = -stress * SIDE**2  # push the last block towards the fixed one
    return scene.with_loads(dead=dead)


@pytest.mark.parametrize(
    ("spacing", "distance"),
    [(SIDE / 3, "planes"), (SIDE / 7.5, "planes"), (SIDE / 3, "level_set")],
)
def test_chain_shortens_by_m_sigma_over_kn(spacing, distance):
    """A chain of M+1 blocks under stress sigma shortens by M sigma / k_n (seed 000 Sec. 2.3).

    Each interface is counted once, the tributary areas sum to the face area exactly, so the
    result holds at any node spacing (here 3 and 7.5 nodes per side, the latter with clipped
    edge cells), with the face planes or with level-set grids (trilinear interpolation is exact
    where a grid cell sees one face plane only).
    """
    m_interfaces, stress, k_n = 3, 2e6, 1e11
    scene = chain_scene(m_interfaces + 1, stress)
    settings = ExplicitSettings(k_n=k_n, node_spacing=spacing, signed_distance=distance,
                                level_set_spacing=SIDE / 20)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.relax(RelaxationSettings(ke_speed=1e-9, min_steps=2000, max_steps=200000,
                                   global_damping=0.2))  # fmt: skip
    shortening = model.ref_centroid[-1, 0] - model.pos[-1, 0]
    np.testing.assert_allclose(shortening, m_interfaces * stress / k_n, rtol=1e-4)
    # the middle blocks do not rotate or move sideways
    np.testing.assert_allclose(model.pos[:, 1:], model.ref_centroid[:, 1:], atol=1e-12)


def incline_scene(angle, mu):
    ground = cube(-0.02, -0.02, -0.01, sx=0.06, sy=0.05, sz=0.01)
    top = cube(0.0, 0.0, 0.0, sz=0.003)  # flat: no uplift of the uphill edge up to mu = 0.6
    scene = Scene.from_convex_blocks([ground, top], DENSITY, fixed=[0], mu=mu, g=0.0)
    g = 9.81
    dead = np.zeros((2, 6))
    # gravity tilted by `angle` about y: the slope descends along +x
    mass = scene.assembly.mass[1]
    dead[1, 0] = mass * g * math.sin(angle)
    dead[1, 2] = -mass * g * math.cos(angle)
    return scene.with_loads(dead=dead)


def run_incline(angle, mu, duration=0.03, local_damping=0.0):
    scene = incline_scene(angle, mu)
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4, global_damping=0.0,
                                local_damping=local_damping)  # fmt: skip
    model = ExplicitModel(scene, settings)
    n = int(duration / model.dt)
    model.advance(n // 2)
    x1, v1, t1 = model.pos[1, 0], model.vel[1, 0], model.t
    model.advance(n - n // 2)
    return model, x1, v1, t1


@pytest.mark.parametrize("mu", [0.3, 0.6])
def test_block_on_incline_slides_at_tan_angle_mu(mu):
    """A block on a slope sticks below tan(alpha) = mu and slides above it with the closed-form
    acceleration g (sin alpha - mu cos alpha)."""
    critical = math.atan(mu)
    below, x1, _, _ = run_incline(critical - math.radians(2.0), mu)
    assert abs(below.pos[1, 0] - x1) < 1e-7  # elastic creep only: sticks
    above, _, v1, t1 = run_incline(critical + math.radians(2.0), mu)
    alpha = critical + math.radians(2.0)
    expected = 9.81 * (math.sin(alpha) - mu * math.cos(alpha))
    measured = (above.vel[1, 0] - v1) / (above.t - t1)
    np.testing.assert_allclose(measured, expected, rtol=0.02)


def test_local_damping_scales_sliding_acceleration():
    """Local damping c removes c |F| from a force along the motion: a block sliding down a slope
    accelerates at (1 - c) g (sin alpha - mu cos alpha) (c = 0.5 here), it still slides."""
    mu, c = 0.3, 0.5
    alpha = math.atan(mu) + math.radians(5.0)
    above, _, v1, t1 = run_incline(alpha, mu, local_damping=c)
    expected = (1 - c) * 9.81 * (math.sin(alpha) - mu * math.cos(alpha))
    measured = (above.vel[1, 0] - v1) / (above.t - t1)
    np.testing.assert_allclose(measured, expected, rtol=0.03)


def test_resting_block_weight_at_support():
    """A block resting on a fixed block: the support reaction equals its weight (1e-6)."""
    ground = cube(-0.01, -0.01, -0.01, sx=0.03, sy=0.03, sz=0.01)
    scene = Scene.from_convex_blocks([ground, cube(0, 0, 0)], DENSITY, fixed=[0], mu=0.5)
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 5))
    model.relax(RelaxationSettings(ke_speed=1e-12, min_steps=5000, max_steps=400000,
                                   global_damping=0.2))  # fmt: skip
    force, torque, *_ = model.contact_wrenches()
    weight = scene.assembly.mass[1] * 9.81
    np.testing.assert_allclose(force[0], [0.0, 0.0, -weight], rtol=0, atol=1e-6 * weight)
    np.testing.assert_allclose(force[1], [0.0, 0.0, weight], rtol=0, atol=1e-6 * weight)


def free_pair(mu):
    a = cube(0.0, 0.0, 0.0)
    b = cube(SIDE + 2e-5, 0.003, 0.002)  # offset: an eccentric, partial-face impact
    return Scene.from_convex_blocks([a, b], DENSITY, mu=mu, g=0.0)


def momenta(model):
    m = 1.0 / model.inv_mass
    p = (m[:, None] * model.vel).sum(axis=0)
    model_rot = np.zeros((model.n_blocks, 3, 3))
    from dem.kernels.integrate import quat_to_rot

    quat_to_rot(model.quat, model_rot)
    spin = [
        r @ i @ r.T @ w for r, i, w in zip(model_rot, model.inertia_ref, model.omega, strict=True)
    ]
    ang = (np.cross(model.pos, m[:, None] * model.vel) + np.array(spin)).sum(axis=0)
    return p, ang


def test_momentum_conserved_without_supports():
    """Equal and opposite nodal forces at one point: linear and angular momentum are exact."""
    scene = free_pair(mu=0.4)
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4, global_damping=0.0,
                                margin=5e-4)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.vel[0] = [0.5, 0.1, -0.05]
    model.omega[0] = [3.0, -2.0, 5.0]
    p0, l0 = momenta(model)
    model.advance(int(2e-3 / model.dt))
    assert np.any(np.abs(model.vel[1]) > 0.05)  # they did collide
    p1, l1 = momenta(model)
    np.testing.assert_allclose(p1, p0, rtol=0, atol=1e-12 * np.linalg.norm(p0))
    np.testing.assert_allclose(l1, l0, rtol=0, atol=1e-10 * np.linalg.norm(l0) + 1e-15)


def test_energy_does_not_grow_frictionless_undamped():
    """Frictionless, undamped eccentric impact: kinetic plus penalty energy stays at its initial
    value (0.2 % after the impact, 1 % during it at dt = 0.05 dt_crit: the O(dt) error of the
    explicit scheme) and never grows beyond that."""
    scene = free_pair(mu=0.0)
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4, global_damping=0.0,
                                contact_damping=0.0, margin=5e-4, dt_safety=0.05)  # fmt: skip
    model = ExplicitModel(scene, settings)
    model.vel[0] = [0.5, 0.0, 0.0]
    e0 = model.kinetic_energy()
    history = []
    for _ in range(40):
        model.advance(int(1e-4 / model.dt))
        history.append(model.kinetic_energy() + model.elastic_energy(current=True))
    assert max(history) <= e0 * 1.01
    np.testing.assert_allclose(model.kinetic_energy(), e0, rtol=2e-3)


def test_overlapping_blocks_rejected():
    a = cube(0.0, 0.0, 0.0)
    b = cube(SIDE - 1e-4, 0.0, 0.0)
    scene = Scene.from_convex_blocks([a, b], DENSITY, fixed=[0], mu=0.3)
    with pytest.raises(ValueError, match="overlap"):
        ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))


def test_forced_time_step_above_limit_rejected():
    scene = chain_scene(3, 1e5)
    with pytest.raises(ValueError, match="stable limit"):
        ExplicitModel(scene, ExplicitSettings(k_n=1e11, node_spacing=SIDE / 3, dt=1e-3))


def test_nan_inputs_rejected():
    with pytest.raises(ValueError, match="k_n"):
        ExplicitSettings(k_n=float("nan"))
    scene = chain_scene(3, 1e5)
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e11, node_spacing=SIDE / 3))
    model.vel[1, 0] = float("nan")
    with pytest.raises(SimulationError, match="NaN"):
        model.advance(10)


def test_deep_overlap_without_touching_faces_rejected():
    """A cube sunk half-way into another along its diagonal: no pair of faces is within the
    margin, so no contact node sees it; the toolkit's geometric check refuses it."""
    from dem import OverlapError

    scene = Scene.from_convex_blocks(
        [cube(0.0, 0.0, 0.0), cube(SIDE / 2, SIDE / 2, SIDE / 2)], DENSITY, fixed=[0], mu=0.3
    )
    with pytest.raises(OverlapError, match="blocks 0 and 1"):
        ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))
