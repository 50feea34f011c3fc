"""A scene without interfaces: its free blocks are held only by their restrained dofs.

A live load on an unrestrained dof of a block that touches nothing is resisted by nothing,
so every entry point gives the collapse multiplier 0 (not a crash, not an error); a dead
load on such a dof makes the structure fall down by itself.
"""

import numpy as np
import pytest

from dem.scene import Scene, Supports, proportional_to_weight
from dem.units import G
from limit import (
    DeadLoadInfeasibleError,
    LimitSettings,
    bounds_and_estimates,
    kinematic_analysis,
    limit_analysis,
    stands,
)
from tests.limit._scenes import box

DENSITY = 2000.0
HUNG = ((-0.2, -0.2, 0.5), (0.2, 0.2, 1.0))  # 0.5 m above the ground: no interface
HUNG_WEIGHT = DENSITY * G * 0.4 * 0.4 * 0.5  # [N]


def hung_block(restrain_uz: bool = True) -> Scene:
    """A block that touches nothing, its uz restrained (hung from above), pushed along +x
    by its weight."""
    ground = box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0))
    scene = Scene.from_convex_blocks([ground, box(*HUNG)], DENSITY, fixed=[0], mu=0.6)
    restrained = np.zeros((2, 6), dtype=bool)
    restrained[1, 2] = restrain_uz
    scene = scene.with_supports(Supports(scene.supports.fixed, restrained))
    live = proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0))
    live[0] = 0.0
    return scene.with_loads(live=live)


def unit_power_slide() -> np.ndarray:
    """The mechanism by hand: the hung block slides along x at unit live-load power."""
    vel = np.zeros((2, 6))
    vel[1, 0] = 1.0 / HUNG_WEIGHT
    return vel


@pytest.mark.parametrize(
    "settings",
    [
        LimitSettings(),
        LimitSettings(interface_model="resultant"),
        LimitSettings(friction_polygon=6),
        LimitSettings(mu=np.inf),
        LimitSettings(compressive_strength=1e6),
        LimitSettings(interface_model="resultant", compressive_strength=1e6),
        LimitSettings(interface_model="resultant", torsion_bending=True),
    ],
    ids=["vertex", "resultant", "polygon", "no_sliding", "f_c", "resultant_f_c", "bending"],
)
def test_static_multiplier_is_zero(settings):
    scene = hung_block()
    assert scene.assembly.interfaces().n_interfaces == 0
    res = limit_analysis(scene, settings)
    np.testing.assert_allclose(res.lam, 0.0, atol=1e-9)
    assert res.interface_forces.shape == (0, 6)
    assert res.certificate.worst() <= settings.cert_tol
    np.testing.assert_allclose(res.velocities, unit_power_slide(), rtol=1e-6, atol=1e-12)


def test_every_entry_point_agrees():
    scene = hung_block()
    lam, vel, status = kinematic_analysis(scene)
    assert status == "optimal"
    np.testing.assert_allclose(lam, 0.0, atol=1e-9)
    np.testing.assert_allclose(vel, unit_power_slide(), rtol=1e-6, atol=1e-12)
    bounds = bounds_and_estimates(scene)
    # upper = lower = 0 brackets the non-associated multiplier exactly
    np.testing.assert_allclose([bounds.upper, bounds.lower], 0.0, atol=1e-9)
    assert bounds.consistent
    check = stands(scene)  # the dead load sits on the restrained uz only
    assert check.stands


def test_dead_load_on_a_free_dof_falls_at_every_entry_point():
    scene = hung_block(restrain_uz=False)
    for solve in (limit_analysis, kinematic_analysis, bounds_and_estimates):
        with pytest.raises(DeadLoadInfeasibleError, match="touch no other block"):
            solve(scene)
    check = stands(scene)
    assert not check.stands
    assert check.blocks == (1,)
