"""Newton corrector of the static analysis (:mod:`dem.static.newton`): its matrix."""

import numpy as np
import pytest
from scipy.linalg import block_diag

from dem.geometry.compatibility import compatibility_matrix
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import StaticSettings
from dem.static.model import Model


def test_bordered_matrix_is_HtDH_with_the_load_and_the_constraint():
    # the corrector's matrix, assembled into a fixed sparse structure, against a dense
    # H^T D H from the compatibility matrix, bordered by -F_L and the constraint row w
    scene = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="weight")
    model = Model(scene, StaticSettings())
    m, n = model.m, model.n_free
    D = np.random.default_rng(3).standard_normal((m, 6, 6))  # any, also non-symmetric
    w = np.zeros(n)
    w[[1, 7, n - 2]] = [0.5, -2.0, 1.0]
    H = compatibility_matrix(scene.assembly.centroid, model.itf).toarray()
    free = model.free_mask.ravel()
    K = (H.T @ block_diag(*D) @ H)[np.ix_(free, free)]
    ref = np.block([[K, -model.F_live[:, None]], [w[None, :], np.zeros((1, 1))]])
    scale = np.abs(K).max()
    np.testing.assert_allclose(model.stiffness(D, w).toarray(), ref, atol=1e-12 * scale)
    np.testing.assert_allclose(model.stiffness(D).toarray(), K, atol=1e-12 * scale)


@pytest.mark.parametrize("when", ["dead load", "live load"])
def test_a_nan_tangent_is_an_error_naming_the_interface(monkeypatch, when):
    # a NaN in one joint's tangent makes every factorisation fail; that must not read as a
    # singular stiffness (a mechanism) or a stalled path, but name the joint
    from dem.static import StaticSolverError, solve_collapse
    from dem.static.laws import ResultantLaw

    scene = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="weight")
    evaluate = ResultantLaw.evaluate
    poisoned = {"from_call": 0 if when == "dead load" else 12, "calls": 0}

    def nan_tangent(self, q, floor):
        response = evaluate(self, q, floor)
        poisoned["calls"] += 1
        if poisoned["calls"] > poisoned["from_call"]:
            response.D[4, 1, 2] = np.nan
        return response

    monkeypatch.setattr(ResultantLaw, "evaluate", nan_tangent)
    with pytest.raises(StaticSolverError, match="NaN or inf in the tangent") as err:
        solve_collapse(scene, StaticSettings(mu=0.7))
    assert err.value.interfaces == [4] and 1 <= len(err.value.blocks) <= 2


def test_contraction_monitor_stops_a_diverging_or_stalled_solve_only():
    from dem.static.newton import STAGNATION_WINDOW, THETA_MAX, Contraction

    diverging = Contraction()
    assert diverging.correction(np.array([1.0, 0.0])) == ""
    assert "contraction" in diverging.correction(np.array([0.0, 1.5 * THETA_MAX]))
    assert diverging.theta0 == pytest.approx(1.5 * THETA_MAX)
    # a residual that falls below half of its value STAGNATION_WINDOW iterations ago never
    # stops; one that stays for more than STAGNATION_WINDOW iterations does
    falling, stalled = Contraction(), Contraction()
    norms = [0.6**k for k in range(3 * STAGNATION_WINDOW)]
    assert all(falling.residual(r) == "" for r in norms)
    stops = [stalled.residual(1e3) for _ in range(STAGNATION_WINDOW + 1)]
    assert stops[:-1] == [""] * STAGNATION_WINDOW and "not halved" in stops[-1]


@pytest.mark.parametrize("factor", [30.0, 1000.0])
def test_a_watched_solve_converges_as_the_unwatched_one_or_stops_early(factor):
    # the monitor only stops solves: one that converges watched has taken exactly the
    # iterations of the unwatched solve and ends at the same equilibrium; a step far too long
    # (1000 first increments on a small wall: no convergence in the whole budget) stops
    # before the budget, naming why
    from dem.static.dead_load import solve_dead_load
    from dem.static.newton import Constraint, Corrector
    from dem.static.path import first_increment

    scene = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="weight")
    settings = StaticSettings(mu=0.7)
    model = Model(scene, settings)
    corrector = Corrector(model, settings)
    dead, _ = solve_dead_load(corrector)
    dc = factor * first_increment(model, corrector, dead.u)
    con = Constraint(w=model.w, c=float(model.w @ dead.u) + dc, dc=dc)
    plain = corrector.solve(dead, con)
    watched = corrector.solve(dead, con, watch=True)
    if factor < 100:
        assert plain.converged and watched.converged and plain.iterations > 1
        assert watched.iterations == plain.iterations
        np.testing.assert_array_equal(watched.point.u, plain.point.u)
        assert watched.point.lam == plain.point.lam
    else:
        assert not plain.converged and plain.iterations == settings.max_iterations
        assert not watched.converged and watched.stopped
        assert watched.iterations < plain.iterations
