r"""Rigid-plastic capacities of the spring grid: shear, torsion and the torsion section.

Under a normal force ``N`` [N] alone each spring has the friction capacity
:math:`r_i = A_i (c - \mu N / A)` [N] (:func:`shear_capacities`). The admissible
``(f1, f2, m3)`` [N, N, N m] form the Minkowski sum of the spring discs; its boundary points for a
generalised sliding velocity ``(v1, v2, omega)`` [m/s, m/s, rad/s] or a twisting centre [m] are
given in closed form (:func:`support_resultants`, :func:`twist_centre_resultants`), and the
largest torsion at a fixed shear by a batched Newton method (:func:`torsion_section`). Also the
closed-form torsion coefficient of a rectangle ``c_T`` [m] (seed 001, Eq. (11)).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial

import numpy as np

from dem.interface_strength.springs import CoulombSpringLaw, SpringInterface, _positive
from dem.kernels.interface_law import torsion_coefficient


class InterfaceStrengthError(RuntimeError):
    """A strength computation failed (solver status other than optimal, no convergence)."""


def torsion_coefficient_rectangle(l1: float, l2: float) -> float:
    r"""Torsion coefficient ``c_T`` of a rectangle under uniform pressure (closed form).

    Under uniform normal stress and pure twist about the centroid, every point slides with the
    friction stress :math:`\mu |N| / A` perpendicular to its radius, so
    :math:`m_{3,u} = c_T \mu |N|` with the mean distance to the centroid

    .. math::

        c_T = \frac{1}{A}\int_A \sqrt{y_1^2 + y_2^2}\,dA
            = \frac{1}{6}\left[d + \frac{l_1^2}{2 l_2}\ln\frac{l_2 + d}{l_1}
              + \frac{l_2^2}{2 l_1}\ln\frac{l_1 + d}{l_2}\right],
        \qquad d = \sqrt{l_1^2 + l_2^2}.

    Derivation: on one quarter :math:`[0,p]\times[0,q]` (``p = l1/2``, ``q = l2/2``), polar
    integration over the two triangles cut by the diagonal gives
    :math:`\int r\,dA = \frac{1}{6}[2pq\,\rho + p^3 \ln\frac{q+\rho}{p} + q^3\ln\frac{p+\rho}{q}]`
    with :math:`\rho = \sqrt{p^2+q^2}`; dividing by ``pq`` gives the formula. For a square of
    side ``a``: :math:`c_T = a(\sqrt2 + \ln(1+\sqrt2))/6 \approx 0.3826\,a`. The printed seed
    001 Eq. (11) has :math:`l_1^2/(2 l_2^2)` where a length is needed (a typo); with
    ``l1 = 0.3 m``, ``l2 = 0.2 m`` this form gives ``c_T = 0.096812 m`` and
    ``m_{3,u} = 16.26 N m`` for ``mu |N| = 168 N`` (seed 001: 16.2 N m).

    Parameters
    ----------
    l1, l2 : float
        Sides of the rectangle [m].

    Returns
    -------
    float
        ``c_T`` [m].
    """
    l1 = _positive("l1 (interface side along y1) [m]", l1)
    l2 = _positive("l2 (interface side along y2) [m]", l2)
    return float(torsion_coefficient(l1, l2))


def shear_capacities(
    interface: SpringInterface, law: CoulombSpringLaw, normal_force: float
) -> np.ndarray:
    r"""Friction capacity of each spring under a uniformly distributed normal force.

    .. math:: r_i = A_i \,(c - \mu N / A), \qquad N \le \sigma_t A.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Spring law.
    normal_force : float
        Normal force ``N = f3`` [N], negative in compression.

    Returns
    -------
    ndarray, shape (n,)
        Capacities ``r_i`` [N].

    Raises
    ------
    ValueError
        If ``normal_force`` is not below the tensile capacity ``sigma_t A`` (for a dry joint:
        if ``N >= 0``), or if the capacities vanish.
    """
    n_force = float(normal_force)
    if not math.isfinite(n_force):
        raise ValueError(f"normal_force [N] must be finite, got {normal_force!r}")
    area = interface.area
    tensile_capacity = law.tensile_strength * area
    if n_force >= tensile_capacity:
        raise ValueError(
            "normal_force [N] must be below the tensile capacity sigma_t*A = "
            f"{tensile_capacity:g} N (compression negative); got {n_force:g} N"
        )
    sigma_n = n_force / area
    caps = interface.areas * (law.cohesion - law.mu * sigma_n)
    if not np.all(caps >= 0.0) or not np.any(caps > 0.0):
        raise ValueError(
            f"normal_force [N] = {n_force:g} leaves no shear strength (c - mu*sigma_n <= 0)"
        )
    return caps


def _slip_velocity(positions: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slip velocities (m, n) of springs for generalised velocities w (m, 3)."""
    v1 = w[:, 0:1] - w[:, 2:3] * positions[None, :, 1]
    v2 = w[:, 1:2] + w[:, 2:3] * positions[None, :, 0]
    return v1, v2


def _support(positions, caps, w, eps):
    """Support value, point (f1, f2, m3) and Hessian blocks for w (m, 3); |v| floored by eps."""
    v1, v2 = _slip_velocity(positions, w)
    norm = np.sqrt(v1 * v1 + v2 * v2 + eps * eps)
    # a spring exactly at the twisting centre (possible only with eps = 0) carries no force
    safe = np.where(norm > 0.0, norm, 1.0)
    u1, u2 = v1 / safe, v2 / safe
    f1 = u1 @ caps
    f2 = u2 @ caps
    m3 = (positions[None, :, 0] * u2 - positions[None, :, 1] * u1) @ caps
    h = norm @ caps
    return h, f1, f2, m3, u1, u2, norm


def support_resultants(
    interface: SpringInterface, capacities: np.ndarray, directions: np.ndarray
) -> np.ndarray:
    r"""Boundary points of the strength set for generalised sliding velocities.

    For ``w = (v1, v2, omega)`` each spring slides with velocity
    :math:`(v_1 - \omega y_2,\; v_2 + \omega y_1)` and carries the force ``r_i`` along it; the
    resultant maximises ``w . (f1, f2, m3)`` over all admissible spring forces (maximum
    dissipation), i.e. it is the support point of the Minkowski sum of spring discs.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    capacities : ndarray, shape (n,)
        Spring friction capacities [N] (:func:`shear_capacities`).
    directions : ndarray, shape (m, 3) or (3,)
        Generalised velocities ``(v1, v2, omega)`` [m/s, m/s, rad/s] (any common scale).

    Returns
    -------
    ndarray, shape (m, 3) or (3,)
        ``(f1, f2, m3)`` [N, N, N m] about the interface reference point.
    """
    w = np.asarray(directions, dtype=np.float64)
    single = w.ndim == 1
    w = np.atleast_2d(w)
    if w.shape[1] != 3:
        raise ValueError(f"directions must have shape (m, 3), got {w.shape}")
    caps = np.asarray(capacities, dtype=np.float64)
    if caps.shape != (interface.n_springs,):
        raise ValueError(f"capacities must have shape ({interface.n_springs},), got {caps.shape}")
    _, f1, f2, m3, *_ = _support(interface.positions, caps, w, 0.0)
    out = np.column_stack([f1, f2, m3])
    return out[0] if single else out


def twist_centre_resultants(
    interface: SpringInterface, capacities: np.ndarray, centres: np.ndarray
) -> np.ndarray:
    """Resultants when the interface twists (counter-clockwise) about given centres.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    capacities : ndarray, shape (n,)
        Spring friction capacities [N].
    centres : ndarray, shape (m, 2)
        Twisting centres ``(y1, y2)`` [m].

    Returns
    -------
    ndarray, shape (m, 3)
        ``(f1, f2, m3)`` [N, N, N m] about the interface reference point.
    """
    c = np.atleast_2d(np.asarray(centres, dtype=np.float64))
    if c.shape[1] != 2:
        raise ValueError(f"centres must have shape (m, 2), got {c.shape}")
    # rotation omega = 1 about c: v(y) = omega x (y - c) -> (v1, v2) = (c2, -c1) at the origin
    w = np.column_stack([c[:, 1], -c[:, 0], np.ones(c.shape[0])])
    return support_resultants(interface, capacities, w)


def shear_strength(
    interface: SpringInterface, law: CoulombSpringLaw, normal_force: float, angle: float = 0.0
) -> float:
    """Shear strength along the direction ``angle`` with no torsion applied [N].

    A uniform translation makes every spring slide in the same direction, so the strength is
    ``sum r_i = mu (f_t - N)`` for any angle (seed 001, Eq. (10)), with ``f_t = sigma_t A`` the
    tensile capacity of the interface and ``N`` the normal force (negative in compression).

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Spring law.
    normal_force : float
        Normal force [N], negative in compression.
    angle : float
        Direction of the shear in the ``(y1, y2)`` plane [rad].

    Returns
    -------
    float
        Magnitude of the ultimate shear force [N].
    """
    caps = shear_capacities(interface, law, normal_force)
    e = np.array([math.cos(angle), math.sin(angle), 0.0])
    point = support_resultants(interface, caps, e)
    return float(point[:2] @ e[:2])


def torsion_section(
    interface: SpringInterface,
    capacities: np.ndarray,
    shear: np.ndarray,
    *,
    tol: float = 1e-12,
    max_residual: float = 1e-7,
    max_iter: int = 100,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Largest torsion compatible with given shear forces (batched Newton, exact).

    Solves, for each prescribed shear ``f = (f1, f2)``,

    .. math::

        m_3^{max}(f) = \min_{v}\; h(v, 1) - f\cdot v, \qquad
        h(w) = \sum_i r_i\,|(w_1 - w_3 y_{2,i},\; w_2 + w_3 y_{1,i})|,

    the dual of maximising ``m3`` over the Minkowski sum of spring discs at fixed shear. The
    minimiser ``v`` locates the twisting centre ``(-v2, v1)``; the gradient condition is
    ``f(v) = f``. Newton steps use the exact Hessian
    :math:`\sum_i r_i (I - u_i u_i^T)/|v_i|` with a backtracking line search.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    capacities : ndarray, shape (n,)
        Spring friction capacities [N].
    shear : ndarray, shape (m, 2)
        Prescribed shear forces [N]; each must lie strictly inside the shear strength disc.
    tol : float
        Target tolerance on the shear residual, relative to the shear strength ``sum r_i``.
    max_residual : float
        Largest relative residual accepted when Newton stagnates at round-off (near the kinks
        of ``h`` at the springs). The returned point is exact for the shear actually reached,
        which is returned too.
    max_iter : int
        Newton iteration limit.

    Returns
    -------
    m3 : ndarray, shape (m,)
        Maximum torsion [N m].
    centres : ndarray, shape (m, 2)
        Twisting centres [m].
    shear_reached : ndarray, shape (m, 2)
        Shear of the returned boundary point [N] (equal to ``shear`` within ``max_residual``).

    Raises
    ------
    InterfaceStrengthError
        If Newton does not converge.
    """
    caps = np.asarray(capacities, dtype=np.float64)
    f_target = np.atleast_2d(np.asarray(shear, dtype=np.float64))
    f_u = float(caps.sum())
    s = np.hypot(f_target[:, 0], f_target[:, 1])
    if np.any(s >= f_u):
        raise ValueError(f"shear magnitude must be below the shear strength {f_u:g} N")
    pos = interface.positions
    size = float(np.max(np.ptp(pos, axis=0))) + float(np.sqrt(interface.area))
    eps = 1e-9 * size
    v = _initial_points(interface, f_target, s, f_u, size)
    m = f_target.shape[0]
    dual = partial(_dual_terms, pos, caps, eps)
    gnorm = _minimise_dual(dual, v, f_target, tol * f_u, max_iter)
    # a residual g means the point found is the exact boundary point for the shear f + g
    if gnorm.max() > max_residual * f_u:
        raise InterfaceStrengthError(
            f"torsion_section: Newton did not converge in {max_iter} iterations "
            f"(max shear residual {gnorm.max():.3g} N for shear strength {f_u:.6g} N)"
        )
    w = np.hstack([v, np.ones((m, 1))])
    _, f1, f2, m3, *_ = _support(pos, caps, w, eps)
    centres = np.column_stack([-v[:, 1], v[:, 0]])
    return m3, centres, np.column_stack([f1, f2])


def _initial_points(interface, f_target, s, f_u, size) -> np.ndarray:
    """Newton's start ``v`` (m, 2) for the shears ``f_target`` (m, 2) [N] of magnitude ``s``:
    a twist centre on the normal to the shear through the centroid, further out [m] (relative
    to the interface ``size``) the nearer the shear is to the strength ``f_u``."""
    shat = s / f_u
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.where(s[:, None] > 0, f_target / np.where(s > 0, s, 1.0)[:, None], 0.0)
    dist = size * shat / (1.0 - shat)
    return e * dist[:, None] + interface.centroid[None, ::-1] * np.array([1.0, -1.0])


def _dual_terms(
    positions: np.ndarray, caps: np.ndarray, eps: float, vv: np.ndarray, ft: np.ndarray
):
    r"""The dual function of :func:`torsion_section`, :math:`\phi(v) = h(v, 1) - f \cdot v`,
    at the points ``vv`` (k, 2) for the shears ``ft`` (k, 2) [N]: ``(phi, g, h11, h12, h22)``,
    with ``g`` its gradient (the shear residual [N]) and the three entries of its Hessian."""
    w = np.hstack([vv, np.ones((vv.shape[0], 1))])
    h, f1, f2, _, u1, u2, norm = _support(positions, caps, w, eps)
    phi = h - np.einsum("ij,ij->i", vv, ft)
    g = np.column_stack([f1, f2]) - ft
    k = caps[None, :] / norm
    h11 = (k * (1.0 - u1 * u1)).sum(1)
    h22 = (k * (1.0 - u2 * u2)).sum(1)
    h12 = -(k * u1 * u2).sum(1)
    return phi, g, h11, h12, h22


def _minimise_dual(
    dual: Callable, v: np.ndarray, f_target: np.ndarray, gtol: float, max_iter: int
) -> np.ndarray:
    """Batched Newton with backtracking on ``dual`` from ``v`` (m, 2), updated in place, until
    each shear residual is at most ``gtol`` [N] (``dual(vv, ft)`` is :func:`_dual_terms` bound to
    the springs); returns the last residual norm of each point.

    A point whose line search fails has stagnated at round-off (kinks of ``h`` at the springs):
    it is frozen, and the caller judges its residual.
    """
    gnorm = np.full(f_target.shape[0], np.inf)
    todo = np.arange(f_target.shape[0])
    for _ in range(max_iter):
        vt, ft = v[todo], f_target[todo]
        phi, g, h11, h12, h22 = dual(vt, ft)
        gnorm[todo] = np.hypot(g[:, 0], g[:, 1])
        keep = gnorm[todo] > gtol
        todo, vt, ft, phi, g = todo[keep], vt[keep], ft[keep], phi[keep], g[keep]
        h11, h12, h22 = h11[keep], h12[keep], h22[keep]
        if todo.size == 0:
            break
        det = h11 * h22 - h12 * h12
        det = np.where(det > 0, det, np.finfo(float).tiny)
        step = -np.column_stack([h22 * g[:, 0] - h12 * g[:, 1], h11 * g[:, 1] - h12 * g[:, 0]])
        step /= det[:, None]
        ok, t = _backtrack(dual, vt, ft, phi, np.einsum("ij,ij->i", g, step), step)
        v[todo[ok]] = vt[ok] + t[ok, None] * step[ok]
        todo = todo[ok]
        if todo.size == 0:
            break
    return gnorm


def _backtrack(dual, vt, ft, phi, slope, step) -> tuple[np.ndarray, np.ndarray]:
    """Armijo backtracking along ``step`` (k, 2), at most 40 halvings: whether each point found
    a decrease, and its step length."""
    t = np.ones(len(vt))
    ok = np.zeros(len(vt), dtype=bool)
    for _ in range(40):
        trial = ~ok
        phi_new = dual(vt[trial] + t[trial, None] * step[trial], ft[trial])[0]
        ok[trial] = phi_new <= (
            phi[trial] + 1e-4 * t[trial] * slope[trial] + 1e-15 * np.abs(phi[trial])
        )
        if ok.all():
            break
        t = np.where(ok, t, 0.5 * t)
    return ok, t


def torsion_strength(
    interface: SpringInterface, law: CoulombSpringLaw, normal_force: float
) -> float:
    """Pure torsion strength ``m_{3,u}`` of the spring grid [N m] (no shear, no bending).

    The twisting centre is found by :func:`torsion_section` at zero shear (for a grid symmetric
    about its centroid it is the centroid and ``m_{3,u} = sum r_i |y_i|``).

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Spring law.
    normal_force : float
        Normal force [N], negative in compression.

    Returns
    -------
    float
        Torsion strength [N m] (``c_T mu (f_t - N)`` in the continuum limit, seed 001 Eq. (12)).
    """
    caps = shear_capacities(interface, law, normal_force)
    m3, _, _ = torsion_section(interface, caps, np.zeros((1, 2)))
    return float(m3[0])
