"""Nodal penalty contact with regularised Coulomb friction (seed 000, Eqs. (1)-(2)).

A contact entry ``e`` is a pair (surface node ``i`` of block ``a``, neighbour block ``b``). The
node sits at ``x = c_a + R_a r_i`` and penetrates ``b`` by ``d = -phi_b(x)`` (signed distance of
``b``, see :mod:`dem.kernels.signed_distance`). With ``n`` the outward normal of ``b`` there, the
force on block ``a`` at ``x`` is (``-F`` acts on ``b`` at the same point)::

    F = w A_i [ sigma n - k_t s ],   sigma = max(0, k_n d + beta k_n d_dot)

- ``k_n`` [Pa/m] is a traction per penetration (seed 000 Eq. (2)), so ``sum_i k_n d_i A_i``
  converges to ``k_n int d dA`` as nodes are refined.
- ``w`` is the entry's weight: 1 when the interface is counted on this side only, 1/2 when
  both sides carry nodes (halving), 0 when the other side counts it.
- ``beta`` [s] is a stiffness-proportional normal dashpot (``beta = 2 zeta / omega_max``).
- ``s`` (3,) [m] is the node's elastic shear displacement history relative to ``b``: each step it
  is rotated into the current tangent plane (length kept), incremented by the tangential
  relative velocity times ``dt`` and capped so that ``k_t |s| <= mu sigma`` (seed 000 Eq. (1),
  no static/kinetic distinction). ``k_t`` [Pa/m] is a shear traction per displacement.

The per-item law is :func:`traction_one` (scalars only); :func:`contact_entries` evaluates a
range of entries, writes only their rows and adds their wrenches to the block forces and
moments it is given, in entry order: :func:`node_contacts` passes the step's totals (one
pass over the entries), :func:`node_contacts_parallel` one buffer per ``prange`` chunk, added
in chunk order afterwards (deterministic, so runs are reproducible).
"""

import math

import numpy as np
from numba import njit, prange

from dem.kernels.signed_distance import convex_sdf_one, level_set_sdf_one

MU_RULE_MEAN = 0
MU_RULE_MIN = 1
ENTRY_CHUNK = 512
"""Entries per parallel chunk."""


@njit(cache=True)
def pair_mu(mu_a, mu_b, rule):
    """Friction coefficient of a pair from the blocks' values (0: mean, 1: min)."""
    if rule == MU_RULE_MIN:
        return min(mu_a, mu_b)
    return 0.5 * (mu_a + mu_b)


@njit(cache=True)
def traction_one(depth, n0, n1, n2, vr0, vr1, vr2, s0, s1, s2, k_n, k_t, mu, beta, dt):
    """Contact law of one node: normal penalty with dashpot and regularised Coulomb friction.

    Parameters
    ----------
    depth : float
        Penetration ``d > 0`` [m].
    n0, n1, n2 : float
        Unit normal, pointing out of the neighbour (towards the node's block).
    vr0, vr1, vr2 : float
        Velocity of the node's material point relative to the neighbour's [m/s].
    s0, s1, s2 : float
        Shear history at the start of the step [m].
    k_n, k_t : float
        Penalties [Pa/m].
    mu : float
        Friction coefficient.
    beta : float
        Normal dashpot [s].
    dt : float
        [s].

    Returns
    -------
    t0, t1, t2 : float
        Traction on the node's block [Pa].
    s0, s1, s2 : float
        Updated shear history [m].
    """
    vn = vr0 * n0 + vr1 * n1 + vr2 * n2
    # penetration rate is -vn (a's point moving against n goes deeper into b)
    sigma = k_n * (depth - beta * vn)
    if sigma < 0.0:
        sigma = 0.0
    t0 = sigma * n0
    t1 = sigma * n1
    t2 = sigma * n2
    if k_t > 0.0:
        old = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
        sn = s0 * n0 + s1 * n1 + s2 * n2
        s0 -= sn * n0
        s1 -= sn * n1
        s2 -= sn * n2
        new = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
        if new > 0.0:
            # rotate with the contact frame: keep the length of the history
            scale = old / new
            s0 *= scale
            s1 *= scale
            s2 *= scale
        s0 += (vr0 - vn * n0) * dt
        s1 += (vr1 - vn * n1) * dt
        s2 += (vr2 - vn * n2) * dt
        cap = mu * sigma
        trial = k_t * math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
        if trial > cap:
            scale = cap / trial
            s0 *= scale
            s1 *= scale
            s2 *= scale
        t0 -= k_t * s0
        t1 -= k_t * s1
        t2 -= k_t * s2
    else:
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
    return t0, t1, t2, s0, s1, s2


@njit(cache=True)
def contact_entries(
    e_begin, e_end, nodes, contacts, motion, bodies, shapes, law, dt, scratch, force, torque
):
    """Forces of entries ``e_begin:e_end``: updates their shear, writes their output rows and
    adds their wrenches to ``force`` and ``torque``.

    Parameters
    ----------
    e_begin, e_end : int
        Range of entries.
    nodes : Nodes
        Surface nodes (``block``, ``r0``, ``n0``, ``area``), see :mod:`dem.explicit.state`.
    contacts : Contacts
        The entries (``node``, ``block``, ``weight``) and their shear history ``shear``
        [m] (updated in place).
    motion : Motion
        Block poses and velocities (``pos``, ``vel``, ``omega``; world frame).
    bodies : Bodies
        ``ref_centroid`` [m] and ``block_mu`` (the pair's coefficient by ``law.mu_rule``).
    shapes : Shapes
        Face planes (CSR by block) or level-set grids (``use_level_set``).
    law : Law
        ``k_n``, ``k_t`` [Pa/m], ``beta`` [s], ``mu_rule`` and ``compat_cos``: with face
        planes, a node takes its normal from the nearest plane among ``b``'s faces whose
        normal is within ``acos(compat_cos)`` of the reverse of the node's face normal, and
        the penetration ``d_c`` below that plane less ``max(0, delta)``, ``delta`` the
        distance outside ``b``'s other face planes (the nearest one, negative inside): full
        depth up to ``b``'s edges, going continuously to zero over an overhang equal to the
        depth. A node more than the list's ``margin`` [m] below that plane (or with no such
        face) cannot have come in through it within a list period: it takes the nearest
        plane (a node on the side face of a block standing on a longer block is on that
        block's top plane and far below its end face). A ``compat_cos``
        above 1 switches this off: nearest plane always, the exact convex signed distance,
        which gives a node on an edge shared with ``b`` the depth ``min(d_c, -delta)``,
        about zero, so a hinge along such an edge carries nothing there.
    dt : float
        Time step [s].
    scratch : Scratch
        ``rot`` (n, 3, 3) rotations of the current poses (input); ``out_force``,
        ``out_point`` (m, 3): force on the node's block [N] and its point [m];
        ``out_depth`` (m,): penetration ``d`` [m] (negative: separation, lower bound);
        ``skip_gap``, ``skip_drift`` (m,) and ``drift`` (n,) [m]: see Notes.
    force, torque : (n, 3) float64
        Accumulated in place: each entry's force on its node's block [N] and its negative on
        the neighbour, with their moments about the centroids [N m], in entry order.

    Notes
    -----
    Separated entries are skipped while they cannot touch. With face planes, a node at plane
    distance ``phi > 0`` outside ``b`` must move by at least ``phi`` relative to ``b`` before
    it can penetrate. ``drift[k]`` accumulates a bound on how far any point of block ``k``
    within the list's reach has moved (:func:`dem.kernels.integrate.run_steps`); an entry found
    separated stores ``skip_gap = phi`` (compatible plane: half of ``max(0, delta) - d_c``,
    which changes at most twice as fast as the node moves) and ``skip_drift = drift[a] +
    drift[b]`` and is not evaluated again until ``drift[a] + drift[b] - skip_drift >=
    skip_gap``. Its force and
    shear history are zero meanwhile, as an evaluation would give: the result is exactly that
    of evaluating every entry (its ``out_depth`` and ``out_point`` keep the last evaluated
    values). Level sets are not a distance bound: no skipping there.
    """
    pair_node, pair_block, pair_weight = contacts.node, contacts.block, contacts.weight
    pair_shear = contacts.shear
    node_block, node_r0, node_n0, node_area = nodes.block, nodes.r0, nodes.n0, nodes.area
    pos, vel, omega, rot = motion.pos, motion.vel, motion.omega, scratch.rot
    ref_centroid, block_mu = bodies.ref_centroid, bodies.block_mu
    face_ptr, face_normal, face_offset = shapes.face_ptr, shapes.face_normal, shapes.face_offset
    ls_origin, ls_spacing, ls_dims = shapes.ls_origin, shapes.ls_spacing, shapes.ls_dims
    ls_ptr, ls_values, use_level_set = shapes.ls_ptr, shapes.ls_values, shapes.use_level_set
    k_n, k_t, beta, mu_rule = law.k_n, law.k_t, law.beta, law.mu_rule
    compat_cos, margin = law.compat_cos, law.margin
    out_force, out_point, out_depth = scratch.out_force, scratch.out_point, scratch.out_depth
    skip_gap, skip_drift, drift = scratch.skip_gap, scratch.skip_drift, scratch.drift
    for e in range(e_begin, e_end):
        i = pair_node[e]
        b = pair_block[e]
        a = node_block[i]
        gap = skip_gap[e]
        if gap > 0.0 and drift[a] + drift[b] - skip_drift[e] < gap:
            continue  # still separated: its force and shear history are zero (see Notes)
        r0x, r0y, r0z = node_r0[i, 0], node_r0[i, 1], node_r0[i, 2]
        rx = rot[a, 0, 0] * r0x + rot[a, 0, 1] * r0y + rot[a, 0, 2] * r0z
        ry = rot[a, 1, 0] * r0x + rot[a, 1, 1] * r0y + rot[a, 1, 2] * r0z
        rz = rot[a, 2, 0] * r0x + rot[a, 2, 1] * r0y + rot[a, 2, 2] * r0z
        x0 = pos[a, 0] + rx
        x1 = pos[a, 1] + ry
        x2 = pos[a, 2] + rz
        out_point[e, 0] = x0
        out_point[e, 1] = x1
        out_point[e, 2] = x2
        dx = x0 - pos[b, 0]
        dy = x1 - pos[b, 1]
        dz = x2 - pos[b, 2]
        # reference frame of b: X = R_b^T (x - c_b) + C0_b
        X0 = rot[b, 0, 0] * dx + rot[b, 1, 0] * dy + rot[b, 2, 0] * dz + ref_centroid[b, 0]
        X1 = rot[b, 0, 1] * dx + rot[b, 1, 1] * dy + rot[b, 2, 1] * dz + ref_centroid[b, 1]
        X2 = rot[b, 0, 2] * dx + rot[b, 1, 2] * dy + rot[b, 2, 2] * dz + ref_centroid[b, 2]
        if use_level_set:
            phi, g0, g1, g2 = level_set_sdf_one(
                X0, X1, X2, ls_origin[b], ls_spacing[b], ls_dims[b], ls_values, ls_ptr[b]
            )
        elif compat_cos <= 1.0:
            # normal-compatible face: among b's faces facing the node's own face, the nearest
            # plane gives penetration and normal; b's other faces only bound the contact
            # laterally, continuously (a node on a shared edge keeps its full depth)
            m0, m1, m2 = node_n0[i, 0], node_n0[i, 1], node_n0[i, 2]
            w0 = rot[a, 0, 0] * m0 + rot[a, 0, 1] * m1 + rot[a, 0, 2] * m2
            w1 = rot[a, 1, 0] * m0 + rot[a, 1, 1] * m1 + rot[a, 1, 2] * m2
            w2 = rot[a, 2, 0] * m0 + rot[a, 2, 1] * m1 + rot[a, 2, 2] * m2
            q0 = rot[b, 0, 0] * w0 + rot[b, 1, 0] * w1 + rot[b, 2, 0] * w2
            q1 = rot[b, 0, 1] * w0 + rot[b, 1, 1] * w1 + rot[b, 2, 1] * w2
            q2 = rot[b, 0, 2] * w0 + rot[b, 1, 2] * w1 + rot[b, 2, 2] * w2
            best_c = -math.inf
            best_o = -math.inf
            f_c = -1
            f_o = face_ptr[b]
            for g in range(face_ptr[b], face_ptr[b + 1]):
                dist = (
                    face_normal[g, 0] * X0
                    + face_normal[g, 1] * X1
                    + face_normal[g, 2] * X2
                    - face_offset[g]
                )
                c = face_normal[g, 0] * q0 + face_normal[g, 1] * q1 + face_normal[g, 2] * q2
                if c <= -compat_cos:
                    if dist > best_c:
                        best_c = dist
                        f_c = g
                elif dist > best_o:
                    best_o = dist
                    f_o = g
            # contact in either case needs best_c + max(best_o, 0) < 0, a 2-Lipschitz
            # function of the node's position: half of it bounds the motion to contact
            bound = 0.5 * (best_c + max(best_o, 0.0)) if f_c >= 0 else best_o
            if best_c >= -margin:
                phi, f = best_c + max(best_o, 0.0), f_c
            elif best_c > best_o:
                phi, f = best_c, f_c
            else:
                phi, f = best_o, f_o
            g0, g1, g2 = face_normal[f, 0], face_normal[f, 1], face_normal[f, 2]
        else:
            phi, f = convex_sdf_one(
                X0, X1, X2, face_normal, face_offset, face_ptr[b], face_ptr[b + 1]
            )
            bound = phi
            g0, g1, g2 = face_normal[f, 0], face_normal[f, 1], face_normal[f, 2]
        out_depth[e] = -phi
        if phi >= 0.0 or pair_weight[e] == 0.0:
            pair_shear[e, 0] = 0.0
            pair_shear[e, 1] = 0.0
            pair_shear[e, 2] = 0.0
            out_force[e, 0] = 0.0
            out_force[e, 1] = 0.0
            out_force[e, 2] = 0.0
            if not use_level_set and bound > 0.0:
                skip_gap[e] = bound
                skip_drift[e] = drift[a] + drift[b]
            continue
        skip_gap[e] = 0.0
        n0 = rot[b, 0, 0] * g0 + rot[b, 0, 1] * g1 + rot[b, 0, 2] * g2
        n1 = rot[b, 1, 0] * g0 + rot[b, 1, 1] * g1 + rot[b, 1, 2] * g2
        n2 = rot[b, 2, 0] * g0 + rot[b, 2, 1] * g1 + rot[b, 2, 2] * g2
        # relative velocity of a's material point against b's material point at x
        vr0 = vel[a, 0] + omega[a, 1] * rz - omega[a, 2] * ry
        vr1 = vel[a, 1] + omega[a, 2] * rx - omega[a, 0] * rz
        vr2 = vel[a, 2] + omega[a, 0] * ry - omega[a, 1] * rx
        vr0 -= vel[b, 0] + omega[b, 1] * dz - omega[b, 2] * dy
        vr1 -= vel[b, 1] + omega[b, 2] * dx - omega[b, 0] * dz
        vr2 -= vel[b, 2] + omega[b, 0] * dy - omega[b, 1] * dx
        mu = pair_mu(block_mu[a], block_mu[b], mu_rule)
        t0, t1, t2, s0, s1, s2 = traction_one(
            -phi, n0, n1, n2, vr0, vr1, vr2, pair_shear[e, 0], pair_shear[e, 1],
            pair_shear[e, 2], k_n, k_t, mu, beta, dt,
        )  # fmt: skip
        pair_shear[e, 0] = s0
        pair_shear[e, 1] = s1
        pair_shear[e, 2] = s2
        area = node_area[i] * pair_weight[e]
        f0, f1, f2 = t0 * area, t1 * area, t2 * area
        out_force[e, 0] = f0
        out_force[e, 1] = f1
        out_force[e, 2] = f2
        add_wrench(force, torque, a, x0 - pos[a, 0], x1 - pos[a, 1], x2 - pos[a, 2], f0, f1, f2)
        add_wrench(force, torque, b, dx, dy, dz, -f0, -f1, -f2)


@njit(cache=True)
def add_wrench(force, torque, k, r0, r1, r2, f0, f1, f2):
    """``force[k] += f``, ``torque[k] += r x f`` (``r`` from block ``k``'s centroid)."""
    force[k, 0] += f0
    force[k, 1] += f1
    force[k, 2] += f2
    torque[k, 0] += r1 * f2 - r2 * f1
    torque[k, 1] += r2 * f0 - r0 * f2
    torque[k, 2] += r0 * f1 - r1 * f0


@njit(cache=True)
def node_contacts(nodes, contacts, motion, bodies, shapes, law, dt, scratch):
    """Every entry, serially, adding to ``scratch.force`` and ``scratch.torque`` (arguments as
    :func:`contact_entries`)."""
    contact_entries(0, contacts.node.shape[0], nodes, contacts, motion, bodies, shapes, law, dt,
                    scratch, scratch.force, scratch.torque)  # fmt: skip


@njit(cache=True, parallel=True)
def node_contacts_parallel(nodes, contacts, motion, bodies, shapes, law, dt, scratch):
    """Every entry, in parallel chunks (``prange``): each chunk writes its own rows and sums its
    wrenches in its own buffer; the buffers are added in chunk order (deterministic)."""
    m = contacts.node.shape[0]
    n_blocks = scratch.force.shape[0]
    n_chunks = (m + ENTRY_CHUNK - 1) // ENTRY_CHUNK
    chunk_force = np.zeros((n_chunks, n_blocks, 3))
    chunk_torque = np.zeros((n_chunks, n_blocks, 3))
    for c in prange(n_chunks):
        contact_entries(
            c * ENTRY_CHUNK, min(m, (c + 1) * ENTRY_CHUNK), nodes, contacts, motion, bodies,
            shapes, law, dt, scratch, chunk_force[c], chunk_torque[c],
        )  # fmt: skip
    for c in range(n_chunks):
        for k in range(n_blocks):
            for j in range(3):
                scratch.force[k, j] += chunk_force[c, k, j]
                scratch.torque[k, j] += chunk_torque[c, k, j]


@njit(cache=True)
def sphere_contacts(indenter, motion, rot, centre, beta, force, torque):
    """Frictionless penalty contact of a rigid sphere (the indenter) with block surface nodes.

    Parameters
    ----------
    indenter : Indenter
        ``block`` (k,), ``r0`` (k, 3) [m], ``area`` (k,) [m^2] of the indenter nodes; sphere
        ``radius`` [m], ``velocity`` (3,) [m/s] (for the normal dashpot), penalty ``k_n``
        [Pa/m]; ``out_force`` (k, 3): force on each node's block [N] (output).
    motion : Motion
        Block poses and velocities.
    rot : (n_blocks, 3, 3) float64
        Rotations of the current poses.
    centre : (3,) float64
        Sphere centre [m].
    beta : float
        Normal damping [s].
    force, torque : (n_blocks, 3) float64
        Accumulated in place.

    Returns
    -------
    float
        Total force on the sphere, z component negated: the indenter load ``P`` [N] (positive
        when the sphere pushes down).
    """
    ind_block, ind_r0, ind_area = indenter.block, indenter.r0, indenter.area
    radius, velocity, k_n = indenter.radius, indenter.velocity, indenter.k_n
    out_force = indenter.out_force
    pos, vel, omega = motion.pos, motion.vel, motion.omega
    p_total = 0.0
    for e in range(ind_block.shape[0]):
        a = ind_block[e]
        r = rot[a] @ ind_r0[e]
        x0 = pos[a, 0] + r[0]
        x1 = pos[a, 1] + r[1]
        x2 = pos[a, 2] + r[2]
        d0 = x0 - centre[0]
        d1 = x1 - centre[1]
        d2 = x2 - centre[2]
        dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        depth = radius - dist
        if depth <= 0.0 or dist == 0.0:
            out_force[e, 0] = 0.0
            out_force[e, 1] = 0.0
            out_force[e, 2] = 0.0
            continue
        n0, n1, n2 = d0 / dist, d1 / dist, d2 / dist
        va0 = vel[a, 0] + omega[a, 1] * r[2] - omega[a, 2] * r[1] - velocity[0]
        va1 = vel[a, 1] + omega[a, 2] * r[0] - omega[a, 0] * r[2] - velocity[1]
        va2 = vel[a, 2] + omega[a, 0] * r[1] - omega[a, 1] * r[0] - velocity[2]
        vn = va0 * n0 + va1 * n1 + va2 * n2
        sigma = k_n * (depth - beta * vn)
        if sigma < 0.0:
            sigma = 0.0
        f0 = sigma * ind_area[e] * n0
        f1 = sigma * ind_area[e] * n1
        f2 = sigma * ind_area[e] * n2
        out_force[e, 0] = f0
        out_force[e, 1] = f1
        out_force[e, 2] = f2
        force[a, 0] += f0
        force[a, 1] += f1
        force[a, 2] += f2
        torque[a, 0] += r[1] * f2 - r[2] * f1
        torque[a, 1] += r[2] * f0 - r[0] * f2
        torque[a, 2] += r[0] * f1 - r[1] * f0
        p_total -= f2
    return p_total


@njit(cache=True)
def elastic_energy(pair_node, pair_weight, node_area, out_depth, k_n):
    """Normal penalty energy ``sum 1/2 k_n d^2 w A`` of the entries in contact [J]."""
    total = 0.0
    for e in range(pair_node.shape[0]):
        d = out_depth[e]
        if d > 0.0:
            total += 0.5 * k_n * d * d * pair_weight[e] * node_area[pair_node[e]]
    return total
