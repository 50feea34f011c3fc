"""The sparse LUs of the static Newton (:mod:`dem.static.newton`, :mod:`dem.static.pardiso`):
solutions against a dense solve, analysis reuse, singular matrices reported as singular."""

import numpy as np
import pytest
import scipy.sparse as sp

from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import StaticSettings, newton, solve_collapse
from dem.static.model import Model
from dem.static.newton import LinearSolver, PardisoBackend, SuperLUBackend, select_backend
from dem.static.pardiso import AVAILABLE, PardisoError, PardisoLU

needs_mkl = pytest.mark.skipif(not AVAILABLE, reason="oneMKL (the mkl package) not installed")
BACKENDS = [SuperLUBackend(), pytest.param(PardisoBackend(), marks=needs_mkl)]


@pytest.fixture(scope="module")
def wall():
    """A small running-bond wall's model and its bordered tangent at rest (floor 1e-3)."""
    scene = running_bond_wall(4, 4, 81, 210, 70, 20, 0.7, live="weight")
    model = Model(scene, StaticSettings())
    D = model.evaluate(np.zeros(model.n_free), 1e-3).law.D
    return model, D


def _bordered(model, D) -> sp.csc_matrix:
    return model.stiffness(D, model.w)


def _rhs(n: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).standard_normal(n)


@pytest.mark.parametrize("backend", BACKENDS, ids=lambda b: b.name)
def test_a_solve_with_the_bordered_tangent_matches_a_dense_solve(wall, backend):
    model, D = wall
    A = _bordered(model, D)
    b = _rhs(A.shape[0])
    x = backend.factor(A).solve(b)
    expected = np.linalg.solve(A.toarray(), b)  # LAPACK's dense LU, an independent method
    np.testing.assert_allclose(x, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


@needs_mkl
def test_pardiso_refactors_in_place_with_the_kept_or_a_new_analysis(wall):
    # same pattern, other values (the law's tangent scaled per interface): numeric only;
    # then the unbordered matrix (another pattern): a new analysis; both against dense solves
    model, D = wall
    lu = PardisoLU()
    lu.factor(_bordered(model, D))
    D2 = D * np.random.default_rng(1).uniform(0.5, 2.0, (len(D), 1, 1))
    for A in (_bordered(model, D2), model.stiffness(D2)):
        b = _rhs(A.shape[0], 2)
        x = lu.factor(A).solve(b)
        np.testing.assert_allclose(A @ x, b, atol=1e-10 * np.linalg.norm(b))
        np.testing.assert_allclose(x, np.linalg.solve(A.toarray(), b), rtol=1e-8, atol=1e-14)
    assert lu.fill >= model.stiffness(D2).nnz
    with pytest.raises(ValueError, match="b must have shape"):
        lu.solve(np.ones(3))


def _singular(model, D) -> sp.csc_matrix:
    """The bordered tangent with every joint of block 5 open (its D zero): a free block, a
    singular matrix with the pattern of the regular one."""
    D = D.copy()
    D[(model.a == 5) | (model.b == 5)] = 0.0
    return _bordered(model, D)


@pytest.mark.parametrize("backend", BACKENDS, ids=lambda b: b.name)
def test_a_singular_matrix_is_reported_as_singular(wall, backend):
    model, D = wall
    A = _singular(model, D)
    assert np.linalg.matrix_rank(A.toarray()) < A.shape[0]  # the premise
    assert isinstance(backend.factor(A), Exception)


@needs_mkl
def test_a_failed_pardiso_factorisation_cannot_be_solved_with(wall):
    model, D = wall
    lu = PardisoLU()
    lu.factor(_bordered(model, D))
    with pytest.raises(PardisoError, match="perturbed"):
        lu.factor(_singular(model, D))
    with pytest.raises(PardisoError, match="no valid factorisation"):
        lu.solve(_rhs(lu.shape[0]))


@pytest.mark.parametrize("backend", BACKENDS, ids=lambda b: b.name)
def test_the_linear_solver_drops_its_lu_after_a_singular_matrix(wall, backend, monkeypatch):
    # the LU kept for GMRES may be overwritten by a failed factorisation: the next solve
    # must factor afresh, not precondition with it
    model, D = wall
    monkeypatch.setattr(newton, "BACKEND", backend)
    solver = LinearSolver()
    A = _bordered(model, D)
    b = _rhs(A.shape[0])
    solver.solve(A, b)
    assert isinstance(solver.solve(_singular(model, D), b), Exception)
    assert solver.lu is None
    np.testing.assert_allclose(A @ solver.solve(A, b), b, atol=1e-10 * np.linalg.norm(b))


def test_an_unknown_backend_is_an_error_naming_the_variable():
    with pytest.raises(ValueError, match="BLOCKMECH_SPARSE_LU"):
        select_backend("umfpack")
    assert select_backend("superlu").name == "superlu"
    assert select_backend("auto").name == ("pardiso" if AVAILABLE else "superlu")


@needs_mkl
def test_a_collapse_gives_the_same_lambda_with_either_lu(monkeypatch):
    # a wall to collapse in numba's threads with each LU: the path is the same equilibria,
    # so lambda agrees to the Newton tolerance, far inside its error bar
    scene = running_bond_wall(3, 4, 81, 210, 70, 20, 0.7, live="weight")
    lams = {}
    for backend in (SuperLUBackend(), PardisoBackend()):
        monkeypatch.setattr(newton, "BACKEND", backend)
        res = solve_collapse(scene, StaticSettings(mu=0.7))
        lams[backend.name] = (res.lambda_max, res.lambda_estimate.error)
    (lam_s, err_s), (lam_p, _) = lams["superlu"], lams["pardiso"]
    assert abs(lam_p - lam_s) <= max(1e-6 * lam_s, 0.01 * err_s)
