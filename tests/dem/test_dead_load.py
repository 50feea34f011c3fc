"""The dead load in increments with automatic cutting (:mod:`dem.static.dead_load`).

One Newton solve for the whole dead load, from unloaded joints, decided every joint's state at
once: seed 001 S23 (resultant law, return walls of blocks) found its dead load under one
OpenBLAS kernel only. The increments are cut on failure; when even the smallest fails, the
error says how much of the dead load was carried and names the blocks. Expectations: the
limit analysis' certified dead-load check (:func:`limit.stands`, with the blocks that move)
and closed forms.
"""

import numpy as np
import pytest

from dem.scene import Scene, proportional_to_weight
from dem.scenes.return_walls import wall_with_returns
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import DeadLoadError, StaticSettings, StaticSolverError, solve_collapse
from dem.static.dead_load import solve_dead_load
from dem.static.model import Model
from dem.static.newton import Corrector

A, B, S = 28.24, 79.78, 39.68  # seed 001 Table 2 blocks [mm]


def _wall_with_opening(n, courses, x, z):
    """A dry running-bond wall on a foundation with one opening ``x`` blocks wide and ``z``
    courses high (block units)."""
    opening = [(x[0] * B, z[0] * A, x[1] * B, z[1] * A)]
    return running_bond_wall(
        n, courses, A, B, S, unit_weight_kn_m3=26.8, mu=0.7, base=True, openings_mm=opening
    )


def _dead_load(scene, **kw):
    settings = StaticSettings(interface_model="resultant", **kw)
    model = Model(scene, settings)
    point, _ = solve_dead_load(Corrector(model, settings))
    return model, point


def test_wall_over_an_opening_is_carried_in_increments():
    # 7 x 9 wall with two return walls of blocks (as seed 001 S23), an opening 3 blocks wide
    # over courses 3-6: the blocks over it corbel on their neighbours. The limit analysis
    # certifies that it stands; the dead load in increments and in one Newton solve
    # (dead_min_step = 1; it stalled while the shear-torsion return lost the torsion's digits
    # near the sliding corner) both end in equilibrium.
    from limit import stands

    opening = [(1 * B, 3 * A, 4 * B, 6 * A)]
    scene = wall_with_returns(
        7, 9, A, B, S, 26.8, mu=0.7, returns=("left", "right"), openings_mm=opening
    )
    assert stands(scene).stands
    for min_step in (1.0, None):
        model, point = (
            _dead_load(scene) if min_step is None else _dead_load(scene, dead_min_step=min_step)
        )
        assert np.linalg.norm(point.residual) <= 1e-6 * model.dead_norm


def test_wall_over_a_too_wide_opening_is_not_carried():
    # 5 x 6 wall, opening 3 blocks wide over courses 2-5: the blocks over it cannot corbel
    # (limit analysis: they move). No part of the dead load is carried, and the error names
    # the blocks the limit analysis finds moving.
    from limit import stands

    scene = _wall_with_opening(5, 6, (1, 4), (2, 5))
    check = stands(scene)
    assert not check.stands
    with pytest.raises(DeadLoadError, match="no equilibrium under any part") as err:
        _dead_load(scene)
    assert err.value.fraction == 0.0
    assert set(check.blocks) <= set(err.value.blocks)


def _box(x0, x1, z0, z1, depth=0.3):
    return np.array(
        [(x, y, z) for x in (x0, x1) for y in (-depth / 2, depth / 2) for z in (z0, z1)]
    )


def test_overhanging_block_names_itself():
    # a block whose centroid lies beyond the edge of its support overturns under any load
    blocks = [_box(-1, 0.05, -0.2, 0), _box(0.0, 0.2, 0, 0.5)]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.6)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    with pytest.raises(StaticSolverError) as err:
        solve_collapse(scene, StaticSettings(interface_model="resultant"))
    assert isinstance(err.value, DeadLoadError)
    assert err.value.fraction == 0.0 and err.value.blocks[0] == 1


def test_hanging_block_carried_up_to_its_mortar_strength():
    # a block hanging from a fixed block through a mortared joint: pure tension t W, carried
    # up to f_t A (closed form t* = f_t A / W), then the joint breaks. The increments find
    # the dead load carried to within the smallest increment below t*
    b, h, depth, density = 0.2, 0.5, 0.3, 2000.0
    blocks = [_box(-1, 1, 0.0, 0.2), _box(-b / 2, b / 2, -h, 0.0)]
    scene = Scene.from_convex_blocks(blocks, density, fixed=[0], mu=0.6)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    weight = density * 9.81 * b * depth * h
    sigma_t = 0.4 * weight / (b * depth)
    with pytest.raises(DeadLoadError, match="carried up to") as err:
        _dead_load(scene, tensile_strength=sigma_t)
    t_star = sigma_t * b * depth / weight
    assert t_star - 1e-3 <= err.value.fraction <= t_star
    assert err.value.blocks[0] == 1
