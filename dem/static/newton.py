r"""Newton corrector of the static analysis: one equilibrium under load or path control.

Load control (the dead load, lambda fixed) or a linear path constraint ``w . u = c`` (lambda an
unknown, bordered system

.. math::

    \begin{bmatrix} K_t & -F_L \\ w^T & 0 \end{bmatrix}
    \begin{bmatrix} \delta U \\ \delta\lambda \end{bmatrix} =
    \begin{bmatrix} F_D + \lambda F_L - H^T f(U) \\ c - w^T U \end{bmatrix},

with the tangent ``K_t = H^T D H`` of the interface law), damped Levenberg-Marquardt style on
the tangent floor: yielded and open components of the iteration matrix keep a fraction
``floor`` of their elastic stiffness; an iterate that raises the residual is rejected and the
floor grows tenfold (a stiffer, shorter step); an accepted one lowers it tenfold down to the
law's ``tangent_floor``. The floor changes only the iteration matrix: the residual uses the
exact law, so every converged point is an equilibrium of it.
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from dem.static.model import Evaluation, Model
from dem.static.pardiso import AVAILABLE as PARDISO_AVAILABLE
from dem.static.pardiso import PardisoError, PardisoLU
from dem.static.result import StaticSolverError
from dem.static.settings import StaticSettings

logger = logging.getLogger(__name__)

BACKTRACK = (1.0, 0.5, 0.25, 0.125, 1 / 32, 1 / 256)  # step lengths tried along a direction


class SuperLUBackend:
    """scipy's SuperLU with a symmetric-mode ordering (the pattern of ``H^T D H`` is
    symmetric): MMD on ``A + A^T``, diagonal pivots preferred down to 0.01 of the column's
    largest entry."""

    name = "superlu"
    reuse_as_preconditioner = True

    def factor(self, A: sp.csc_matrix, previous=None):
        """The LU of ``A`` (``previous`` is not used), or the exception if it is singular."""
        try:
            return spla.splu(
                A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.01,
                options={"SymmetricMode": True},
            )  # fmt: skip
        except RuntimeError as exc:  # "Factor is exactly singular"
            return exc


class PardisoBackend:
    """MKL PARDISO (:mod:`dem.static.pardiso`), refactoring ``previous`` in place (its
    analysis is kept while the pattern is the same); a matrix that PARDISO cannot factor
    without perturbing a pivot goes to SuperLU, which factors it or reports it singular."""

    name = "pardiso"
    reuse_as_preconditioner = False

    def factor(self, A: sp.csc_matrix, previous=None):
        """The LU of ``A`` (a :class:`PardisoLU`, or SuperLU's), or the exception if it is
        singular."""
        lu = previous if isinstance(previous, PardisoLU) else PardisoLU()
        try:
            return lu.factor(A)
        except PardisoError as exc:
            logger.debug("PARDISO: %s; SuperLU factors this matrix", exc)
            return SuperLUBackend().factor(A)


def select_backend(name: str):
    """The sparse LU named ``name``: "pardiso", "superlu", or "auto" (PARDISO where oneMKL
    is installed, else SuperLU)."""
    if name not in ("auto", "pardiso", "superlu"):
        raise ValueError(f"{LU_ENV} must be auto, pardiso or superlu, got {name!r}")
    if name == "pardiso" and not PARDISO_AVAILABLE:
        raise ValueError(f"{LU_ENV}=pardiso but oneMKL's library (the mkl package) is missing")
    if name == "superlu" or not PARDISO_AVAILABLE:
        return SuperLUBackend()
    return PardisoBackend()


LU_ENV = "BLOCKMECH_SPARSE_LU"
BACKEND = select_backend(os.environ.get(LU_ENV, "auto"))
"""The sparse LU of the static Newton, chosen once at import by the environment variable
``BLOCKMECH_SPARSE_LU`` (default "auto")."""


def factor(A: sp.csc_matrix, previous=None):
    """LU of ``A`` by :data:`BACKEND` (``previous``: an LU of the same backend that may be
    overwritten), or the exception if the matrix is singular."""
    return BACKEND.factor(A, previous)


def _non_finite(what: str, lam: float, interfaces: np.ndarray, blocks: list) -> StaticSolverError:
    """The error of a NaN or inf ``what`` at ``lam``, naming (up to 10) interfaces and blocks."""
    return StaticSolverError(
        f"NaN or inf{what} at lambda = {lam:.6g}: interfaces {interfaces[:10].tolist()}, "
        f"blocks {blocks[:10]}",
        blocks=blocks,
        interfaces=interfaces[:10],
        lam=lam,
    )


class LinearSolver:
    """Solves with the current tangent by :data:`BACKEND`, reusing an older LU as a GMRES
    preconditioner where the backend's ``reuse_as_preconditioner`` says it pays.

    Between two Newton iterations only the interfaces that change state change the tangent:
    a low-rank update, which GMRES preconditioned with the previous factorisation resolves in
    a few iterations. A new factorisation is made when GMRES does not reach ``rtol`` within
    ``max_krylov`` iterations, and reuse stops once it fails more often than not. Each GMRES
    iteration is a solve with the old LU: the reuse pays only while ``max_krylov`` solves
    cost well below one factorisation, which holds for SuperLU and not for PARDISO (a
    numeric factorisation on a kept analysis costs about ten of its solves).
    """

    def __init__(self, rtol: float = 1e-10, max_krylov: int = 10):
        self.lu = None
        self.rtol = rtol
        self.max_krylov = max_krylov
        self.n_factor = 0
        self.n_krylov = 0
        self.n_tries = 0

    def _krylov(self, A: sp.csc_matrix, rhs: np.ndarray):
        self.n_tries += 1
        lu = self.lu
        x0 = lu.solve(rhs)
        if not np.all(np.isfinite(x0)):
            return None
        M = spla.LinearOperator(A.shape, matvec=lu.solve, dtype=float)
        x, info = spla.gmres(
            A, rhs, x0=x0, rtol=self.rtol, atol=0.0, restart=self.max_krylov, maxiter=1, M=M
        )
        res = np.linalg.norm(A @ x - rhs)
        if info == 0 and np.isfinite(res) and res <= 10 * self.rtol * np.linalg.norm(rhs):
            self.n_krylov += 1
            return x
        return None

    def solve(self, A: sp.csc_matrix, rhs: np.ndarray):
        """``A^{-1} rhs``, or the exception of a singular factorisation."""
        useful = self.n_tries < 10 or self.n_krylov >= 0.5 * self.n_tries
        useful = useful and BACKEND.reuse_as_preconditioner
        if useful and self.lu is not None and self.lu.shape == A.shape:
            x = self._krylov(A, rhs)
            if x is not None:
                return x
        lu = factor(A, previous=self.lu)
        if isinstance(lu, Exception):
            self.lu = None  # ``previous`` may have been overwritten
            return lu
        self.lu = lu
        self.n_factor += 1
        return lu.solve(rhs)


@dataclass(frozen=True)
class Constraint:
    """What closes the equations: a dead-load target (lambda fixed), or ``w . u = c``.

    Attributes
    ----------
    w : (n_free,) float or None
        Constraint weights (path control); None under load control.
    c : float
        Target of ``w . u`` [m].
    dc : float
        Increment of the constraint from the start point [m] (the scale of its residual).
    dead_target : (n_free,) float or None
        The load under load control [N, N m].
    """

    w: np.ndarray | None = None
    c: float = 0.0
    dc: float = 0.0
    dead_target: np.ndarray | None = None


@dataclass(eq=False)
class Iterate:
    """A point ``(u, lambda)`` with the law's response and the residual there."""

    u: np.ndarray
    lam: float
    ev: Evaluation
    residual: np.ndarray

    @property
    def norm(self) -> float:
        return float(np.linalg.norm(self.residual))


@dataclass(eq=False)
class Outcome:
    """Result of :meth:`Corrector.solve`."""

    converged: bool
    point: Iterate
    iterations: int
    floor: float
    singular: str = ""
    loose: bool = False


class Corrector:
    """Newton iterations of one step (module notes)."""

    def __init__(self, model: Model, settings: StaticSettings):
        self.model = model
        self.settings = settings
        law = settings.law_settings
        self.floor_min = law.tangent_floor
        accept = law.accept_tolerance
        self.accept_tolerance = settings.tolerance if accept is None else accept
        self.linear = LinearSolver()

    def evaluate(self, u: np.ndarray, lam: float, floor: float, con: Constraint) -> Iterate:
        """The law and the residual at ``(u, lam)``; NaN raises, naming where."""
        model = self.model
        ev = model.evaluate(u, floor)
        target = con.dead_target if con.w is None else model.F_dead + lam * model.F_live
        R = target - ev.internal
        if not (np.all(np.isfinite(ev.law.f)) and np.all(np.isfinite(R))):
            bad_itf = np.flatnonzero(~np.isfinite(ev.law.f).all(axis=1))
            bad_dof = np.flatnonzero(~np.isfinite(R))[:20]
            blocks = sorted({model.block_of_dof(int(i))[0] for i in bad_dof})
            raise _non_finite("", lam, bad_itf, blocks)
        return Iterate(u, lam, ev, R)

    def check_tangent(self, it: Iterate) -> None:
        """Raise, naming the interfaces, if the law's tangent at ``it`` is not finite (a
        singular or NaN solve must not be taken for a mechanism)."""
        bad = np.flatnonzero(~np.isfinite(it.ev.law.D).all(axis=(1, 2)))
        if bad.size:
            model = self.model
            blocks = sorted({int(x) for k in bad[:10] for x in (model.a[k], model.b[k])})
            what = f" in the tangent of the {model.law.settings.name} law"
            raise _non_finite(what, it.lam, bad, blocks)

    def tolerance(self, lam: float, loose: bool = False) -> float:
        """Residual norm of convergence at ``lam`` [N]."""
        tol = self.accept_tolerance if loose else self.settings.tolerance
        model = self.model
        return tol * (model.dead_norm + 1e-300 + abs(lam) * model.live_norm)

    def _direction(self, it: Iterate, con: Constraint):
        """Newton direction ``(du, dlam)``, or the exception of a singular matrix."""
        model = self.model
        if con.w is None:
            return self.linear.solve(model.stiffness(it.ev.law.D), it.residual)
        A = model.stiffness(it.ev.law.D, con.w)
        rhs = np.concatenate([it.residual, [con.c - con.w @ it.u]])
        return self.linear.solve(A, rhs)

    def _line_search(self, it: Iterate, sol: np.ndarray, floor: float, con: Constraint, first):
        """Backtrack along the direction to the first trial that lowers the residual (or the
        shortest); the full step on the first iteration of a step (the constraint row is
        linear: a partial step keeps a proportional constraint residual)."""
        n = self.model.n_free
        for step in BACKTRACK:
            lam = it.lam if con.w is None else it.lam + step * sol[-1]
            trial = self.evaluate(it.u + step * sol[:n], lam, floor, con)
            if first or trial.norm <= it.norm:
                break
        return trial

    def solve(
        self,
        start: Iterate,
        con: Constraint,
        floor: float | None = None,
        max_iterations: int | None = None,
    ) -> Outcome:
        """Iterate from ``start`` (an equilibrium, or a predicted point) to ``con``."""
        floor = self.floor_min if floor is None else max(floor, self.floor_min)
        max_iterations = max_iterations or self.settings.max_iterations
        it = self.evaluate(start.u, start.lam, floor, con) if start.ev is None else start
        first, best = True, None
        for n_iter in range(1, max_iterations + 1):
            if not first and it.norm <= self.tolerance(it.lam):
                return Outcome(True, it, n_iter - 1, floor)
            sol = self._direction(it, con)
            if isinstance(sol, Exception) or not np.all(np.isfinite(sol)):
                self.check_tangent(it)
                if floor >= 1.0:
                    return Outcome(False, it, n_iter, floor, singular=str(sol))
                floor = min(10.0 * floor, 1.0)
                it = self.evaluate(it.u, it.lam, floor, con)
                continue
            trial = self._line_search(it, sol, floor, con, first)
            if first or trial.norm <= it.norm or floor >= 1.0:
                it, first = trial, False
                on_constraint = con.w is None or abs(con.c - con.w @ it.u) <= 1e-9 * abs(con.dc)
                if on_constraint and (best is None or it.norm < best.norm):
                    best = it
                # the lower floor takes effect at the next evaluation (saves one evaluation)
                floor = max(0.1 * floor, self.floor_min)
            else:
                floor = min(10.0 * floor, 1.0)
                it = self.evaluate(it.u, it.lam, floor, con)
        if not first and it.norm <= self.tolerance(it.lam):
            return Outcome(True, it, max_iterations, floor)
        # stalled near a kink of the law (typically the apex of a joint's cone at N -> 0):
        # accept the best iterate if its residual is below the law's looser tolerance
        if best is not None and best.norm <= self.tolerance(best.lam, loose=True):
            return Outcome(True, best, max_iterations, floor, loose=True)
        return Outcome(False, it, max_iterations, floor)
