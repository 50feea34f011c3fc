"""Elastic-perfectly-plastic Coulomb springs of a fibre (spring grid) interface.

One rectangular (or any planar) interface between two rigid blocks is represented by ``n``
independent springs placed at the centres of its sub-areas (seed 001, Sec. 2.1, Fig. 3). Each
spring carries a normal force and a tangential force. The law of one spring is:

- normal: linear elastic, ``f_n = k_n u_n`` (``u_n > 0`` opens the joint, ``f_n < 0`` is
  compression), capped in tension by the spring's tensile force ``f_t`` (0 for a dry joint). A
  spring whose trial normal force exceeds ``f_t`` detaches: both forces vanish, and if it had a
  tensile strength it is marked broken and loses cohesion and tensile strength for good.
- tangential: linear elastic ``f_s = k_s (u_s - s)`` with the plastic slip ``s`` (2 components),
  inside the Coulomb cone ``|f_s| <= c_f - mu f_n`` (``c_f`` the cohesion force, seed 001
  Eq. (7) multiplied by the sub-area); a radial return maps a trial force outside the cone onto it
  and updates ``s`` (associated in the tangential plane, no dilatancy).

All quantities are per spring, SI: displacements [m], forces [N], stiffnesses [N/m]. The
kernels import only numpy, numba and math (house style); the typed wrappers live in
``dem.interface_strength``.
"""

import math

import numpy as np
from numba import njit

STATUS_STICK = 0
STATUS_SLIP = 1
STATUS_OPEN = 2


@njit(cache=True)
def friction_limit(f_n, mu, cohesion_force, touch_force):
    """Coulomb limit ``c_f - mu f_n >= 0`` of a spring [N]; a touching spring
    (``|f_n| <= touch_force``, a gap of round-off size) takes none from its normal force."""
    if abs(f_n) <= touch_force:
        return cohesion_force
    return max(cohesion_force - mu * f_n, 0.0)


@njit(cache=True)
def spring_return_map_one(u, slip, is_broken, spring, touch=0.0):
    """Return map of one Coulomb spring for a total displacement.

    Parameters
    ----------
    u : (float, float, float)
        ``(u_n, u_t1, u_t2)``: normal relative displacement, positive when the joint opens,
        and tangential relative displacements [m].
    slip : (float, float)
        Plastic slip ``(slip1, slip2)`` at the start of the step [m].
    is_broken : bool
        True if the spring has already failed in tension (then its cohesion and tensile
        forces are ignored: it behaves as a dry spring).
    spring : (float, float, float, float, float)
        ``(k_n, k_s, mu, cohesion_force, tensile_force)``: normal and tangential stiffness
        of the spring [N/m] (stiffness per area times the spring's area), friction
        coefficient ``tan(phi)`` [-], cohesion and tensile strength (0 for a no-tension
        spring) times the spring's area [N].
    touch : float
        Gap [m] below which a spring counts as touching, whatever the sign of its round-off
        (:mod:`dem.kernels.fibre_law`): closed up to this gap beyond its tensile strength,
        no friction from a normal force within ``k_n touch``, and sticking while its trial
        slip exceeds the friction limit by at most ``touch``. 0: the exact decisions.

    Returns
    -------
    f_n, f_t1, f_t2 : float
        Spring forces [N] (``f_n < 0`` compression).
    slip1, slip2 : float
        Updated plastic slip [m].
    is_broken : bool
        Updated tensile failure flag.
    status : int
        ``STATUS_STICK`` (0), ``STATUS_SLIP`` (1) or ``STATUS_OPEN`` (2).
    """
    u_n, u_t1, u_t2 = u
    slip1, slip2 = slip
    k_n, k_s, mu, cohesion_force, tensile_force = spring
    c_f = cohesion_force
    t_f = tensile_force
    if is_broken:
        c_f = 0.0
        t_f = 0.0
    f_n = k_n * u_n
    if f_n > t_f + k_n * touch:
        # detached: no force; the slip follows the motion so that re-contact starts unloaded
        return 0.0, 0.0, 0.0, u_t1, u_t2, is_broken or tensile_force > 0.0, STATUS_OPEN
    f_t1 = k_s * (u_t1 - slip1)
    f_t2 = k_s * (u_t2 - slip2)
    limit = friction_limit(f_n, mu, c_f, k_n * touch)
    norm = math.sqrt(f_t1 * f_t1 + f_t2 * f_t2)
    if norm <= limit + k_s * touch:
        return f_n, f_t1, f_t2, slip1, slip2, is_broken, STATUS_STICK
    scale = limit / norm
    f_t1 *= scale
    f_t2 *= scale
    return f_n, f_t1, f_t2, u_t1 - f_t1 / k_s, u_t2 - f_t2 / k_s, is_broken, STATUS_SLIP


@njit(cache=True)
def spring_return_map_many(u, state, springs, mu, out):
    """Batch of :func:`spring_return_map_one`.

    Parameters
    ----------
    u : ndarray, shape (n, 3)
        Spring displacements ``(u_t1, u_t2, u_n)`` [m].
    state : (slip, is_broken)
        Plastic slip (n, 2) [m] and tensile failure flags (n,) bool at the start of the step.
    springs : (k_n, k_s, cohesion_force, tensile_force)
        Per-spring (n,) stiffnesses [N/m] and cohesion and tensile strength forces [N].
    mu : float
        Friction coefficient [-].
    out : (force, slip, broken, status)
        Output forces ``(f_t1, f_t2, f_n)`` (n, 3) [N], slip (n, 2) [m] and flags (n,) (may
        alias ``state``), status codes (n,) int64.
    """
    slip, is_broken = state
    k_n, k_s, cohesion_force, tensile_force = springs
    out_force, out_slip, out_broken, out_status = out
    for i in range(u.shape[0]):
        f_n, f_t1, f_t2, s1, s2, brk, st = spring_return_map_one(
            (u[i, 2], u[i, 0], u[i, 1]),
            (slip[i, 0], slip[i, 1]),
            is_broken[i],
            (k_n[i], k_s[i], mu, cohesion_force[i], tensile_force[i]),
        )
        out_force[i, 0] = f_t1
        out_force[i, 1] = f_t2
        out_force[i, 2] = f_n
        out_slip[i, 0] = s1
        out_slip[i, 1] = s2
        out_broken[i] = brk
        out_status[i] = st


@njit(cache=True)
def spring_displacements(positions, d, out_u):
    """Spring displacements of a rigid relative motion of the two faces.

    Parameters
    ----------
    positions : ndarray, shape (n, 2)
        Spring positions ``(y1, y2)`` in the interface frame, relative to its reference point [m].
    d : ndarray, shape (6,)
        Relative motion ``(d1, d2, d3, delta1, delta2, delta3)``: translations [m] and small
        rotations [rad] about the reference point.
    out_u : ndarray, shape (n, 3)
        Output ``(u_t1, u_t2, u_n)`` [m]: ``u = d + delta x y``.
    """
    for i in range(positions.shape[0]):
        y1 = positions[i, 0]
        y2 = positions[i, 1]
        out_u[i, 0] = d[0] - d[5] * y2
        out_u[i, 1] = d[1] + d[5] * y1
        out_u[i, 2] = d[2] + d[3] * y2 - d[4] * y1


@njit(cache=True)
def spring_resultants(positions, force):
    """Force and moment resultants of the spring forces about the reference point.

    Parameters
    ----------
    positions : ndarray, shape (n, 2)
        Spring positions [m].
    force : ndarray, shape (n, 3)
        Spring forces ``(f_t1, f_t2, f_n)`` [N].

    Returns
    -------
    ndarray, shape (6,)
        ``(f1, f2, f3, m1, m2, m3)``: forces [N] and moments [N m], ``m = sum y x f``.
    """
    out = np.zeros(6)
    for i in range(positions.shape[0]):
        y1 = positions[i, 0]
        y2 = positions[i, 1]
        out[0] += force[i, 0]
        out[1] += force[i, 1]
        out[2] += force[i, 2]
        out[3] += y2 * force[i, 2]
        out[4] -= y1 * force[i, 2]
        out[5] += y1 * force[i, 1] - y2 * force[i, 0]
    return out


@njit(cache=True)
def spring_grid_path(
    positions, path, k_n, k_s, mu, cohesion_force, tensile_force, out_resultants, out_n_slip
):
    """Follow a path of relative motions with the spring grid (strain driven, no iteration).

    Each step applies the total relative motion ``path[k]`` and return-maps every spring from
    the state of step ``k - 1``. Because each spring is independent (a Winkler bed, seed 001
    Sec. 2.1) no equilibrium iteration is needed: the resultants are the interface actions.

    Parameters
    ----------
    positions : ndarray, shape (n, 2)
        Spring positions [m].
    path : ndarray, shape (n_steps, 6)
        Total relative motion at each step (see :func:`spring_displacements`).
    k_n, k_s, cohesion_force, tensile_force : ndarray, shape (n,)
        Per-spring stiffnesses [N/m] and strengths [N].
    mu : float
        Friction coefficient [-].
    out_resultants : ndarray, shape (n_steps, 6)
        Output resultants ``(f1, f2, f3, m1, m2, m3)`` [N, N m] at each step.
    out_n_slip : ndarray of int64, shape (n_steps,)
        Output number of sliding springs at each step.
    """
    n = positions.shape[0]
    u = np.zeros((n, 3))
    slip = np.zeros((n, 2))
    broken = np.zeros(n, dtype=np.bool_)
    force = np.zeros((n, 3))
    status = np.zeros(n, dtype=np.int64)
    for k in range(path.shape[0]):
        spring_displacements(positions, path[k], u)
        spring_return_map_many(
            u,
            (slip, broken),
            (k_n, k_s, cohesion_force, tensile_force),
            mu,
            (force, slip, broken, status),
        )
        res = spring_resultants(positions, force)
        for j in range(6):
            out_resultants[k, j] = res[j]
        count = 0
        for i in range(n):
            if status[i] == STATUS_SLIP:
                count += 1
        out_n_slip[k] = count
