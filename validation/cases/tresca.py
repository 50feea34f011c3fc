"""Seed 003: Tresca friction in jammed 2D packings and RT0 stress reconstruction.

``tresca-verification``: edge forces of the LP (seed 003 Eq. 16) on the verification meshes
(Sec. 4.3), the brick-wall shear test (Sec. 4.4) and the 60-cell homogeneous compression
(Sec. 4.5). ``tresca-reconstruction``: the RT0 stress of Sec. 3 on the same scenes; it also
writes ``validation/results/tresca_fields.npz`` for ``paper_figures/fig_tresca.py``.

Stresses are in [Pa] with the paper's unit data: imposed stress -1 Pa, Tresca threshold 10 Pa
(brick wall: 1 Pa); the model is positively homogeneous, so only ratios matter.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from dem.estimate import Estimate
from fem_check.rt_reconstruction import reconstruct_stress
from limit.tresca import (
    TrescaSettings,
    admissibility_residuals,
    cell_loads,
    facet_tractions,
    forces_from_uniform_stress,
    max_load_multiplier,
    solve_tresca,
)
from limit.voronoi_packing import (
    brick_wall_packing,
    uniform_stress_traction,
    verification_packing,
    voronoi_packing,
)
from validation.cases import tresca_bars as tb
from validation.cases.bars import EPS, diagnostic, per_unit, residual
from validation.report import Row, output_dir

PRESSURE = 1.0  # imposed compression [Pa] (seed 003 Sec. 4.3, 4.5: sigma = -I on the boundary)
S_VERIF = 10.0  # Tresca threshold of the compression tests [Pa]
S_WALL = 1.0  # Tresca threshold of the brick wall [Pa]
TAU_WALL = 0.5  # imposed shear of the brick wall [Pa]
WALL = {"n_courses": 6, "bricks_per_course": 4, "brick_length": 0.2, "brick_height": 0.1}
HOM_SEED = 136985  # seed of numpy.random.default_rng (the paper's seed, another generator)
HOM_CELLS = 60
FIELDS_NPZ = "tresca_fields.npz"
SRC_CLOSED = "closed form"

_VARIANTS = (
    ("CLARABEL", "solver"),  # interior point like the paper's cvxopt
    ("HIGHS", "solver"),  # simplex vertex
    ("CLARABEL", "min_energy"),  # our selection rule
)


def _settings(solver: str, selection: str, **extra) -> dict:
    return {"solver": solver, "selection": selection, **extra}


def _wall_sigma() -> np.ndarray:
    return np.array([[-PRESSURE, TAU_WALL], [TAU_WALL, -PRESSURE]])


def _hom_packing(n_cells: int = HOM_CELLS):
    return voronoi_packing(n_cells, 1.0, 1.0, seed=HOM_SEED)


def _solve(packing, sigma_bc, s, solver, selection):
    traction = uniform_stress_traction(packing, sigma_bc)
    res = solve_tresca(packing, traction, s, tb.solve_settings(solver, selection))
    return traction, res


def _certificate_rows(tag: str, packing, res, settings: dict) -> list[Row]:
    """The certificate of a solve as residuals, each with the tolerance it was solved to."""
    tresca_settings = tb.solve_settings(res.solver, res.selection)
    imbalance = tb.imbalance_tolerance(res, tresca_settings)
    gap = tb.gap_tolerance(packing, res, tresca_settings)
    return [
        Row(
            f"{tag}: cell force imbalance / max cell load [-]",
            residual(res.equilibrium_residual, imbalance, "solver tolerance"),
            0.0,
            SRC_CLOSED,
            res.wall_s,
            settings,
        ),
        Row(
            f"{tag}: duality gap [J/m]",
            residual(res.duality_gap, gap, "solver tolerance"),
            0.0,
            SRC_CLOSED,
            res.wall_s,
            settings,
        ),
    ]


def _stress_estimate(value: float, bar: np.ndarray | None, unit: float = 1.0, span=None):
    """``value`` [unit] of a max over absolute edge stresses whose bars are ``bar`` [Pa] (a max
    moves by at most the largest bar). A solver's own dual has no bar but may have ``span``
    ``(low, high)`` [unit], the least and largest values the admissible set allows
    (:func:`validation.cases.tresca_bars.range_bar`); without either, the bare value."""
    if bar is not None:
        return Estimate(value, {"solver tolerance": float(np.max(bar)) / unit})
    return _span_estimate(value, span)


def _span_estimate(value: float, span):
    """``value`` with the bar that holds ``span = (low, high)``, the values the admissible
    forces allow; the bare value without a span."""
    if span is None:
        return value
    notes = "the LP's admissible forces are not unique: the model gives [low, high]"
    return Estimate(value, tb.range_bar(value, *span), notes=notes)


def _bed_joint_rows(packing, res, settings: dict) -> list[Row]:
    """Equilibrium of the wall above each bed joint: vertical force p W, horizontal tau W."""
    width = WALL["bricks_per_course"] * WALL["brick_length"]
    n = packing.edge_normal
    force_on_b = (
        res.normal_force[:, None] * n + res.tangential_force[:, None] * packing.edge_tangent
    )
    rows = []
    for k in range(1, WALL["n_courses"]):
        y = k * WALL["brick_height"]
        on = (np.abs(n[:, 1]) > 0.5) & np.isclose(packing.edge_midpoint[:, 1], y)
        force_on_upper = np.sign(n[on, 1])[:, None] * force_on_b[on]
        total = force_on_upper.sum(axis=0)
        bar = {"equilibrium": tb.resultant_bar(packing, res, packing.centres[:, 1] > y) / width}
        rows += [
            Row(
                f"brick wall bed joint {k}: mean compressive traction [Pa]",
                Estimate(total[1] / width, bar),
                PRESSURE,
                "closed form (equilibrium of the wall above)",
                res.wall_s,
                settings,
            ),
            Row(
                f"brick wall bed joint {k}: mean shear traction [Pa]",
                Estimate(-total[0] / width, bar),
                TAU_WALL,
                "closed form (equilibrium of the wall above)",
                res.wall_s,
                settings,
            ),
        ]
    return rows


VERIFICATION_NOTES = (
    "Seed 003 (Tresca friction in jammed packings). Imposed stress -1 Pa on the boundary, "
    f"Tresca threshold {S_VERIF} Pa (brick wall {S_WALL} Pa, shear {TAU_WALL} Pa). "
    "The LP dual has a zero objective, so every admissible force set is optimal "
    "(seed 003 Remark 4, Sec. 4.5). Variants: CLARABEL/solver (interior-point duals, as "
    "the paper's cvxopt), HIGHS/solver (simplex vertex), CLARABEL/min_energy (our rule: "
    "least sum d_e (lambda^2 + f_t^2) / |e|, which returns the uniform stress on any "
    "Voronoi packing under a uniform load). The five-cell mesh is our reading of seed 003 "
    "Fig. 7a (quarter points plus centre; its Delaunay graph has one self-stress, so the "
    "raw duals are not unique even without friction). The 60-cell seeds come from "
    f"numpy.random.default_rng({HOM_SEED}), not the paper's generator, so the mesh differs "
    "from seed 003 Fig. 10; the paper gives no numbers for it, only that the solver's "
    "stress is not homogeneous, exceeds the imposed value and has cells in tension. "
    f"Brick wall: running bond {WALL}, uniform stress [[-p, tau], [tau, -p]] on the boundary; "
    "the paper's wall geometry and loads are not in its text."
)


def run_verification(quick: bool) -> tuple[list[Row], str]:
    """Edge forces: verification meshes, brick-wall shear, 60-cell compression."""
    rows: list[Row] = []
    for name in ("four-cells", "five-cells"):
        rows += _verification_mesh_rows(name)
    wall = brick_wall_packing(**WALL)
    rows += _brick_wall_rows(wall)
    rows += _brick_wall_capacity_rows(wall)
    rows += _homogeneous_rows(_hom_packing())
    if not quick:
        for n_cells in (250, 1000):
            rows += _large_packing_rows(n_cells)
    return rows, VERIFICATION_NOTES


def _verification_mesh_rows(name: str) -> list[Row]:
    """Seed 003 Sec. 4.3: sigma_nn = -p on every internal edge of a verification mesh."""
    packing = verification_packing(name)
    traction = uniform_stress_traction(packing, -PRESSURE * np.eye(2))
    normal = tb.admissible_range(packing, traction, S_VERIF, "normal")
    span = None if normal is None else (0.0, float(np.max(np.abs(normal + PRESSURE))))
    rows: list[Row] = []
    for solver, selection in _VARIANTS:
        _, res = _solve(packing, -PRESSURE * np.eye(2), S_VERIF, solver, selection)
        st = _settings(solver, selection, s_pa=S_VERIF, mesh=name)
        tag = f"{name} [{solver}/{selection}]"
        bar = tb.stress_bar(packing, res, tb.solve_settings(solver, selection))
        if (solver, selection) == ("CLARABEL", "min_energy"):
            rows += [
                Row(
                    f"{tag} edge {e} normal stress [Pa]",
                    Estimate(float(value), {"solver tolerance": float(bar[e])}),
                    -PRESSURE,
                    "closed form (seed 003 Sec. 4.3)",
                    res.wall_s,
                    st,
                )
                for e, value in enumerate(res.normal_stress)
            ]
        rows.append(
            Row(
                f"{tag}: max_e |sigma_nn + p| [Pa]",
                _stress_estimate(
                    float(np.max(np.abs(res.normal_stress + PRESSURE))), bar, span=span
                ),
                0.0,
                "closed form (seed 003 Sec. 4.3)",
                res.wall_s,
                st,
            )
        )
        rows += _certificate_rows(tag, packing, res, st)
    return rows


def _brick_wall_rows(wall) -> list[Row]:
    """Seed 003 Sec. 4.4: the brick wall under shear; bed joints balance the wall above."""
    rows: list[Row] = []
    shear = tb.admissible_range(wall, uniform_stress_traction(wall, _wall_sigma()), S_WALL, "shear")
    span = None if shear is None else (0.0, float(np.max(np.abs(shear))) / S_WALL)
    for solver, selection in _VARIANTS[::2]:
        _, res = _solve(wall, _wall_sigma(), S_WALL, solver, selection)
        st = _settings(solver, selection, s_pa=S_WALL, tau_pa=TAU_WALL, **WALL)
        if selection == "solver":
            rows += _bed_joint_rows(wall, res, st)
        bar = tb.stress_bar(wall, res, tb.solve_settings(solver, selection))
        rows.append(
            Row(
                f"brick wall [{solver}/{selection}]: max |shear| / s [-]",
                _stress_estimate(
                    float(np.max(np.abs(res.shear_stress))) / S_WALL, bar, S_WALL, span
                ),
                None,
                "bounded by 1 (Tresca)",
                res.wall_s,
                st,
            )
        )
        rows += _certificate_rows(f"brick wall [{solver}/{selection}]", wall, res, st)
    return rows


def _brick_wall_capacity_rows(wall) -> list[Row]:
    """Shear capacity of the brick wall under the imposed compression: the full-width bed joint
    slides at tau = s."""
    rows: list[Row] = []
    for solver in ("HIGHS", "CLARABEL"):
        mult = max_load_multiplier(
            wall,
            uniform_stress_traction(wall, -PRESSURE * np.eye(2)),
            uniform_stress_traction(wall, [[0.0, 1.0], [1.0, 0.0]]),
            S_WALL,
            TrescaSettings(solver=solver),
        )
        rows.append(
            Row(
                "brick wall: shear capacity tau_max / s [-]",
                per_unit(mult.load_multiplier_estimate, S_WALL),
                1.0,
                "closed form (full-width bed joint)",
                mult.wall_s,
                _settings(solver, "load multiplier", s_pa=S_WALL, **WALL),
            )
        )
    return rows


def _homogeneous_rows(hom) -> list[Row]:
    """Seed 003 Sec. 4.5: 60 cells under homogeneous compression. The uniform stress -p I is
    admissible; the solvers' duals need not be it, the min-energy rule returns it."""
    sigma_c = -PRESSURE * np.eye(2)
    traction = uniform_stress_traction(hom, sigma_c)
    lam_u, ft_u = forces_from_uniform_stress(hom, sigma_c)
    start = time.perf_counter()
    eq_u, fr_u = admissibility_residuals(hom, traction, S_VERIF, lam_u, ft_u)
    eq_bar = tb.uniform_round_off(hom, traction, lam_u, ft_u)
    # the friction/sign violation compares |f_t| with s|e|: one rounding of the larger
    fr_bar = (
        float(np.max(S_VERIF * hom.edge_length))
        * 2
        * EPS
        / np.max(np.linalg.norm(cell_loads(hom, traction), axis=1))
    )
    st0 = {"n_cells": HOM_CELLS, "seed": HOM_SEED, "s_pa": S_VERIF}
    src_uniform = "seed 003 Sec. 4.5 (-I is admissible)"
    rows = [
        Row(
            "60 cells: uniform sigma=-I forces, cell imbalance [-]",
            residual(eq_u, eq_bar, "round-off"),
            0.0,
            src_uniform,
            time.perf_counter() - start,
            st0,
        ),
        Row(
            "60 cells: uniform sigma=-I forces, Tresca/sign violation [-]",
            residual(max(fr_u, 0.0), fr_bar, "round-off"),
            0.0,
            src_uniform,
            None,
            st0,
        ),
    ]
    spans = _hom_spans(hom, traction)
    for solver, selection in _VARIANTS:
        _, res = _solve(hom, sigma_c, S_VERIF, solver, selection)
        st = _settings(solver, selection, **st0)
        tag = f"60 cells [{solver}/{selection}]"
        homog = selection == "min_energy"
        bar = tb.stress_bar(hom, res, tb.solve_settings(solver, selection))
        threshold = 1e-9 * PRESSURE * hom.edge_length
        dev, peak, count = spans
        rows += [
            Row(
                f"{tag}: max_e |sigma_nn + p| [Pa]",
                _stress_estimate(
                    float(np.max(np.abs(res.normal_stress + PRESSURE))), bar, 1.0, dev
                ),
                0.0 if homog else None,
                SRC_CLOSED if homog else "seed 003 Sec. 4.5: not homogeneous",
                res.wall_s,
                st,
            ),
            Row(
                f"{tag}: max_e |sigma_nn| / p [-]",
                _stress_estimate(float(np.max(-res.normal_stress)) / PRESSURE, bar, PRESSURE, peak),
                1.0 if homog else None,
                SRC_CLOSED if homog else "seed 003 Sec. 4.5: exceeds 1 (concentration)",
                res.wall_s,
                st,
            ),
            Row(
                f"{tag}: open contacts (lambda < 1e-9 p|e|) [-]",
                _count_estimate(res.normal_force, threshold, bar, hom.edge_length, count),
                None,
                "",
                res.wall_s,
                st,
            ),
        ]
        rows += _certificate_rows(tag, hom, res, st)
    return rows


def _count_estimate(forces, threshold, bar, edge_length, span=None):
    """The number of ``forces < threshold`` [N/m], with the number whose bar (stress ``bar``
    [Pa] times ``edge_length`` [m]) straddles the threshold as its half-width; without a bar,
    the bar that holds ``span`` (the counts the admissible forces allow), if given."""
    count = float(np.sum(forces < threshold))
    if bar is None:
        return _span_estimate(count, span)
    return Estimate(count, {"solver tolerance": tb.count_bar(forces, threshold, bar * edge_length)})


def _hom_spans(hom, traction):
    """What the admissible forces of the 60-cell packing allow (seed 003 Remark 4), from each
    edge's normal-stress range (:func:`validation.cases.tresca_bars.admissible_range`):
    ``(low, high)`` of max_e |sigma_nn + p| [Pa], of max_e |sigma_nn| / p [-] (the max over
    edges lies between the largest of their least values and the largest of their largest),
    and of the number of open contacts (between the edges that cannot close and those that
    can open). None each above the range's size limit."""
    normal = tb.admissible_range(hom, traction, S_VERIF, "normal")
    if normal is None:
        return None, None, None
    lam = -normal[::-1] * hom.edge_length  # least and largest lambda [N/m], shape (2, n_e)
    threshold = 1e-9 * PRESSURE * hom.edge_length
    return (
        (0.0, float(np.max(np.abs(normal + PRESSURE)))),
        (float(np.max(-normal[1])) / PRESSURE, float(np.max(-normal[0])) / PRESSURE),
        (float(np.sum(lam[1] < threshold)), float(np.sum(lam[0] < threshold))),
    )


def _large_packing_rows(n_cells: int) -> list[Row]:
    """Certificates (and the min-energy rule's uniform stress) on a larger random packing."""
    big = _hom_packing(n_cells)
    rows: list[Row] = []
    for solver, selection in _VARIANTS:
        _, res = _solve(big, -PRESSURE * np.eye(2), S_VERIF, solver, selection)
        st = _settings(
            solver, selection, n_cells=n_cells, n_edges=big.n_edges, seed=HOM_SEED, s_pa=S_VERIF
        )
        tag = f"{n_cells} cells [{solver}/{selection}]"
        if selection == "min_energy":
            bar = tb.stress_bar(big, res, tb.solve_settings(solver, selection))
            rows.append(
                Row(
                    f"{tag}: max_e |sigma_nn + p| [Pa]",
                    _stress_estimate(float(np.max(np.abs(res.normal_stress + PRESSURE))), bar),
                    0.0,
                    SRC_CLOSED,
                    res.wall_s,
                    st,
                )
            )
        rows += _certificate_rows(tag, big, res, st)
    return rows


def _facet_normals(packing) -> np.ndarray:
    nxt = np.empty_like(packing.cell_xy)
    for c in range(packing.n_cells):
        rows = slice(packing.cell_ptr[c], packing.cell_ptr[c + 1])
        nxt[rows] = np.roll(packing.cell_xy[rows], -1, axis=0)
    d = nxt - packing.cell_xy
    return np.stack([d[:, 1], -d[:, 0]], axis=1) / np.linalg.norm(d, axis=1)[:, None]


def _traction_continuity(packing, rec) -> float:
    """Max |sigma_a n + sigma_b (-n)| at internal facet midpoints [Pa] (RT0 conformity)."""
    normals = _facet_normals(packing)
    mid = 0.5 * (rec.sigma_vertex[:, 1] + rec.sigma_vertex[:, 2])  # facet is vertices 1-2
    trac = np.einsum("fij,fj->fi", mid, normals)
    internal = packing.facet_edge >= 0
    total = np.zeros((packing.n_edges, 2))
    np.add.at(total, packing.facet_edge[internal], trac[internal])
    return float(np.max(np.linalg.norm(total, axis=1)))


def _stress_jump(packing, rec) -> float:
    """Max |sigma_a - sigma_b| (2-norm) at internal facet midpoints [Pa]."""
    mid = 0.5 * (rec.sigma_vertex[:, 1] + rec.sigma_vertex[:, 2])
    internal = np.nonzero(packing.facet_edge >= 0)[0]
    order = internal[np.argsort(packing.facet_edge[internal], kind="stable")]
    # every internal edge has exactly one facet in each of its two cells
    pairs = order.reshape(-1, 2)
    return float(np.max(np.linalg.norm(mid[pairs[:, 0]] - mid[pairs[:, 1]], ord=2, axis=(1, 2))))


_PAPER = {
    "tension": "seed 003 Sec. 4.5: several cells in tension",
    "concentration": "seed 003 Sec. 4.5: |sigma| exceeds the imposed value",
    "skew": "seed 003 Sec. 4.4: not completely symmetric",
    "jump": "seed 003 Sec. 4.4: discontinuous across interfaces",
}


@dataclasses.dataclass(frozen=True)
class TrescaScene:
    """A packing under a uniform boundary stress ``sigma_bc`` (2, 2) [Pa] with Tresca
    threshold ``s`` [Pa]; ``label`` names it in rows, ``settings`` go into them."""

    label: str
    packing: object
    sigma_bc: np.ndarray
    s: float
    settings: dict


def tresca_scenes() -> dict[str, TrescaScene]:
    """The scenes of seed 003 Secs. 4.3-4.5: verification meshes, brick wall, 60 cells."""
    sigma_c = -PRESSURE * np.eye(2)
    scenes = {
        name: TrescaScene(name, verification_packing(name), sigma_c, S_VERIF, {"mesh": name})
        for name in ("four-cells", "five-cells")
    }
    scenes["brick-wall"] = TrescaScene(
        "brick wall",
        brick_wall_packing(**WALL),
        _wall_sigma(),
        S_WALL,
        {"tau_pa": TAU_WALL, **WALL},
    )
    scenes["hom60"] = TrescaScene(
        "60 cells", _hom_packing(), sigma_c, S_VERIF, {"n_cells": HOM_CELLS, "seed": HOM_SEED}
    )
    return scenes


@dataclasses.dataclass(frozen=True)
class RtCase:
    """One reconstruction: the forces of ``solver``/``selection`` on ``scene``, stored in the
    fields file under ``key``.

    ``exact_source`` names the source of the exact stress -p I when it is known (else None);
    ``paper`` lists the ``_PAPER`` observations the case's rows are compared with;
    ``cell_rows`` adds the mean stress of every cell."""

    key: str
    scene: str
    solver: str
    selection: str
    exact_source: str | None = None
    paper: tuple[str, ...] = ()
    cell_rows: bool = False


RT_CASES = (
    *(
        case
        for name in ("four-cells", "five-cells")
        for case in (
            RtCase(name, name, "CLARABEL", "min_energy", SRC_CLOSED, cell_rows=True),
            # the paper's solver returned sigma = -I on both meshes (seed 003 Figs. 6b, 7b)
            RtCase(f"{name}-raw", name, "CLARABEL", "solver", "seed 003 Sec. 4.3 (sigma = -I)"),
        )
    ),
    RtCase("brick-wall", "brick-wall", "CLARABEL", "solver", paper=("skew", "jump")),
    RtCase("brick-wall-min-energy", "brick-wall", "CLARABEL", "min_energy", paper=("skew", "jump")),
    RtCase("hom60", "hom60", "CLARABEL", "solver", paper=("tension", "concentration")),
    RtCase("hom60-highs", "hom60", "HIGHS", "solver", paper=("tension", "concentration")),
    RtCase("hom60-min-energy", "hom60", "CLARABEL", "min_energy", SRC_CLOSED),
)

RECONSTRUCTION_NOTES = (
    "Row-wise RT0 on each cell triangulated from its centre (Voronoi seed; brick centroid), "
    "boundary fluxes from the LP edge forces and the Neumann data, least-squares "
    "divergence with weak symmetry by a P0 multiplier (seed 003 Eq. 15), one batched "
    "dense KKT solve per polygon size. Since the Tresca cells are only in force balance, "
    "the moment M_c of a cell's tractions is generally non-zero; with exact weak symmetry "
    "Green's identity forces int_c (x-C) x div sigma = M_c, so div sigma cannot vanish "
    "(the Green-identity row checks this to round-off). "
    "Raw-dual rows of the verification meshes use the paper's result (sigma = -I, seed "
    "003 Figs. 6b, 7b) as reference: our interior-point duals reach it on four cells "
    "(~2e-10) but only to ~8e-5 on five cells, whose contact graph has a self-stress "
    "(the paper's solver choice among admissible forces is not reproducible); the "
    "min-energy rows reach it to round-off. "
    f"Fields for the figures: {FIELDS_NPZ}."
)


def _rt_rows(tag: str, scene: TrescaScene, case: RtCase, traction, res, st: dict, ranges):
    """Checks of the RT0 stress reconstructed from one force set: rows and the fields
    stored for the figures. ``ranges`` are the scene's admissible ``(normal, shear)`` stress
    ranges (:func:`_admissible_ranges`), which bound a solver's own dual."""
    packing = scene.packing
    ft = facet_tractions(packing, res, traction)
    rec = reconstruct_stress(packing.cell_ptr, packing.cell_xy, packing.centres, ft)
    scale = float(np.max(np.abs(traction)))
    exact = case.exact_source is not None

    def ref(name: str, exact_value: float):
        if exact:
            return exact_value, case.exact_source
        return None, _PAPER.get(name, "") if name in case.paper else ""

    widths = tb.stress_bar(packing, res, tb.solve_settings(res.solver, res.selection))
    source = "round-off and force bars"
    if widths is None and ranges is not None:
        widths, source = tb.dual_widths(res, *ranges), "round-off and admissible range"
    bars = _RtCheckBars(packing, rec, scale, widths)
    rows = [
        Row(
            f"{tag}: {quantity}",
            _checked(value, reference[0], bar, source),
            *reference,
            rec.wall_s,
            st,
        )
        for quantity, value, reference, bar in _rt_checks(packing, rec, scale, ref, bars)
    ]
    if exact:
        err = np.abs(rec.sigma_vertex - scene.sigma_bc).max(axis=(1, 2, 3))
        rows.append(
            Row(
                f"{tag}: max |sigma - sigma_exact| over all vertices [Pa]",
                _checked(float(err.max()), 0.0, bars.of("vertex"), source),
                0.0,
                case.exact_source,
                rec.wall_s,
                st,
            )
        )
    fields = {
        "cell_ptr": packing.cell_ptr,
        "cell_xy": packing.cell_xy,
        "edge_xy": packing.edge_xy,
        "normal_force": res.normal_force,
        "edge_length": packing.edge_length,
        "centres": packing.centres,
        "tri_xy": rec.tri_xy,
        "tri_cell": rec.tri_cell,
        "sigma_mean": rec.sigma_mean,
        "sigma_vertex": rec.sigma_vertex,
        "cell_stress": rec.cell_stress,
    }
    return rows, fields, bars


class _RtCheckBars:
    """The bar of each check of an RT0 reconstruction, in the check's unit: round-off
    (:func:`validation.cases.tresca_bars.rt_round_off`) for the checks that vanish for any
    forces; for the others, the round-off plus what the force bars ``widths`` [Pa] move them
    by (:func:`validation.cases.tresca_bars.rt_bars`): the min-energy forces' certified bars,
    or for a solver's own dual the widths of the admissible ranges around it
    (:func:`validation.cases.tresca_bars.dual_widths`); None without widths."""

    def __init__(self, packing, rec, scale: float, widths: np.ndarray | None):
        self.round_off = tb.rt_round_off(rec)
        self.scale = scale
        self.area = float(rec.tri_area.sum())
        self.cell_area = np.bincount(rec.tri_cell, weights=rec.tri_area)
        self.sens = None if widths is None else tb.rt_bars(packing, widths)
        self.tri_area = rec.tri_area

    def of(self, name: str) -> float | None:
        """The bar of check ``name`` (the keys of :meth:`_force_dependent`)."""
        fixed = {
            "continuity": self.round_off,
            "weak symmetry": self.round_off / self.scale,
            "green": self.round_off * float(self.cell_area.max()),
        }
        if name in fixed:
            return fixed[name]
        if self.sens is None:
            return None
        return self._force_dependent()[name]

    def _force_dependent(self) -> dict[str, float]:
        b, p, r = self.sens, self.scale, self.round_off
        skew = b.sigma_vertex[..., 0, 1] + b.sigma_vertex[..., 1, 0]  # (n_tri, 3)
        mid = 0.5 * (b.sigma_vertex[:, 1] + b.sigma_vertex[:, 2])
        frob = np.linalg.norm(b.sigma_vertex, axis=(-2, -1))
        l2 = np.sqrt(self.area)
        return {
            "vertex": float(b.sigma_vertex.max()) + r,
            "div": float(np.sqrt(np.sum(self.tri_area * np.sum(b.div**2, axis=1)))) / (p * l2),
            "skew L2": float(np.sqrt(np.sum(self.tri_area * skew.max(axis=1) ** 2))) / (p * l2),
            "skew": (float(skew.max()) + 2 * r) / p,
            "jump": (2 * float(np.linalg.norm(mid, axis=(-2, -1)).max()) + 2 * r) / p,
            "moment": float(b.traction_moment.max()) * len(self.cell_area) / (p * self.area),
            "norm": (float(frob.max()) + 2 * r) / p,
        }

    def cells(self) -> np.ndarray | None:
        """Bound [Pa] on each cell's mean stress, shape (n_cells, 2, 2), or None."""
        return None if self.sens is None else self.sens.cell_stress + self.round_off


def _checked(value: float, reference: float | None, bar: float | None, source: str):
    """A check with its ``bar`` (:class:`_RtCheckBars`) named ``source``; without one, against
    0 a discrepancy with no bar of its own, else the bare value."""
    if bar is not None:
        return residual(value, bar, source)
    return diagnostic(value) if reference == 0.0 else value


def _rt_checks(packing, rec, scale: float, ref, bars: _RtCheckBars) -> list[tuple]:
    """(quantity, value, (reference, source), bar) of each check of an RT0 reconstruction;
    ``scale`` is the largest imposed traction p [Pa], ``ref(name, exact)`` the reference of a
    check that the paper observed or that holds for the exact stress."""
    d = rec.tri_xy.mean(axis=1) - rec.tri_xy[:, 0]
    first = rec.tri_area * (d[:, 0] * rec.div[:, 1] - d[:, 1] * rec.div[:, 0])
    identity = np.abs(np.bincount(rec.tri_cell, weights=first) - rec.traction_moment)
    sym = 0.5 * (rec.cell_stress + np.transpose(rec.cell_stress, (0, 2, 1)))
    principal = np.linalg.eigvalsh(sym)
    skew_pt = np.abs(rec.sigma_vertex[..., 0, 1] - rec.sigma_vertex[..., 1, 0])
    area = rec.tri_area.sum()
    sigma_norm = np.linalg.norm(rec.sigma_vertex, ord=2, axis=(-2, -1))
    return [
        (
            "traction continuity max |sigma_a n_a + sigma_b n_b| [Pa]",
            _traction_continuity(packing, rec),
            (0.0, "closed form (RT0 conformity, Remark 5)"),
            bars.of("continuity"),
        ),
        (
            "weak symmetry max_T |int_T (s_xy - s_yx)| / (|T| p) [-]",
            float(rec.weak_symmetry_residual.max()) / (scale * area / len(rec.tri_area)),
            (0.0, SRC_CLOSED),
            bars.of("weak symmetry"),
        ),
        (
            "||div sigma||_L2 / (p sqrt|Omega|) [1/m]",
            float(np.sqrt(np.sum(rec.div_norm**2))) / (scale * np.sqrt(area)),
            ref("div", 0.0),
            bars.of("div"),
        ),
        (
            "||s_xy - s_yx||_L2 / (p |Omega|^0.5) [-]",
            float(np.sqrt(np.sum(rec.skew_norm**2))) / (scale * np.sqrt(area)),
            ref("skew", 0.0),
            bars.of("skew L2"),
        ),
        (
            "max pointwise |s_xy - s_yx| / p [-]",
            float(skew_pt.max()) / scale,
            ref("skew", 0.0),
            bars.of("skew"),
        ),
        (
            "max stress jump across internal edges / p [-]",
            _stress_jump(packing, rec) / scale,
            ref("jump", 0.0),
            bars.of("jump"),
        ),
        (
            "max_c |M_c - int_c (x-C) x div sigma| [N m/m]",
            float(identity.max()),
            (0.0, "closed form (Green identity)"),
            bars.of("green"),
        ),
        (
            "max_c |traction moment M_c| / (p |Omega|/n_c) [-]",
            float(np.abs(rec.traction_moment).max()) / (scale * area / packing.n_cells),
            ref("moment", 0.0),
            bars.of("moment"),
        ),
        (
            "cells in tension (max principal of mean stress > 1e-9 p) [-]",
            float(np.sum(principal[:, 1] > 1e-9 * scale)),
            ref("tension", 0.0),
            _tension_count_bar(principal[:, 1], 1e-9 * scale, bars.cells()),
        ),
        (
            "max |sigma| (2-norm, vertices) / p [-]",
            float(sigma_norm.max()) / scale,
            ref("concentration", 1.0),
            bars.of("norm"),
        ),  # fmt: skip
    ]


def _tension_count_bar(principal, threshold: float, cell_bars) -> float | None:
    """Cells whose largest principal mean stress [Pa] is within its bound (the Frobenius norm
    of the cell's bar bounds an eigenvalue's shift) of ``threshold``; None without bars."""
    if cell_bars is None:
        return None
    return tb.count_bar(principal, threshold, np.linalg.norm(cell_bars, axis=(-2, -1)))


def run_reconstruction(quick: bool) -> tuple[list[Row], str]:
    """RT0 stresses (seed 003 Sec. 3) on the verification meshes, brick wall and 60 cells."""
    rows: list[Row] = []
    npz: dict[str, np.ndarray] = {}
    scenes = tresca_scenes()
    ranges: dict[str, tuple | None] = {}
    for case in RT_CASES:
        scene = scenes[case.scene]
        traction, res = _solve(scene.packing, scene.sigma_bc, scene.s, case.solver, case.selection)
        st = _settings(case.solver, case.selection, s_pa=scene.s, **scene.settings)
        tag = f"{scene.label} [{case.solver}/{case.selection}]"
        if case.selection == "solver" and case.scene not in ranges:
            ranges[case.scene] = _admissible_ranges(scene, traction)
        scene_ranges = ranges.get(case.scene)
        new_rows, fields, bars = _rt_rows(tag, scene, case, traction, res, st, scene_ranges)
        rows += new_rows
        npz.update({f"{case.key}__{name}": np.asarray(v) for name, v in fields.items()})
        if case.cell_rows:
            rows += _cell_stress_rows(scene.label, fields["cell_stress"], bars.cells())
    if not quick:
        for n_cells in (250, 1000):
            rows.append(_rt_timing_row(n_cells))
    fields_path = output_dir() / FIELDS_NPZ
    fields_path.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(fields_path, **npz)
    return rows, RECONSTRUCTION_NOTES


def _admissible_ranges(scene: TrescaScene, traction) -> tuple | None:
    """The admissible ``(normal, shear)`` stress ranges [Pa] of ``scene``'s edges, each shape
    (2, n_edges) (:func:`validation.cases.tresca_bars.admissible_range`), or None above its
    size limit."""
    normal = tb.admissible_range(scene.packing, traction, scene.s, "normal")
    shear = tb.admissible_range(scene.packing, traction, scene.s, "shear")
    return None if normal is None or shear is None else (normal, shear)


def _cell_stress_rows(name: str, cell_stress: np.ndarray, cell_bars) -> list[Row]:
    """The uniform stress -p I in every cell of a verification mesh (seed 003 Figs. 6b, 7b),
    with the bounds ``cell_bars`` [Pa] (n_cells, 2, 2) of the min-energy forces' bars."""
    return [
        Row(
            f"{name} cell {c}: mean sigma_{axis} [Pa]",
            Estimate(float(cell_sigma[k, k]), {"force bars": float(cell_bars[c, k, k])}),
            -PRESSURE,
            "closed form (seed 003 Sec. 4.3)",
            None,
            {"mesh": name},
        )
        for c, cell_sigma in enumerate(cell_stress)
        for k, axis in ((0, "xx"), (1, "yy"))
    ]


def _rt_timing_row(n_cells: int) -> Row:
    """Wall time of the batched RT0 reconstruction on a larger random packing."""
    big = _hom_packing(n_cells)
    traction, res = _solve(big, -PRESSURE * np.eye(2), S_VERIF, "CLARABEL", "solver")
    start = time.perf_counter()
    rec = reconstruct_stress(
        big.cell_ptr, big.cell_xy, big.centres, facet_tractions(big, res, traction)
    )
    return Row(
        f"{n_cells} cells: RT0 batched wall time [s]",
        time.perf_counter() - start,
        None,
        "",
        rec.wall_s,
        {"n_cells": n_cells, "n_triangles": len(rec.tri_area)},
        cost=True,
    )


CASES = {"tresca-verification": run_verification, "tresca-reconstruction": run_reconstruction}
