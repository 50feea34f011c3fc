"""The interface laws decide a joint at a zero gap the same way whatever the round-off.

Head joints of a wall under its weight carry almost no normal force: their springs sat at
gaps of round-off size, open under one OpenBLAS kernel and closed under another, and the
Newton iterations picked different frictional equilibria (seed 001 S13 with return walls of
blocks: lambda 0.1780 / 0.1834 / 0.1829). Now a gap below ``TOUCH`` = 1e-12 of the model's
extent counts as touching (:mod:`dem.kernels.fibre_law`, :mod:`dem.kernels.interface_law`):
gaps of +-1e-16 m must give the same state, actions and tangent, while a physical gap
(1e-9 m) still opens.
"""

import numpy as np
import pytest

from dem.kernels import fibre_law as fk
from dem.kernels.interface_law import TOUCH
from dem.scene import Scene, proportional_to_weight
from dem.static import STATE_DETACHED, STATE_FLEXURE, StaticSettings
from dem.static.model import Model

FLOOR = 1e-9


def _box(x0, x1, z0, z1, depth=0.3):
    return np.array(
        [(x, y, z) for x in (x0, x1) for y in (-depth / 2, depth / 2) for z in (z0, z1)]
    )


def _law(model_name):
    """The law of a block on a fixed base: one joint (fibre law: 3 x 3 Lobatto springs)."""
    blocks = [_box(-1, 1, -0.2, 0), _box(-0.1, 0.1, 0, 0.5)]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.6)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    kw = {"fibre_points": 3} if model_name == "fibre" else {}
    model = Model(scene, StaticSettings(interface_model=model_name, **kw))
    assert model.m == 1
    return model.law


@pytest.fixture(scope="module")
def law():
    return _law("fibre")


@pytest.fixture(scope="module", params=["fibre", "resultant"])
def any_law(request):
    return _law(request.param)


def _evaluate(law, q):
    return law.evaluate(np.array([q], dtype=float), FLOOR)


def _assert_same(a, b):
    assert a.state[0] == b.state[0]
    scale = np.abs(a.D).max()
    np.testing.assert_allclose(a.D, b.D, rtol=0, atol=1e-8 * scale)
    # the gaps themselves move the forces by k_n A 2e-16 m = 3e-8 N (weight 589 N)
    np.testing.assert_allclose(a.f, b.f, rtol=0, atol=1e-8 * np.abs(a.f).max() + 1e-6)


def test_touch_is_relative_to_the_model_extent(law):
    # the model spans 2 m (the base): touching up to 2e-12 m
    np.testing.assert_allclose(law.params[:, fk.F_TOUCH], 2.0 * TOUCH)


@pytest.mark.parametrize("slide", [0.0, 1e-6])
def test_joint_at_a_round_off_gap_is_decided_by_no_sign(any_law, slide):
    # the whole joint at a gap of +1e-16 or -1e-16 m, with or without a sliding trial: it is
    # touching either way. Before, +1e-16 opened it (detached, tangent floor k_n).
    up = _evaluate(any_law, [1e-16, slide, 0, 0, 0, 0])
    down = _evaluate(any_law, [-1e-16, slide, 0, 0, 0, 0])
    assert not up.state[0] & STATE_DETACHED
    _assert_same(up, down)


@pytest.mark.parametrize("gap", [1e-16, 1e-9])
def test_rocking_joint_with_its_hinge_row_at_a_gap(law, gap):
    # rocking about t2 so that only the row of springs on the edge y1 = max touches, at a
    # gap of +-gap, while the joint slides. A round-off gap (1e-16 m) must not decide
    # between rocking and detached; a physical gap (1e-9 m) does.
    y1 = law.springs[:, 0].max()
    phi = 1e-4
    results = [_evaluate(law, [sign * gap + phi * y1, 1e-6, 0, 0, phi, 0]) for sign in (1.0, -1.0)]
    if gap < 1e-12:
        _assert_same(*results)
        assert results[0].state[0] & STATE_FLEXURE
    else:
        assert results[0].state[0] == STATE_DETACHED
        assert results[1].state[0] & STATE_FLEXURE


def test_joint_moved_by_round_off_only_keeps_its_elastic_tangent(any_law):
    # after the dead load of S13 (return walls of blocks) 21 joints (fibre law) and 75
    # (resultant law) carried nothing, their relative motions of round-off size (1e-20 m) in
    # directions that differed between the kernels. They slid or stuck, opened or closed, in
    # those directions, and so did their tangents (up to half the largest entry apart). Such
    # a joint touches and sticks: the elastic tangent, whatever the direction of the round-off.
    rng = np.random.default_rng(3)
    results = [_evaluate(any_law, 1e-20 * rng.standard_normal(6)) for _ in range(4)]
    for other in results[1:]:
        _assert_same(results[0], other)
    elastic = _evaluate(any_law, [-1e-9, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(results[0].D, elastic.D, rtol=0, atol=1e-8 * np.abs(elastic.D).max())
