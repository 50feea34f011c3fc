"""Explicit rigid-body time stepping with quaternions and global viscous damping.

One step (semi-implicit, symplectic Euler), for every *free* block (fixed blocks are never
integrated, their contact forces are the support reactions)::

    F = F_contact + F_ext - alpha m v           T = T_contact + T_ext - alpha I_w omega
    v += dt F / m,  c += dt v
    omega += dt I_w^{-1} (T - omega x I_w omega),   q = exp(dt omega / 2) * q

with ``I_w = R I_0 R^T`` the world inertia, ``alpha`` [1/s] the global (mass-proportional)
damping rate and ``omega`` the world-frame angular velocity. Optional local (non-viscous)
damping, as in Itasca's codes (Cundall 1987): each component of the unbalanced force and of
the body-frame moment ``F_k`` is reduced by ``local_damping |F_k| sign(v_k)``; it opposes
accelerations in the direction of motion and not steady motion, so it damps vibrations without
the drag of viscous damping (a mechanism still accelerates, at ``1 - local_damping`` of its
unbalanced force). Restrained single dofs (world
axes) have their velocity component set to zero. Quaternions are ``(w, x, y, z)``, scalar first.
``m`` and ``I_0`` are the inertial (possibly mass-scaled) values; ``F_ext`` carries the true
weight, so mass scaling changes inertia only.
"""

import math

import numpy as np
from numba import njit

from dem.kernels.broadphase import needs_rebuild
from dem.kernels.contact_force import (
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
def _sign(x):
    """-1, 0 or 1."""
    if x > 0.0:
        return 1.0
    if x < 0.0:
        return -1.0
    return 0.0


@njit(cache=True, inline="always")
def advance_block_one(i, dt, alpha, local_damping, bodies, motion, scratch):
    """Advance one free block by one step (see the module docstring).

    Parameters
    ----------
    i : int
        Block index.
    dt, alpha : float
        Time step [s], global damping rate [1/s].
    local_damping : float
        Local (non-viscous) damping coefficient in [0, 1), see the module docstring.
    bodies : Bodies
        ``inv_mass`` [1/kg], ``inertia_ref``, ``inertia_ref_inv`` (reference frame) [kg m^2],
        ``ext_force`` [N], ``ext_torque`` [N m] (weight plus other loads), ``restrained``
        world dofs ``(ux, uy, uz, rx, ry, rz)``; see :mod:`dem.explicit.state`.
    motion : Motion
        Block state, updated in place.
    scratch : Scratch
        ``rot`` at the start of the step; ``force``, ``torque``: contact force and moment.
    """
    inv_mass, inertia_ref, inertia_ref_inv = (
        bodies.inv_mass,
        bodies.inertia_ref,
        bodies.inertia_ref_inv,
    )
    ext_force, ext_torque, restrained = bodies.ext_force, bodies.ext_torque, bodies.restrained
    pos, quat, vel, omega = motion.pos, motion.quat, motion.vel, motion.omega
    rot, force, torque = scratch.rot, scratch.force, scratch.torque
    m = 1.0 / inv_mass[i]
    for k in range(3):
        f = force[i, k] + ext_force[i, k] - alpha * m * vel[i, k]
        if local_damping > 0.0:
            f -= local_damping * abs(f) * _sign(vel[i, k])
        vel[i, k] += dt * f * inv_mass[i]
        if restrained[i, k]:
            vel[i, k] = 0.0
        pos[i, k] += dt * vel[i, k]
    # body-frame angular velocity w, moment t and momentum l: I_0 is constant there
    w0 = rot[i, 0, 0] * omega[i, 0] + rot[i, 1, 0] * omega[i, 1] + rot[i, 2, 0] * omega[i, 2]
    w1 = rot[i, 0, 1] * omega[i, 0] + rot[i, 1, 1] * omega[i, 1] + rot[i, 2, 1] * omega[i, 2]
    w2 = rot[i, 0, 2] * omega[i, 0] + rot[i, 1, 2] * omega[i, 1] + rot[i, 2, 2] * omega[i, 2]
    m0 = torque[i, 0] + ext_torque[i, 0]
    m1 = torque[i, 1] + ext_torque[i, 1]
    m2 = torque[i, 2] + ext_torque[i, 2]
    t0 = rot[i, 0, 0] * m0 + rot[i, 1, 0] * m1 + rot[i, 2, 0] * m2
    t1 = rot[i, 0, 1] * m0 + rot[i, 1, 1] * m1 + rot[i, 2, 1] * m2
    t2 = rot[i, 0, 2] * m0 + rot[i, 1, 2] * m1 + rot[i, 2, 2] * m2
    inertia = inertia_ref[i]
    l0 = inertia[0, 0] * w0 + inertia[0, 1] * w1 + inertia[0, 2] * w2
    l1 = inertia[1, 0] * w0 + inertia[1, 1] * w1 + inertia[1, 2] * w2
    l2 = inertia[2, 0] * w0 + inertia[2, 1] * w1 + inertia[2, 2] * w2
    # Euler's equations, I w' = t - w x I w (the gyroscopic term), plus damping
    r0 = t0 - alpha * l0 - (w1 * l2 - w2 * l1)
    r1 = t1 - alpha * l1 - (w2 * l0 - w0 * l2)
    r2 = t2 - alpha * l2 - (w0 * l1 - w1 * l0)
    if local_damping > 0.0:
        r0 -= local_damping * abs(r0) * _sign(w0)
        r1 -= local_damping * abs(r1) * _sign(w1)
        r2 -= local_damping * abs(r2) * _sign(w2)
    inv = inertia_ref_inv[i]
    w0, w1, w2 = (
        w0 + dt * (inv[0, 0] * r0 + inv[0, 1] * r1 + inv[0, 2] * r2),
        w1 + dt * (inv[1, 0] * r0 + inv[1, 1] * r1 + inv[1, 2] * r2),
        w2 + dt * (inv[2, 0] * r0 + inv[2, 1] * r1 + inv[2, 2] * r2),
    )
    for k in range(3):
        omega[i, k] = rot[i, k, 0] * w0 + rot[i, k, 1] * w1 + rot[i, k, 2] * w2
        if restrained[i, 3 + k]:
            omega[i, k] = 0.0
    rotate_quat_one(quat[i], omega[i, 0], omega[i, 1], omega[i, 2], dt)


@njit(cache=True)
def run_steps(n_steps, t, settings, model, state, scratch, pairs, indenter, acc):
    """Run up to ``n_steps`` steps; stop early when the neighbour list must be rebuilt.

    Parameters
    ----------
    n_steps : int
    t : float
        Time at the start [s].
    settings : (float, float, float, bool)
        ``(dt, alpha, local_damping, parallel)``: time step [s], global damping rate [1/s],
        local damping coefficient (see the module docstring), and whether to evaluate the
        contact entries with ``prange``.
    model : (Nodes, Bodies, Shapes, Law)
        The model's constants (:mod:`dem.explicit.state`).
    state : (Contacts, Motion)
        The state, advanced in place.
    scratch : Scratch
        Work arrays.
    pairs : PairFrames
        Block pairs of the list (their frames are work arrays too).
    indenter : Indenter
        When ``active``, its centre is ``centre0 + velocity (t - t0)`` [m].
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
    dt, parallel = settings[0], settings[3]
    bodies, law = model[1], model[3]
    contacts, motion = state
    centre = np.empty(3)
    for step in range(n_steps):
        quat_to_rot(motion.quat, scratch.rot)
        scratch.force[:, :] = 0.0
        scratch.torque[:, :] = 0.0
        if parallel:
            node_contacts_parallel(model, state, dt, scratch, pairs, False)
        else:
            node_contacts(model, state, dt, scratch, pairs, False)
        if indenter.active:
            _indent(indenter, t, dt, law.beta, motion, scratch, centre, acc)
        finite = _advance_blocks(settings, bodies, law.margin, motion, scratch)
        t += dt
        if not finite:
            return step + 1, STATUS_NOT_FINITE, t
        if needs_rebuild(motion.pos, motion.quat, contacts.pos_build, contacts.quat_build,
                         bodies.radius, law.margin):  # fmt: skip
            return step + 1, STATUS_REBUILD, t
    return n_steps, STATUS_DONE, t


@njit(cache=True)
def _indent(indenter, t, dt, beta, motion, scratch, centre, acc):
    """The indenter's contact forces at time ``t`` [s] into ``scratch.force`` and
    ``scratch.torque``; its load, work and largest load into ``acc`` (see :func:`run_steps`).
    ``beta`` [s] is the normal dashpot, ``centre`` (3,) a work array (the sphere's centre
    [m])."""
    for k in range(3):
        centre[k] = indenter.centre0[k] + indenter.velocity[k] * (t - indenter.t0)
    p = sphere_contacts(indenter, motion, scratch.rot, centre, beta, scratch.force,
                        scratch.torque)  # fmt: skip
    acc[0] = p
    acc[1] += -p * indenter.velocity[2] * dt
    if p > acc[2]:
        acc[2] = p


@njit(cache=True)
def _advance_blocks(settings, bodies, margin, motion, scratch):
    """Advance every free block by one step (:func:`advance_block_one`; ``settings`` as
    :func:`run_steps`) and add to ``scratch.drift`` a bound on the motion of any point within
    the list's reach (``margin`` [m]) of each block. Returns False if a position or velocity
    is not finite."""
    dt, alpha, local_damping = settings[0], settings[1], settings[2]
    pos, vel, omega = motion.pos, motion.vel, motion.omega
    free_blocks = bodies.free_blocks
    finite = True
    for j in range(free_blocks.shape[0]):
        i = free_blocks[j]
        advance_block_one(i, dt, alpha, local_damping, bodies, motion, scratch)
        for k in range(3):
            if not (math.isfinite(pos[i, k]) and math.isfinite(vel[i, k])):
                finite = False
        # bound on the motion of any point within the list's reach of the centroid
        reach = bodies.radius[i] + 2.0 * margin
        w = omega[i]
        scratch.drift[i] += dt * (
            math.sqrt(vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
            + math.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2) * reach
        )
    return finite


@njit(cache=True)
def kinetic_energy(bodies, motion, rot):
    """Translational plus rotational kinetic energy of the free blocks (inertial masses) [J].

    ``rot`` (n, 3, 3) is overwritten with the rotations of ``motion.quat``.
    """
    free_blocks, inv_mass, inertia_ref = bodies.free_blocks, bodies.inv_mass, bodies.inertia_ref
    quat, vel, omega = motion.quat, motion.vel, motion.omega
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
