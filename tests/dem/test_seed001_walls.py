"""Builders of the seed 001 specimens against the seed's stated dimensions and loads."""

import numpy as np
import pytest

from dem.scenes.seed001_walls import (
    CHEE_LIANG_NAMES,
    RESTREPO_NAMES,
    SPECIMENS,
    chee_liang_specimen,
    orduna_panel,
    restrepo_specimen,
)
from dem.units import G


def _wall_extent(scene):
    in_wall = np.array(scene.meta["course"]) >= 0  # all but the foundation
    verts = np.concatenate(
        [b.vertices for b, f in zip(scene.assembly.blocks, in_wall, strict=True) if f]
    )
    return verts.max(0) - verts.min(0)


def test_specimen_table_matches_seed_tables():
    # seed 001 Tables 1-3: 2 + 10 + 6 specimens
    tables = [s.table for s in SPECIMENS.values()]
    assert tables.count("Table 1") == 2
    assert tables.count("Table 2") == 10
    assert tables.count("Table 3") == 6
    assert SPECIMENS["orduna-3x13"].seed_dem == 0.175
    assert SPECIMENS["orduna-6x13"].references == {"fem": 0.260, "limit": 0.193}
    assert SPECIMENS["restrepo-S15"].reference == 0.199
    assert SPECIMENS["chee-liang-10-11"].references == {"test_1": 5.20, "test_2": 4.51}


@pytest.mark.parametrize("n, length", [(3, 0.630), (6, 1.260)])
def test_orduna_panels_have_the_seed_dimensions_and_restraints(n, length):
    scene = orduna_panel(n)
    ext = _wall_extent(scene)
    # seed 001 Sec. 3.1: L = 0.630 or 1.260 m, H = 1.053 m, s = 0.07 m
    np.testing.assert_allclose(ext, [length, 0.07, 1.053], rtol=1e-12)
    restrained = scene.supports.restrained
    assert restrained[:, :3].all(axis=1).sum() == 13 * (1 if n == 3 else 2)
    assert not restrained[:, 3:].any()
    # live load = weight of the wall along +y: gamma L H s
    live = scene.loads.live_wrench[~scene.supports.fixed, 1].sum()
    np.testing.assert_allclose(live, 20e3 * length * 1.053 * 0.07, rtol=1e-12)


def test_orduna_rejects_other_panels():
    with pytest.raises(ValueError, match="3 x 13"):
        orduna_panel(13)


@pytest.mark.parametrize("name", RESTREPO_NAMES)
def test_restrepo_specimens(name):
    scene = restrepo_specimen(name)
    n = SPECIMENS[f"restrepo-{name}"].args["n_per_course"]
    ext = _wall_extent(scene)
    np.testing.assert_allclose(ext[0], n * 79.78e-3, rtol=1e-12)
    np.testing.assert_allclose(ext[2], 21 * 28.24e-3, rtol=1e-12)
    n_fixed_cols = {"left": 1, "both": 2}.get(SPECIMENS[f"restrepo-{name}"].supports[:4], None)
    if name == "S32":
        # eleven beams of 16.46 N (seed 001 Sec. 3.2)
        np.testing.assert_allclose(-scene.loads.dead_wrench[:, 2].sum(), 11 * 16.46, rtol=1e-12)
        assert scene.supports.fixed.sum() == 1
    elif n_fixed_cols is not None:
        assert scene.supports.fixed.sum() == 1 + 21 * n_fixed_cols


@pytest.mark.parametrize("name", ["S15", "S5", "S23"])
def test_restrepo_return_walls_as_blocks_interlock(name):
    scene = restrepo_specimen(name, return_walls="blocks")  # raises OverlapError on overlaps
    itf = scene.assembly.interfaces()
    wall = np.array(scene.meta["wall"])
    touched = np.zeros(scene.n_blocks, dtype=int)
    np.add.at(touched, itf.block_a, 1)
    np.add.at(touched, itf.block_b, 1)
    assert (touched > 0).all()
    # every return-wall course touches the main wall through the corner bond
    between = (wall[itf.block_a] == 0) & (wall[itf.block_b] > 0)
    n_returns = 1 if name == "S15" else 2
    assert between.sum() >= 21 * n_returns
    # same weight per unit volume as the fixed-column model
    dens = scene.assembly.density
    np.testing.assert_allclose(dens * G, 26.8e3, rtol=1e-12)


def test_restrepo_bad_inputs():
    with pytest.raises(ValueError, match="unknown"):
        restrepo_specimen("S99")
    with pytest.raises(ValueError, match="return_walls"):
        restrepo_specimen("S11", return_walls="rigid")


@pytest.mark.parametrize("name", CHEE_LIANG_NAMES)
def test_chee_liang_walls_have_table3_size_and_unit_pressure(name):
    spec = SPECIMENS[f"chee-liang-{name}"]
    scene = chee_liang_specimen(name)
    length, height = spec.args["length_m"], spec.args["height_m"]
    ext = _wall_extent(scene)
    np.testing.assert_allclose(ext[0], length, rtol=1e-9)
    # unit pressure (1 Pa) on the face of area L H
    live = scene.loads.live_wrench[:, 1].sum()
    np.testing.assert_allclose(live, length * height, rtol=1e-9)
    supported = scene.supports.restrained[:, 1]
    assert supported.sum() > 0
