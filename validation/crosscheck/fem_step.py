"""FEM step: elastic blocks loaded by the DEM collapse state (scikit-fem).

Each free block is loaded by the interface resultants of the static DEM at ``lambda_max``
(spread as the least traction with the same wrench over each interface polygon), its weight,
and the extra dead and ``lambda`` times live forces at its centroid (as uniform body forces).
Before solving, the imbalance of these loads is the block's equilibrium residual: a DEM state
in equilibrium makes it (nearly) zero. A block that gmsh cannot mesh (a sliver below its
tolerance) is listed in ``not_meshed`` with the reason, and fails the verdict. The stresses of
a statically determinate free block do not depend on Young's modulus, so ``young`` is a
placeholder.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from dem.scene import Scene
from fem_check.elastic import BlockSolver, ElasticMaterial
from fem_check.loads import (
    EQUILIBRIUM_REL_TOL,
    BlockLoad,
    EquilibriumError,
    InterfaceResultants,
    interface_block_loads,
    polygon_quadrature,
)
from fem_check.mesh import MeshingError, MeshSettings
from fem_check.recovery import recover_nodal_stress, summarise
from fem_check.stress_output import stress_field
from validation.crosscheck.steps import Context, StepResult

DEM_STEPS = ("dem-fibre", "dem-resultant")
EPS = float(np.finfo(float).eps)
OPS_PER_TERM = 64
"""A generous count of the floating-point operations that make one term of a block's load
resultant (a quadrature weight from the polygon's triangles, the traction's affine field at the
point, the lever arm's cross product, the sum)."""


def block_residual(load: BlockLoad, block) -> float:
    """Relative equilibrium residual [-] of a block's loads: the larger of the force
    imbalance over the load scale and the moment imbalance over the load scale times the block
    size (:meth:`fem_check.loads.BlockLoad.scale`)."""
    f, m = load.resultant(block)
    scale = load.scale(block)
    return float(max(np.linalg.norm(f) / scale, np.linalg.norm(m) / (scale * block.size)))


def residual_round_off(load: BlockLoad, block) -> float:
    r"""Bound [-] on the rounding of a block's relative equilibrium residual: Higham's
    :math:`\gamma_n \sum |x_i|` (*Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
    Sec. 4.2) with :math:`\sum |x_i|` at most the load scale the residual is divided by (lever
    arms at most the block size for the moment), ``n`` the terms (point forces, quadrature
    points of the traction patches, one per vertex for the body load) times
    :data:`OPS_PER_TERM`, times ``1 + |x|_max / size``: a lever arm is a difference of
    coordinates, rounded relative to the coordinates, not to the block. A residual above it is
    the DEM state's, not its computation's."""
    quad = sum(len(polygon_quadrature(p.polygon, 2)[1]) for p in load.patches)
    terms = len(load.forces) + quad + len(block.vertices)
    reach = 1.0 + float(np.abs(block.vertices).max()) / block.size
    return terms * OPS_PER_TERM * EPS * reach


def _state(ctx: Context) -> StepResult | None:
    """The DEM result to check: the first that collapsed, else the first that ran."""
    ran = [ctx.ok(name) for name in DEM_STEPS if ctx.ok(name) is not None]
    done = [r for r in ran if r.values.get("collapsed")]
    return (done or ran or [None])[0]


def _in_scene_order(result, interfaces) -> np.ndarray:
    """(m, 6) DEM interface forces at the peak, in the order of the scene's interfaces."""
    pairs = {
        (int(a), int(b)): k
        for k, (a, b) in enumerate(zip(result.block_a, result.block_b, strict=True))
    }
    order = []
    for k in range(interfaces.n_interfaces):
        key = (int(interfaces.block_a[k]), int(interfaces.block_b[k]))
        if key not in pairs:
            raise ValueError(f"interface {k} {key} is missing from the DEM state")
        order.append(pairs[key])
    return np.asarray(result.interface_forces)[order]


@dataclass(frozen=True)
class FemCheck:
    """Stresses and equilibrium residual of every free block at the DEM collapse state.

    Attributes
    ----------
    young, poisson : float
        Placeholder elasticity [Pa, -].
    mesh_fraction : float
        Tetrahedron size as a fraction of the median block size (bounding-box diagonal) [-].
    degree : int
        Displacement degree (1 or 2).
    rel_tol : float
        Largest accepted load imbalance of a block, relative to its load scale [-].
    """

    young: float = 10e9
    poisson: float = 0.2
    mesh_fraction: float = 0.25
    degree: int = 2
    rel_tol: float = EQUILIBRIUM_REL_TOL
    name: str = "fem"
    method: str = "FEM check of the DEM collapse state (scikit-fem)"

    def run(self, scene: Scene, ctx: Context) -> StepResult:
        state = _state(ctx)
        if state is None:
            return StepResult(self.name, self.method, "skipped", "no static DEM state to check")
        if not math.isfinite(state.values["lambda_max"]):
            why = (
                f"{state.name} ended by {state.values['termination']} at lambda = "
                f"{state.values['lambda_max']}: no DEM state at a finite load to check"
            )
            return StepResult(self.name, self.method, "skipped", why)
        res = state.payload
        a = scene.assembly
        itf = a.interfaces()
        forces = _in_scene_order(res, itf)
        # dem.static: N > 0 in tension, conjugate to the motion of b relative to a, so the
        # action of a on b is minus the stored resultants (fem_check.loads)
        loads = interface_block_loads(
            InterfaceResultants(itf, -forces), a.n_blocks, a.density, scene.loads.gravity
        )
        extra = scene.loads.dead_wrench + res.lambda_max * scene.loads.live_wrench
        h = self.mesh_fraction * float(np.median([b.size for b in a.blocks]))
        settings = {
            **dataclasses.asdict(self),
            "mesh_size": h,
            "state": state.name,
            "lambda": res.lambda_max,
        }
        solver = BlockSolver(
            ElasticMaterial(self.young, self.poisson),
            MeshSettings(size=h),
            self.degree,
            rel_tol=self.rel_tol,
        )
        rows, sols, ids, skipped = [], [], [], []
        restrained = scene.supports.restrained
        for i in scene.free_blocks:
            if np.any(extra[i, 3:] != 0) or np.any(restrained[i, 3:]):
                skipped.append(int(i))  # a concentrated moment has no body-force equivalent
                continue
            ld = dataclasses.replace(
                loads[i], gravity=scene.loads.gravity + extra[i, :3] / a.mass[i]
            )
            f, _ = ld.resultant(a.blocks[i])
            # a restrained translation's reaction acts at the centroid (the DEM dof)
            reaction = np.where(restrained[i, :3], -f, 0.0)
            ld = dataclasses.replace(ld, gravity=ld.gravity + reaction / a.mass[i])
            row = {
                "block": int(i),
                "residual": block_residual(ld, a.blocks[i]),
                "residual_round_off": residual_round_off(ld, a.blocks[i]),
                "load_scale_N": ld.scale(a.blocks[i]),
            }
            try:
                sol = solver.solve(a.blocks[i], ld, f"block {i}")
            except EquilibriumError:
                rows.append(row)  # out of equilibrium: reported, not solved
                continue
            except MeshingError as exc:
                rows.append({**row, "not_meshed": str(exc)})  # reported; the others go on
                continue
            nodal = recover_nodal_stress(sol)
            s = summarise(sol, nodal)
            row.update(
                max_principal=s.max_principal,
                min_principal=s.min_principal,
                max_von_mises=s.max_von_mises,
            )
            rows.append(row)
            sols.append((sol, nodal))
            ids.append(int(i))
        values = _summary(rows, skipped, self.rel_tol)
        field = stress_field([s for s, _ in sols], ids, [n for _, n in sols]) if sols else None
        reasons = [f"blocks {skipped} carry concentrated moments: not solved"] if skipped else []
        unmeshed = [r["not_meshed"] for r in rows if "not_meshed" in r]
        if unmeshed:
            reasons.append(f"blocks {values['not_meshed']} not meshed ({unmeshed[0]})")
        reason = "; ".join(reasons)
        return StepResult(self.name, self.method, "ok", reason, 0.0, settings, values, field)


def _summary(rows: list[dict], skipped: list[int], rel_tol: float) -> dict:
    solved = [r for r in rows if "max_principal" in r]
    worst_t = max(solved, key=lambda r: r["max_principal"], default=None)
    worst_c = min(solved, key=lambda r: r["min_principal"], default=None)
    worst_r = max(rows, key=lambda r: r["residual"], default=None)
    return {
        "max_residual": None if worst_r is None else worst_r["residual"],
        "max_residual_round_off": None if worst_r is None else worst_r["residual_round_off"],
        "residual_tolerance": rel_tol,
        "max_tension_Pa": None if worst_t is None else worst_t["max_principal"],
        "max_tension_block": None if worst_t is None else worst_t["block"],
        "max_compression_Pa": None if worst_c is None else worst_c["min_principal"],
        "max_compression_block": None if worst_c is None else worst_c["block"],
        "n_solved": len(solved),
        "not_in_equilibrium": [
            r["block"] for r in rows if "max_principal" not in r and "not_meshed" not in r
        ],
        "not_meshed": [r["block"] for r in rows if "not_meshed" in r],
        "skipped_blocks": skipped,
        "blocks": rows,
    }
