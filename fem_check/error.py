r"""Error bars of the FEM check's headline numbers, as :class:`dem.estimate.Estimate`.

Stress extremes of a block (:class:`fem_check.recovery.StressSummary`) are estimated from
further solves of the same block, at a cost the caller chooses
(:data:`dem.estimate.ErrorBudget`). With P2 displacements the further solves are on coarser
meshes, the coarsest twice the size :math:`h` of the fine one:

``"none"``
    The value alone, with an unknown (``inf``) error.
``"cheap"``
    One coarser level (about ``MESH_RATIO**3`` times fewer tetrahedra). Source ``"mesh"`` =
    :math:`|s_h - s_{2h}|`: the error of the fine level if the value converges with order
    at least 1 (then :math:`|s_h - s_\infty| \le |s_h - s_{2h}| / (2^p - 1) \le |s_h - s_{2h}|`).
    It does not see a value that diverges (a stress peak under a point force).
``"full"``
    Two coarser levels, :math:`rh` and :math:`r^2 h = 2h` with :math:`r` =
    :data:`FULL_RATIO` :math:`= \sqrt 2`: levels at :math:`4h` would leave a small block (a TIS
    block is five 1.6 mm elements across) a couple of elements across, outside the
    asymptotic range whose steps the index extrapolates. The observed order
    :math:`p = \log_r(|s_{2h} - s_{rh}| / |s_{rh} - s_h|)`, capped at the formal order (the
    displacement degree: a stress converges no faster where the field is smooth); from
    :data:`MIN_ORDER` up, the bar is Roache's grid convergence index with the three-grid
    safety factor 1.25, :math:`1.25\,|s_h - s_{rh}| / (r^p - 1)`. Steps that grow or barely
    shrink (:math:`p` below :data:`MIN_ORDER`: the value runs away under refinement, as a peak
    at a singular point does) give an infinite bar, named ``"mesh (diverging)"``. Steps of
    opposite signs (oscillating convergence, where no order can be read) give the larger step
    (Celik et al. 2008). Steps within :data:`ROUND_OFF` of the value are round-off (an exact
    value, such as a linear stress field with P2). Every bar adds that fraction of the value,
    the resolution of the solves.

With P1 displacements (``"cheap"`` or ``"full"``) the reference is the P2 solution on the same
mesh, source ``"P1/P2"`` = :math:`|s_{P1} - s_{P2}|`. The extremes of P1 stresses (constant per
tetrahedron, and their L2 recovery) do not converge on unstructured meshes (not even on a bar
in pure bending), so coarser P1 levels would only measure noise; P2 reproduces the linear part
of the field that P1 misses.

A cut through a block (:func:`fem_check.recovery.cut_resultant`) has an exact answer in the
continuum: the resultant of the loads on one side (Cauchy). Its ``"equilibrium residual"``
source is the difference, component by component, which is the FE error itself.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from dem.estimate import ErrorBudget, Estimate, check_error_budget
from dem.geometry.polyhedron import ConvexBlock
from fem_check.elastic import BlockSolution, BlockSolver
from fem_check.loads import BlockLoad, loads_on_side
from fem_check.mesh import MeshSettings
from fem_check.recovery import StressSummary, cut_resultant, summarise

__all__ = [
    "FULL_RATIO",
    "MESH_RATIO",
    "MIN_ORDER",
    "CutCheck",
    "StressEstimates",
    "degree_estimate",
    "reference_solvers",
    "cut_check",
    "level_estimate",
    "solve_with_error",
]

MESH_RATIO = 2.0
"""Ratio of the mesh sizes of the coarser level of ``"cheap"`` and the fine one."""
FULL_RATIO = math.sqrt(2.0)
"""Ratio of mesh sizes between successive levels of ``"full"`` (module notes)."""
MIN_ORDER = 0.5
"""Smallest observed order read as convergence: stresses near re-entrant edges converge with
order about 0.5; below it the steps do not shrink enough to bound what is left."""
ROUND_OFF = 1e-9
"""Steps below this fraction of the value are round-off of the sparse solves [-]."""
SAFETY_FULL = 1.25
"""Roache's safety factor of the grid convergence index with three grids."""
QUANTITIES = ("max_principal", "max_von_mises", "min_principal")


def level_estimate(
    values: list[float], budget: ErrorBudget, cost_s: float = 0.0, formal_order: float = 2.0
) -> Estimate:
    """The finest of ``values`` (finest first, each level ``MESH_RATIO`` coarser for
    ``"cheap"``, ``FULL_RATIO`` for ``"full"``) with the bar of ``budget``; ``formal_order``
    caps the observed order (module notes)."""
    check_error_budget(budget)
    fine = float(values[0])
    if budget == "none":
        return Estimate.unknown(fine, "error budget 'none'")
    need = 2 if budget == "cheap" else 3
    if len(values) < need:
        raise ValueError(f"error budget {budget!r} needs {need} mesh levels, got {len(values)}")
    floor = ROUND_OFF * abs(fine)
    step = abs(values[0] - values[1])
    if budget == "cheap":
        return Estimate(fine, {"mesh": step + floor}, cost_s, "|s_h - s_2h|, order >= 1 assumed")
    before = abs(values[1] - values[2])
    if before <= floor and step <= floor:
        return Estimate(fine, {"mesh": max(step, before) + floor}, cost_s, "steps at round-off")
    if (values[0] - values[1]) * (values[1] - values[2]) < 0 and step > floor:
        note = "oscillating levels: the larger of the two steps"
        return Estimate(fine, {"mesh": max(step, before) + floor}, cost_s, note)
    if step <= floor:
        return Estimate(fine, {"mesh": step + floor}, cost_s, "last step at round-off")
    order = math.log(before / step) / math.log(FULL_RATIO)
    if order < MIN_ORDER:
        return Estimate(
            fine,
            {"mesh (diverging)": math.inf},
            cost_s,
            f"observed order {order:.2f}: the value does not converge under refinement",
        )
    used = min(order, formal_order)
    gci = SAFETY_FULL * step / (FULL_RATIO**used - 1.0) + floor
    note = f"GCI, observed order {order:.2f}, used {used:.2f}"
    return Estimate(fine, {"mesh": gci}, cost_s, note)


def degree_estimate(p1: float, p2: float, cost_s: float = 0.0) -> Estimate:
    """A P1 value with the ``"P1/P2"`` source, its distance to the P2 value on the same
    mesh."""
    width = abs(p1 - p2) + ROUND_OFF * abs(p2)
    return Estimate(p1, {"P1/P2": width}, cost_s, "P2 on the same mesh as reference")


def reference_solvers(solver: BlockSolver, budget: ErrorBudget) -> list[BlockSolver]:
    """The further solvers a ``budget`` needs (module notes), sharing ``solver``'s material
    and tolerance: for P2, 0, 1 or 2 coarser levels; for P1, the P2 solver on the same mesh
    (none for ``"none"``). Reuse them over the blocks of an assembly (each meshes and
    factorises a shape once)."""
    n_levels = {"none": 0, "cheap": 1, "full": 2}[check_error_budget(budget)]
    ms = solver.mesh_settings
    if solver.degree == 1:
        return [] if n_levels == 0 else [BlockSolver(solver.material, ms, 2, solver.rel_tol)]
    ratio = FULL_RATIO if budget == "full" else MESH_RATIO
    return [
        BlockSolver(
            solver.material,
            MeshSettings(ms.size * ratio**k, ms.order, ms.algorithm_3d, ms.optimize),
            solver.degree,
            solver.rel_tol,
        )
        for k in range(1, n_levels + 1)
    ]


@dataclass(frozen=True)
class StressEstimates:
    """Stress extremes of one block with their bars (module notes).

    Attributes
    ----------
    max_principal, max_von_mises, min_principal : Estimate
        As in :class:`~fem_check.recovery.StressSummary` [Pa], at the finest level.
    summary : StressSummary
        The finest level's summary (with the location of the peak).
    mesh_sizes : tuple of float
        Mesh size of each level, finest first [m].
    """

    max_principal: Estimate
    max_von_mises: Estimate
    min_principal: Estimate
    summary: StressSummary
    mesh_sizes: tuple

    def to_dict(self) -> dict:
        out = {q: getattr(self, q).to_dict() for q in QUANTITIES}
        return {**out, "mesh_sizes": list(self.mesh_sizes)}


def solve_with_error(
    solver: BlockSolver,
    block: ConvexBlock,
    load: BlockLoad,
    references: list[BlockSolver],
    error: ErrorBudget = "cheap",
    name: str = "block",
) -> tuple[BlockSolution, StressEstimates]:
    """Solve a block with ``solver`` and estimate its stress extremes' errors from the
    ``references`` (:func:`reference_solvers` of the same ``solver`` and ``error`` budget);
    the cost of their solves is each Estimate's ``cost_s``."""
    budget = check_error_budget(error)
    sol = solver.solve(block, load, name)
    summaries = [summarise(sol)]
    t0 = time.perf_counter()
    for other in references if budget != "none" else ():
        summaries.append(summarise(other.solve(block, load, f"{name} (error reference)")))
    cost = time.perf_counter() - t0
    ests = {}
    for q in QUANTITIES:
        values = [getattr(s, q) for s in summaries]
        p1 = solver.degree == 1 and budget != "none"
        ests[q] = (
            degree_estimate(*values[:2], cost)
            if p1
            else level_estimate(values, budget, cost, formal_order=solver.degree)
        )
    used = [solver, *references][: len(summaries)]
    sizes = tuple(r.mesh_settings.size for r in used)
    return sol, StressEstimates(**ests, summary=summaries[0], mesh_sizes=sizes)


@dataclass(frozen=True)
class CutCheck:
    """A Cauchy cut through a block: the FE resultant and the exact one, with bars.

    Attributes
    ----------
    force, moment : tuple of Estimate
        Components of :math:`\\int \\sigma n\\,dA` [N] and its moment [N m] (world frame),
        each with the ``"equilibrium residual"`` source: its distance to the exact component.
    force_exact, moment_exact : (3,) float
        Resultant of the loads on the side ``n . x >= offset`` [N, N m].
    """

    force: tuple
    moment: tuple
    force_exact: np.ndarray
    moment_exact: np.ndarray


def cut_check(
    sol: BlockSolution,
    block: ConvexBlock,
    load: BlockLoad,
    normal: np.ndarray,
    offset: float,
    about: np.ndarray,
    stress: str = "fe",
) -> CutCheck:
    """The cut resultant of ``sol`` (:func:`fem_check.recovery.cut_resultant`) with its
    equilibrium residual against the loads on the side ``normal . x >= offset``."""
    f_cut, m_cut, _ = cut_resultant(sol, normal, offset, about, stress)
    f_ref, m_ref = loads_on_side(block, load, normal, offset, about)

    def ests(cut, ref):
        return tuple(
            Estimate(float(c), {"equilibrium residual": abs(float(c) - float(r))})
            for c, r in zip(cut, ref, strict=True)
        )

    return CutCheck(ests(f_cut, f_ref), ests(m_cut, m_ref), f_ref, m_ref)
