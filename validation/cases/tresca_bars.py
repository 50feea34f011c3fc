"""Error bars of the seed-003 rows (:mod:`validation.cases.tresca`), each from work the solve
did itself.

- A certificate (cell imbalance, duality gap) is a residual whose exact value is 0; its bar is
  the tolerance the forces were solved to (:func:`imbalance_tolerance`, :func:`gap_tolerance`),
  so that the reference 0 lies in the bar exactly when the solve kept its promise.
- A min-energy force is unique; its bar is the certified distance to the exact minimiser
  (:func:`limit.tresca.min_energy_force_bound`), divided by the edge length for a stress.
- A sum that statics alone determines (the forces across a bed joint of the brick wall) is off
  by at most the imbalances of the cells whose balance determines it
  (:func:`resultant_bar`).
- Forces of a closed form (the uniform stress) are exact up to the round-off of their sums
  (:func:`uniform_round_off`).
- A check of the RT0 reconstruction that holds for any forces (conformity, weak symmetry,
  Green's identity) is exact up to the round-off of the local solves (:func:`rt_round_off`);
  one that depends on the forces moves by at most the reconstruction of their bars
  (:func:`rt_bars`).

The forces that ``selection="solver"`` returns are one of many admissible sets (seed 003
Remark 4): their stresses are the solver's choice, not a converged answer
(:func:`stress_bar` returns None). What the model does fix is the range of each stress over
every admissible set (:func:`admissible_range`, two LPs per edge and component): a solver's
value gets the bar that holds that whole range (:func:`range_bar`), and a quantity linear in
the stresses (the RT0 reconstruction) the bar of the box the ranges span
(:func:`dual_widths`, then :func:`rt_bars`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fem_check.rt_reconstruction import reconstruct_stress
from limit.tresca import (
    TrescaResult,
    TrescaSettings,
    cell_loads,
    equilibrium_matrix,
    min_energy_force_bound,
)
from validation.cases.bars import sum_round_off


def solve_settings(solver: str, selection: str) -> TrescaSettings:
    """The settings every seed-003 row solves with (the defaults of :class:`TrescaSettings`)."""
    return TrescaSettings(solver=solver, selection=selection)


def imbalance_tolerance(res: TrescaResult, settings: TrescaSettings) -> float:
    """Largest cell imbalance / largest cell load [-] that the solve of ``res`` allows: the
    min-energy QP's feasibility tolerance ``qp_tol`` (Clarabel's rule: relative to the larger
    of 1, the loads and the forces), else the acceptance tolerance ``feas_tol`` of
    :func:`limit.tresca.solve_tresca`."""
    scale = float(np.max(np.linalg.norm(res.cell_load, axis=1)))
    if res.selection != "min_energy":
        return settings.feas_tol
    forces = np.concatenate([res.normal_force, res.tangential_force])
    # the rule bounds each component; a cell's imbalance is the norm of two of them
    bound = settings.qp_tol * max(1.0, scale, float(np.max(np.abs(forces))))
    return np.sqrt(2.0) * bound / scale


def gap_tolerance(packing, res: TrescaResult, settings: TrescaSettings) -> float:
    """Largest duality gap [J/m] that :func:`limit.tresca.solve_tresca` accepts: ``feas_tol``
    x largest cell load [N/m] x the packing's length scale sqrt(area) [m]."""
    scale = float(np.max(np.linalg.norm(res.cell_load, axis=1)))
    return settings.feas_tol * scale * float(np.sqrt(np.sum(packing.cell_area)))


def stress_bar(packing, res: TrescaResult, settings: TrescaSettings) -> np.ndarray | None:
    """Certified half-width [Pa] of each edge's normal and shear stress, shape (n_edges,), for
    a min-energy result; None for a solver's own dual (module notes)."""
    if res.selection != "min_energy":
        return None
    return min_energy_force_bound(packing, res, settings) / packing.edge_length


def count_bar(values: np.ndarray, threshold: np.ndarray, widths: np.ndarray) -> float:
    """Half-width of the count of ``values < threshold`` when each value is known to within
    ``widths``: the number of values whose interval straddles the threshold."""
    return float(np.sum(np.abs(values - threshold) <= widths))


def resultant_bar(packing, res: TrescaResult, cells: np.ndarray) -> float:
    """Bound [N/m] on the error of the resultant of the edge forces that the cells ``cells``
    (bool, shape (n_cells,)) receive across their boundary with the other cells, as statics
    determines it from their loads: the sum of their imbalances' norms, plus the round-off
    of the sum."""
    A = equilibrium_matrix(packing)
    z = np.concatenate([res.normal_force, res.tangential_force])
    imbalance = (A @ z).reshape(-1, 2) + res.cell_load
    terms = (abs(A) @ np.abs(z)).reshape(-1, 2)
    own = float(np.sum(np.linalg.norm(imbalance[cells], axis=1)))
    return own + sum_round_off(np.sum(terms[cells]), A.getnnz(axis=1).max() * np.sum(cells))


def uniform_round_off(packing, traction: np.ndarray, normal_force, tangential_force) -> float:
    """Round-off bound [-] of the largest cell imbalance / largest cell load of edge forces
    computed from a closed form: each cell's sum of its edge forces and load, with a few
    operations per force for the projections that made it."""
    A = equilibrium_matrix(packing)
    load = cell_loads(packing, traction)
    z = np.abs(np.concatenate([normal_force, tangential_force]))
    terms = (abs(A) @ z) + np.abs(load.ravel())
    n_terms = A.getnnz(axis=1) + 4
    scale = float(np.max(np.linalg.norm(load, axis=1)))
    # the norm of a 2-vector is at most sqrt(2) times its largest component
    return sum_round_off(terms, n_terms) * np.sqrt(2.0) / scale


def rt_round_off(rec) -> float:
    """Round-off bound [Pa] of a stress of the RT0 reconstruction ``rec``
    (:class:`fem_check.rt_reconstruction.RTReconstruction`): the backward error of Gaussian
    elimination on the largest local system (size ``3 m`` for an ``m``-gon) and the three
    fluxes of each evaluation, applied to the largest stress. It assumes the local systems are
    well conditioned: a check above it points at a badly shaped cell."""
    m_max = int(np.max(np.bincount(rec.tri_cell)))
    sigma = float(np.max(np.abs(rec.sigma_vertex)))
    return sum_round_off(sigma, 3 * (3 * m_max + 3))


@dataclass(frozen=True)
class RtBars:
    """Certified bounds on how far the outputs of an RT0 reconstruction move when each facet
    traction moves by at most its width (the reconstruction is linear in the tractions, so
    the bound is the sum of the absolute responses to each facet's width, up to round-off).

    Attributes
    ----------
    sigma_vertex : ndarray, shape (n_tri, 3, 2, 2)
        [Pa], per component.
    cell_stress : ndarray, shape (n_cells, 2, 2)
        [Pa], per component.
    div : ndarray, shape (n_tri, 2)
        [Pa/m], per row.
    traction_moment : ndarray, shape (n_cells,)
        [N m/m].
    """

    sigma_vertex: np.ndarray
    cell_stress: np.ndarray
    div: np.ndarray
    traction_moment: np.ndarray


def rt_bars(packing, stress_widths: np.ndarray) -> RtBars:
    """:class:`RtBars` of the reconstruction of ``packing`` when the stress on each internal
    edge is known to within ``stress_widths`` [Pa], shape (n_edges,) (normal and shear alike:
    each traction component within sqrt(2) times it); the Neumann data are exact.

    One reconstruction per facet slot and traction component: the cells are independent, so
    slot ``k`` of every cell is perturbed at once (``2 m_max`` reconstructions)."""
    edge = packing.facet_edge
    widths = np.where(edge >= 0, np.sqrt(2.0) * stress_widths[np.maximum(edge, 0)], 0.0)
    sizes = np.diff(packing.cell_ptr)
    slot = np.arange(len(edge)) - np.repeat(packing.cell_ptr[:-1], sizes)
    acc = None
    for k in range(int(sizes.max())):
        for i in range(2):
            traction = np.zeros((len(edge), 2))
            traction[slot == k, i] = widths[slot == k]
            rec = reconstruct_stress(packing.cell_ptr, packing.cell_xy, packing.centres, traction)
            parts = [np.abs(rec.sigma_vertex), np.abs(rec.cell_stress), np.abs(rec.div)]
            parts.append(np.abs(rec.traction_moment))
            acc = parts if acc is None else [a + p for a, p in zip(acc, parts, strict=True)]
    return RtBars(*acc)


RANGE_MAX_EDGES = 400
"""Largest packing [internal edges] whose solver-dual rows get the admissible range: two
small LPs per edge and component, each growing with the packing (the 60-cell packing's 153
edges take a few seconds for both components)."""


def admissible_range(packing, traction, s: float, component: str) -> np.ndarray | None:
    """Least and largest stress [Pa] of each internal edge over every admissible force set
    (seed 003 Eq. 12-14: cell balance, ``lambda >= 0``, ``|f_t| <= s|e|``), shape (2, n_edges):
    the normal stress ``-lambda/|e|`` (``component="normal"``) or the shear ``f_t/|e|``. Two
    LPs per edge (HiGHS); None above :data:`RANGE_MAX_EDGES`.

    The duals a solver returns are one point of this set (seed 003 Remark 4): a stress of
    theirs is determined by the model only to within its range."""
    from scipy.optimize import linprog

    n_e = packing.n_edges
    if n_e > RANGE_MAX_EDGES:
        return None
    A = equilibrium_matrix(packing)
    keep = slice(0, 2 * packing.n_cells - 2)  # the last balance follows (zero resultant)
    b = -cell_loads(packing, traction).ravel()[keep]
    cap = s * packing.edge_length
    bounds = [(0.0, None)] * n_e + [(-c, c) for c in cap]
    offset = 0 if component == "normal" else n_e
    sign = -1.0 if component == "normal" else 1.0
    out = np.empty((2, n_e))
    for e in range(n_e):
        for k, direction in enumerate((1.0, -1.0)):
            c = np.zeros(2 * n_e)
            c[offset + e] = direction * sign / packing.edge_length[e]
            res = linprog(c, A_eq=A[keep], b_eq=b, bounds=bounds, method="highs")
            if res.status != 0:
                raise RuntimeError(f"admissible range of edge {e}: {res.message}")
            out[k, e] = direction * res.fun
    return out


def dual_widths(res: TrescaResult, normal: np.ndarray, shear: np.ndarray) -> np.ndarray:
    """Half-width [Pa] of each internal edge's stress around a solver's own dual ``res``,
    shape (n_edges,): the larger distance from its normal and its shear stress to the ends of
    their admissible ranges ``normal`` and ``shear`` (:func:`admissible_range`, shape
    (2, n_edges)). Every admissible force set lies in the box these widths span around
    ``res`` (a box holds the polytope, so the bar is valid, if loose), and so
    :func:`rt_bars` of them bounds how far any admissible set moves a reconstruction."""
    dn = np.maximum(res.normal_stress - normal[0], normal[1] - res.normal_stress)
    ds = np.maximum(res.shear_stress - shear[0], shear[1] - res.shear_stress)
    return np.maximum(np.maximum(dn, ds), 0.0)


def range_bar(value: float, low: float, high: float) -> dict[str, float]:
    """The half-width that puts every value of ``[low, high]`` in the bar of ``value``."""
    return {"admissible range": max(value - low, high - value, 0.0)}
