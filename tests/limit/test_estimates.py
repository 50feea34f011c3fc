"""Ordering of the bounds and estimates on random small walls (theorems, not our numbers).

- mu* <= mu shrinks every friction cone, so estimate (a) <= the associated upper bound;
- the frictionless problem is contained in both, so the lower bound is below both;
- a fixed-capacity iterate that satisfies Coulomb with its own normal forces is an
  associated-admissible force field, so it is below the upper bound too.
"""

import numpy as np
import pytest

from dem.scene import Supports
from dem.scenes.running_bond_wall import running_bond_wall
from limit.errors import InconsistentBoundsError, NumericalFailureError
from limit.estimates import bounds_and_estimates, iterative_estimate, reduced_friction
from limit.problems import LimitSettings
from tests.limit._scenes import block_on_ground, seed_wall


def _random_wall(seed: int):
    rng = np.random.default_rng(seed)
    n, nc = int(rng.integers(2, 4)), int(rng.integers(3, 6))
    a, b, s = rng.uniform(40, 80), rng.uniform(150, 250), rng.uniform(60, 120)
    mu = float(rng.uniform(0.4, 0.9))
    kind = seed % 3
    scene = running_bond_wall(
        n,
        nc,
        a,
        b,
        s,
        20.0,
        mu=mu,
        fixed_columns=("left",) if kind == 0 else (),
        simply_supported=("left", "right") if kind == 1 else (),
    )
    if kind == 2:  # translations only along the left column
        course = np.array(scene.meta["course"])
        restrained = scene.supports.restrained.copy()
        left = [np.flatnonzero(course == k)[0] for k in range(nc)]
        restrained[left, :3] = True
        scene = scene.with_supports(Supports(scene.supports.fixed, restrained))
    return scene


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_estimates_below_upper_bound(seed, model):
    scene = _random_wall(seed)
    b = bounds_and_estimates(scene, LimitSettings(interface_model=model), max_updates=15)
    tol = 1e-6 * max(1.0, b.upper)
    assert b.reduced_mu <= b.upper + tol
    assert b.lower is not None and b.lower <= b.reduced_mu + tol
    assert b.estimates_below_upper()
    if b.iterative.admissible:
        assert b.iterative.lam <= b.upper + tol
    assert len(b.iterative.history) == b.iterative.n_iter + 1 or b.iterative.failure


def test_reduced_friction_sliding_block():
    """A sliding block (wide and low) collapses at mu in the associated problem and at
    mu* = mu / sqrt(1 + mu^2) in estimate (a); the frictionless bound is 0."""
    mu = 0.6
    b = bounds_and_estimates(block_on_ground(1.0, 1.0, 0.2, mu), iterate=True)
    np.testing.assert_allclose(b.upper, mu, rtol=1e-6)
    np.testing.assert_allclose(b.reduced_mu, reduced_friction(mu), rtol=1e-6)
    np.testing.assert_allclose(reduced_friction(mu), np.sin(np.arctan(mu)), rtol=1e-14)
    assert b.lower == 0.0
    # a single sliding joint has a unique normal force: the iteration is exact at once
    assert b.iterative.converged
    np.testing.assert_allclose(b.iterative.lam, mu, rtol=1e-6)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_static_equals_kinematic(seed):
    """The kinematic theorem (independent programme over block velocities, associated flow)
    gives the same multiplier as the static one; its mechanism does unit live-load power and
    its dead-load power is -lambda."""
    from limit.solve import kinematic_analysis, limit_analysis

    scene = _random_wall(seed)
    static = limit_analysis(scene, LimitSettings(interface_model="vertex"))
    lam_k, vel, _ = kinematic_analysis(scene, LimitSettings(interface_model="vertex"))
    np.testing.assert_allclose(lam_k, static.lam, rtol=1e-6)
    np.testing.assert_allclose(np.sum(vel * scene.loads.live_wrench), 1.0, rtol=1e-9)
    np.testing.assert_allclose(-np.sum(vel * scene.dead_wrench), lam_k, rtol=1e-6)


def test_old_budget_name_is_refused_with_its_new_name():
    scene = block_on_ground(1.0, 1.0, 0.2, 0.6)
    with pytest.raises(TypeError, match="max_iter was renamed max_updates"):
        bounds_and_estimates(scene, max_iter=10)
    with pytest.raises(TypeError, match="max_iter was renamed max_updates"):
        iterative_estimate(scene, max_iter=10)


def test_default_budget_settles_a_45_block_dry_wall():
    """Seed 001's Orduna panel (3 x 13, 45 free blocks, mu 0.7) with its side column held in
    translation and rotation: the fixed-capacity iteration needs 31 updates here (measured),
    more than the old fixed budget of 30; the default budget grows with the wall."""
    from dem.scenes.seed001_walls import orduna_panel

    scene = orduna_panel(3)
    restrained = scene.supports.restrained.copy()
    restrained[restrained[:, :3].all(axis=1), :] = True
    scene = scene.with_supports(Supports(scene.supports.fixed, restrained))
    assert int((~scene.supports.fixed).sum()) == 45
    b = bounds_and_estimates(scene, LimitSettings(mu=0.7), lower=False)
    assert b.iterative.converged and b.iterative.admissible, b.iterative.n_iter
    assert b.lower is None and b.consistent
    assert b.iterative.lam <= b.upper


def _iterate_above_the_bound(monkeypatch, admissible: bool):
    """Estimate (b) made a failed, unconverged iterate 1.1 times the upper bound, as seen on a
    dry wall (issue 13) and on seed 001 Chee Liang 14-15 (resultant model: 47.31 kN/m^2, upper
    bound 44.85)."""
    import limit.estimates as est

    real = est.iterative_estimate

    def wrong(*args, **kw):
        it = real(*args, **kw)
        it.lam, it.failure = 1.1 * kw["start"].lam, "iteration 3: ..."
        it.converged, it.admissible = False, admissible
        return it

    monkeypatch.setattr(est, "iterative_estimate", wrong)
    return block_on_ground(1.0, 1.0, 0.2, 0.6)  # upper bound 0.6


def test_an_inadmissible_iterate_above_the_upper_bound_is_no_estimate(monkeypatch):
    """It cannot be the non-associated multiplier: no estimate (b), a note that says why, and
    the certified upper bound is kept."""
    b = bounds_and_estimates(_iterate_above_the_bound(monkeypatch, admissible=False))
    assert b.iterative.lam is None and b.consistent
    assert "0.66 lies above the upper bound 0.6" in b.iterative.note
    assert b.upper == pytest.approx(0.6, rel=1e-6)
    assert b.to_dict()["iterative"] is None


def test_an_admissible_iterate_above_the_upper_bound_is_an_inconsistency(monkeypatch):
    """An admissible iterate is statically admissible for the associated problem: above the
    upper bound it contradicts it, and is refused, or flagged with strict=False."""
    scene = _iterate_above_the_bound(monkeypatch, admissible=True)
    with pytest.raises(InconsistentBoundsError, match=r"estimate \(b\) 0.66 is above") as info:
        bounds_and_estimates(scene)
    assert not info.value.bounds.estimates_below_upper()
    b = bounds_and_estimates(scene, strict=False)
    assert not b.consistent and not b.estimates_below_upper()
    assert b.to_dict()["issues"] == b.issues != []


def test_no_estimate_of_a_seed_wall_lies_above_its_upper_bound():
    """Seed 001 Chee Liang 14-15, resultant model: the fixed-capacity iteration stops at its
    second update (Clarabel fails) on an iterate of 47.31 kN/m^2, above the certified upper
    bound of 44.85. Whatever the iteration does, a reported estimate (b) is at or below the
    upper bound, and the bound itself is kept."""
    import warnings

    scene, settings = seed_wall("chee-liang-14-15", "resultant")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # optimal_inaccurate, certified
        b = bounds_and_estimates(scene, settings, max_updates=30, lower=False)
    assert b.consistent
    it = b.iterative
    assert (it.lam is None and "above the upper bound" in it.note) or it.lam <= b.upper


def test_the_kinematic_mechanism_is_checked_by_its_own_work_balance():
    """A 0.4 x 0.3 x 0.8 m block on the ground, mu = 0.7: the kinematic answer (tipping,
    b / h = 0.5) passes its check; a pure slide (no opening: inadmissible with dilatancy) and
    a wrong multiplier do not."""
    from limit.solve import _check_mechanism, kinematic_analysis

    scene = block_on_ground(0.4, 0.3, 0.8, mu=0.7)
    settings = LimitSettings(interface_model="vertex")
    lam, vel, _ = kinematic_analysis(scene, settings)
    np.testing.assert_allclose(lam, 0.5, rtol=1e-6)
    _check_mechanism(scene, settings, vel, lam, 1.0)
    with pytest.raises(NumericalFailureError, match="work balance"):
        _check_mechanism(scene, settings, vel, 1.01 * lam, 1.0)
    slide = np.zeros_like(vel)
    slide[1, 0] = 1.0 / scene.loads.live_wrench[1, 0]  # unit live power, no opening
    with pytest.raises(NumericalFailureError, match="slides beyond mu"):
        _check_mechanism(scene, settings, slide, 0.0, 1.0)
