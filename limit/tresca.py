r"""Normal and friction forces in a jammed 2D packing of rigid cells with Tresca friction.

Seed 003 (Marazzato, *Computation of stresses in jammed packings modeled with Tresca
friction*), Sec. 2 and 4.1. Cells translate rigidly (no rotation, so only force balance is
imposed per cell); neighbouring cells may not interpenetrate and dissipate
:math:`s\,|[u]\cdot t|` per unit length of their common edge (Tresca threshold :math:`s`). The
primal linear program, seed 003 Eq. (16), in the cell translations :math:`u_c` and one slack
:math:`\tau_e` per internal edge reads

.. math::

    \min_{u, \tau}\; \sum_{e \in E_i} s\,|e|\,\tau_e - \sum_{b \in E_b} |b|\, g_b \cdot u_{c(b)}
    \quad\text{s.t.}\quad [u]_e\cdot n_e \ge 0,\;\; -\tau_e \le [u]_e\cdot t_e \le \tau_e,\;\;
    \sum_c u_c = 0,

with :math:`[u]_e = u_b - u_a` for the edge normal :math:`n_e` pointing from cell ``a`` to
cell ``b`` and :math:`g_b` the traction on boundary edge :math:`b` (Neumann data). Its dual
(seed 003 Eq. 12-14) is a pure feasibility problem: find a normal force :math:`\lambda_e \ge 0`
and a friction force :math:`|f_{t,e}| \le s|e|` on every internal edge so that every cell is
in force balance. The multipliers of the non-interpenetration constraints are the normal forces.

Because the dual objective is identically zero, any statically admissible force set is
dual-optimal (seed 003, Remark 4 and Sec. 4.5). ``selection="solver"`` returns the multipliers
the LP solver found, as in the paper. ``selection="min_energy"`` (our addition) picks the
admissible set that minimises :math:`\sum_e d_e (\lambda_e^2 + f_{t,e}^2) / (2|e|)`, with
:math:`d_e` the distance between the two cell centres along :math:`n_e`. On a Voronoi packing
the Voronoi property (centre-to-centre vector parallel to the edge normal) makes the forces of
any uniform stress a KKT point of that problem, so a homogeneous load returns the homogeneous
stress, which the paper shows is admissible but which its solver did not find.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from dataclasses import dataclass

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from dem.estimate import Estimate
from limit.errors import (
    DeadLoadInfeasibleError,
    LimitAnalysisError,
    NoMechanismError,
    NumericalFailureError,
)
from limit.voronoi_packing import Packing

logger = logging.getLogger(__name__)

_SELECTIONS = ("solver", "min_energy")
_LP_SOLVERS = ("HIGHS", "CLARABEL")


@dataclass(frozen=True)
class TrescaSettings:
    """Solver settings for :func:`solve_tresca`.

    Parameters
    ----------
    solver : {"HIGHS", "CLARABEL"}
        cvxpy solver for the primal LP, seed 003 Eq. (16). Default ``"CLARABEL"`` (interior point,
        like the cvxopt solver of the paper; ``"HIGHS"`` returns simplex vertices).
    selection : {"solver", "min_energy"}
        Which of the (non-unique) admissible force sets to return; see the module notes.
        Default ``"solver"`` (the paper's choice).
    qp_solver : str
        cvxpy solver for the ``min_energy`` quadratic program. Default ``"CLARABEL"``.
    qp_tol : float
        Gap and feasibility tolerances passed to Clarabel for the ``min_energy`` QP. The
        weights :math:`d_e/|e|` span orders of magnitude on random Voronoi cells (tiny edges),
        and the error a gap ``g`` leaves on an edge force grows as ``sqrt(g / w_e)``
        (:func:`min_energy_force_bound`), so the default is far tighter than Clarabel's own
        (1e-8). Default 1e-12.
    feas_tol : float
        Relative tolerance of the certificates (equilibrium, friction bound, gap) above which
        the result is rejected with :class:`NumericalFailureError`. Default 1e-6.
    """

    solver: str = "CLARABEL"
    selection: str = "solver"
    qp_solver: str = "CLARABEL"
    qp_tol: float = 1e-12
    feas_tol: float = 1e-6

    def __post_init__(self) -> None:
        if self.solver not in _LP_SOLVERS:
            raise ValueError(f"solver must be one of {_LP_SOLVERS}, got {self.solver!r}")
        if self.selection not in _SELECTIONS:
            raise ValueError(f"selection must be one of {_SELECTIONS}, got {self.selection!r}")
        if not (0.0 < self.qp_tol < 1.0):
            raise ValueError(f"qp_tol must lie in (0, 1), got {self.qp_tol!r}")
        if not (0.0 < self.feas_tol < 1.0):
            raise ValueError(f"feas_tol must lie in (0, 1), got {self.feas_tol!r}")


@dataclass(frozen=True)
class TrescaResult:
    """Solution of the Tresca packing problem, seed 003 Eq. (13)-(16), with its certificate.

    Forces are per unit out-of-plane thickness [N/m]; ``n_c`` cells, ``n_e`` internal edges.

    Attributes
    ----------
    displacement : ndarray, shape (n_c, 2)
        Primal cell translations :math:`u_c` [m]; zero (up to round-off) for a jammed packing.
    slip : ndarray, shape (n_e,)
        Primal slack :math:`\\tau_e \\ge |[u]_e \\cdot t_e|` [m].
    normal_force : ndarray, shape (n_e,)
        :math:`\\lambda_e \\ge 0` [N/m], compression positive; cell ``a`` pushes cell ``b``
        with :math:`\\lambda_e n_e`.
    tangential_force : ndarray, shape (n_e,)
        :math:`f_{t,e}` [N/m]; cell ``a`` pulls cell ``b`` along :math:`t_e` with it.
    normal_stress : ndarray, shape (n_e,)
        :math:`\\sigma_{nn} = -\\lambda_e/|e|` [Pa], negative in compression (seed 003 Eq. 14).
    shear_stress : ndarray, shape (n_e,)
        :math:`f_{t,e}/|e|` [Pa], the shear traction on cell ``b``.
    cell_load : ndarray, shape (n_c, 2)
        External force on each cell from the boundary tractions [N/m].
    status : str
        cvxpy status of the LP (``"optimal"`` or ``"optimal_inaccurate"``).
    is_inaccurate : bool
        True when any solve returned ``optimal_inaccurate``.
    solver, selection : str
        As in :class:`TrescaSettings`.
    primal_objective : float
        Value of Eq. (16) at the returned point [J/m].
    duality_gap : float
        ``primal_objective`` minus the dual objective, which is 0 [J/m].
    primal_residual : float
        Largest violation of the LP constraints at the returned primal point [m].
    equilibrium_residual : float
        Largest cell force imbalance divided by the largest cell load [-].
    friction_residual : float
        Largest violation of :math:`\\lambda \\ge 0` and :math:`|f_t| \\le s|e|`, divided by the
        largest cell load [-].
    wall_s : float
        Wall time of the solve [s].
    """

    displacement: np.ndarray
    slip: np.ndarray
    normal_force: np.ndarray
    tangential_force: np.ndarray
    normal_stress: np.ndarray
    shear_stress: np.ndarray
    cell_load: np.ndarray
    status: str
    is_inaccurate: bool
    solver: str
    selection: str
    primal_objective: float
    duality_gap: float
    primal_residual: float
    equilibrium_residual: float
    friction_residual: float
    wall_s: float


def _check_traction(packing: Packing, traction: np.ndarray) -> np.ndarray:
    traction = np.asarray(traction, dtype=np.float64)
    if traction.shape != (packing.n_bnd, 2):
        raise ValueError(
            f"boundary traction must have shape (n_bnd, 2) = ({packing.n_bnd}, 2), "
            f"got {traction.shape}"
        )
    if not np.all(np.isfinite(traction)):
        raise ValueError("boundary traction must be finite")
    return traction


def _check_s(packing: Packing, s: float | np.ndarray) -> np.ndarray:
    s_e = np.broadcast_to(np.asarray(s, dtype=np.float64), (packing.n_edges,)).copy()
    if not np.all(np.isfinite(s_e)) or np.any(s_e < 0.0):
        raise ValueError("Tresca threshold s must be finite and >= 0 [Pa]")
    return s_e


def cell_loads(packing: Packing, traction: np.ndarray) -> np.ndarray:
    """External force on each cell, :math:`F_c = \\sum_{b \\subset \\partial c} |b|\\, g_b`.

    Parameters
    ----------
    packing : Packing
    traction : array_like, shape (n_bnd, 2)
        Traction on each boundary edge [Pa].

    Returns
    -------
    ndarray, shape (n_cells, 2)
        [N/m].
    """
    traction = _check_traction(packing, traction)
    out = np.zeros((packing.n_cells, 2))
    np.add.at(out, packing.bnd_cell, traction * packing.bnd_length[:, None])
    return out


def equilibrium_matrix(packing: Packing) -> sp.csr_matrix:
    """Matrix mapping edge forces :math:`(\\lambda, f_t)` to net interface force per cell.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (2 n_cells, 2 n_edges)
        Row ``2c + k`` is component ``k`` of the force that the neighbours exert on cell ``c``;
        columns are ``[lambda_0..lambda_{n_e-1}, f_t_0..f_t_{n_e-1}]``. Cell balance reads
        ``A @ z + cell_load.ravel() = 0``.
    """
    n_e = packing.n_edges
    a, b = packing.edge_cells[:, 0], packing.edge_cells[:, 1]
    n, t = packing.edge_normal, packing.edge_tangent
    rows, cols, vals = [], [], []
    e = np.arange(n_e)
    for k in range(2):
        for cells, sign in ((b, 1.0), (a, -1.0)):
            rows += [2 * cells + k, 2 * cells + k]
            cols += [e, n_e + e]
            vals += [sign * n[:, k], sign * t[:, k]]
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(2 * packing.n_cells, 2 * n_e),
    )


def forces_from_uniform_stress(
    packing: Packing, sigma: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Edge forces of a uniform stress field (seed 003 Sec. 4.5, the "constant stress" guess).

    Parameters
    ----------
    packing : Packing
    sigma : array_like, shape (2, 2)
        Cauchy stress [Pa].

    Returns
    -------
    normal_force, tangential_force : ndarray, shape (n_edges,)
        :math:`\\lambda_e = -|e|\\, n_e\\cdot\\sigma n_e`, :math:`f_{t,e} = -|e|\\, t_e\\cdot\\sigma
        n_e` [N/m], in the sign convention of :class:`TrescaResult`.
    """
    sigma = np.asarray(sigma, dtype=np.float64)
    if sigma.shape != (2, 2):
        raise ValueError(f"sigma must have shape (2, 2), got {sigma.shape}")
    # traction on cell a's face (outward normal n_e) is sigma n_e; b receives its opposite
    trac_a = packing.edge_normal @ sigma.T
    lam = -packing.edge_length * np.sum(trac_a * packing.edge_normal, axis=1)
    f_t = -packing.edge_length * np.sum(trac_a * packing.edge_tangent, axis=1)
    return lam, f_t


def admissibility_residuals(
    packing: Packing,
    traction: np.ndarray,
    s: float | np.ndarray,
    normal_force: np.ndarray,
    tangential_force: np.ndarray,
) -> tuple[float, float]:
    """Certificate of a force set: is it equilibrated and inside the Tresca cone?

    Parameters
    ----------
    packing : Packing
    traction : array_like, shape (n_bnd, 2)
        Boundary traction [Pa].
    s : float or array_like, shape (n_edges,)
        Tresca threshold [Pa].
    normal_force, tangential_force : array_like, shape (n_edges,)
        Edge forces [N/m].

    Returns
    -------
    equilibrium_residual : float
        ``max_c |F_c + sum of edge forces on c| / max_c |F_c|`` [-].
    friction_residual : float
        ``max(0, -lambda, |f_t| - s |e|) / max_c |F_c|`` [-].
    """
    load = cell_loads(packing, traction)
    s_e = _check_s(packing, s)
    z = np.concatenate([normal_force, tangential_force])
    scale = max(float(np.max(np.linalg.norm(load, axis=1), initial=0.0)), np.finfo(float).tiny)
    imbalance = (equilibrium_matrix(packing) @ z).reshape(-1, 2) + load
    eq = float(np.max(np.linalg.norm(imbalance, axis=1))) / scale
    viol = np.concatenate(
        [[0.0], -normal_force, np.abs(tangential_force) - s_e * packing.edge_length]
    )
    return eq, float(np.max(viol)) / scale


def _accept(
    problem: cp.Problem,
    what: str,
    hint: str,
    unbounded: type[LimitAnalysisError] = NumericalFailureError,
    infeasible: type[LimitAnalysisError] = DeadLoadInfeasibleError,
) -> bool:
    """Status map of STYLE.md: return True if inaccurate, raise unless optimal.

    An unbounded or infeasible programme raises the outcome it means for this programme
    (``unbounded``, ``infeasible``: classes of :mod:`limit.errors`); any other status is a
    :class:`NumericalFailureError`.
    """
    status = problem.status
    if status == cp.OPTIMAL:
        return False
    if status == cp.OPTIMAL_INACCURATE:
        warnings.warn(f"{what}: solver returned 'optimal_inaccurate'", RuntimeWarning, stacklevel=3)
        return True
    error = {
        cp.UNBOUNDED: unbounded,
        cp.UNBOUNDED_INACCURATE: unbounded,
        cp.INFEASIBLE: infeasible,
        cp.INFEASIBLE_INACCURATE: infeasible,
    }.get(status, NumericalFailureError)
    raise error(f"{what}: solver status {status!r}. {hint}")


def solve_tresca(
    packing: Packing,
    traction: np.ndarray,
    s: float | np.ndarray,
    settings: TrescaSettings | None = None,
) -> TrescaResult:
    """Solve seed 003 Eq. (16) and return the edge forces of its dual, with a certificate.

    Parameters
    ----------
    packing : Packing
        Rigid convex cells.
    traction : array_like, shape (n_bnd, 2)
        Neumann data :math:`g_b` on every boundary edge [Pa]; its resultant must vanish.
    s : float or array_like, shape (n_edges,)
        Tresca friction threshold [Pa] (seed 003 Eq. 2).
    settings : TrescaSettings, optional

    Returns
    -------
    TrescaResult

    Raises
    ------
    ValueError
        Bad shapes, non-finite data, or a traction with a non-zero resultant.
    DeadLoadInfeasibleError
        The LP is unbounded: no equilibrated force set respects non-interpenetration and the
        Tresca bound (the packing is not jammed under this load).
    NumericalFailureError
        The solver fails, or the returned point fails its certificate.
    """
    settings = settings or TrescaSettings()
    if packing.n_edges == 0:
        raise ValueError("packing has no internal edges")
    traction = _check_traction(packing, traction)
    s_e = _check_s(packing, s)
    load, scale = _balanced_load(packing, traction)
    start = time.perf_counter()
    lp = _TrescaLP(packing, load, s_e)
    lp.problem.solve(solver=settings.solver)
    inaccurate = _accept(
        lp.problem,
        "Tresca LP (seed 003 Eq. 16)",
        "An unbounded LP means no force set balances the load with compression and "
        "|f_t| <= s|e| (tensile load, or shear above the Tresca threshold).",
        unbounded=DeadLoadInfeasibleError,
    )
    lam, f_t = lp.forces()
    if settings.selection == "min_energy":
        lam, f_t, qp_inaccurate = _min_energy_forces(packing, load, s_e, settings)
        inaccurate = inaccurate or qp_inaccurate
    u, slip = np.asarray(lp.x.value), np.asarray(lp.tau.value)
    primal_objective = float(lp.weight @ slip - load.ravel() @ u)
    eq_res, fr_res = admissibility_residuals(packing, traction, s_e, lam, f_t)
    gap = primal_objective - 0.0
    wall = time.perf_counter() - start
    _accept_certificate(packing, settings, scale, eq_res, fr_res, gap, wall)
    return TrescaResult(
        displacement=u.reshape(packing.n_cells, 2),
        slip=slip,
        normal_force=lam,
        tangential_force=f_t,
        normal_stress=-lam / packing.edge_length,
        shear_stress=f_t / packing.edge_length,
        cell_load=load,
        status=lp.problem.status,
        is_inaccurate=inaccurate,
        solver=settings.solver,
        selection=settings.selection,
        primal_objective=primal_objective,
        duality_gap=gap,
        primal_residual=lp.primal_residual(),
        equilibrium_residual=eq_res,
        friction_residual=fr_res,
        wall_s=wall,
    )


def _accept_certificate(packing, settings, scale, eq_res, fr_res, gap, wall) -> None:
    """Raise ``NumericalFailureError`` unless the equilibrium and friction residuals [-] are
    at most ``feas_tol`` and the duality gap [J/m] at most ``feas_tol`` x load ``scale``
    [N/m] x the packing's length scale [m]; log the accepted solve."""
    tol = settings.feas_tol
    length_scale = float(np.sqrt(np.sum(packing.cell_area)))
    if eq_res > tol or fr_res > tol or abs(gap) > tol * scale * length_scale:
        raise NumericalFailureError(
            f"Tresca solution fails its certificate: equilibrium {eq_res:.2e}, friction "
            f"{fr_res:.2e}, duality gap {gap:.2e} J/m (tolerance {tol:.1e})"
        )
    logger.info(
        "Tresca %s/%s: %d cells, %d edges, eq %.1e, gap %.1e, %.3f s",
        settings.solver,
        settings.selection,
        packing.n_cells,
        packing.n_edges,
        eq_res,
        gap,
        wall,
    )


def _balanced_load(packing: Packing, traction: np.ndarray) -> tuple[np.ndarray, float]:
    """Cell loads (n_cells, 2) [N/m] of a boundary traction and the largest of them; raises
    ``ValueError`` for a zero traction or one whose resultant does not vanish."""
    load = cell_loads(packing, traction)
    scale = float(np.max(np.linalg.norm(load, axis=1), initial=0.0))
    if scale == 0.0:
        raise ValueError("boundary traction is zero: nothing to compute")
    resultant = np.linalg.norm(load.sum(axis=0))
    if resultant > 1e-9 * np.abs(load).sum():
        raise ValueError(
            f"boundary traction resultant must vanish (Neumann data), got |R| = {resultant:.3e} N/m"
        )
    return load, scale


class _TrescaLP:
    """The LP of seed 003 Eq. (16) in the cell translations ``x`` (2 n_cells,) and edge slacks
    ``tau`` (n_edges,); its constraint rows are the transposed equilibrium blocks
    ``[u]_e . n_e`` (``B_n``) and ``[u]_e . t_e`` (``B_t``), and ``S`` sums the translations."""

    def __init__(self, packing: Packing, load: np.ndarray, s_e: np.ndarray):
        n_c, n_e = packing.n_cells, packing.n_edges
        A = equilibrium_matrix(packing)
        self.B_n = sp.csr_matrix(A[:, :n_e].T)
        self.B_t = sp.csr_matrix(A[:, n_e:].T)
        self.S = sp.csr_matrix(np.kron(np.ones((1, n_c)), np.eye(2)))
        self.x = cp.Variable(2 * n_c)
        self.tau = cp.Variable(n_e)
        self.weight = s_e * packing.edge_length
        objective = cp.Minimize(self.weight @ self.tau - load.ravel() @ self.x)
        self.c_normal = self.B_n @ self.x >= 0
        self.c_plus = self.tau - self.B_t @ self.x >= 0
        self.c_minus = self.tau + self.B_t @ self.x >= 0
        self.problem = cp.Problem(
            objective, [self.c_normal, self.c_plus, self.c_minus, self.S @ self.x == 0]
        )

    def forces(self) -> tuple[np.ndarray, np.ndarray]:
        """Normal and tangential edge forces [N/m] from the solver's duals."""
        lam = np.asarray(self.c_normal.dual_value, dtype=np.float64)
        f_t = np.asarray(self.c_minus.dual_value, dtype=np.float64) - np.asarray(
            self.c_plus.dual_value
        )
        return lam, f_t

    def primal_residual(self) -> float:
        """Largest violation of the primal constraints at the solution."""
        u, slip = np.asarray(self.x.value), np.asarray(self.tau.value)
        jn, jt = self.B_n @ u, self.B_t @ u
        return float(
            max(
                np.max(-jn, initial=0.0),
                np.max(np.abs(jt) - slip, initial=0.0),
                np.max(np.abs(self.S @ u)),
            )
        )


def _min_energy_forces(
    packing: Packing, load: np.ndarray, s_e: np.ndarray, settings: TrescaSettings
) -> tuple[np.ndarray, np.ndarray, bool]:
    """Admissible edge forces of least weighted norm (our selection rule, see module notes)."""
    n_e = packing.n_edges
    A = equilibrium_matrix(packing)
    w = _min_energy_weights(packing)
    # the last cell's balance follows from the others since the resultant vanishes
    keep = slice(0, 2 * packing.n_cells - 2)
    lam = cp.Variable(n_e)
    f_t = cp.Variable(n_e)
    z = cp.hstack([lam, f_t])
    cap = s_e * packing.edge_length
    problem = cp.Problem(
        cp.Minimize(0.5 * (cp.sum(cp.multiply(w, cp.square(lam) + cp.square(f_t))))),
        [A[keep] @ z == -load.ravel()[keep], lam >= 0, cp.abs(f_t) <= cap],
    )
    options = {}
    if settings.qp_solver == "CLARABEL":
        options = {k: settings.qp_tol for k in ("tol_gap_abs", "tol_gap_rel", "tol_feas")}
    problem.solve(solver=settings.qp_solver, **options)
    inaccurate = _accept(problem, "Tresca min-energy selection", "The admissible set is empty.")
    return np.asarray(lam.value), np.asarray(f_t.value), inaccurate


def _min_energy_weights(packing: Packing) -> np.ndarray:
    """Weights :math:`w_e = d_e / |e|` [-] of the min-energy objective, shape (n_edges,)."""
    d = packing.centres[packing.edge_cells[:, 1]] - packing.centres[packing.edge_cells[:, 0]]
    return np.abs(np.sum(d * packing.edge_normal, axis=1)) / packing.edge_length


def min_energy_force_bound(
    packing: Packing, result: TrescaResult, settings: TrescaSettings | None = None
) -> np.ndarray:
    """Certified half-width [N/m] of each min-energy edge force, shape (n_edges,): the exact
    minimiser's :math:`\\lambda_e` and :math:`f_{t,e}` lie within it of ``result``'s.

    Notes
    -----
    The objective :math:`f(z) = \\tfrac12 \\sum_e w_e (\\lambda_e^2 + f_{t,e}^2)` is strongly
    convex in the :math:`w`-norm, so for an admissible :math:`z` the optimality of the
    minimiser :math:`z^*` over the convex admissible set gives
    :math:`\\tfrac12 \\|z - z^*\\|_w^2 \\le f(z) - f(z^*)`, which is at most the duality gap;
    Clarabel stops when the gap is below ``qp_tol`` absolutely or relative to the objective,
    so the gap is at most :math:`g = \\text{qp\\_tol}\\,\\max(1, f(z))` [J/m] and
    :math:`|z_e - z^*_e| \\le \\sqrt{2 g / w_e}`. The returned point is admissible only to
    ``qp_tol``; the largest cell load times ``qp_tol`` is added for that. The bound is
    certified but loose: a gap of :math:`g` only bounds the distance by :math:`\\sqrt{g}`.
    """
    settings = settings or TrescaSettings(selection="min_energy")
    if result.selection != "min_energy":
        raise ValueError(
            f"min_energy_force_bound needs a min_energy result, got selection {result.selection!r}"
        )
    if settings.qp_solver != "CLARABEL":
        raise ValueError(f"the bound needs Clarabel's gap tolerance, got {settings.qp_solver!r}")
    w = _min_energy_weights(packing)
    z = np.concatenate([result.normal_force, result.tangential_force])
    energy = 0.5 * float(np.sum(np.concatenate([w, w]) * z**2))
    gap = settings.qp_tol * max(1.0, energy)
    load = float(np.max(np.linalg.norm(result.cell_load, axis=1), initial=0.0))
    return np.sqrt(2.0 * gap / w) + settings.qp_tol * load


def facet_tractions(packing: Packing, result: TrescaResult, traction: np.ndarray) -> np.ndarray:
    """Traction :math:`\\sigma n` on every facet of every cell, from the edge forces.

    Parameters
    ----------
    packing : Packing
    result : TrescaResult
    traction : array_like, shape (n_bnd, 2)
        Boundary traction [Pa].

    Returns
    -------
    ndarray, shape (n_facets, 2)
        Traction on facet ``k`` of each cell with the cell's outward normal [Pa], in the order
        of ``packing.cell_xy`` (seed 003 Eq. 14 plus the Neumann data).
    """
    traction = _check_traction(packing, traction)
    force_on_b = (
        result.normal_force[:, None] * packing.edge_normal
        + result.tangential_force[:, None] * packing.edge_tangent
    ) / packing.edge_length[:, None]
    out = np.empty((len(packing.facet_edge), 2))
    cell_of_facet = np.repeat(np.arange(packing.n_cells), np.diff(packing.cell_ptr))
    internal = packing.facet_edge >= 0
    e = packing.facet_edge[internal]
    is_b = packing.edge_cells[e, 1] == cell_of_facet[internal]
    out[internal] = np.where(is_b[:, None], force_on_b[e], -force_on_b[e])
    out[~internal] = traction[-1 - packing.facet_edge[~internal]]
    return out


_CLARABEL_TIGHT = {
    "tol_gap_abs": 1e-10,
    "tol_gap_rel": 1e-10,
    "tol_feas": 1e-10,
    "tol_ktratio": 1e-8,
    "max_iter": 400,
}
"""Clarabel options of the second multiplier solve: a hundred times its default tolerances and
twice its iterations, as the last attempt of :mod:`limit.clarabel`."""


@dataclass(frozen=True)
class TrescaMultiplierResult:
    """Largest multiplier of a live traction that the packing carries, with its certificate.

    Attributes
    ----------
    load_multiplier : float
        :math:`\\alpha^*` [-]: the traction ``dead + alpha * live`` is admissible iff
        ``alpha <= alpha^*``.
    upper_bound : float
        Dual objective [-]: the kinematic multiplier of the mechanism read from the duals of
        the equilibrium rows (see :func:`max_load_multiplier`).
    normal_force, tangential_force : ndarray, shape (n_edges,)
        An admissible force set at :math:`\\alpha^*` [N/m], sign convention of
        :class:`TrescaResult`.
    status : str
        cvxpy status of the accepted solve.
    is_inaccurate : bool
        True if the accepted solve returned ``optimal_inaccurate``.
    equilibrium_residual, friction_residual : float
        Certificates of the forces, as in :class:`TrescaResult` [-].
    duality_gap : float
        :math:`|\\bar\\alpha - \\alpha^*|` relative to the multiplier [-] (notes of
        :func:`max_load_multiplier`).
    dual_residual : float
        Largest interpenetration of the mechanism relative to its largest jump [-].
    attempts : tuple of (str, str)
        ``(attempt, status)`` of every solve, in order.
    wall_s : float
        [s].
    feasibility_shift : float
        How far the optimum may lie from ``load_multiplier`` because the returned forces
        violate their rows (balance, compression, Tresca) [-]: each violation times its dual,
        the first-order sensitivity of the optimum (as in :mod:`limit.certificates`).
    """

    load_multiplier: float
    upper_bound: float
    normal_force: np.ndarray
    tangential_force: np.ndarray
    status: str
    is_inaccurate: bool
    equilibrium_residual: float
    friction_residual: float
    duality_gap: float
    dual_residual: float
    attempts: tuple
    wall_s: float
    feasibility_shift: float = float("nan")

    @property
    def load_multiplier_estimate(self) -> Estimate:
        """``load_multiplier`` with its error bar (the half-width of an interval that holds
        the programme's optimum): source ``"duality gap"``, the distance to the kinematic
        multiplier of the duals' mechanism, an upper bound of the optimum;
        ``"feasibility"``, :attr:`feasibility_shift`; ``"round-off"``, 16 ulps of the
        multiplier (a simplex vertex is exact up to the rounding of its scaling)."""
        gap = abs(self.upper_bound - self.load_multiplier)
        shift = self.feasibility_shift if math.isfinite(self.feasibility_shift) else math.inf
        ulps = 16 * float(np.spacing(max(abs(self.load_multiplier), abs(self.upper_bound))))
        return Estimate(
            self.load_multiplier,
            {"duality gap": gap, "feasibility": shift, "round-off": ulps},
            notes="solver error of the programme's optimum (duality gap, primal violations)",
        )


def max_load_multiplier(
    packing: Packing,
    dead_traction: np.ndarray,
    live_traction: np.ndarray,
    s: float | np.ndarray,
    settings: TrescaSettings | None = None,
) -> TrescaMultiplierResult:
    """Maximise :math:`\\alpha` such that ``dead + alpha * live`` has an admissible force set.

    The static (lower-bound) form of the dual of seed 003 Eq. (16) with a load multiplier:
    :math:`\\max \\alpha` s.t. :math:`A z + F_{dead} + \\alpha F_{live} = 0`,
    :math:`\\lambda \\ge 0`, :math:`|f_t| \\le s|e|`.

    Parameters
    ----------
    packing : Packing
    dead_traction, live_traction : array_like, shape (n_bnd, 2)
        Boundary tractions [Pa], each with zero resultant; the live one not zero.
    s : float or array_like, shape (n_edges,)
        Tresca threshold [Pa].
    settings : TrescaSettings, optional
        Only ``solver`` and ``feas_tol`` are used.

    Returns
    -------
    TrescaMultiplierResult

    Raises
    ------
    ValueError
        Bad shapes, a traction with a non-zero resultant, or a zero live traction.
    NoMechanismError
        Unbounded: the live load never fails the packing.
    DeadLoadInfeasibleError
        Infeasible, or optimal at a negative multiplier: the dead load alone is not admissible.
    NumericalFailureError
        Any other non-optimal status, or a point that fails its certificate (after a solve
        with tighter tolerances for Clarabel).

    Notes
    -----
    The programme is solved in scaled units, whatever the units of the data, so that the
    solver's absolute tolerances are relative to the loads: forces divided by the largest cell
    load :math:`F = \\max(\\max_c|F_{dead,c}|, \\max_c|F_{live,c}|)` and :math:`\\alpha` by
    :math:`F / \\max_c|F_{live,c}|`. (Its only data are forces per unit length, so no length
    scale enters.)

    The multipliers :math:`v` of the equilibrium rows, normalised to unit live power
    :math:`F_{live}\\cdot v = 1`, are cell velocities of the Lagrange dual
    :math:`\\bar\\alpha = \\min_v \\sum_e s|e|\\,|[v]_e\\cdot t_e| - F_{dead}\\cdot v` s.t.
    :math:`[v]_e\\cdot n_e \\ge 0` (the kinematic, upper-bound multiplier of the mechanism
    :math:`v`). The result is accepted only if the forces pass the equilibrium and friction
    certificates, the mechanism does not interpenetrate, and the gap
    :math:`|\\bar\\alpha - \\alpha^*| / \\max(|\\alpha^*|, |\\bar\\alpha|, \\epsilon\\,\\alpha_F)`
    is at most ``feas_tol`` (:math:`\\epsilon` = ``feas_tol``, :math:`\\alpha_F` the
    multiplier unit above: a multiplier that vanishes is resolved to the forces' tolerance).
    """
    settings = settings or TrescaSettings()
    s_e = _check_s(packing, s)
    start = time.perf_counter()
    prog = _MultiplierProgramme(packing, dead_traction, live_traction, s_e)
    return _certified_multiplier(prog, packing, dead_traction, live_traction, s_e, settings, start)


def _certified_multiplier(prog, packing, dead_traction, live_traction, s_e, settings, start):
    """Solve the multiplier programme (Clarabel: again with tighter tolerances if the first
    solve is inaccurate or fails its certificate) and return the first certified point;
    ``wall_s`` counts from ``start`` [s]."""
    attempts = [("default", {})]
    if settings.solver == "CLARABEL":
        attempts.append(("tightened", _CLARABEL_TIGHT))
    history: list[tuple[str, str]] = []
    failure = ""
    for i, (label, options) in enumerate(attempts):
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Solution may be inaccurate")
            prog.problem.solve(solver=settings.solver, **options)
        status = prog.problem.status
        history.append((label, status))
        if status == cp.OPTIMAL_INACCURATE and i < len(attempts) - 1:
            failure = f"solver status {status}"
            continue
        if status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE):
            _raise_multiplier_status(prog.problem, prog.admissible, settings.solver)
        tol = settings.feas_tol
        point = _multiplier_point(prog, packing, dead_traction, live_traction, s_e, tol)
        checks = {name: point[key] for name, key in _CERTIFICATE.items()}
        if all(value <= tol for value in checks.values()):  # False for NaN
            return _multiplier_result(point, status, tuple(history), start)
        failure = (
            f"alpha = {point['load_multiplier']:.9g}, dual bound {point['upper_bound']:.9g}; "
            + ", ".join(f"{k} {val:.2e}" for k, val in checks.items())
            + f" (tolerance {tol:.1e})"
        )
        logger.info("Tresca load multiplier, %s solve rejected: %s", label, failure)
    text = ", ".join(f"{a} {st}" for a, st in history)
    raise NumericalFailureError(
        f"Tresca load multiplier: no certified optimum after {len(history)} solves ({text}); "
        f"last: {failure}"
    )


class _MultiplierProgramme:
    """The scaled multiplier programme of :func:`max_load_multiplier` (see its notes).

    ``A`` holds the balance rows of every cell but the last (whose balance follows from the
    zero resultants: its velocity is the reference, zero, in the dual); ``d_hat``, ``l_hat``
    and ``cap_hat`` are the dead load, live load and Tresca capacities in scaled units; the
    unknowns are the normal and tangential edge forces ``lam``, ``f_t`` and ``alpha``.
    Raises ``ValueError`` for a traction with a non-zero resultant or a zero live traction.
    """

    def __init__(self, packing: Packing, dead_traction, live_traction, s_e: np.ndarray):
        dead = cell_loads(packing, dead_traction)
        live = cell_loads(packing, live_traction)
        for name, load in (("dead traction", dead), ("live traction", live)):
            if np.linalg.norm(load.sum(axis=0)) > 1e-9 * max(np.abs(load).sum(), 1e-300):
                raise ValueError(f"{name} resultant must vanish")
        live_max = float(np.max(np.linalg.norm(live, axis=1), initial=0.0))
        if live_max == 0.0:
            raise ValueError("live traction is zero: no load multiplier to compute")
        self.force_scale = max(float(np.max(np.linalg.norm(dead, axis=1), initial=0.0)), live_max)
        self.alpha_unit = self.force_scale / live_max
        keep = slice(0, 2 * packing.n_cells - 2)
        self.A = equilibrium_matrix(packing)[keep]
        self.d_hat = dead.ravel()[keep] / self.force_scale
        self.l_hat = live.ravel()[keep] / live_max
        self.cap_hat = s_e * packing.edge_length / self.force_scale
        self.lam = cp.Variable(packing.n_edges)
        self.f_t = cp.Variable(packing.n_edges)
        self.alpha = cp.Variable()
        self.constraints = self.admissible(self.alpha)
        self.problem = cp.Problem(cp.Maximize(self.alpha), self.constraints)

    def admissible(self, multiplier) -> list:
        """Balance (first), non-interpenetration and Tresca rows at ``multiplier``."""
        balance = self.A @ cp.hstack([self.lam, self.f_t]) + self.d_hat + multiplier * self.l_hat
        return [balance == 0, self.lam >= 0, cp.abs(self.f_t) <= self.cap_hat]


_CERTIFICATE = {
    "equilibrium": "equilibrium_residual",
    "friction": "friction_residual",
    "duality gap": "duality_gap",
    "mechanism interpenetration": "dual_residual",
}
"""The residuals a multiplier must pass (each at most ``feas_tol``), by the result field."""


def _multiplier_result(point: dict, status: str, attempts: tuple, start: float):
    """The certified result (an accepted ``optimal_inaccurate`` warns)."""
    inaccurate = status == cp.OPTIMAL_INACCURATE
    if inaccurate:
        warnings.warn(
            "Tresca load multiplier: solver returned 'optimal_inaccurate'; the point "
            "passed its certificate",
            RuntimeWarning,
            stacklevel=4,  # the caller of max_load_multiplier
        )
    wall = time.perf_counter() - start
    return TrescaMultiplierResult(
        **point, status=status, is_inaccurate=inaccurate, attempts=attempts, wall_s=wall
    )


def _multiplier_point(prog, packing, dead_traction, live_traction, s_e, tol: float) -> dict:
    """An optimal point of ``prog`` in SI with its residuals, as the fields of
    :class:`TrescaMultiplierResult` that the point fixes; raises ``DeadLoadInfeasibleError``
    for a negative multiplier."""
    a_star = float(prog.alpha.value) * prog.alpha_unit
    if a_star < 0:
        raise DeadLoadInfeasibleError(
            f"Tresca load multiplier: the dead load alone is not carried (only the live "
            f"load reversed, times {-a_star:.6g}, would balance it): no load multiplier "
            "exists"
        )
    lam_si = np.asarray(prog.lam.value) * prog.force_scale
    f_t_si = np.asarray(prog.f_t.value) * prog.force_scale
    traction = np.asarray(dead_traction) + a_star * np.asarray(live_traction)
    eq, fr = admissibility_residuals(packing, traction, s_e, lam_si, f_t_si)
    y = np.asarray(prog.constraints[0].dual_value, dtype=np.float64)
    upper, dual_res = _mechanism_bound(y, prog.A, prog.d_hat, prog.l_hat, prog.cap_hat)
    upper *= prog.alpha_unit
    gap = abs(upper - a_star) / max(abs(a_star), abs(upper), tol * prog.alpha_unit)
    return {
        "feasibility_shift": _feasibility_shift(prog) * prog.alpha_unit,
        "load_multiplier": a_star,
        "upper_bound": upper,
        "normal_force": lam_si,
        "tangential_force": f_t_si,
        "equilibrium_residual": eq,
        "friction_residual": fr,
        "duality_gap": gap,
        "dual_residual": dual_res,
    }


def _feasibility_shift(prog) -> float:
    """``sum |dual| x violation`` over the rows of the solved (scaled) programme: the
    first-order move of its optimum [scaled alpha] that the returned point's violations can
    hide."""
    z = np.concatenate([np.ravel(prog.lam.value), np.ravel(prog.f_t.value)])
    balance = prog.A @ z + prog.d_hat + float(prog.alpha.value) * prog.l_hat
    rows = (
        (prog.constraints[0], np.abs(balance)),
        (prog.constraints[1], np.maximum(-np.ravel(prog.lam.value), 0.0)),
        (prog.constraints[2], np.maximum(np.abs(np.ravel(prog.f_t.value)) - prog.cap_hat, 0.0)),
    )
    return float(sum(np.abs(np.ravel(c.dual_value)) @ viol for c, viol in rows))


def _mechanism_bound(y, A, d_hat, l_hat, cap_hat) -> tuple[float, float]:
    """Kinematic multiplier of the mechanism read from the duals ``y`` of the (scaled)
    balance rows ``A [lam; f_t] + d_hat + alpha l_hat = 0`` (notes of
    :func:`max_load_multiplier`), and its largest interpenetration relative to its largest
    jump [-]. The duals are cell velocities, normalised here to unit live power (which also
    fixes cvxpy's sign convention)."""
    power = float(l_hat @ y)
    v = y / power if power != 0.0 else np.full_like(y, np.nan)
    n_e = len(cap_hat)
    jump_n, jump_t = A[:, :n_e].T @ v, A[:, n_e:].T @ v
    upper = float(cap_hat @ np.abs(jump_t) - d_hat @ v)
    jump_max = float(np.max(np.abs(np.concatenate([jump_n, jump_t]))))
    return upper, max(float(np.max(-jump_n)), 0.0) / jump_max


def _raise_multiplier_status(problem: cp.Problem, admissible, solver: str) -> None:
    """Raise the outcome of a multiplier programme that ended without an optimum."""
    try:
        _accept(
            problem,
            "Tresca load multiplier",
            "Unbounded: the live load never fails; infeasible: the dead load alone is not carried.",
            unbounded=NoMechanismError,
        )
    except NoMechanismError:
        # an interior-point solver may report a programme that is both primal and dual
        # infeasible as unbounded: only a dead load that is carried leaves the live load free
        dead_only = cp.Problem(cp.Minimize(0), admissible(0.0))
        dead_only.solve(solver=solver)
        if dead_only.status in (cp.INFEASIBLE, cp.INFEASIBLE_INACCURATE):
            raise DeadLoadInfeasibleError(
                "Tresca load multiplier: the dead load alone is not carried (no admissible "
                "force set at multiplier 0)"
            ) from None
        raise
