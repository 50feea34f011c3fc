"""The static DEM on a single block under loads a user may apply: a torque instead of a force,
and a push that tips the block about a corner (both laws, closed forms of the rigid block)."""

import math

import numpy as np
import pytest

from dem.scene import Scene, proportional_to_weight
from dem.static import StaticSettings, solve_collapse

B, H = 0.4, 1.0  # base side and height of the block [m]


def _box(lo, hi):
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def _block_on_ground(mu=0.9):
    ground = _box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0))
    block = _box((-B / 2, -B / 2, 0.0), (B / 2, B / 2, H))
    return Scene.from_convex_blocks([ground, block], 2000.0, fixed=[0], mu=mu)


@pytest.mark.parametrize("law", ["resultant", "fibre"])
def test_a_torque_alone_tips_the_block_at_half_its_weight_times_its_base(law):
    """A live load of one moment about y (no force): the block tips about its edge when the
    moment reaches W B / 2 (it was refused as a zero live load)."""
    scene = _block_on_ground()
    weight = scene.assembly.mass[1] * 9.81
    live = np.zeros((2, 6))
    live[1, 4] = weight * B  # lambda = 1/2 at tipping
    result = solve_collapse(scene.with_loads(live=live), StaticSettings(interface_model=law))
    assert result.collapsed
    assert result.lambda_max == pytest.approx(0.5, rel=0.01)


@pytest.mark.parametrize("law", ["resultant", "fibre"])
def test_a_push_tips_the_block_about_an_edge(law):
    """Weight-proportional push: the rigid block tips about its edge at lambda = B / H. The
    resultant law's elastic compressed part shrinks towards the edge only as a power of the
    rotation, so it ends a little below."""
    scene = _block_on_ground()
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    result = solve_collapse(scene, StaticSettings(interface_model=law))
    assert result.termination == "plateau"
    assert B / H * (1 - 0.015) <= result.lambda_max <= B / H * (1 + 1e-6)


def test_a_corner_tipping_is_reached_by_both_laws():
    """Pushed along the diagonal the rigid block tips about a corner at sqrt(2) B / H. The
    fibre law has a spring at the corner and reaches it; the resultant law's compressed part
    shrinks as theta^(-1/3), an approach its path follows (in growing steps) until lambda may
    rise by less than 0.1 %: within 0.1 %, and the closed form inside its stated bar."""
    scene = _block_on_ground()
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 1.0, 0.0)))
    expected = math.sqrt(2.0) * B / H
    for model in ("fibre", "resultant"):
        result = solve_collapse(scene, StaticSettings(interface_model=model))
        assert result.termination == "plateau"
        assert result.lambda_max == pytest.approx(expected, rel=1e-3)
        assert result.lambda_estimate.contains(expected), result.lambda_estimate
