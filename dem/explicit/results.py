"""Results of explicit runs: the indentation curve and its summary, interface resultants and the
nodal state exported for FEM post-processing."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from dem.estimate import Estimate
    from dem.explicit.model import ExplicitModel

PEAK_DROP_FRACTION = 0.85
"""The peak of a P-delta curve counts as reached once the load has fallen after it to this
fraction of it (the validation's studies of the peak load stop there)."""


@dataclass
class IndentationResult:
    """P-delta curve, summary numbers, poses and interface forces of an indentation run.

    See the module docstring for the definitions. Arrays over records have length ``k``.

    Attributes
    ----------
    delta, load : (k,) float
        Indenter travel [m] and load [N].
    time : (k,) float
        [s] since the start of indentation.
    kinetic, elastic, work : (k,) float
        Kinetic energy, normal penalty energy and indenter work [J].
    block_pos, block_quat : (k, n_blocks, 3), (k, n_blocks, 4) float
        Poses of all blocks at every record.
    peak_load, deflection_at_peak, ultimate_deflection, loading_energy, energy_to_peak : float
        [N], [m], [m], [J], [J].
    peak_reached : bool
        The load fell after ``peak_load`` (see :mod:`dem.explicit.indentation`); if False,
        ``peak_load`` is the largest load so far, a lower bound of the peak.
    snapshots : list of dict
        ``delta`` [m], ``pairs`` (p, 2) int, ``force`` (p, 3) [N] resultant on the first block
        of each pair, ``point`` (p, 3) [m] its point (force-weighted mean of nodal points).
    peak_state : dict
        Nodal forces at the peak record (see :func:`export_peak_state`).
    info : dict
        dt, omega_max, nodes, entries, steps, wall times, cost per node per step, settings;
        ``stopped_by``: why the run stopped before its end (empty if it did not);
        ``indenter_overlap_max`` [m]: the deepest overlap of the tip with a block at the
        records (see :meth:`dem.explicit.ExplicitModel.check_indenter`);
        ``delta_first_contact`` [m]: the first recorded travel with a positive load (NaN if
        none; see :mod:`dem.explicit.indentation`).
    estimates : dict
        ``"peak_load"``, ``"deflection_at_peak"``, ``"loading_energy"``,
        ``"ultimate_deflection"`` -> :class:`~dem.estimate.Estimate` of that number (SI) with
        its error bar (:mod:`dem.explicit.indentation_error`; unknown bars under the error
        budget ``"none"``).
    """

    delta: np.ndarray
    load: np.ndarray
    time: np.ndarray
    kinetic: np.ndarray
    elastic: np.ndarray
    work: np.ndarray
    block_pos: np.ndarray
    block_quat: np.ndarray
    peak_load: float
    deflection_at_peak: float
    ultimate_deflection: float
    loading_energy: float
    energy_to_peak: float
    peak_reached: bool
    snapshots: list = field(default_factory=list)
    peak_state: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)
    estimates: dict = field(default_factory=dict)


@dataclass(frozen=True)
class PairForces:
    """Resultant contact force of each pair of blocks in contact at one state.

    Attributes
    ----------
    pairs : (p, 2) int64
        ``(i, j)`` with ``i < j``.
    force : (p, 3) float
        Resultant force on block ``i`` from block ``j`` [N].
    point : (p, 3) float
        Force-weighted mean of the nodal points [m].
    gap : (p,) float
        Separation of the two blocks in the reference configuration along their face
        normals [m] (0 when they touch).
    interface : (p,) bool
        The two blocks share a face interface in the reference configuration (what the
        static DEM and the limit analysis model).
    """

    pairs: np.ndarray
    force: np.ndarray
    point: np.ndarray
    gap: np.ndarray
    interface: np.ndarray

    def ranked(self) -> np.ndarray:
        """Indices of the pairs: those without a face interface first, then by force."""
        magnitude = np.linalg.norm(self.force, axis=1)
        return np.lexsort((-magnitude, self.interface))

    def describe(self, limit: int = 5) -> str:
        """The first ``limit`` pairs of :meth:`ranked` in words, e.g. ``blocks 2-4 (no face
        interface, gap 0 mm, 141 N)``."""
        parts = []
        for k in self.ranked()[:limit]:
            i, j = self.pairs[k]
            kind = "face interface" if self.interface[k] else "no face interface"
            parts.append(
                f"blocks {i}-{j} ({kind}, gap {self.gap[k] * 1e3:.3g} mm, "
                f"{np.linalg.norm(self.force[k]):.3g} N)"
            )
        more = len(self.pairs) - limit
        return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")


@dataclass(frozen=True, eq=False)
class LateralResult:
    """Outcome of :func:`dem.explicit.simulate_lateral`.

    Attributes
    ----------
    collapsed : bool
        A moving step was found below the driver's ``max_lambda``.
    lambda_stable : float
        Last multiplier at which every block came to rest (tilting: ``tan theta``).
    lambda_moving : float
        First multiplier at which a block kept moving; NaN if none.
    moving_blocks : (k,) int64
        Blocks moving at ``lambda_moving`` once the motion was followed (displaced more than
        ``displacement_tol`` or faster than ``speed_tol``).
    mechanism_confirmed : bool
        The motion at ``lambda_moving`` grew to several displacement thresholds when followed,
        or it jumped far past the elastic response and stopped (``arrested``). False: a slow
        motion that may still stop; ``lambda_moving`` is then an upper end found by speed
        alone.
    arrested : bool
        The mechanism formed at ``lambda_moving`` and stopped after a finite motion (blocks
        bearing on each other after finite rotations, e.g. columns side by side): the collapse
        of the rigid-block methods, in small displacements; the structure may carry more with
        its deformed geometry.
    contacts_at_rest : PairForces or None
        The pairs of blocks in contact at the last state at rest (``lambda_stable``), with
        their forces, reference gaps and whether they share a face interface
        (:func:`dem.explicit.diagnosis.pair_forces`).
    estimate : Estimate or None
        The collapse multiplier at the material stiffness with its error (the bracket, and
        what the error budget measured: loading rate, time step, node spacing); None without
        a collapse.
    rigid : Estimate or None
        Its continuation to rigid joints (:func:`dem.explicit.continuation.rigid_limit`).
    levels : list of dict
        The runs of the continuation, the material stiffness first.
    record_lambda : (r,) float
        Multiplier at the end of each ramp-and-hold step, in the order run (bisection trials
        included).
    record_displacement : (r,) float
        Largest displacement of any block since the start of loading, at those ends [m].
    record_time : (r,) float
        Model time [s] (a bisection trial restarts from the time of the last stable step).
    record_stable : (r,) bool
        Whether that step ended at rest.
    detection_lambda : float
        Largest overshoot of the bracket above the true threshold that the motion criteria
        allow, ``2 displacement_tol / ((1 - c) g T^2)`` with ``c`` the local damping and ``T``
        the longest hold (see :mod:`dem.explicit.lateral`).
    speed_tol, displacement_tol : float
        The motion thresholds [m/s], [m].
    wall_s : float
    settings, driver : dict
        The solver settings and the driver, for the record.
    info : dict
        ``dt``, ``omega_max``, ``n_nodes``, relaxation, steps, hold and ramp times.
    """

    collapsed: bool
    lambda_stable: float
    lambda_moving: float
    moving_blocks: np.ndarray
    mechanism_confirmed: bool
    record_lambda: np.ndarray
    record_displacement: np.ndarray
    record_time: np.ndarray
    record_stable: np.ndarray
    detection_lambda: float
    speed_tol: float
    displacement_tol: float
    wall_s: float
    settings: dict
    driver: dict
    info: dict = field(default_factory=dict)
    arrested: bool = False
    contacts_at_rest: PairForces | None = None
    estimate: Estimate | None = None
    rigid: Estimate | None = None
    levels: list = field(default_factory=list)


def curve_summary(
    delta: np.ndarray,
    load: np.ndarray,
    ultimate_fraction: float,
    out_confirm: float,
    peak_drop: float = PEAK_DROP_FRACTION,
) -> dict:
    """Peak load, deflection at peak, ultimate deflection and loading energy of a P-delta curve.

    Parameters
    ----------
    delta, load : (k,) float
        [m], [N], with ``delta`` increasing.
    ultimate_fraction, out_confirm : float
        See :class:`IndentationSettings`.
    peak_drop : float
        The peak is reached once the load has fallen after it to this fraction of it.

    Returns
    -------
    dict
        ``peak_load`` [N], ``deflection_at_peak`` [m], ``ultimate_deflection`` [m] (NaN if not
        reached), ``loading_energy`` [J], ``energy_to_peak`` [J], ``peak_reached`` (bool; False
        also when no load was positive).
    """
    delta = np.asarray(delta, dtype=float)
    load = np.asarray(load, dtype=float)
    if len(delta) == 0:
        nan = float("nan")
        return dict(peak_load=nan, deflection_at_peak=nan, ultimate_deflection=nan,
                    loading_energy=nan, energy_to_peak=nan, peak_reached=False)  # fmt: skip
    k_peak = int(np.argmax(load))
    p_max = float(load[k_peak])
    ultimate = float("nan")
    k_end = len(delta) - 1
    below = load <= ultimate_fraction * p_max
    for k in range(k_peak + 1, len(delta)):
        if not below[k]:
            continue
        rest = np.flatnonzero(~below[k:])
        end = delta[k + rest[0]] if len(rest) else delta[-1]
        if end - delta[k] >= out_confirm or (not len(rest) and end - delta[k] >= out_confirm):
            ultimate = float(delta[k])
            k_end = k
            break
    d0 = np.concatenate([[0.0], delta])
    p0 = np.concatenate([[load[0]], load])
    energy = float(np.trapezoid(p0[: k_end + 2], d0[: k_end + 2]))
    energy_peak = float(np.trapezoid(p0[: k_peak + 2], d0[: k_peak + 2]))
    reached = p_max > 0 and bool(np.any(load[k_peak + 1 :] <= peak_drop * p_max))
    return dict(peak_load=p_max, deflection_at_peak=float(delta[k_peak]),
                ultimate_deflection=ultimate, loading_energy=energy,
                energy_to_peak=energy_peak, peak_reached=reached)  # fmt: skip


def interface_resultants(
    pair_node: np.ndarray,
    pair_block: np.ndarray,
    node_block: np.ndarray,
    entry_force: np.ndarray,
    entry_point: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Resultant force between each pair of blocks in contact (for force chains).

    Returns
    -------
    pairs : (p, 2) int64
        ``(i, j)`` with ``i < j``.
    force : (p, 3) float
        Resultant force on block ``i`` from block ``j`` [N].
    point : (p, 3) float
        Force-magnitude-weighted mean of the nodal points [m].
    """
    a = node_block[pair_node]
    b = pair_block
    mag = np.linalg.norm(entry_force, axis=1)
    act = mag > 0
    if not np.any(act):
        return np.zeros((0, 2), dtype=np.int64), np.zeros((0, 3)), np.zeros((0, 3))
    a, b, f, p, mag = a[act], b[act], entry_force[act], entry_point[act], mag[act]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    f = np.where((a == lo)[:, None], f, -f)
    keys, inverse = np.unique(lo * (int(b.max()) + int(a.max()) + 2) + hi, return_inverse=True)
    force = np.zeros((len(keys), 3))
    np.add.at(force, inverse, f)
    wsum = np.zeros(len(keys))
    np.add.at(wsum, inverse, mag)
    point = np.zeros((len(keys), 3))
    np.add.at(point, inverse, p * mag[:, None])
    point /= wsum[:, None]
    pairs = np.zeros((len(keys), 2), dtype=np.int64)
    pairs[inverse, 0] = lo
    pairs[inverse, 1] = hi
    return pairs, force, point


def _to_reference(model: ExplicitModel, blocks: np.ndarray, points: np.ndarray) -> np.ndarray:
    """World points on given blocks mapped to the reference configuration [m]."""
    rot = model.rotations()
    rel = points - model.pos[blocks]
    return np.einsum("mji,mj->mi", rot[blocks], rel) + model.ref_centroid[blocks]


def export_peak_state(model: ExplicitModel, sphere: tuple) -> dict:
    """Every nodal force at the model's current state, on both sides, for FEM post-processing.

    Points are given in the reference configuration of their block (the frame of
    ``block_vertices``); vectors (forces, gravity, accelerations, angular velocities) in the
    world frame; ``quaternion`` maps each block's reference frame to the world,
    ``v_world = R v_ref`` (``fem_check.loads.read_point_state`` reads this layout).

    Returns
    -------
    dict
        ``block`` (k,) int64; ``point`` (k, 3) [m], reference configuration of that block;
        ``force`` (k, 3) [N] acting on that block at that point (each block-block node force
        appears twice, once per side, plus the indenter's nodal forces; support reactions are
        not included); ``gravity`` (3,) [m/s^2]; ``acceleration`` (n_blocks, 6) linear
        [m/s^2] and angular [rad/s^2] accelerations of the centroids and
        ``angular_velocity`` (n_blocks, 3) [rad/s], such that with the true mass and inertia
        (``density``), in each block's reference frame, ``sum R^T force + m R^T gravity =
        m R^T a`` and ``sum (point - C0) x R^T force = I alpha' + omega' x I omega'``
        (primes: ``R^T`` times the world vectors) for every free block (zero for fixed blocks;
        ``a`` includes what global damping and mass scaling add to the motion);
        ``quaternion`` (n_blocks, 4) scalar first; ``fixed`` (n_blocks,) bool; ``density``
        (n_blocks,) [kg/m^3]; ``block_vertices`` (n_vert, 3) [m] with ``vert_ptr``
        (n_blocks + 1,); ``centroid`` (n_blocks, 3) [m], reference centroids.
    """
    force, torque, ef, ep, ind = model.contact_wrenches(sphere)
    contacts = model.state.contacts
    a_blk = model.surface.block[contacts.node]
    act = np.linalg.norm(ef, axis=1) > 0
    blocks = np.concatenate([a_blk[act], contacts.block[act]])
    points = np.concatenate([ep[act], ep[act]])
    forces = np.concatenate([ef[act], -ef[act]])
    act_i = np.linalg.norm(ind, axis=1) > 0
    rot = model.rotations()
    if np.any(act_i):
        ib = model.indenter.block[act_i]
        ipts = model.pos[ib] + np.einsum("mij,mj->mi", rot[ib], model.indenter.r0[act_i])
        blocks = np.concatenate([blocks, ib])
        points = np.concatenate([points, ipts])
        forces = np.concatenate([forces, ind[act_i]])
    ref_points = _to_reference(model, blocks, points)
    asm = model.scene.assembly
    gravity = np.asarray(model.scene.loads.gravity, dtype=float)
    acc = np.zeros((model.n_blocks, 6))
    omega = np.zeros((model.n_blocks, 3))
    for i in model.free_blocks:
        r = rot[i]
        m = model.mass_true[i]
        acc[i, :3] = (force[i] + model.bodies.ext_force[i]) / m
        iw = r @ model.inertia_true[i] @ r.T
        w = model.omega[i]
        moment = torque[i] + model.bodies.ext_torque[i]
        acc[i, 3:] = np.linalg.solve(iw, moment - np.cross(w, iw @ w))
        omega[i] = w
    arrays = asm.arrays
    return {
        "block": blocks.astype(np.int64),
        "point": ref_points,
        "force": forces,
        "gravity": gravity,
        "acceleration": acc,
        "angular_velocity": omega,
        "quaternion": model.quat.copy(),
        "fixed": model.fixed.copy(),
        "density": asm.density.copy(),
        "block_vertices": arrays.vertices.copy(),
        "vert_ptr": arrays.vert_ptr.copy(),
        "centroid": model.ref_centroid.copy(),
    }
