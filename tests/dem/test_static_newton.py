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
