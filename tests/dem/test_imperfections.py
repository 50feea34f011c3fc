"""Geometric imperfections: face planes moved inward, box walls with jittered joints.

Expectations: closed forms of shrunk boxes (dimensions, volumes, gaps = sum of the two
offsets), contacts kept by the joint jitter, the spread of block dimensions sqrt(2) sigma, and
the live load equal to each block's weight.
"""

import numpy as np
import pytest

from dem.scene import Scene
from dem.scenes.imperfections import (
    interface_faces,
    jitter_box_wall,
    offset_faces,
    uniform_contact_face_offsets,
)
from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import restrepo_specimen
from dem.scenes.tis_panel import tis_panel
from dem.units import MM, G


def _cube():
    from tests.conftest import box_corners

    return Scene.from_convex_blocks([box_corners((0, 0, 0), (1, 1, 1))], density=1000.0)


def test_offset_faces_shrinks_a_box_by_its_offsets():
    cube = _cube()
    block = cube.assembly.blocks[0]
    rng = np.random.default_rng(0)
    delta = rng.uniform(0.0, 0.1, len(block.normals))
    out = offset_faces(cube, [delta]).assembly.blocks[0]
    # a face with outward normal +e_k moves to x_k = 1 - delta, with -e_k to x_k = delta
    lo, hi = np.zeros(3), np.ones(3)
    for n, d in zip(block.normals, delta, strict=True):
        k = int(np.argmax(np.abs(n)))
        if n[k] > 0:
            hi[k] -= d
        else:
            lo[k] += d
    np.testing.assert_allclose(out.vertices.min(axis=0), lo, atol=1e-12)
    np.testing.assert_allclose(out.vertices.max(axis=0), hi, atol=1e-12)
    np.testing.assert_allclose(out.volume, np.prod(hi - lo), rtol=1e-12)


@pytest.mark.parametrize(
    "delta, match",
    [([-0.1, 0, 0, 0, 0, 0], "finite and >= 0"), ([0.6, 0.6, 0.6, 0.6, 0.6, 0.6], "no volume"),
     ([0.1, 0.1], "faces"), ([np.nan, 0, 0, 0, 0, 0], "finite")],
)  # fmt: skip
def test_offset_faces_rejects_bad_offsets(delta, match):
    with pytest.raises(ValueError, match=match):
        offset_faces(_cube(), [np.array(delta)])
    with pytest.raises(ValueError, match="blocks"):
        offset_faces(_cube(), [])


def test_contact_offsets_open_gaps_equal_to_their_sum(two_block_stack):
    rng = np.random.default_rng(3)
    offsets = uniform_contact_face_offsets(two_block_stack, 0.01, rng)
    touching = interface_faces(two_block_stack)
    for off, mask in zip(offsets, touching, strict=True):
        assert np.all(off[~mask] == 0) and np.all((off[mask] > 0) & (off[mask] <= 0.01))
    gappy = offset_faces(two_block_stack, offsets)
    low, high, ground = (b.vertices for b in gappy.assembly.blocks)
    # low sits on the ground (interface 0) and carries high (interface 1): z gaps
    blocks = two_block_stack.assembly.blocks
    top_low = [o for o, n in zip(offsets[0], blocks[0].normals, strict=True) if n[2] > 0.5][0]
    bot_high = [o for o, n in zip(offsets[1], blocks[1].normals, strict=True) if n[2] < -0.5][0]
    np.testing.assert_allclose(high[:, 2].min() - low[:, 2].max(), top_low + bot_high, rtol=1e-9)
    assert gappy.assembly.interfaces().n_interfaces == 0


def test_tis_panel_with_gaps_keeps_its_blocks_apart():
    panel = tis_panel(3, 2.5)
    offsets = uniform_contact_face_offsets(panel, 0.01 * MM, np.random.default_rng(1))
    gappy = offset_faces(panel, offsets, "gaps")
    assert panel.assembly.interfaces().n_interfaces > 0
    assert gappy.assembly.interfaces().n_interfaces == 0
    assert gappy.meta["imperfection"] == "gaps"
    assert np.all(gappy.assembly.volume < panel.assembly.volume)


def test_jittered_wall_keeps_every_contact_and_scatters_block_sizes():
    wall = running_bond_wall(6, 12, 50.0, 200.0, 100.0, 20.0, 0.6, base=True)
    sigma = 1.0 * MM
    out = jitter_box_wall(wall, (sigma, sigma, sigma), np.random.default_rng(5))
    before, after = wall.assembly.interfaces(), out.assembly.interfaces()
    pairs = set(zip(after.block_a.tolist(), after.block_b.tolist(), strict=True))
    assert set(zip(before.block_a.tolist(), before.block_b.tolist(), strict=True)) <= pairs
    free = ~wall.supports.fixed
    size0 = np.array([np.ptp(b.vertices, axis=0) for b in wall.assembly.blocks])[free]
    size1 = np.array([np.ptp(b.vertices, axis=0) for b in out.assembly.blocks])[free]
    full = np.isclose(size0[:, 0], 0.2)  # full blocks: both ends are jittered head joints
    # a dimension is the difference of two independent N(0, sigma) knots: std sqrt(2) sigma
    for k, sel in ((0, full), (1, slice(None)), (2, slice(None))):
        std = np.std(size1[sel, k] - size0[sel, k], ddof=1)
        assert 0.7 * np.sqrt(2) * sigma < std < 1.3 * np.sqrt(2) * sigma, (k, std)
    # live load: each block's own weight along +y, fixed blocks unloaded
    live = out.loads.live_wrench
    np.testing.assert_allclose(live[free, 1], out.assembly.mass[free] * G, rtol=1e-12)
    assert np.all(live[~free] == 0)


def test_jittered_wall_with_returns_stands_and_keeps_contacts():
    wall = restrepo_specimen("S15", return_walls="blocks", return_blocks=3)
    out = jitter_box_wall(wall, (0.35 * MM,) * 3, np.random.default_rng(2))
    before, after = wall.assembly.interfaces(), out.assembly.interfaces()
    pairs = set(zip(after.block_a.tolist(), after.block_b.tolist(), strict=True))
    assert set(zip(before.block_a.tolist(), before.block_b.tolist(), strict=True)) <= pairs
    # the foundation is untouched
    np.testing.assert_array_equal(
        out.assembly.blocks[-1].vertices, wall.assembly.blocks[-1].vertices
    )


def test_jitter_rejects_non_boxes_and_swapped_joints():
    with pytest.raises(ValueError, match="course"):
        jitter_box_wall(tis_panel(3, 2.5), (1e-4,) * 3, np.random.default_rng(0))
    wall = running_bond_wall(3, 3, 50.0, 200.0, 100.0, 20.0, 0.6, base=True)
    with pytest.raises(ValueError, match="swaps"):
        jitter_box_wall(wall, (0.5, 0.5, 0.5), np.random.default_rng(0))
