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
  relative velocity times ``dt`` and capped so that ``k_t |s| <= mu max(0, sigma - k_n
  touch)`` (seed 000 Eq. (1), no static/kinetic distinction). ``k_t`` [Pa/m] is a shear
  traction per displacement.
- ``touch`` [m] is the touching depth (``law.touch``, ``TOUCH`` times the model's extent, as
  in the static interface laws, :mod:`dem.kernels.interface_law`): the part of a penetration
  within it carries no friction. Faces that conform at zero gap (vertical TIS faces at theta
  = 0, masonry joints) touch at depths of round-off size (1e-19 m) whose signs and sizes
  follow the arithmetic, not the geometry; the friction they would carry is a seed that a
  friction-driven instability (a block sliding in a slot without clearance) amplifies, so
  that the outcome would be decided by round-off. The friction cap stays continuous in the
  depth.

The per-item law is :func:`traction_one` (scalars only); :func:`contact_entries` evaluates a
range of entries, writes only their rows and adds their wrenches to the block forces and
moments it is given, in entry order: :func:`node_contacts` passes the step's totals (one
pass over the entries), :func:`node_contacts_parallel` one buffer per ``prange`` chunk, added
in chunk order afterwards (deterministic, so runs are reproducible). The kernels take the
model's constants as one tuple ``model = (nodes, bodies, shapes, law)`` and the state as
``state = (contacts, motion)`` (:mod:`dem.explicit.state`).

Plane choice with face planes: with ``law.compat_cos <= 1`` a node takes the normal-compatible
plane (:func:`_compatible_plane`); above 1 the nearest plane, the exact convex signed distance,
which gives a node on an edge shared with ``b`` the depth ``min(d_c, -delta)``, about zero, so
a hinge along such an edge carries nothing there; only the one or two faces of
``pairs.near_faces`` are tested when the entry has them (the same result).

Separated entries are skipped while they cannot touch. With face planes, a node at plane
distance ``phi > 0`` outside ``b`` must move by at least ``phi`` relative to ``b`` before it
can penetrate. ``drift[k]`` accumulates a bound on how far any point of block ``k`` within the
list's reach has moved (:func:`dem.kernels.integrate.run_steps`); an entry found separated
stores ``skip_gap = phi`` (compatible plane: the bound of :func:`_compatible_plane`) and
``skip_drift = drift[a] + drift[b]`` and is not evaluated again until
``drift[a] + drift[b] - skip_drift >= skip_gap``. Its force and shear history are zero
meanwhile, as an evaluation would give: the result is exactly that of
evaluating every entry (its ``out_depth`` and ``out_point`` keep the last evaluated values).
Level sets are not a distance bound: no skipping there.

The helpers of the entry loop take and return scalars and tuples of scalars, inlined
(``inline="always"``; :func:`_run_frame`, once per run of entries, reads arrays); the plane
choice and the writes into the entry arrays stay in :func:`contact_entries`: numba
reference-counts the arrays passed to a helper in the loop, inlined or not, and the loop over
one run's entries as a function of its own adds a call per run, so :func:`contact_entries`
is longer than a screen (the costs are measured with ``benchmarks/bench_explicit.py``).
"""

import math

import numpy as np
from numba import njit, prange

from dem.kernels.signed_distance import convex_sdf_one, level_set_sdf_one

MU_RULE_MEAN = 0
MU_RULE_MIN = 1
ENTRY_CHUNK = 2048
"""Entries per chunk of the entry loop (serial or parallel), up to ``MAX_CHUNKS`` chunks."""
MAX_CHUNKS = 64


@njit(cache=True)
def pair_mu(mu_a, mu_b, rule):
    """Friction coefficient of a pair from the blocks' values (0: mean, 1: min)."""
    if rule == MU_RULE_MIN:
        return min(mu_a, mu_b)
    return 0.5 * (mu_a + mu_b)


@njit(cache=True, inline="always")
def traction_one(depth, normal, v_rel, shear, law, dt):
    """Contact law of one node: normal penalty with dashpot and regularised Coulomb friction.

    Parameters
    ----------
    depth : float
        Penetration ``d > 0`` [m].
    normal : (float, float, float)
        Unit normal, pointing out of the neighbour (towards the node's block).
    v_rel : (float, float, float)
        Velocity of the node's material point relative to the neighbour's [m/s].
    shear : (float, float, float)
        Shear history at the start of the step [m].
    law : (float, float, float, float, float)
        ``(k_n, k_t, mu, beta, touch)``: penalties [Pa/m], friction coefficient [-], normal
        dashpot [s], touching depth without friction [m] (module docstring).
    dt : float
        Time step [s].

    Returns
    -------
    traction : (float, float, float)
        Traction on the node's block [Pa].
    shear : (float, float, float)
        Updated shear history [m].
    """
    n0, n1, n2 = normal
    vr0, vr1, vr2 = v_rel
    s0, s1, s2 = shear
    k_n, k_t, mu, beta, touch = law
    vn = vr0 * n0 + vr1 * n1 + vr2 * n2
    # penetration rate is -vn (a's point moving against n goes deeper into b)
    sigma = k_n * (depth - beta * vn)
    if sigma < 0.0:
        sigma = 0.0
    t0 = sigma * n0
    t1 = sigma * n1
    t2 = sigma * n2
    if k_t > 0.0:
        old2 = s0 * s0 + s1 * s1 + s2 * s2
        sn = s0 * n0 + s1 * n1 + s2 * n2
        s0 -= sn * n0
        s1 -= sn * n1
        s2 -= sn * n2
        new2 = s0 * s0 + s1 * s1 + s2 * s2
        if new2 > 0.0 and sn != 0.0:
            # rotate with the contact frame: keep the length of the history
            scale = math.sqrt(old2 / new2)
            s0 *= scale
            s1 *= scale
            s2 *= scale
        s0 += (vr0 - vn * n0) * dt
        s1 += (vr1 - vn * n1) * dt
        s2 += (vr2 - vn * n2) * dt
        cap = mu * (sigma - k_n * touch)
        if cap < 0.0:
            cap = 0.0
        trial2 = k_t * k_t * (s0 * s0 + s1 * s1 + s2 * s2)
        if trial2 > cap * cap:
            scale = cap / math.sqrt(trial2)
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
    return (t0, t1, t2), (s0, s1, s2)


@njit(cache=True)
def pair_frames(motion, rot, bodies, shapes, pairs):
    """Write each pair's relative frame (see :class:`dem.explicit.state.PairFrames`).

    Parameters
    ----------
    motion : Motion
        Poses and velocities.
    rot : (n_blocks, 3, 3) float64
        Rotations of the current poses.
    bodies : Bodies
        ``ref_centroid`` [m].
    shapes : Shapes
        Reference-frame face planes (CSR by block).
    pairs : PairFrames
        ``a``, ``b``, ``face_ptr`` (input); the other arrays are written.
    """
    pos, vel, omega = motion.pos, motion.vel, motion.omega
    ref_centroid = bodies.ref_centroid
    face_ptr, face_normal, face_offset = shapes.face_ptr, shapes.face_normal, shapes.face_offset
    for q in range(pairs.a.shape[0]):
        a = pairs.a[q]
        b = pairs.b[q]
        arm = pairs.arm[q]
        for j in range(3):
            arm[j] = pos[a, j] - pos[b, j]
            pairs.omega[q, j] = omega[a, j] - omega[b, j]
        w = omega[b]
        pairs.vel[q, 0] = vel[a, 0] - vel[b, 0] - (w[1] * arm[2] - w[2] * arm[1])
        pairs.vel[q, 1] = vel[a, 1] - vel[b, 1] - (w[2] * arm[0] - w[0] * arm[2])
        pairs.vel[q, 2] = vel[a, 2] - vel[b, 2] - (w[0] * arm[1] - w[1] * arm[0])
        for i in range(3):
            pairs.shift[q, i] = ref_centroid[b, i]
            for j in range(3):
                pairs.shift[q, i] += rot[b, j, i] * arm[j]
                pairs.to_b[q, i, j] = (
                    rot[b, 0, i] * rot[a, 0, j]
                    + rot[b, 1, i] * rot[a, 1, j]
                    + rot[b, 2, i] * rot[a, 2, j]
                )
        row = pairs.face_ptr[q]
        for g in range(face_ptr[b], face_ptr[b + 1]):
            ng = face_normal[g]
            d = face_offset[g]
            for i in range(3):
                u = rot[b, i, 0] * ng[0] + rot[b, i, 1] * ng[1] + rot[b, i, 2] * ng[2]
                pairs.face_u[row, i] = u
                d -= u * arm[i] + ng[i] * ref_centroid[b, i]
                pairs.face_v[row, i] = (
                    pairs.to_b[q, 0, i] * ng[0]
                    + pairs.to_b[q, 1, i] * ng[1]
                    + pairs.to_b[q, 2, i] * ng[2]
                )
            pairs.face_d[row] = d
            row += 1


@njit(cache=True)
def contact_entries(e_begin, e_end, model, state, dt, scratch, pairs, record, sums):
    """Forces of entries ``e_begin:e_end`` [N]: updates their shear history ``contacts.shear``
    (m, 3) [m] and adds, in entry order, their forces on ``a`` [N] and moments about ``c_a``
    [N m] to ``sums`` (p, 6), per pair (:func:`pair_wrenches` makes block wrenches of them).

    ``model = (nodes, bodies, shapes, law)`` and ``state = (contacts, motion)`` as in
    :mod:`dem.explicit.state`; ``dt`` [s]; ``pairs`` the entries' block pairs with the frames
    of :func:`pair_frames`, handled run by run (``run_ptr``; a range may start and end inside
    a run). ``scratch``: ``rot`` (n, 3, 3) the current rotations (input); written:
    ``out_depth`` (m,) the penetration [m] (negative: separation, a lower bound), and the
    skipping of separated entries (``skip_gap``, ``skip_drift`` (m,), ``drift`` (n,) [m],
    module docstring); with ``record`` also ``out_force`` (m, 3), the force on the node's
    block [N], and ``out_point`` (m, 3), the node [m], of every evaluated entry. The plane
    choice stays in this function (module docstring).
    """
    nodes, bodies, shapes, law = model
    contacts, motion = state
    pair_node, pair_weight, pair_shear = contacts.node, contacts.weight, contacts.shear
    node_r0, node_n0, node_area = nodes.r0, nodes.n0, nodes.area
    patch_r0, patch_u, patch_v = nodes.patch_r0, nodes.patch_u, nodes.patch_v
    rot, drift, out_depth = scratch.rot, scratch.drift, scratch.out_depth
    skip_gap, skip_drift, use_level_set = scratch.skip_gap, scratch.skip_drift, shapes.use_level_set
    run_ptr, near_faces, face_v, face_d, face_u = (
        pairs.run_ptr, pairs.near_faces, pairs.face_v, pairs.face_d, pairs.face_u
    )  # fmt: skip
    k = np.searchsorted(run_ptr, e_begin, side="right") - 1  # the run holding e_begin
    e_run = e_begin
    while e_run < e_end:
        # one run of entries of pair q: its data once (the same arithmetic as per entry)
        q = pairs.run_pair[k]
        e_stop = min(run_ptr[k + 1], e_end)
        a, b, faces, drift_ab, rot_a, vw, law_q = _run_frame(q, pairs, rot, drift, bodies, law)
        s_f, s_m = (sums[q, 0], sums[q, 1], sums[q, 2]), (sums[q, 3], sums[q, 4], sums[q, 5])
        # unsigned indices: numba wraps negative signed ones, a compare and a select per access
        for e in range(np.uint64(e_run), np.uint64(e_stop)):
            gap = skip_gap[e]
            if gap > 0.0 and drift_ab - skip_drift[e] < gap:
                continue  # still separated: its force and shear history are zero
            i = np.uint64(pair_node[e])
            r0 = r0x, r0y, r0z = node_r0[i, 0], node_r0[i, 1], node_r0[i, 2]
            # the plane choice stays here: no helper taking arrays (module docstring)
            if use_level_set:
                phi, n = _level_set_plane(r0, q, b, pairs.to_b, pairs.shift, rot, shapes)
                bound = 0.0
            else:
                if law.compat_cos <= 1.0:
                    m = (node_n0[i, 0], node_n0[i, 1], node_n0[i, 2])
                    patch = (
                        (patch_r0[i, 0], patch_r0[i, 1], patch_r0[i, 2]),
                        (patch_u[i, 0], patch_u[i, 1], patch_u[i, 2]),
                        (patch_v[i, 0], patch_v[i, 1], patch_v[i, 2]),
                    )
                    phi, f_c, bound = _compatible_plane(r0, m, patch, face_v, face_d, faces,
                                                        law)  # fmt: skip
                    f = np.uint64(f_c)
                elif near_faces[e, 0] >= 0:
                    f = np.uint64(faces[0] + near_faces[e, 0])
                    phi = face_v[f, 0] * r0x + face_v[f, 1] * r0y + face_v[f, 2] * r0z - face_d[f]
                    if near_faces[e, 1] >= 0:
                        # the later face wins only when strictly larger, as in the full scan
                        g = np.uint64(faces[0] + near_faces[e, 1])
                        dist = (
                            face_v[g, 0] * r0x + face_v[g, 1] * r0y + face_v[g, 2] * r0z
                            - face_d[g]
                        )  # fmt: skip
                        if dist > phi:
                            phi, f = dist, g
                    bound = phi
                else:
                    phi, f_c = convex_sdf_one(r0x, r0y, r0z, face_v, face_d, faces[0], faces[1])
                    f = np.uint64(f_c)
                    bound = phi
                n = (face_u[f, 0], face_u[f, 1], face_u[f, 2])
            out_depth[e] = -phi
            touching = phi < 0.0 and pair_weight[e] != 0.0
            if not touching:
                pair_shear[e, 0], pair_shear[e, 1], pair_shear[e, 2] = 0.0, 0.0, 0.0
                if not use_level_set and bound > 0.0:
                    skip_gap[e], skip_drift[e] = bound, drift_ab
                if not record:
                    continue
            else:
                skip_gap[e] = 0.0
            r = _rotate(rot_a, r0)
            force = (0.0, 0.0, 0.0)
            if touching:
                shear = (pair_shear[e, 0], pair_shear[e, 1], pair_shear[e, 2])
                area = node_area[i] * pair_weight[e]
                force, shear = _node_force(-phi, n, r, vw, shear, law_q, dt, area)
                pair_shear[e, 0], pair_shear[e, 1], pair_shear[e, 2] = shear
                s_f, s_m = _add_wrench(s_f, s_m, r, force)
            if record:
                _record(scratch, e, force, motion.pos, a, r)
        sums[q, 0], sums[q, 1], sums[q, 2] = s_f
        sums[q, 3], sums[q, 4], sums[q, 5] = s_m
        e_run = e_stop
        k += 1


@njit(cache=True, inline="always")
def _run_frame(q, pairs, rot, drift, bodies, law):
    """Data of pair ``q`` shared by its entries: blocks ``a``, ``b``; its face rows
    ``(begin, end)``; ``drift[a] + drift[b]`` [m]; ``a``'s rotation (rows); ``(v, w)``, the
    pair's relative velocity [m/s] and angular velocity [rad/s] (:func:`pair_frames`); the
    law's scalars ``(k_n, k_t, mu, beta, touch)`` with the pair's friction coefficient."""
    a, b = pairs.a[q], pairs.b[q]
    rot_a = (
        (rot[a, 0, 0], rot[a, 0, 1], rot[a, 0, 2]),
        (rot[a, 1, 0], rot[a, 1, 1], rot[a, 1, 2]),
        (rot[a, 2, 0], rot[a, 2, 1], rot[a, 2, 2]),
    )
    v = (pairs.vel[q, 0], pairs.vel[q, 1], pairs.vel[q, 2])
    w = (pairs.omega[q, 0], pairs.omega[q, 1], pairs.omega[q, 2])
    mu = pair_mu(bodies.block_mu[a], bodies.block_mu[b], law.mu_rule)
    faces = (pairs.face_ptr[q], pairs.face_ptr[q + 1])
    law_q = (law.k_n, law.k_t, mu, law.beta, law.touch)
    return a, b, faces, drift[a] + drift[b], rot_a, (v, w), law_q


@njit(cache=True, inline="always")
def _rotate(rot, r0):
    """``R r0`` with ``R`` given by its rows (three 3-tuples)."""
    return (
        rot[0][0] * r0[0] + rot[0][1] * r0[1] + rot[0][2] * r0[2],
        rot[1][0] * r0[0] + rot[1][1] * r0[1] + rot[1][2] * r0[2],
        rot[2][0] * r0[0] + rot[2][1] * r0[1] + rot[2][2] * r0[2],
    )


@njit(cache=True, inline="always")
def _node_force(depth, n, r, vw, shear, law_q, dt, area):
    """Force [N] on a touching node's block and its new shear history [m] (:func:`traction_one`).

    ``depth`` [m], normal ``n`` and ``shear`` [m] as :func:`traction_one`; ``r`` the node
    relative to ``c_a`` [m]; ``vw = (v, w)`` the pair's relative velocity [m/s] and angular
    velocity [rad/s]; ``law_q = (k_n, k_t, mu, beta, touch)``; ``area`` the node's weighted area
    [m^2]."""
    v, w = vw
    # relative velocity of a's material point against b's material point at x
    v_rel = (
        v[0] + w[1] * r[2] - w[2] * r[1],
        v[1] + w[2] * r[0] - w[0] * r[2],
        v[2] + w[0] * r[1] - w[1] * r[0],
    )
    t, shear = traction_one(depth, n, v_rel, shear, law_q, dt)
    return (t[0] * area, t[1] * area, t[2] * area), shear


@njit(cache=True, inline="always")
def _add_wrench(s_f, s_m, r, f):
    """``s_f + f`` and ``s_m + r x f`` (3-tuples)."""
    return (s_f[0] + f[0], s_f[1] + f[1], s_f[2] + f[2]), (
        s_m[0] + (r[1] * f[2] - r[2] * f[1]),
        s_m[1] + (r[2] * f[0] - r[0] * f[2]),
        s_m[2] + (r[0] * f[1] - r[1] * f[0]),
    )


@njit(cache=True)
def _record(scratch, e, force, pos, a, r):
    """Entry ``e``'s force on its node's block [N] and its point ``c_a + r`` [m] into
    ``scratch.out_force`` and ``scratch.out_point``."""
    scratch.out_force[e, 0], scratch.out_force[e, 1], scratch.out_force[e, 2] = force
    scratch.out_point[e, 0] = pos[a, 0] + r[0]
    scratch.out_point[e, 1] = pos[a, 1] + r[1]
    scratch.out_point[e, 2] = pos[a, 2] + r[2]


@njit(cache=True)
def _level_set_plane(r0, q, b, to_b, shift, rot, shapes):
    """Level-set value [m] and world normal (3-tuple) of neighbour ``b`` at a node ``r0`` of
    pair ``q``."""
    r0x, r0y, r0z = r0
    phi, g0, g1, g2 = level_set_sdf_one(
        to_b[q, 0, 0] * r0x + to_b[q, 0, 1] * r0y + to_b[q, 0, 2] * r0z + shift[q, 0],
        to_b[q, 1, 0] * r0x + to_b[q, 1, 1] * r0y + to_b[q, 1, 2] * r0z + shift[q, 1],
        to_b[q, 2, 0] * r0x + to_b[q, 2, 1] * r0y + to_b[q, 2, 2] * r0z + shift[q, 2],
        shapes.ls_origin[b], shapes.ls_spacing[b], shapes.ls_dims[b], shapes.ls_values,
        shapes.ls_ptr[b],
    )  # fmt: skip
    n0 = rot[b, 0, 0] * g0 + rot[b, 0, 1] * g1 + rot[b, 0, 2] * g2
    n1 = rot[b, 1, 0] * g0 + rot[b, 1, 1] * g1 + rot[b, 1, 2] * g2
    n2 = rot[b, 2, 0] * g0 + rot[b, 2, 1] * g1 + rot[b, 2, 2] * g2
    return phi, (n0, n1, n2)


@njit(cache=True)
def _compatible_plane(r0, m, patch, face_v, face_d, faces, law):
    """Plane distance [m], face row and skip bound [m] of a node against the
    normal-compatible plane.

    Rows ``faces = (begin, end)`` of the pair's ``face_v`` (f, 3) and ``face_d`` (f,) [m];
    ``r0`` the node, ``m`` its face normal and ``patch = (centre, half_u, half_v)`` the box of
    face it stands for (:func:`dem.contact_nodes.node_patches`), all in its block's reference
    frame. The node takes its normal from the nearest plane among ``b``'s faces whose normal
    is within ``acos(law.compat_cos)`` of ``-m``, and as its depth the penetration ``d_c``
    below that plane times the fraction of its patch that lies over ``b``: inside each of
    ``b``'s other face planes (a box cut by a plane: linear in the distance ``delta`` of its
    centre, from 1 at ``delta = -e`` to 0 at ``delta = e``, ``e`` the box's half extent along
    the plane's normal; the fractions of the planes multiply, exact for a box in a corner
    of right angles). So a node on an edge shared with an equal neighbour (a hinge) keeps its
    full depth, half of a patch over a head joint counts half, and a patch beside ``b`` (a
    block that only shares an edge line with ``b``, or stands a gap away from its side)
    counts nothing, however deep ``d_c`` below the plane of ``b``'s face it lies.

    A node more than ``law.margin`` [m] below that plane (or with no such face) cannot have
    come in through it within a list period: it takes the nearest plane (a node on the side
    face of a block standing on a longer block is on that block's top plane and far below its
    end face).

    The bound: contact needs ``d_c > 0`` and every plane's ``delta < e``, and the
    nearest-plane depth needs the same (the node is a point of its patch), so the largest of
    ``-d_c`` and ``delta - e`` over the planes bounds the motion to contact (each is the
    distance of a point of the patch to a plane).
    """
    r0x, r0y, r0z = r0
    m0, m1, m2 = m
    (c0, c1, c2), (u0, u1, u2), (v0, v1, v2) = patch
    compat_cos = law.compat_cos
    best_c = -math.inf
    best_o = -math.inf
    outside = -math.inf  # largest delta - e over the other planes
    fraction = 1.0
    f_c = -1
    f_o = faces[0]
    for g in range(faces[0], faces[1]):
        n0, n1, n2 = face_v[g, 0], face_v[g, 1], face_v[g, 2]
        dist = n0 * r0x + n1 * r0y + n2 * r0z - face_d[g]
        c = n0 * m0 + n1 * m1 + n2 * m2
        if c <= -compat_cos:
            if dist > best_c:
                best_c = dist
                f_c = g
            continue
        if dist > best_o:
            best_o = dist
            f_o = g
        delta = n0 * c0 + n1 * c1 + n2 * c2 - face_d[g]
        extent = abs(n0 * u0 + n1 * u1 + n2 * u2) + abs(n0 * v0 + n1 * v1 + n2 * v2)
        outside = max(outside, delta - extent)
        if delta >= extent:
            fraction = 0.0
        elif delta > -extent:
            fraction *= 0.5 * (extent - delta) / extent
    bound = max(best_c, outside) if f_c >= 0 else best_o
    if best_c >= -law.margin:
        if fraction == 0.0:
            return max(best_c, 0.0), f_c, bound  # the patch lies beside b: no contact
        return best_c * fraction, f_c, bound
    if best_c > best_o:
        return best_c, f_c, bound
    return best_o, f_o, bound


@njit(cache=True)
def pair_wrenches(pairs, sums, force, torque):
    """Add the pairs' sums (:func:`contact_entries`) to the blocks: ``F`` and ``M`` about
    ``c_a`` on ``a``, ``-F`` and ``-(M + arm x F)`` about ``c_b`` on ``b``."""
    for q in range(pairs.a.shape[0]):
        a = pairs.a[q]
        b = pairs.b[q]
        arm = pairs.arm[q]
        f0, f1, f2 = sums[q, 0], sums[q, 1], sums[q, 2]
        force[a, 0] += f0
        force[a, 1] += f1
        force[a, 2] += f2
        torque[a, 0] += sums[q, 3]
        torque[a, 1] += sums[q, 4]
        torque[a, 2] += sums[q, 5]
        force[b, 0] -= f0
        force[b, 1] -= f1
        force[b, 2] -= f2
        torque[b, 0] -= sums[q, 3] + arm[1] * f2 - arm[2] * f1
        torque[b, 1] -= sums[q, 4] + arm[2] * f0 - arm[0] * f2
        torque[b, 2] -= sums[q, 5] + arm[0] * f1 - arm[1] * f0


@njit(cache=True)
def _chunks(model, state, scratch, pairs):
    """Write the pairs' frames; the chunks of the entries (count and size, a function of their
    number only, so that the serial and the parallel loops add in the same order and agree bit
    for bit) and their zeroed sums (n_chunks, p, 6)."""
    contacts, motion = state
    pair_frames(motion, scratch.rot, model[1], model[2], pairs)
    m = contacts.node.size
    n_chunks = max(1, min(MAX_CHUNKS, (m + ENTRY_CHUNK - 1) // ENTRY_CHUNK))
    return n_chunks, (m + n_chunks - 1) // n_chunks, np.zeros((n_chunks, pairs.a.shape[0], 6))


@njit(cache=True)
def node_contacts(model, state, dt, scratch, pairs, record):
    """Every entry, adding to ``scratch.force`` and ``scratch.torque`` (arguments as
    :func:`contact_entries`; ``scratch.rot`` holds the current rotations)."""
    n_chunks, size, sums = _chunks(model, state, scratch, pairs)
    for c in range(n_chunks):
        _chunk(c, size, model, state, dt, scratch, pairs, record, sums)
    _add_chunks(sums, pairs, scratch)


@njit(cache=True)
def node_contacts_parallel(model, state, dt, scratch, pairs, record):
    """:func:`node_contacts` with the chunks in a ``prange`` loop (:func:`_parallel_chunks`):
    each chunk sums into its own buffer, and the buffers are added in chunk order (same
    result, bit for bit)."""
    n_chunks, size, sums = _chunks(model, state, scratch, pairs)
    nodes, bodies, shapes, law = model
    contacts, motion = state
    _parallel_chunks(nodes, bodies, shapes, law, contacts, motion, scratch, pairs, sums,
                     (dt, record, size))  # fmt: skip
    _add_chunks(sums, pairs, scratch)


@njit(cache=True, parallel=True)
def _parallel_chunks(nodes, bodies, shapes, law, contacts, motion, scratch, pairs, sums, step):
    """Chunk ``c`` into ``sums[c]`` for every chunk, in a ``prange`` loop; ``step = (dt,
    record, size)`` (see :func:`_chunk`). The state's groups come in one by one and the
    tuples are built inside the loop: numba 0.68 rejects a tuple of them as an argument of
    the loop's body, and can lose writes into arrays unpacked from a tuple before the loop."""
    for c in prange(sums.shape[0]):
        _chunk(c, step[2], (nodes, bodies, shapes, law), (contacts, motion), step[0], scratch,
               pairs, step[1], sums)  # fmt: skip


@njit(cache=True)
def _chunk(c, size, model, state, dt, scratch, pairs, record, sums):
    """Entries of chunk ``c`` (of ``size`` entries) into ``sums[c]``."""
    m = state[0].node.size
    contact_entries(c * size, min(m, (c + 1) * size), model, state, dt, scratch, pairs, record,
                    sums[c])  # fmt: skip


@njit(cache=True)
def _add_chunks(sums, pairs, scratch):
    """Chunk sums, in chunk order, into the blocks' wrenches."""
    for c in range(1, sums.shape[0]):
        sums[0] += sums[c]
    pair_wrenches(pairs, sums[0], scratch.force, scratch.torque)


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
        # no temporaries in this loop (an array per node and step was half the step's cost)
        r0x, r0y, r0z = ind_r0[e, 0], ind_r0[e, 1], ind_r0[e, 2]
        rx = rot[a, 0, 0] * r0x + rot[a, 0, 1] * r0y + rot[a, 0, 2] * r0z
        ry = rot[a, 1, 0] * r0x + rot[a, 1, 1] * r0y + rot[a, 1, 2] * r0z
        rz = rot[a, 2, 0] * r0x + rot[a, 2, 1] * r0y + rot[a, 2, 2] * r0z
        # the node relative to the centre and its velocity relative to the sphere's
        d = (pos[a, 0] + rx - centre[0], pos[a, 1] + ry - centre[1], pos[a, 2] + rz - centre[2])
        va = (
            vel[a, 0] + omega[a, 1] * rz - omega[a, 2] * ry - velocity[0],
            vel[a, 1] + omega[a, 2] * rx - omega[a, 0] * rz - velocity[1],
            vel[a, 2] + omega[a, 0] * ry - omega[a, 1] * rx - velocity[2],
        )
        touching, f = _sphere_force(d, va, radius, k_n, ind_area[e], beta)
        out_force[e, 0], out_force[e, 1], out_force[e, 2] = f
        if touching:
            f0, f1, f2 = f
            force[a, 0] += f0
            force[a, 1] += f1
            force[a, 2] += f2
            torque[a, 0] += ry * f2 - rz * f1
            torque[a, 1] += rz * f0 - rx * f2
            torque[a, 2] += rx * f1 - ry * f0
            p_total -= f2
    return p_total


@njit(cache=True, inline="always")
def _sphere_force(d, va, radius, k_n, area, beta):
    """Whether a node touches the sphere, and the sphere's force on it [N] (zero if not).

    ``d`` (3-tuple) is the node relative to the sphere's centre [m], ``va`` its velocity
    relative to the sphere [m/s], ``radius`` [m], ``k_n`` the penalty [Pa/m], ``area`` the
    node's area [m^2], ``beta`` the normal dashpot [s]."""
    dist = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    depth = radius - dist
    touching = not (depth <= 0.0 or dist == 0.0)
    f = (0.0, 0.0, 0.0)
    if touching:
        n0, n1, n2 = d[0] / dist, d[1] / dist, d[2] / dist
        vn = va[0] * n0 + va[1] * n1 + va[2] * n2
        sigma = k_n * (depth - beta * vn)
        if sigma < 0.0:
            sigma = 0.0
        f = (sigma * area * n0, sigma * area * n1, sigma * area * n2)
    return touching, f


@njit(cache=True)
def elastic_energy(pair_node, pair_weight, node_area, out_depth, k_n):
    """Normal penalty energy ``sum 1/2 k_n d^2 w A`` of the entries in contact [J]."""
    total = 0.0
    for e in range(pair_node.shape[0]):
        d = out_depth[e]
        if d > 0.0:
            total += 0.5 * k_n * d * d * pair_weight[e] * node_area[pair_node[e]]
    return total
