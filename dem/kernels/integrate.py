"""Explicit rigid-body time stepping with quaternions and global viscous damping.

One step (semi-implicit, symplectic Euler), for every *free* block (fixed blocks are never
integrated, their contact forces are the support reactions)::

    F = F_contact + F_ext - alpha m v           T = T_contact + T_ext - alpha I_w omega
    v += dt F / m,  c += dt v
    omega += dt I_w^{-1} (T - omega x I_w omega),   q = exp(dt omega / 2) * q

with ``I_w = R I_0 R^T`` the world inertia, ``alpha`` [1/s] the global (mass-proportional)
damping rate and ``omega`` the world-frame angular velocity. Restrained single dofs (world
axes) have their velocity component set to zero. Quaternions are ``(w, x, y, z)``, scalar first.
``m`` and ``I_0`` are the inertial (possibly mass-scaled) values; ``F_ext`` carries the true
weight, so mass scaling changes inertia only.
"""

import math

import numpy as np
from numba import njit

from dem.kernels.broadphase import needs_rebuild
from dem.kernels.contact_force import (
    accumulate_wrenches,
    node_contacts,
    node_contacts_parallel,
    sphere_contacts,
)

STATUS_DONE = 0
STATUS_REBUILD = 1
STATUS_NOT_FINITE = 2


@njit(cache=True)
def quat_to_rot_one(q, out):
    """Rotation matrix (3, 3) of a unit quaternion ``q`` (4,) ``(w, x, y, z)`` into ``out``."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    out[0, 0] = 1.0 - 2.0 * (y * y + z * z)
    out[0, 1] = 2.0 * (x * y - w * z)
    out[0, 2] = 2.0 * (x * z + w * y)
    out[1, 0] = 2.0 * (x * y + w * z)
    out[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    out[1, 2] = 2.0 * (y * z - w * x)
    out[2, 0] = 2.0 * (x * z - w * y)
    out[2, 1] = 2.0 * (y * z + w * x)
    out[2, 2] = 1.0 - 2.0 * (x * x + y * y)


@njit(cache=True)
def quat_to_rot(quat, out):
    """Batch :func:`quat_to_rot_one`: ``quat`` (n, 4) -> ``out`` (n, 3, 3)."""
    for i in range(quat.shape[0]):
        quat_to_rot_one(quat[i], out[i])


@njit(cache=True)
def rotate_quat_one(q, w0, w1, w2, dt):
    """``q <- exp(dt omega / 2) * q`` in place, renormalised (world-frame ``omega``)."""
    norm_w = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    half = 0.5 * norm_w * dt
    if norm_w > 0.0:
        s = math.sin(half) / norm_w
        d0, d1, d2, d3 = math.cos(half), w0 * s, w1 * s, w2 * s
    else:
        d0, d1, d2, d3 = 1.0, 0.0, 0.0, 0.0
    a0, a1, a2, a3 = q[0], q[1], q[2], q[3]
    q0 = d0 * a0 - d1 * a1 - d2 * a2 - d3 * a3
    q1 = d0 * a1 + d1 * a0 + d2 * a3 - d3 * a2
    q2 = d0 * a2 - d1 * a3 + d2 * a0 + d3 * a1
    q3 = d0 * a3 + d1 * a2 - d2 * a1 + d3 * a0
    n = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    q[0], q[1], q[2], q[3] = q0 / n, q1 / n, q2 / n, q3 / n


@njit(cache=True)
def advance_block_one(
    i, dt, alpha, inv_mass, inertia_ref, inertia_ref_inv, ext_force, ext_torque, restrained,
    pos, quat, vel, omega, rot, force, torque,
):  # fmt: skip
    """Advance one free block by one step (see the module docstring).

    Parameters
    ----------
    i : int
        Block index.
    dt, alpha : float
        Time step [s], global damping rate [1/s].
    inv_mass : (n_blocks,) float64
        Inverse inertial mass [1/kg].
    inertia_ref, inertia_ref_inv : (n_blocks, 3, 3) float64
        Inertia about the centroid in the reference frame and its inverse [kg m^2].
    ext_force, ext_torque : (n_blocks, 3) float64
        Weight plus dead loads [N], their moments [N m].
    restrained : (n_blocks, 6) bool
        Restrained world dofs ``(ux, uy, uz, rx, ry, rz)``.
    pos, quat, vel, omega : block state, updated in place.
    rot : (n_blocks, 3, 3) float64
        Rotation at the start of the step.
    force, torque : (n_blocks, 3) float64
        Contact force and moment of this step.
    """
    m = 1.0 / inv_mass[i]
    for k in range(3):
        f = force[i, k] + ext_force[i, k] - alpha * m * vel[i, k]
        vel[i, k] += dt * f * inv_mass[i]
        if restrained[i, k]:
            vel[i, k] = 0.0
        pos[i, k] += dt * vel[i, k]
    # body-frame angular velocity and moment: I_0 is constant there
    w_b = np.zeros(3)
    t_b = np.zeros(3)
    for k in range(3):
        for j in range(3):
            w_b[k] += rot[i, j, k] * omega[i, j]
            t_b[k] += rot[i, j, k] * (torque[i, j] + ext_torque[i, j])
    l_b = np.zeros(3)
    for k in range(3):
        for j in range(3):
            l_b[k] += inertia_ref[i, k, j] * w_b[j]
    rhs = np.zeros(3)
    rhs[0] = t_b[0] - alpha * l_b[0] - (w_b[1] * l_b[2] - w_b[2] * l_b[1])
    rhs[1] = t_b[1] - alpha * l_b[1] - (w_b[2] * l_b[0] - w_b[0] * l_b[2])
    rhs[2] = t_b[2] - alpha * l_b[2] - (w_b[0] * l_b[1] - w_b[1] * l_b[0])
    for k in range(3):
        wdot_b = 0.0
        for j in range(3):
            wdot_b += inertia_ref_inv[i, k, j] * rhs[j]
        w_b[k] += dt * wdot_b
    for k in range(3):
        omega[i, k] = rot[i, k, 0] * w_b[0] + rot[i, k, 1] * w_b[1] + rot[i, k, 2] * w_b[2]
        if restrained[i, 3 + k]:
            omega[i, k] = 0.0
    rotate_quat_one(quat[i], omega[i, 0], omega[i, 1], omega[i, 2], dt)


@njit(cache=True)
def run_steps(
    n_steps, dt, t, free_blocks, alpha, inv_mass, inertia_ref, inertia_ref_inv, ext_force,
    ext_torque, restrained, pos, quat, vel, omega, rot, force, torque,
    ref_centroid, face_ptr, face_normal, face_offset, radius,
    use_level_set, ls_origin, ls_spacing, ls_dims, ls_ptr, ls_values,
    node_block, node_r0, node_n0, node_area, pair_node, pair_block, pair_weight, pair_shear,
    out_force, out_point, out_depth, block_mu, mu_rule, compat_cos, edge_tol, k_n, k_t, beta,
    parallel,
    ind_active, ind_block, ind_r0, ind_area, ind_centre0, ind_t0, ind_radius, ind_velocity,
    k_ind, ind_force, pos_build, quat_build, margin, acc,
):  # fmt: skip
    """Run up to ``n_steps`` steps; stop early when the neighbour list must be rebuilt.

    Parameters
    ----------
    n_steps : int
    dt : float
        [s].
    t : float
        Time at the start [s].
    free_blocks : (n_free,) int64
        Blocks that are integrated.
    (block, contact and level-set arrays)
        See :func:`advance_block_one` and :func:`dem.kernels.contact_force.node_contact_one`.
    parallel : bool
        Evaluate contact entries with ``prange``.
    ind_active : bool
        The indenter sphere is present; its centre is
        ``ind_centre0 + ind_velocity (t - ind_t0)`` [m].
    ind_block, ind_r0, ind_area, ind_radius, k_ind, ind_force
        See :func:`dem.kernels.contact_force.sphere_contacts`.
    pos_build, quat_build : (n_blocks, 3), (n_blocks, 4) float64
        Poses when the neighbour list was built.
    margin : float
        Neighbour-list margin [m].
    acc : (3,) float64
        Out: ``acc[0]`` indenter load ``P`` of the last step [N], ``acc[1]`` += work done by the
        indenter [J], ``acc[2]`` largest ``P`` seen [N].

    Returns
    -------
    steps : int
        Steps done.
    status : int
        ``STATUS_DONE``, ``STATUS_REBUILD`` (list invalid: rebuild, then continue) or
        ``STATUS_NOT_FINITE`` (NaN or inf in the state: the run has blown up).
    t : float
        Time at the end [s].
    """
    centre = np.empty(3)
    for step in range(n_steps):
        quat_to_rot(quat, rot)
        force[:, :] = 0.0
        torque[:, :] = 0.0
        if parallel:
            node_contacts_parallel(
                pair_node, pair_block, pair_weight, pair_shear, node_block, node_r0, node_n0,
                node_area, pos, rot, vel, omega, ref_centroid, face_ptr, face_normal,
                face_offset, use_level_set, ls_origin, ls_spacing, ls_dims, ls_ptr, ls_values,
                block_mu, mu_rule, compat_cos, edge_tol, k_n, k_t, beta, dt, out_force, out_point,
                out_depth,
            )  # fmt: skip
        else:
            node_contacts(
                pair_node, pair_block, pair_weight, pair_shear, node_block, node_r0, node_n0,
                node_area, pos, rot, vel, omega, ref_centroid, face_ptr, face_normal,
                face_offset, use_level_set, ls_origin, ls_spacing, ls_dims, ls_ptr, ls_values,
                block_mu, mu_rule, compat_cos, edge_tol, k_n, k_t, beta, dt, out_force, out_point,
                out_depth,
            )  # fmt: skip
        accumulate_wrenches(pair_node, pair_block, node_block, pos, out_force, out_point,
                            force, torque)  # fmt: skip
        if ind_active:
            for k in range(3):
                centre[k] = ind_centre0[k] + ind_velocity[k] * (t - ind_t0)
            p = sphere_contacts(
                ind_block, ind_r0, ind_area, pos, rot, vel, omega, centre, ind_radius,
                ind_velocity, k_ind, beta, force, torque, ind_force,
            )  # fmt: skip
            acc[0] = p
            acc[1] += -p * ind_velocity[2] * dt
            if p > acc[2]:
                acc[2] = p
        finite = True
        for j in range(free_blocks.shape[0]):
            i = free_blocks[j]
            advance_block_one(
                i, dt, alpha, inv_mass, inertia_ref, inertia_ref_inv, ext_force, ext_torque,
                restrained, pos, quat, vel, omega, rot, force, torque,
            )  # fmt: skip
            for k in range(3):
                if not (math.isfinite(pos[i, k]) and math.isfinite(vel[i, k])):
                    finite = False
        t += dt
        if not finite:
            return step + 1, STATUS_NOT_FINITE, t
        if needs_rebuild(pos, quat, pos_build, quat_build, radius, margin):
            return step + 1, STATUS_REBUILD, t
    return n_steps, STATUS_DONE, t


@njit(cache=True)
def kinetic_energy(free_blocks, inv_mass, inertia_ref, quat, vel, omega, rot):
    """Translational plus rotational kinetic energy of the free blocks (inertial masses) [J]."""
    quat_to_rot(quat, rot)
    total = 0.0
    for j in range(free_blocks.shape[0]):
        i = free_blocks[j]
        m = 1.0 / inv_mass[i]
        total += 0.5 * m * (vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
        iw = rot[i] @ inertia_ref[i] @ rot[i].T
        w = omega[i]
        total += 0.5 * (w @ (iw @ w))
    return total
