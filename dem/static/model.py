r"""The assembled static model of one scene: unknowns, kinematics, loads, law, stiffness.

- unknowns: the 6 dofs ``(ux, uy, uz, rx, ry, rz)`` of every free block about its centroid;
  fixed blocks and restrained dofs are eliminated, not penalised;
- kinematics: ``q = H U`` from the actual interface and block centroids (seed 001 Eq. (3) and
  (A1)-(A3) are the running-bond special case), one dense 6 x 12 block per interface
  (:mod:`dem.kernels.stiffness`);
- internal forces ``H^T f(q)`` and tangent ``K = H^T D H`` from the interface law object
  (:mod:`dem.static.laws`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from dem.kernels.stiffness import (
    block_forces,
    local_compatibility,
    relative_motion,
    stiffness_triplets,
    stiffness_values,
)
from dem.scene import DOFS, Scene
from dem.static.laws import InterfaceLaw, JointArrays, LawResponse, build_law
from dem.static.result import StaticSolverError
from dem.static.settings import StaticSettings


@dataclass(eq=False)
class Evaluation:
    """The law's response to the total dofs, and the internal forces on the unknowns.

    Attributes
    ----------
    law : LawResponse
        Actions ``f`` (m, 6), tangents ``D`` (m, 6, 6), states (m,), plastic trial state.
    internal : (n_free,) float
        ``H^T f`` on the unknowns [N, N m].
    """

    law: LawResponse
    internal: np.ndarray


def joint_arrays(scene: Scene, settings: StaticSettings) -> JointArrays:
    """Geometry and strengths of the scene's joints under ``settings``."""
    itf = scene.assembly.interfaces()
    m = itf.n_interfaces
    a, b = itf.block_a, itf.block_b
    if settings.mu is not None:
        mu = np.full(m, float(settings.mu))
    elif scene.assembly.mu is not None:
        mu = np.minimum(scene.assembly.mu[a], scene.assembly.mu[b])
    else:
        raise ValueError("no friction coefficient: set StaticSettings.mu or Assembly.mu")
    rigid = np.flatnonzero(~np.isfinite(mu))
    if rigid.size:
        pairs = ", ".join(f"{k} (blocks {a[k]}-{b[k]})" for k in rigid[:10])
        raise ValueError(
            f"the static DEM needs a finite friction coefficient; mu = inf (no sliding) at "
            f"interfaces {pairs}{' ...' if rigid.size > 10 else ''}. The limit analysis and the "
            "explicit DEM take mu = inf; here set StaticSettings(mu=...) or a large finite "
            "Assembly.mu (sliding then needs that many times the normal force)"
        )
    tensile = np.full(m, settings.tensile_strength)
    cohesion = mu * tensile if settings.cohesion is None else np.full(m, settings.cohesion)
    if not settings.tension_at_supports:
        at_support = scene.supports.fixed[a] | scene.supports.fixed[b]
        tensile[at_support] = 0.0
        cohesion = np.where(at_support, 0.0, cohesion)
    dims = np.zeros((m, 2))
    for i in range(m):
        poly = itf.local_polygon(i)
        dims[i] = poly.max(0) - poly.min(0)
    f_c = settings.compressive_strength
    return JointArrays(
        area=itf.area,
        second_moments=itf.second_moments[:, :2],
        dims=dims,
        mu=np.ascontiguousarray(mu, dtype=np.float64),
        tensile=tensile,
        cohesion=np.ascontiguousarray(cohesion, dtype=np.float64),
        compressive=np.inf if f_c is None else float(f_c),
        kn=settings.kn,
        kt=settings.kt,
        kr=settings.kn if settings.kr is None else settings.kr,
        extent=model_extent(scene),
    )


def model_extent(scene: Scene) -> float:
    """Largest side of the scene's bounding box [m]."""
    return float(np.ptp(scene.assembly.arrays.vertices, axis=0).max())


def check_supported(scene: Scene) -> None:
    """Every block must reach a support through interfaces, else K is singular."""
    itf = scene.assembly.interfaces()
    n = scene.n_blocks
    graph = sp.coo_matrix((np.ones(itf.n_interfaces), (itf.block_a, itf.block_b)), shape=(n, n))
    n_comp, label = sp.csgraph.connected_components(graph, directed=False)
    held = scene.supports.fixed | scene.supports.restrained.any(axis=1)
    for comp in range(n_comp):
        members = np.flatnonzero(label == comp)
        if not held[members].any():
            raise StaticSolverError(
                f"blocks {members[:10].tolist()}{' ...' if len(members) > 10 else ''} "
                "reach no support through their interfaces: the stiffness is singular "
                "(a mechanism before any load). Fix a block or add a foundation.",
                blocks=members,
            )


class Model:
    """Arrays of one scene for the kernels, its loads, and its interface law.

    Attributes
    ----------
    law : InterfaceLaw
        Holds the committed plastic state.
    n_free : int
        Unknowns.
    dof_index : (n_blocks, 6) int64
        Unknown of each block dof, -1 where eliminated.
    F_dead, F_live : (n_free,) float
        Dead load and live pattern on the unknowns [N, N m].
    w : (n_free,) float
        Control weights ``F_L / S`` with ``S`` the sum of the live forces' magnitudes [N]
        (of the live moments over the model's extent for a live load of moments only):
        ``c = w . u`` is the live load's work per unit ``S``, a mean displacement [m].
    lambda_scale : float
        Total dead force over ``S`` (1 without dead load).
    """

    def __init__(self, scene: Scene, settings: StaticSettings):
        itf = scene.assembly.interfaces()
        if itf.n_interfaces == 0:
            raise ValueError("the scene has no interfaces: every block is isolated")
        itf.warn_edge_contacts()
        free = scene.supports.free_dofs
        if not free.any():
            raise ValueError("the scene has no free dof: every block is fixed or restrained")
        check_supported(scene)
        self.scene, self.settings = scene, settings
        self.itf, self.m = itf, itf.n_interfaces
        self.n_blocks = scene.n_blocks
        self.free_mask = free
        self.n_free = int(free.sum())
        self.dof_index = np.full((self.n_blocks, 6), -1, dtype=np.int64)
        self.dof_index[free] = np.arange(self.n_free)
        self.a = np.ascontiguousarray(itf.block_a, dtype=np.int64)
        self.b = np.ascontiguousarray(itf.block_b, dtype=np.int64)
        self.B = local_compatibility(
            self.a,
            self.b,
            np.ascontiguousarray(itf.centroid, dtype=np.float64),
            np.ascontiguousarray(scene.assembly.centroid, dtype=np.float64),
            np.ascontiguousarray(itf.frame, dtype=np.float64),
        )
        joints = joint_arrays(scene, settings)
        self.law: InterfaceLaw = build_law(settings.law_settings, joints, itf)
        self._set_loads(scene)
        self._patterns: dict = {}

    def _set_loads(self, scene: Scene) -> None:
        free = self.free_mask
        self.F_dead = scene.dead_wrench[free]
        self.F_live = scene.loads.live_wrench[free]
        is_force = np.broadcast_to(np.arange(6) < 3, (self.n_blocks, 6))[free]
        live_size = np.abs(self.F_live[is_force]).sum()
        if live_size == 0:
            # a live load of moments only (torques): each moment counts as a force at the
            # model's extent, so that c = w . u is still a length
            live_size = np.abs(self.F_live[~is_force]).sum() / model_extent(scene)
        if live_size == 0:
            raise ValueError("the live load is zero on every free dof: nothing to scale")
        dead_force = np.abs(self.F_dead[is_force]).sum()
        self.lambda_scale = dead_force / live_size if dead_force > 0 else 1.0
        self.w = self.F_live / live_size
        self.dead_norm = float(np.linalg.norm(self.F_dead))
        self.live_norm = float(np.linalg.norm(self.F_live))

    def evaluate(self, u: np.ndarray, floor: float) -> Evaluation:
        """The law at the free dofs ``u`` (n_free,) [m, rad], tangent floor ``floor``."""
        q = np.empty((self.m, 6))
        relative_motion(self.B, self.a, self.b, self.full(u), q)
        response = self.law.evaluate(q, floor)
        F = np.empty((self.n_blocks, 6))
        block_forces(self.B, self.a, self.b, response.f, F)
        return Evaluation(response, F[self.free_mask])

    def _pattern(self, nz_w: np.ndarray | None):
        """CSC structure of K (or of the bordered matrix whose last row is nonzero at
        ``nz_w``) and the slot of every triplet: the triplets of ``H^T D H`` keep their order
        between iterations, so each assembly adds the values into their slots of a
        structure built once (:func:`dem.kernels.stiffness.stiffness_values`)."""
        key = None if nz_w is None else nz_w.tobytes()
        if key in self._patterns:
            return self._patterns[key]
        n = self.n_free
        rows, cols, _ = stiffness_triplets(
            self.B, np.ones((self.m, 6, 6)), self.a, self.b, self.dof_index
        )
        size, extra_rows, extra_cols = n, np.zeros(0, np.int64), np.zeros(0, np.int64)
        if nz_w is not None:
            size = n + 1
            nz_f = np.flatnonzero(self.F_live)
            extra_rows = np.concatenate([nz_f, np.full(len(nz_w), n)])
            extra_cols = np.concatenate([np.full(len(nz_f), n), nz_w])
        keys, inverse = np.unique(
            np.concatenate([cols, extra_cols]) * size + np.concatenate([rows, extra_rows]),
            return_inverse=True,
        )
        indices = (keys % size).astype(np.int32)
        indptr = np.searchsorted(keys // size, np.arange(size + 1)).astype(np.int32)
        if len(self._patterns) > 4:  # the path-direction control may change the pattern
            self._patterns.pop(next(k for k in self._patterns if k is not None), None)
        self._patterns[key] = (size, indices, indptr, inverse, len(rows), len(keys))
        return self._patterns[key]

    def stiffness(self, D: np.ndarray, w: np.ndarray | None = None) -> sp.csc_matrix:
        """``K = H^T D H`` on the unknowns, or the bordered ``[[K, -F_L], [w^T, 0]]``."""
        nz_w = None if w is None else np.flatnonzero(w)
        size, indices, indptr, inverse, n_trip, nnz = self._pattern(nz_w)
        data = np.zeros(nnz)
        stiffness_values(self.B, D, self.a, self.b, self.dof_index, inverse, data)
        if w is not None:  # the border's slots are distinct and apart from K's
            data[inverse[n_trip:]] = np.concatenate(
                [-self.F_live[np.flatnonzero(self.F_live)], w[nz_w]]
            )
        return sp.csc_matrix((data, indices, indptr), shape=(size, size))

    def full(self, u_free: np.ndarray) -> np.ndarray:
        """(n_blocks, 6) dofs from the unknowns (zero where eliminated)."""
        U = np.zeros((self.n_blocks, 6))
        U[self.free_mask] = u_free
        return U

    def block_of_dof(self, i: int) -> tuple[int, str]:
        """Block and dof name of unknown ``i``."""
        blk, dof = np.argwhere(self.dof_index == i)[0]
        return int(blk), DOFS[int(dof)]
