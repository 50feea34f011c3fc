"""Outcomes told apart by type: falls by itself (naming its blocks), no mechanism, numerical
failure; the dead-load check ``stands`` against closed forms; the retries of an inaccurate
solve end in one certified answer or one refusal."""

import math
import warnings

import numpy as np
import pytest

import limit
import limit.clarabel as clarabel
import limit.deadload as deadload
from dem.scene import Scene
from limit.errors import (
    DeadLoadInfeasibleError,
    LimitAnalysisError,
    NoMechanismError,
    NumericalFailureError,
)
from limit.problems import LimitSettings
from limit.solve import limit_analysis
from tests.limit._scenes import (
    GROUND,
    block_on_ground,
    box,
    pressed_block,
    seed_wall,
    tilted_block,
)


def overhanging_and_standing():
    """Block 2 rests on a fixed pedestal (block 1) with its centroid 0.1 m past the pedestal
    edge, so it topples; block 3 stands on the ground (block 0). Live load: +x on both."""
    pedestal = box((1.0, -0.1, 0.5), (1.2, 0.1, 0.7))
    falling = box((1.1, -0.1, 0.7), (1.5, 0.1, 0.9))
    standing = box((-0.5, -0.5, 0.0), (0.0, 0.0, 0.3))
    scene = Scene.from_convex_blocks(
        [GROUND, pedestal, falling, standing], 2000.0, fixed=[0, 1], mu=0.6
    )
    live = np.zeros((4, 6))
    live[2:, 0] = 1.0
    return scene.with_loads(live=live)


def test_error_types_derive_from_the_base():
    for cls in (DeadLoadInfeasibleError, NoMechanismError, NumericalFailureError):
        assert issubclass(cls, LimitAnalysisError)
    for name in ("DeadLoadInfeasibleError", "NoMechanismError", "NumericalFailureError"):
        assert getattr(limit, name) is globals()[name]


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_falls_by_itself_names_the_falling_block_and_its_interface(model):
    scene = overhanging_and_standing()
    interfaces = scene.assembly.interfaces()
    (k_fall,) = np.flatnonzero((interfaces.block_a == 1) & (interfaces.block_b == 2))
    with pytest.raises(DeadLoadInfeasibleError, match=r"blocks most involved: \[2\]") as info:
        limit_analysis(scene, LimitSettings(interface_model=model))
    assert info.value.blocks == (2,)
    assert info.value.interfaces == (int(k_fall),)


def test_no_mechanism_is_its_own_type():
    with pytest.raises(NoMechanismError, match="unbounded"):
        limit_analysis(pressed_block())


def test_missing_support_names_the_blocks():
    scene = block_on_ground(0.2, 0.2, 0.5, 0.7)
    far = box((5.0, 5.0, 5.0), (6.0, 6.0, 6.0))
    blocks = [b.vertices for b in scene.assembly.blocks] + [far]
    s2 = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.7)
    with pytest.raises(DeadLoadInfeasibleError) as info:
        limit_analysis(s2.with_loads(live=np.ones((3, 6))))
    assert info.value.blocks == (2,)
    assert not limit.stands(s2).stands


# closed forms (tilted_block): stands iff tan(theta) <= mu and tan(theta) <= b / h
@pytest.mark.parametrize(
    ("width", "height", "theta_deg", "mu", "expected"),
    [
        (0.2, 0.4, 20.0, 0.6, True),  # tan 20 = 0.364 < 0.5, < 0.6
        (0.2, 0.4, 30.0, 0.8, False),  # tan 30 = 0.577 > b/h = 0.5: topples
        (0.4, 0.2, 30.0, 0.5, False),  # tan 30 > mu = 0.5: slides
        (0.4, 0.2, 30.0, 0.6, True),  # tan 30 < 0.6 and < 2
    ],
)
@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_stands_matches_the_tilted_block(width, height, theta_deg, mu, expected, model):
    scene = tilted_block(width, height, math.radians(theta_deg), mu)
    settings = LimitSettings(interface_model=model)
    res = limit.stands(scene, settings)
    assert res.stands is expected
    assert res.certificate.worst() <= settings.cert_tol
    if expected:
        assert res.load_factor == pytest.approx(1.0, abs=1e-6)
        assert res.blocks == () and res.interfaces == ()
    else:
        # for a dry joint no fraction of the dead load can be carried; the dual bound proves it
        assert res.load_factor == pytest.approx(0.0, abs=1e-6)
        assert res.certificate.dual_objective < 1.0
        assert res.blocks == (1,) and res.interfaces == (0,)


def test_stands_agrees_with_limit_analysis_on_the_block():
    """A block that stands has a positive collapse multiplier, b/h for overturning."""
    scene = block_on_ground(0.4, 0.3, 0.8, mu=0.7)
    assert limit.stands(scene).stands
    assert limit_analysis(scene).lam == pytest.approx(0.5, rel=1e-6)


# -- retries of an inaccurate solve ---------------------------------------------------------


def _degrading(monkeypatch, labels, break_point=False):
    """Make the named attempts report optimal_inaccurate (and, with ``break_point``, spoil
    the corner forces so that the certificate must fail)."""
    real = clarabel.run_clarabel
    calls = []

    def fake(problem, settings, attempt=clarabel.REFINED):
        calls.append(attempt.label)
        status, dt = real(problem, settings, attempt)
        if attempt.label in labels:
            if break_point:
                p = problem.var_dict["p"]
                p.save_value(p.value * 1.1)
            return "optimal_inaccurate", dt
        return status, dt

    monkeypatch.setattr(clarabel, "run_clarabel", fake)
    return calls


# the retries of one programme, without the dead-load check's own solves
ONE_PROGRAMME = LimitSettings(dead_load_check=False)


def test_inaccurate_fast_solve_is_repeated(monkeypatch):
    calls = _degrading(monkeypatch, {"fast"})
    res = limit_analysis(block_on_ground(0.4, 0.3, 0.8, mu=0.7), ONE_PROGRAMME)
    assert calls == ["fast", "refined"] and res.status == "optimal"
    assert res.lam == pytest.approx(0.5, rel=1e-6)


def test_accurate_fast_solve_is_returned(monkeypatch):
    calls = _degrading(monkeypatch, set())
    res = limit_analysis(block_on_ground(0.4, 0.3, 0.8, mu=0.7), ONE_PROGRAMME)
    assert calls == ["fast"] and res.status == "optimal"


def test_inaccurate_to_the_end_but_certified_warns_once(monkeypatch):
    calls = _degrading(monkeypatch, {"fast", "refined", "short steps", "tightened"})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = limit_analysis(block_on_ground(0.4, 0.3, 0.8, mu=0.7), ONE_PROGRAMME)
    assert calls == ["fast", "refined", "short steps", "tightened"]
    assert res.status == "optimal_inaccurate" and res.is_inaccurate
    assert res.lam == pytest.approx(0.5, rel=1e-6)
    assert len(caught) == 1 and "passed its certificate" in str(caught[0].message)


def test_inaccurate_and_uncertified_is_refused_with_one_message(monkeypatch):
    _degrading(monkeypatch, {"fast", "refined", "short steps", "tightened"}, break_point=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(NumericalFailureError, match=r"after 4 Clarabel solves") as info:
            limit_analysis(block_on_ground(0.4, 0.3, 0.8, mu=0.7), ONE_PROGRAMME)
    assert "fast optimal_inaccurate, refined optimal_inaccurate" in str(info.value)
    assert "failed its certificate" in str(info.value)
    assert caught == []


def _failing(monkeypatch, labels):
    """Make the named attempts end as a Clarabel failure (``solver_error``, no point)."""
    real = clarabel.run_clarabel
    calls = []

    def fake(problem, settings, attempt=clarabel.REFINED):
        calls.append(attempt.label)
        if attempt.label in labels:
            return "solver_error", 0.0
        return real(problem, settings, attempt)

    monkeypatch.setattr(clarabel, "run_clarabel", fake)
    return calls


def test_a_solver_error_is_retried_with_short_steps(monkeypatch):
    """After Clarabel gave up, the next attempt takes shorter steps and is returned."""
    calls = _failing(monkeypatch, {"fast", "refined"})
    res = limit_analysis(block_on_ground(0.4, 0.3, 0.8, mu=0.7), ONE_PROGRAMME)
    assert calls == ["fast", "refined", "short steps"] and res.status == "optimal"
    assert res.lam == pytest.approx(0.5, rel=1e-6)  # overturning: b/h


def test_a_certified_inaccurate_point_outlives_a_later_failure(monkeypatch):
    """An inaccurate but certified point of an early attempt is returned (with its status and
    one warning) when the later attempts give nothing better."""
    degrading = _degrading(monkeypatch, {"fast", "refined", "short steps"})
    real = clarabel.run_clarabel

    def then_failing(problem, settings, attempt=clarabel.REFINED):
        if attempt.label == "tightened":
            degrading.append(attempt.label)
            return "solver_error", 0.0
        return real(problem, settings, attempt)

    monkeypatch.setattr(clarabel, "run_clarabel", then_failing)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = limit_analysis(block_on_ground(0.4, 0.3, 0.8, mu=0.7), ONE_PROGRAMME)
    assert degrading == ["fast", "refined", "short steps", "tightened"]
    assert res.status == "optimal_inaccurate" and res.attempts[-1] == ("tightened", "solver_error")
    assert res.lam == pytest.approx(0.5, rel=1e-6)
    assert len(caught) == 1 and "passed its certificate" in str(caught[0].message)


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_a_structure_propped_by_its_live_load_gets_no_multiplier(model):
    # a squat block on a 30 deg slope with mu = 0.3 < tan 30 slides down by itself. A horizontal
    # uphill live load of lambda times its weight holds it for tan(30 - phi) <= lambda <=
    # tan(30 + phi) (phi = atan 0.3): the largest end of that interval, tan(46.7 deg) = 1.061,
    # is no collapse multiplier, since lambda = 0 is not admissible.
    from dem.scene import proportional_to_weight

    theta = math.radians(30.0)
    uphill = (1.0, 0.0, 0.0)  # the slope rises towards +x
    settings = LimitSettings(interface_model=model)
    sliding = tilted_block(0.4, 0.1, theta, 0.3)
    scene = sliding.with_loads(live=proportional_to_weight(sliding.assembly, uphill))
    with pytest.raises(DeadLoadInfeasibleError, match="dead load alone") as info:
        limit_analysis(scene, settings)
    assert info.value.blocks == (1,)
    with pytest.raises(DeadLoadInfeasibleError):
        limit.bounds_and_estimates(scene, settings, iterate=False)
    # switched off, the interval's end comes back: the check is what refuses it
    propped = limit_analysis(scene, settings.with_(dead_load_check=False))
    expected = math.tan(theta + math.atan(0.3))
    assert propped.lam == pytest.approx(expected, rel=1e-6)
    # with mu = 0.7 > tan 30 it stands, and sliding uphill at tan(30 + atan 0.7) is its collapse
    standing = tilted_block(0.4, 0.1, theta, 0.7)
    scene = standing.with_loads(live=proportional_to_weight(standing.assembly, uphill))
    expected = math.tan(theta + math.atan(0.7))
    assert limit_analysis(scene, settings).lam == pytest.approx(expected, rel=1e-6)


# -- the dead-load check when the capped programme fails numerically -----------------------


def _capped_fails(monkeypatch):
    """The first programme of the dead-load check (its multiplier capped at one) fails."""
    real = deadload.solve_static
    calls = []

    def fake(sp_, **kw):
        calls.append(sp_)
        if len(calls) == 1:
            raise NumericalFailureError("capped programme: solver status solver_error")
        return real(sp_, **kw)

    monkeypatch.setattr(deadload, "solve_static", fake)
    return calls


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_stands_falls_back_to_the_full_dead_load(monkeypatch, model):
    """tan 20 = 0.364 < mu = 0.6 and < b/h = 0.5: it stands, certified by the fixed programme."""
    calls = _capped_fails(monkeypatch)
    settings = LimitSettings(interface_model=model)
    res = limit.stands(tilted_block(0.2, 0.4, math.radians(20.0), 0.6), settings)
    assert len(calls) == 2
    assert res.stands and res.load_factor == pytest.approx(1.0, abs=1e-6)
    assert res.certificate.worst() <= settings.cert_tol
    assert "fixed" in res.reason


def test_stands_undecided_when_the_full_dead_load_has_no_equilibrium(monkeypatch):
    """tan 30 > b/h = 0.5: it topples; without the capped programme's dual bound the check
    says it cannot decide instead of answering."""
    _capped_fails(monkeypatch)
    with pytest.raises(NumericalFailureError, match="undecided"):
        limit.stands(tilted_block(0.2, 0.4, math.radians(30.0), 0.8))


@pytest.mark.parametrize(
    "key",
    [
        # the capped programme stalled in Clarabel ('insufficient progress')
        "restrepo-S32",
        # the capped programme ended with a duality gap of 6.8e-6 > cert_tol; the equilibrium
        # at the full dead load has primal residuals of 1e-10 and less
        "chee-liang-4-5",
    ],
)
def test_resultant_dead_load_check_of_a_seed_wall(key):
    """Seed 001 walls with the resultant model whose upper bounds were refused for want of a
    certified dead-load check. They stand (the DEM carries their dead load with both laws),
    and the check now says so, certified."""
    scene, settings = seed_wall(key, "resultant")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # optimal_inaccurate, certified
        res = limit.stands(scene, settings)
    assert res.stands
    # standing is proved by the equilibrium's own (primal) residuals
    assert res.certificate.worst(feasibility=True) <= settings.cert_tol
