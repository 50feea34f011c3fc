r"""Row-wise lowest-order Raviart-Thomas stress reconstruction in polygons (seed 003, Sec. 3).

Each convex cell is split into triangles :math:`T_k = (C, P_k, P_{k+1})` from its centre
:math:`C`. Each row :math:`\sigma_i` of the stress is an RT0 field on that triangulation; its
normal flux on the cell boundary is fixed by the tractions (edge forces of the Tresca dual and
the Neumann data), the fluxes through the spokes :math:`C P_j` are unknown. Seed 003, Eq. (15):

.. math::

    \min_{\sigma \in \Sigma_g} \tfrac12 \|\operatorname{div}\sigma\|_{L^2}^2
    \quad\text{s.t.}\quad \int_{T_k} (\sigma_{xy} - \sigma_{yx}) \,\mathrm{d}x = 0 \;\;\forall k,

i.e. the least-squares form :math:`a(\sigma, \tau) = (\operatorname{div}\sigma,
\operatorname{div}\tau)` plus a piecewise-constant Lagrange multiplier :math:`p` for the weak
symmetry :math:`b(\tau, p) = (\tau, p\,J)`, :math:`J` the unit skew matrix.

The cells are independent, so the local saddle-point systems (size :math:`3m` for an
:math:`m`-gon: :math:`2m` spoke fluxes and :math:`m` multipliers) are stacked by ``m`` and solved
with one batched ``numpy.linalg.solve``.

Why hand assembly rather than ``skfem.ElementTriRT0``: the problems hold a dozen unknowns each,
so building one skfem ``Basis`` per cell (mapping, quadrature, global facet orientation) would
cost far more than the solve and defeat batching; skfem also has no row-wise tensor RT element
(``ElementVector`` wraps scalar elements), and the essential flux data would need skfem's
facet-orientation signs. RT0 on a triangle is explicit: with outward edge fluxes
:math:`\Phi_e` and opposite vertices :math:`p_e`,
:math:`v(x) = \sum_e \Phi_e (x - p_e) / (2|T|)`, :math:`\operatorname{div} v = \sum_e \Phi_e/|T|`.

This module takes plain arrays; it imports nothing from ``limit`` or ``dem``.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class RTReconstruction:
    """Reconstructed stress, one RT0 field per row and per sub-triangle.

    ``n_tri`` sub-triangles in total (one per cell facet), ``n_cells`` cells. Triangle ``k`` of
    cell ``c`` is row ``cell_ptr[c] + k``, i.e. the facets' order.

    Attributes
    ----------
    tri_xy : ndarray, shape (n_tri, 3, 2)
        Vertices ``(C, P_k, P_{k+1})`` of every sub-triangle [m].
    tri_cell : ndarray of int64, shape (n_tri,)
        Cell of every sub-triangle.
    tri_area : ndarray, shape (n_tri,)
        [m^2].
    sigma_mean : ndarray, shape (n_tri, 2, 2)
        Mean stress over each sub-triangle [Pa]; ``sigma_mean[t, i]`` is row ``i``.
    sigma_vertex : ndarray, shape (n_tri, 3, 2, 2)
        Stress at the three vertices of each sub-triangle [Pa] (RT0 is linear per triangle).
    div : ndarray, shape (n_tri, 2)
        Row-wise divergence, constant per triangle [Pa/m].
    cell_stress : ndarray, shape (n_cells, 2, 2)
        Area-weighted mean stress of each cell [Pa].
    div_norm : ndarray, shape (n_cells,)
        :math:`\\|\\operatorname{div}\\sigma\\|_{L^2(c)}` [Pa].
    skew_norm : ndarray, shape (n_cells,)
        :math:`\\|\\sigma_{xy} - \\sigma_{yx}\\|_{L^2(c)}` [Pa m] (pointwise asymmetry).
    weak_symmetry_residual : ndarray, shape (n_cells,)
        :math:`\\max_k |\\int_{T_k}(\\sigma_{xy} - \\sigma_{yx})|` [Pa m^2]; zero up to round-off.
    traction_moment : ndarray, shape (n_cells,)
        Moment of the boundary tractions about the centre, :math:`\\int_{\\partial c} (x - C)
        \\times \\sigma n \\,\\mathrm{d}s` [N m/m]. Cells of the Tresca model are not in moment
        balance; a non-zero moment forces a non-zero divergence under exact weak symmetry.
    wall_s : float
        Wall time [s].
    """

    tri_xy: np.ndarray
    tri_cell: np.ndarray
    tri_area: np.ndarray
    sigma_mean: np.ndarray
    sigma_vertex: np.ndarray
    div: np.ndarray
    cell_stress: np.ndarray
    div_norm: np.ndarray
    skew_norm: np.ndarray
    weak_symmetry_residual: np.ndarray
    traction_moment: np.ndarray
    wall_s: float


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _solve_group(P: np.ndarray, C: np.ndarray, t: np.ndarray) -> dict[str, np.ndarray]:
    """Local problems of ``g`` cells with ``m`` facets each.

    Parameters
    ----------
    P : ndarray, shape (g, m, 2)
        Cell vertices, counter-clockwise [m].
    C : ndarray, shape (g, 2)
        Cell centres [m].
    t : ndarray, shape (g, m, 2)
        Traction on each facet [Pa].
    """
    Pn = np.roll(P, -1, axis=1)
    Cb = C[:, None, :]
    area = 0.5 * _cross(P - Cb, Pn - Cb)  # (g, m)
    if np.any(area <= 0.0):
        raise ValueError("every cell centre must lie strictly inside its cell")
    length = np.linalg.norm(Pn - P, axis=2)
    flux_b = t * length[..., None]  # (g, m, 2 rows): outward boundary flux per row
    F = _spoke_fluxes(P, Pn, Cb, area, flux_b)
    return _rt0_fields(P, Pn, Cb, area, flux_b, F)


def _spoke_fluxes(P, Pn, Cb, area, flux_b) -> np.ndarray:
    """Solve the stacked saddle-point systems (least-squares divergence, weak symmetry on
    every triangle) for the spoke fluxes ``F``, shape (g, m spokes, 2 rows) [N/m]; the
    arguments as in :func:`_solve_group`, ``area`` (g, m) [m^2], ``flux_b`` (g, m, 2) [N/m]."""
    g, m, _ = P.shape
    xT = (Cb + P + Pn) / 3.0
    a_b, a_s0, a_s1 = xT - Cb, xT - Pn, xT - P  # centroid minus the vertex opposite each edge

    # div on T_k, row i: (flux_b[k, i] - F_i[k] + F_i[k + 1]) / |T_k|
    G = -np.eye(m) + np.roll(np.eye(m), 1, axis=1)
    w = 1.0 / area
    H = np.einsum("km,gk,kn->gmn", G, w, G)  # per row
    h = np.einsum("km,gk,gki->gim", G, w, flux_b)  # (g, 2 rows, m)

    # weak symmetry on T_k: 0.5 * sum_e Phi_e,0 a_e[1] - Phi_e,1 a_e[0] = 0
    k = np.arange(m)
    kp = (k + 1) % m
    B = np.zeros((g, m, 2 * m))
    B[:, k, k] += -0.5 * a_s0[:, :, 1]
    B[:, k, kp] += 0.5 * a_s1[:, :, 1]
    B[:, k, m + k] += 0.5 * a_s0[:, :, 0]
    B[:, k, m + kp] += -0.5 * a_s1[:, :, 0]
    b0 = 0.5 * (flux_b[:, :, 0] * a_b[:, :, 1] - flux_b[:, :, 1] * a_b[:, :, 0])

    K = np.zeros((g, 3 * m, 3 * m))
    K[:, :m, :m] = H
    K[:, m : 2 * m, m : 2 * m] = H
    K[:, : 2 * m, 2 * m :] = np.transpose(B, (0, 2, 1))
    K[:, 2 * m :, : 2 * m] = B
    rhs = np.concatenate([-h[:, 0], -h[:, 1], -b0], axis=1)
    sol = np.linalg.solve(K, rhs[..., None])[..., 0]
    return np.stack([sol[:, :m], sol[:, m : 2 * m]], axis=2)


def _rt0_fields(P, Pn, Cb, area, flux_b, F) -> dict[str, np.ndarray]:
    """The RT0 stress of every triangle from its three outward fluxes (boundary ``flux_b``,
    spokes ``F``) and the per-cell norms: the dict that :func:`_solve_group` returns."""
    m = P.shape[1]
    kp = (np.arange(m) + 1) % m
    xT = (Cb + P + Pn) / 3.0
    # outward fluxes of T_k per row: boundary, spoke k (-F_k), spoke k+1 (+F_{k+1})
    phi_b, phi_s0, phi_s1 = flux_b, -F, F[:, kp]
    div = (phi_b + phi_s0 + phi_s1) / area[..., None]
    opp = (Cb + 0 * P, Pn, P)  # vertex opposite each of the three edges
    phis = (phi_b, phi_s0, phi_s1)
    two_area = 2.0 * area[..., None, None]
    mean = sum(phi[..., :, None] * (xT - p)[..., None, :] for phi, p in zip(phis, opp, strict=True))
    mean = mean / two_area  # (g, m, row, col)
    verts = (Cb + 0 * P, P, Pn)
    vertex = np.stack(
        [
            sum(phi[..., :, None] * (v - p)[..., None, :] for phi, p in zip(phis, opp, strict=True))
            / two_area
            for v in verts
        ],
        axis=2,
    )  # (g, m, 3, row, col)
    skew_v = vertex[..., 0, 1] - vertex[..., 1, 0]  # (g, m, 3)
    skew_l2 = area / 12.0 * (np.sum(skew_v**2, axis=2) + np.sum(skew_v, axis=2) ** 2)
    weak = area * (mean[..., 0, 1] - mean[..., 1, 0])
    mid = 0.5 * (P + Pn)
    moment = np.sum(_cross(mid - Cb, flux_b), axis=1)  # traction constant per facet
    return {
        "area": area,
        "mean": mean,
        "vertex": vertex,
        "div": div,
        "div_l2": np.sum(area * np.sum(div**2, axis=2), axis=1),
        "skew_l2": np.sum(skew_l2, axis=1),
        "weak": np.max(np.abs(weak), axis=1),
        "moment": moment,
        "tri": np.stack([Cb + 0 * P, P, Pn], axis=2),
    }


def reconstruct_stress(
    cell_ptr: np.ndarray,
    cell_xy: np.ndarray,
    centres: np.ndarray,
    facet_traction: np.ndarray,
) -> RTReconstruction:
    """Row-wise RT0 stress in every cell from the tractions on its facets (seed 003, Eq. 15).

    Parameters
    ----------
    cell_ptr : array_like of int, shape (n_cells + 1,)
        CSR offsets of the cells into ``cell_xy``.
    cell_xy : array_like, shape (n_facets, 2)
        Convex cell polygons, counter-clockwise, facet ``k`` from vertex ``k`` to ``k + 1`` [m].
    centres : array_like, shape (n_cells, 2)
        Triangulation centre of every cell, strictly inside it [m].
    facet_traction : array_like, shape (n_facets, 2)
        Traction :math:`\\sigma n` on each facet with the cell's outward normal [Pa].

    Returns
    -------
    RTReconstruction

    Raises
    ------
    ValueError
        Inconsistent shapes, non-finite data, or a centre outside its cell.
    """
    start = time.perf_counter()
    cell_ptr, cell_xy, centres, facet_traction = _checked_inputs(
        cell_ptr, cell_xy, centres, facet_traction
    )
    n_cells, n_facets = len(cell_ptr) - 1, int(cell_ptr[-1])
    sizes = np.diff(cell_ptr)
    out = _solve_by_size(cell_ptr, cell_xy, centres, facet_traction)
    area, mean = out["area"], out["mean"]
    tri_cell = np.repeat(np.arange(n_cells), sizes)
    cell_area = np.bincount(tri_cell, weights=area, minlength=n_cells)
    cell_stress = np.zeros((n_cells, 2, 2))
    np.add.at(cell_stress, tri_cell, mean * area[:, None, None])
    cell_stress /= cell_area[:, None, None]
    wall = time.perf_counter() - start
    logger.info("RT0 reconstruction: %d cells, %d triangles, %.3f s", n_cells, n_facets, wall)
    return RTReconstruction(
        tri_xy=out["tri"],
        tri_cell=tri_cell,
        tri_area=area,
        sigma_mean=mean,
        sigma_vertex=out["vertex"],
        div=out["div"],
        cell_stress=cell_stress,
        div_norm=np.sqrt(out["div_l2"]),
        skew_norm=np.sqrt(out["skew_l2"]),
        weak_symmetry_residual=out["weak"],
        traction_moment=out["moment"],
        wall_s=wall,
    )


def _checked_inputs(cell_ptr, cell_xy, centres, facet_traction):
    """The four inputs of :func:`reconstruct_stress` as int64 and contiguous float64 arrays;
    a ``ValueError`` names an inconsistent shape or non-finite data."""
    cell_ptr = np.asarray(cell_ptr, dtype=np.int64)
    cell_xy = np.ascontiguousarray(cell_xy, dtype=np.float64)
    centres = np.ascontiguousarray(centres, dtype=np.float64)
    facet_traction = np.ascontiguousarray(facet_traction, dtype=np.float64)
    if cell_ptr.ndim != 1 or len(cell_ptr) < 2 or cell_ptr[0] != 0 or np.any(np.diff(cell_ptr) < 3):
        raise ValueError("cell_ptr must be CSR offsets starting at 0 with >= 3 facets per cell")
    n_cells, n_facets = len(cell_ptr) - 1, int(cell_ptr[-1])
    if cell_xy.shape != (n_facets, 2):
        raise ValueError(f"cell_xy must have shape ({n_facets}, 2), got {cell_xy.shape}")
    if centres.shape != (n_cells, 2):
        raise ValueError(f"centres must have shape ({n_cells}, 2), got {centres.shape}")
    if facet_traction.shape != (n_facets, 2):
        raise ValueError(
            f"facet_traction must have shape ({n_facets}, 2), got {facet_traction.shape}"
        )
    for name, arr in (
        ("cell_xy", cell_xy),
        ("centres", centres),
        ("facet_traction", facet_traction),
    ):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite")
    return cell_ptr, cell_xy, centres, facet_traction


_PER_TRIANGLE = {"mean": (2, 2), "vertex": (3, 2, 2), "div": (2,), "area": (), "tri": (3, 2)}
"""Outputs of :func:`_solve_group` with one entry per sub-triangle, and their trailing shapes."""
_PER_CELL = ("div_l2", "skew_l2", "weak", "moment")
"""Outputs of :func:`_solve_group` with one entry per cell."""


def _solve_by_size(cell_ptr, cell_xy, centres, facet_traction) -> dict[str, np.ndarray]:
    """:func:`_solve_group` on the cells of each facet count, its outputs scattered back into
    arrays over all sub-triangles (``_PER_TRIANGLE``) or all cells (``_PER_CELL``)."""
    n_cells, n_facets = len(cell_ptr) - 1, int(cell_ptr[-1])
    out = {key: np.empty((n_facets, *shape)) for key, shape in _PER_TRIANGLE.items()}
    out.update({key: np.empty(n_cells) for key in _PER_CELL})
    sizes = np.diff(cell_ptr)
    for m in np.unique(sizes):
        cells = np.nonzero(sizes == m)[0]
        rows = cell_ptr[cells][:, None] + np.arange(m)  # (g, m) facet indices
        try:
            group = _solve_group(cell_xy[rows], centres[cells], facet_traction[rows])
        except ValueError as exc:
            raise ValueError(f"{exc} (cells with {m} facets: {cells.tolist()})") from exc
        for key in _PER_TRIANGLE:
            out[key][rows] = group[key]
        for key in _PER_CELL:
            out[key][cells] = group[key]
    return out
