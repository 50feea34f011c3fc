r"""Strength of one rigid-block interface from a fibre (spring grid) model.

The interface between two rigid blocks is cut into ``n1 x n2`` rectangular sub-areas, each with
one spring at its centre (seed 001, Sec. 2.1, Fig. 3). A spring carries a normal force (no
tension, or a tensile strength) and a tangential force bounded by Coulomb friction
:math:`|f_{s,i}| \le c A_i - \mu f_{n,i}` (seed 001, Eq. (7) on each sub-area). The resultant
actions of the interface about its centre are the shear forces ``f1, f2`` [N], the normal force
``f3 = N`` [N] (negative in compression), the bending moments ``m1, m2`` [N m] and the torsion
``m3`` [N m].

Under a normal force alone the springs are equally compressed (uniform normal stress), so each
has a fixed friction capacity :math:`r_i = A_i (c - \mu N / A)` [N]. The set of admissible
``(f1, f2, m3)`` is then the Minkowski sum of the spring discs of radii ``r_i``; its boundary is
reached when every spring slides in the direction of the relative velocity of a rigid planar
motion (a twist about a centre, or a translation). Three routes to that boundary are provided and
agree to round-off:

- kinematic (exact, vectorised): the support point of the set for a generalised velocity
  ``w = (v1, v2, omega)``; the spring forces are ``r_i`` times the unit slip velocity
  (:func:`support_resultants`, :func:`twist_centre_resultants`). Sections at a fixed shear are
  found by a batched Newton method on the (convex) support function (:func:`interaction_domain`).
- static (convex program): maximise the load along a direction subject to the per-spring
  second-order cones, with cvxpy + Clarabel (:func:`coulomb_spring_constraints`,
  :func:`max_torsion_socp`).
- incremental: elastic-perfectly-plastic springs driven along a proportional relative motion
  (numba return mapping in :mod:`dem.kernels.spring_grid`, :func:`incremental_analysis`); once
  every spring slides the resultants equal the kinematic ones.

Units are SI throughout: m, N, Pa, rad.
"""

from __future__ import annotations

import logging
import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from dem.kernels import spring_grid

logger = logging.getLogger(__name__)

__all__ = [
    "SpringInterface",
    "CoulombSpringLaw",
    "InteractionDomain",
    "IncrementalResult",
    "SocpResult",
    "InterfaceStrengthError",
    "torsion_coefficient_rectangle",
    "shear_capacities",
    "support_resultants",
    "twist_centre_resultants",
    "shear_strength",
    "torsion_strength",
    "torsion_section",
    "interaction_domain",
    "fit_alpha",
    "interaction_law_torsion",
    "reduced_rectangle",
    "torsion_strength_with_bending",
    "torsion_strength_with_bending_closed_form",
    "no_tension_normal_forces",
    "torsion_strength_elastic_bending",
    "incremental_analysis",
    "coulomb_spring_constraints",
    "max_torsion_socp",
]


class InterfaceStrengthError(RuntimeError):
    """A strength computation failed (solver status other than optimal, no convergence)."""


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a finite positive number, got {value!r}")
    return value


def _non_negative(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value < 0.0:
        raise ValueError(f"{name} must be a finite non-negative number, got {value!r}")
    return value


# ----------------------------------------------------------------------------------------------
# geometry and law
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SpringInterface:
    """Springs of one planar interface, in its local frame ``(y1, y2)``.

    Parameters
    ----------
    positions : ndarray, shape (n, 2)
        Spring positions relative to the interface reference point (the centre of the
        rectangle for :meth:`rectangle`) [m].
    areas : ndarray, shape (n,)
        Tributary area of each spring [m^2].

    Notes
    -----
    Value semantics: the arrays are copied and made read-only; :meth:`restricted` returns a new
    interface.
    """

    positions: np.ndarray
    areas: np.ndarray

    def __post_init__(self) -> None:
        pos = np.array(self.positions, dtype=np.float64, order="C", copy=True)
        areas = np.array(self.areas, dtype=np.float64, copy=True)
        if pos.ndim != 2 or pos.shape[1] != 2:
            raise ValueError(f"positions must have shape (n, 2), got {pos.shape}")
        if areas.shape != (pos.shape[0],):
            raise ValueError(f"areas must have shape ({pos.shape[0]},), got {areas.shape}")
        if pos.shape[0] == 0:
            raise ValueError("an interface needs at least one spring (n_springs = 0)")
        if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(areas))):
            raise ValueError("positions and areas must be finite")
        if np.any(areas < 0.0) or not np.any(areas > 0.0):
            raise ValueError("areas must be non-negative with a positive total")
        pos.flags.writeable = False
        areas.flags.writeable = False
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "areas", areas)

    @classmethod
    def rectangle(cls, l1: float, l2: float, n1: int, n2: int | None = None) -> SpringInterface:
        """Regular grid of ``n1 x n2`` springs on a rectangle centred at the origin.

        Parameters
        ----------
        l1, l2 : float
            Sides along ``y1`` and ``y2`` [m].
        n1 : int
            Number of sub-areas along ``y1``.
        n2 : int, optional
            Number along ``y2`` (default ``n1``).

        Returns
        -------
        SpringInterface
            ``n1 * n2`` springs at the sub-area centres, each with area ``l1 l2 / (n1 n2)``.
        """
        l1 = _positive("l1 (interface side along y1) [m]", l1)
        l2 = _positive("l2 (interface side along y2) [m]", l2)
        n2 = n1 if n2 is None else n2
        for name, n in (("n1 (springs along y1)", n1), ("n2 (springs along y2)", n2)):
            if isinstance(n, bool) or int(n) != n or int(n) < 1:
                raise ValueError(f"{name} must be a positive integer, got {n!r}")
        n1, n2 = int(n1), int(n2)
        y1 = (np.arange(n1) + 0.5) * (l1 / n1) - 0.5 * l1
        y2 = (np.arange(n2) + 0.5) * (l2 / n2) - 0.5 * l2
        g1, g2 = np.meshgrid(y1, y2, indexing="ij")
        pos = np.column_stack([g1.ravel(), g2.ravel()])
        return cls(pos, np.full(n1 * n2, l1 * l2 / (n1 * n2)))

    @property
    def n_springs(self) -> int:
        """Number of springs."""
        return int(self.positions.shape[0])

    @property
    def area(self) -> float:
        """Total area [m^2]."""
        return float(self.areas.sum())

    @property
    def centroid(self) -> np.ndarray:
        """Area-weighted centroid of the springs, shape (2,) [m]."""
        return self.areas @ self.positions / self.area

    def restricted(self, mask: np.ndarray) -> SpringInterface:
        """The springs selected by a boolean ``mask`` of shape (n,), same reference point."""
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (self.n_springs,):
            raise ValueError(f"mask must have shape ({self.n_springs},), got {mask.shape}")
        if not mask.any():
            raise ValueError("mask selects no spring (n_springs = 0)")
        return SpringInterface(self.positions[mask], self.areas[mask])


@dataclass(frozen=True)
class CoulombSpringLaw:
    """Mohr-Coulomb law of the interface springs (seed 001, Eqs. (7)-(8)).

    Parameters
    ----------
    mu : float
        Friction coefficient ``tan(phi)`` [-].
    cohesion : float
        Cohesion ``c`` [Pa] (0 for a dry joint).
    tensile_strength : float
        Tensile strength ``sigma_t`` [Pa] (0 for a dry joint). The seed takes
        ``c = mu sigma_t`` (the apex of the Coulomb cone); see :meth:`from_tensile_strength`.
    normal_stiffness, shear_stiffness : float
        Stiffness per unit area ``k_n``, ``k_s`` [Pa/m], used only by the incremental analysis.
        Defaults are seed 001 Sec. 2.1: 2.4 MPa/mm and 1 MPa/mm.
    """

    mu: float
    cohesion: float = 0.0
    tensile_strength: float = 0.0
    normal_stiffness: float = 2.4e9
    shear_stiffness: float = 1.0e9

    def __post_init__(self) -> None:
        _non_negative("mu (friction coefficient)", self.mu)
        _non_negative("cohesion [Pa]", self.cohesion)
        _non_negative("tensile_strength [Pa]", self.tensile_strength)
        _positive("normal_stiffness [Pa/m]", self.normal_stiffness)
        _positive("shear_stiffness [Pa/m]", self.shear_stiffness)

    @classmethod
    def from_tensile_strength(cls, mu: float, tensile_strength: float, **kw) -> CoulombSpringLaw:
        """Law with ``c = mu sigma_t`` as in seed 001, appendix (Fig. A1)."""
        return cls(mu=mu, cohesion=mu * tensile_strength, tensile_strength=tensile_strength, **kw)


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
    d = math.hypot(l1, l2)
    term1 = l1**2 / (2.0 * l2) * math.log((l2 + d) / l1)
    term2 = l2**2 / (2.0 * l1) * math.log((l1 + d) / l2)
    return (d + term1 + term2) / 6.0


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


# ----------------------------------------------------------------------------------------------
# kinematic (support function) route
# ----------------------------------------------------------------------------------------------


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
    ``sum r_i = mu (f_t - N)`` for any angle (seed 001, Eq. (10); 168 N for the seed's
    interface).

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
    # initial guess: a twist centre on the normal to the shear, further out for larger shear
    shat = s / f_u
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.where(s[:, None] > 0, f_target / np.where(s > 0, s, 1.0)[:, None], 0.0)
    dist = size * shat / (1.0 - shat)
    v = e * dist[:, None] + interface.centroid[None, ::-1] * np.array([1.0, -1.0])
    m = f_target.shape[0]

    def phi_grad_hess(vv, ft):
        w = np.hstack([vv, np.ones((vv.shape[0], 1))])
        h, f1, f2, _, u1, u2, norm = _support(pos, caps, w, eps)
        phi = h - np.einsum("ij,ij->i", vv, ft)
        g = np.column_stack([f1, f2]) - ft
        k = caps[None, :] / norm
        h11 = (k * (1.0 - u1 * u1)).sum(1)
        h22 = (k * (1.0 - u2 * u2)).sum(1)
        h12 = -(k * u1 * u2).sum(1)
        return phi, g, h11, h12, h22

    gnorm = np.full(m, np.inf)
    todo = np.arange(m)
    for _ in range(max_iter):
        vt, ft = v[todo], f_target[todo]
        phi, g, h11, h12, h22 = phi_grad_hess(vt, ft)
        gnorm[todo] = np.hypot(g[:, 0], g[:, 1])
        keep = gnorm[todo] > tol * f_u
        todo, vt, ft, phi, g = todo[keep], vt[keep], ft[keep], phi[keep], g[keep]
        h11, h12, h22 = h11[keep], h12[keep], h22[keep]
        if todo.size == 0:
            break
        det = h11 * h22 - h12 * h12
        det = np.where(det > 0, det, np.finfo(float).tiny)
        step = -np.column_stack([h22 * g[:, 0] - h12 * g[:, 1], h11 * g[:, 1] - h12 * g[:, 0]])
        step /= det[:, None]
        slope = np.einsum("ij,ij->i", g, step)
        t = np.ones(todo.size)
        ok = np.zeros(todo.size, dtype=bool)
        for _ in range(40):
            trial = ~ok
            phi_new = phi_grad_hess(vt[trial] + t[trial, None] * step[trial], ft[trial])[0]
            ok[trial] = phi_new <= (
                phi[trial] + 1e-4 * t[trial] * slope[trial] + 1e-15 * np.abs(phi[trial])
            )
            if ok.all():
                break
            t = np.where(ok, t, 0.5 * t)
        # points whose line search fails have stagnated at round-off (kinks of h at the
        # springs): they are frozen and judged on their residual below
        v[todo[ok]] = vt[ok] + t[ok, None] * step[ok]
        todo = todo[ok]
        if todo.size == 0:
            break
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


# ----------------------------------------------------------------------------------------------
# m3 - shear interaction domains (seed 001, Figs. 8-9, A4, Table A1)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class InteractionDomain:
    """Torsion-shear strength domain at a fixed normal force, for one shear direction.

    Parameters
    ----------
    shear : ndarray, shape (k,)
        Shear force magnitude [N], increasing from 0 to ``shear_ultimate``.
    torsion : ndarray, shape (k,)
        Torsion at the boundary [N m], decreasing from ``torsion_ultimate`` to 0.
    shear_vectors : ndarray, shape (k, 2)
        Shear forces ``(f1, f2)`` of the boundary points [N].
    shear_ultimate : float
        Shear strength ``f_{s,u}`` [N].
    torsion_ultimate : float
        Pure torsion strength ``m_{3,u}`` [N m].
    shear_angle : float
        Direction [rad] of the shear force (``mode="force"``) or of the relative sliding
        displacement at the centroid (``mode="displacement"``).
    mode : str
        ``"force"`` or ``"displacement"`` (see :func:`interaction_domain`).
    centres : ndarray, shape (k, 2)
        Twisting centres [m] (pure shear has its centre at infinity, stored as NaN).
    """

    shear: np.ndarray
    torsion: np.ndarray
    shear_vectors: np.ndarray = field(repr=False)
    shear_ultimate: float = 0.0
    torsion_ultimate: float = 0.0
    shear_angle: float = 0.0
    mode: str = "displacement"
    centres: np.ndarray = field(default=None, repr=False)

    @property
    def shear_normalised(self) -> np.ndarray:
        """``f / f_{s,u}``, shape (k,)."""
        return self.shear / self.shear_ultimate

    @property
    def torsion_normalised(self) -> np.ndarray:
        """``m3 / m_{3,u}``, shape (k,)."""
        return self.torsion / self.torsion_ultimate


def _displacement_points(interface, caps, e, rho):
    """Boundary points for twist centres at distance rho (k,) on the normal to e (2,)."""
    centres = interface.centroid[None, :] + rho[:, None] * np.array([-e[1], e[0]])[None, :]
    return twist_centre_resultants(interface, caps, centres), centres


def interaction_domain(
    interface: SpringInterface,
    law: CoulombSpringLaw,
    normal_force: float,
    *,
    shear_angle: float = 0.0,
    mode: str = "displacement",
    n_points: int = 129,
) -> InteractionDomain:
    """The m3 - shear strength domain of the spring grid (exact, vectorised).

    Parameters
    ----------
    interface : SpringInterface
        The springs (reference point at the centroid).
    law : CoulombSpringLaw
        Spring law.
    normal_force : float
        Normal force [N], negative in compression.
    shear_angle : float
        Direction [rad]: 0 is ``f1`` (seed 001 Table A1, 2nd column), ``pi/2`` is ``f2``
        (3rd column), ``pi/4`` is "``f1 = f2``" (4th column).
    mode : {"displacement", "force"}
        ``"displacement"``: the boundary reached by incremental analyses that combine a relative
        rotation ``delta3`` with a relative sliding displacement along ``shear_angle`` (seed 001
        Figs. 6b, 8); the twisting centre then lies on the line through the centroid normal to
        that direction, at distance ``rho = |d| / delta3``, and the points are given in closed
        form by :func:`twist_centre_resultants`. ``"force"``: the exact section of the strength
        set by a fixed shear force direction (:func:`torsion_section`, Newton). Both coincide
        when ``shear_angle`` is along a symmetry axis of the grid; for a rectangle at 45 degrees
        the force of the displacement-driven points is not at 45 degrees.
    n_points : int
        Number of points on the curve (>= 3).

    Returns
    -------
    InteractionDomain
        The domain curve, ordered by increasing shear.
    """
    if isinstance(n_points, bool) or int(n_points) != n_points or n_points < 3:
        raise ValueError(f"n_points must be an integer >= 3, got {n_points!r}")
    if mode not in ("displacement", "force"):
        raise ValueError(f"mode must be 'displacement' or 'force', got {mode!r}")
    caps = shear_capacities(interface, law, normal_force)
    f_u = float(caps.sum())
    e = np.array([math.cos(shear_angle), math.sin(shear_angle)])
    k = np.arange(n_points - 1)
    if mode == "displacement":
        size = float(np.max(np.ptp(interface.positions, axis=0))) + math.sqrt(interface.area)
        rho = 0.25 * size * np.tan(0.5 * np.pi * k / (n_points - 1))
        res, centres = _displacement_points(interface, caps, e, rho)
        vectors, m3 = res[:, :2], res[:, 2]
        shear = np.hypot(vectors[:, 0], vectors[:, 1])
    else:
        s = f_u * np.sin(0.5 * np.pi * k / (n_points - 1))
        m3, centres, vectors = torsion_section(interface, caps, s[:, None] * e[None, :])
        # each point is exact for the shear reached; its component along e is what is plotted
        shear = vectors @ e
    shear = np.append(shear, f_u)
    torsion = np.append(m3, 0.0)
    vectors = np.vstack([vectors, f_u * e])
    centres = np.vstack([centres, [np.nan, np.nan]])
    return InteractionDomain(
        shear, torsion, vectors, f_u, float(m3[0]), float(shear_angle), mode, centres
    )


def interaction_law_torsion(shear_normalised: np.ndarray, alpha: float) -> np.ndarray:
    r"""Torsion of the interaction law :math:`(m_3/m_{3,u})^\alpha + (f/f_{s,u})^2 = 1`.

    Seed 001, Eq. (14) and Eq. (A5).

    Parameters
    ----------
    shear_normalised : ndarray, shape (k,)
        ``f / f_{s,u}`` in [0, 1].
    alpha : float
        Exponent [-].

    Returns
    -------
    ndarray, shape (k,)
        ``m3 / m_{3,u}``.
    """
    x = np.clip(np.asarray(shear_normalised, dtype=np.float64), 0.0, 1.0)
    return (1.0 - x * x) ** (1.0 / alpha)


def fit_alpha(
    domain: InteractionDomain,
    method: str = "lsq",
    *,
    interface: SpringInterface | None = None,
    law: CoulombSpringLaw | None = None,
    normal_force: float | None = None,
) -> float:
    r"""Fit the exponent alpha of :math:`(m_3/m_{3,u})^\alpha + (f/f_{s,u})^2 \le 1`.

    Seed 001, Eq. (A5) and Table A1. The seed does not state how alpha was fitted; two
    reproducible definitions are offered.

    Parameters
    ----------
    domain : InteractionDomain
        The computed domain.
    method : {"lsq", "equal_ratio"}
        ``"lsq"``: least squares of the torsion misfit
        :math:`\hat m(\hat f) - (1-\hat f^2)^{1/\alpha}` at 401 uniformly spaced
        :math:`\hat f \in [0, 1]` (domain interpolated linearly).
        ``"equal_ratio"``: the law passes through the domain point where
        :math:`\hat m = \hat f` (the diagonal of the normalised plot),
        :math:`\alpha = \ln(1 - \hat f^2)/\ln \hat f`; that point is located exactly (root
        finding on the exact boundary) when ``interface``, ``law`` and ``normal_force`` are
        given, else by linear interpolation on the curve.

    Returns
    -------
    float
        alpha [-].
    """
    f = domain.shear_normalised
    m = domain.torsion_normalised
    if method == "lsq":
        grid = np.linspace(0.0, 1.0, 401)
        m_grid = np.interp(grid, f, m)

        def misfit(alpha: float) -> float:
            return float(np.sum((m_grid - interaction_law_torsion(grid, alpha)) ** 2))

        res = minimize_scalar(misfit, bounds=(0.3, 6.0), method="bounded",
                              options={"xatol": 1e-8})
        return float(res.x)
    if method != "equal_ratio":
        raise ValueError(f"method must be 'lsq' or 'equal_ratio', got {method!r}")
    g = m - f
    j = int(np.nonzero(g <= 0.0)[0][0])
    x0, x1 = f[j - 1], f[j]
    x = x0 + (x1 - x0) * g[j - 1] / (g[j - 1] - g[j])
    if interface is not None and law is not None and normal_force is not None:
        caps = shear_capacities(interface, law, normal_force)
        e = np.array([math.cos(domain.shear_angle), math.sin(domain.shear_angle)])
        if domain.mode == "displacement":
            cen = interface.centroid
            r0 = float(np.hypot(*(domain.centres[j - 1] - cen)))
            r1 = float(np.hypot(*(domain.centres[j] - cen))) if j < len(f) - 1 else 1e3 * r0

            def gap_rho(rho: float) -> float:
                res, _ = _displacement_points(interface, caps, e, np.array([rho]))
                fx = math.hypot(res[0, 0], res[0, 1]) / domain.shear_ultimate
                return res[0, 2] / domain.torsion_ultimate - fx

            rho = brentq(gap_rho, r0, r1, xtol=1e-15, rtol=1e-14)
            res, _ = _displacement_points(interface, caps, e, np.array([rho]))
            x = math.hypot(res[0, 0], res[0, 1]) / domain.shear_ultimate
        else:

            def gap(xx: float) -> float:
                m3, _, _ = torsion_section(
                    interface, caps, (xx * domain.shear_ultimate * e)[None, :]
                )
                return float(m3[0] / domain.torsion_ultimate - xx)

            x = brentq(gap, x0, x1, xtol=1e-14)
    return float(math.log(1.0 - x * x) / math.log(x))


# ----------------------------------------------------------------------------------------------
# torsion with bending (seed 001, Fig. 10) and with tensile strength (Fig. A1)
# ----------------------------------------------------------------------------------------------


def reduced_rectangle(
    l1: float, l2: float, normal_force: float, m1: float, m2: float
) -> tuple[float, float, float, float]:
    """Compressed rectangle under eccentric normal force (uniform stress hypothesis).

    Following Orduna and Lourenco (2005a) as used in seed 001 Sec. 2.1.3, a no-tension
    interface carries ``N`` as a uniform stress over the largest rectangle centred at the
    eccentric resultant: ``e1 = -m2/N``, ``e2 = m1/N`` and sides ``l1 - 2|e1|``, ``l2 - 2|e2|``.

    Parameters
    ----------
    l1, l2 : float
        Interface sides [m].
    normal_force : float
        Normal force [N], negative (compression).
    m1, m2 : float
        Bending moments about ``y1`` and ``y2`` [N m].

    Returns
    -------
    tuple of float
        ``(e1, e2, l1_red, l2_red)`` [m].

    Raises
    ------
    ValueError
        If the normal force is not compressive or the eccentricity reaches the edge.
    """
    if not normal_force < 0.0:
        raise ValueError(f"normal_force [N] must be negative (compression), got {normal_force!r}")
    e1 = -m2 / normal_force
    e2 = m1 / normal_force
    l1r = l1 - 2.0 * abs(e1)
    l2r = l2 - 2.0 * abs(e2)
    if l1r <= 0.0 or l2r <= 0.0:
        raise ValueError(
            f"bending moments m1={m1:g}, m2={m2:g} N m exceed the rotation strength "
            f"(|m1| < |N| l2/2, |m2| < |N| l1/2)"
        )
    return e1, e2, l1r, l2r


def torsion_strength_with_bending_closed_form(
    l1: float, l2: float, mu: float, normal_force: float, m1: float, m2: float
) -> float:
    """``mu |N| c_T(l1 - 2|e1|, l2 - 2|e2|)`` [N m]: closed form under the uniform hypothesis."""
    _, _, l1r, l2r = reduced_rectangle(l1, l2, normal_force, m1, m2)
    return mu * abs(normal_force) * torsion_coefficient_rectangle(l1r, l2r)


def torsion_strength_with_bending(
    interface: SpringInterface,
    law: CoulombSpringLaw,
    normal_force: float,
    m1: float,
    m2: float,
    l1: float,
    l2: float,
) -> float:
    """Torsion strength of the spring grid when bending moments reduce the compressed area.

    Only the springs whose centres lie inside the reduced rectangle of
    :func:`reduced_rectangle` are compressed, equally (seed 001 Sec. 2.1.3: "an increasing
    relative rotation over a reduced rectangular area"); the torsion strength is found at zero
    shear by :func:`torsion_section`. The grid is not refined, so the curve is a staircase.

    Parameters
    ----------
    interface : SpringInterface
        Springs of the whole rectangle ``l1 x l2`` centred at the origin.
    law : CoulombSpringLaw
        Spring law (dry: no cohesion is used on the reduced area).
    normal_force : float
        Normal force [N], negative.
    m1, m2 : float
        Bending moments [N m].
    l1, l2 : float
        Sides of the rectangle [m].

    Returns
    -------
    float
        Torsion strength [N m].
    """
    e1, e2, l1r, l2r = reduced_rectangle(l1, l2, normal_force, m1, m2)
    p = interface.positions
    tol = 1e-12 * max(l1, l2)
    inside = (np.abs(p[:, 0] - e1) <= 0.5 * l1r + tol) & (np.abs(p[:, 1] - e2) <= 0.5 * l2r + tol)
    if not inside.any():
        # the reduced area is smaller than a cell: the force sits on the nearest spring
        inside[np.argmin(np.hypot(p[:, 0] - e1, p[:, 1] - e2))] = True
    sub = interface.restricted(inside)
    caps = shear_capacities(sub, CoulombSpringLaw(mu=law.mu), normal_force)
    m3, _, _ = torsion_section(sub, caps, np.zeros((1, 2)))
    return float(m3[0])


def no_tension_normal_forces(
    interface: SpringInterface,
    law: CoulombSpringLaw,
    normal_force: float,
    m1: float,
    m2: float,
    *,
    tol: float = 1e-12,
    max_iter: int = 100,
) -> np.ndarray:
    r"""Normal spring forces of elastic no-tension springs under ``(N, m1, m2)``.

    The alternative to the uniform-stress hypothesis of :func:`reduced_rectangle`: the two faces
    stay plane, ``u_i = d_3 + \delta_1 y_{2,i} - \delta_2 y_{1,i}``, and each spring carries
    ``n_i = k_n A_i \min(0, u_i)`` (a partialised section). ``(d_3, \delta_1, \delta_2)``
    minimise the convex energy
    :math:`\sum_i \tfrac12 k_n A_i \min(0,u_i)^2 - N d_3 - m_1\delta_1 - m_2\delta_2`
    (Newton with backtracking); the compressed zone is then generally not a rectangle.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Supplies ``normal_stiffness`` (the result does not depend on its value).
    normal_force : float
        Normal force [N], negative.
    m1, m2 : float
        Bending moments [N m] (``m1 = sum y2 n``, ``m2 = -sum y1 n``).
    tol : float
        Tolerance on the resultant residual relative to ``|N|``.
    max_iter : int
        Newton iteration limit.

    Returns
    -------
    ndarray, shape (n,)
        Normal spring forces [N] (``<= 0``).

    Raises
    ------
    ValueError
        If ``normal_force`` is not negative.
    InterfaceStrengthError
        If no equilibrium is found (resultant outside the core of the springs).
    """
    if not normal_force < 0.0:
        raise ValueError(f"normal_force [N] must be negative (compression), got {normal_force!r}")
    k = law.normal_stiffness * interface.areas
    b = np.column_stack([
        np.ones(interface.n_springs), interface.positions[:, 1], -interface.positions[:, 0]
    ])
    target = np.array([normal_force, m1, m2], dtype=np.float64)
    d = np.array([normal_force / k.sum(), 0.0, 0.0])

    def energy(dd):
        u = np.minimum(b @ dd, 0.0)
        return 0.5 * float(k @ (u * u)) - float(target @ dd)

    for _ in range(max_iter):
        u = b @ d
        n = k * np.minimum(u, 0.0)
        g = b.T @ n - target
        if np.max(np.abs(g)) <= tol * abs(normal_force):
            return n
        active = u < 0.0
        hess = (b[active] * k[active, None]).T @ b[active]
        try:
            step = -np.linalg.solve(hess, g)
        except np.linalg.LinAlgError as exc:
            raise InterfaceStrengthError("no_tension_normal_forces: singular section") from exc
        e0, t = energy(d), 1.0
        while energy(d + t * step) > e0 + 1e-4 * t * float(g @ step) and t > 1e-12:
            t *= 0.5
        d = d + t * step
    raise InterfaceStrengthError(
        f"no_tension_normal_forces: no equilibrium for N={normal_force:g} N, m1={m1:g}, "
        f"m2={m2:g} N m (resultant outside the core of the springs?)"
    )


def torsion_strength_elastic_bending(
    interface: SpringInterface,
    law: CoulombSpringLaw,
    normal_force: float,
    m1: float,
    m2: float,
) -> float:
    """Torsion strength with the elastic no-tension pressure of :func:`no_tension_normal_forces`.

    The friction capacities ``mu |n_i|`` are no longer uniform; the twisting centre is found by
    :func:`torsion_section` at zero shear.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Spring law (dry).
    normal_force : float
        Normal force [N], negative.
    m1, m2 : float
        Bending moments [N m].

    Returns
    -------
    float
        Torsion strength [N m].
    """
    n = no_tension_normal_forces(interface, law, normal_force, m1, m2)
    caps = law.mu * np.abs(n)
    m3, _, _ = torsion_section(interface, caps, np.zeros((1, 2)))
    return float(m3[0])


# ----------------------------------------------------------------------------------------------
# incremental elastic-perfectly-plastic analysis (numba kernel)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class IncrementalResult:
    """History of an incremental analysis of the spring grid.

    Parameters
    ----------
    motion : ndarray, shape (k, 6)
        Relative motion ``(d1, d2, d3, delta1, delta2, delta3)`` at each step [m, rad].
    resultants : ndarray, shape (k, 6)
        ``(f1, f2, f3, m1, m2, m3)`` at each step [N, N m].
    n_slip : ndarray, shape (k,)
        Number of sliding springs at each step.
    """

    motion: np.ndarray
    resultants: np.ndarray
    n_slip: np.ndarray


def incremental_analysis(
    interface: SpringInterface,
    law: CoulombSpringLaw,
    normal_force: float,
    direction: tuple[float, float, float],
    amplitude: float,
    n_steps: int = 100,
) -> IncrementalResult:
    """Elastic-perfectly-plastic analysis along a proportional relative motion.

    Step 0 closes the joint by ``d3 = N / sum(k_n A_i)`` (uniform compression). The steps
    ``1..n_steps`` add ``t (d1, d2, delta3)`` with ``t`` growing linearly to ``amplitude``,
    keeping ``d3`` fixed (the normal force stays ``N`` because the normal and tangential spring
    responses are uncoupled below detachment). Each spring follows a straight path, so the
    radial return is exact for any step size.

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Spring law with stiffnesses.
    normal_force : float
        Normal force [N], negative in compression.
    direction : tuple of float
        ``(d1, d2, delta3)`` of unit amplitude [m, m, rad].
    amplitude : float
        Final value of ``t`` [-].
    n_steps : int
        Number of increments.

    Returns
    -------
    IncrementalResult
        Histories of shape ``(n_steps + 1, ...)``.
    """
    shear_capacities(interface, law, normal_force)  # checks the normal force
    _positive("amplitude", amplitude)
    if isinstance(n_steps, bool) or int(n_steps) != n_steps or n_steps < 1:
        raise ValueError(f"n_steps must be a positive integer, got {n_steps!r}")
    areas = interface.areas
    k_n = law.normal_stiffness * areas
    k_s = law.shear_stiffness * areas
    d3 = normal_force / float(k_n.sum())
    t = np.linspace(0.0, amplitude, int(n_steps) + 1)
    d1, d2, r3 = (float(x) for x in direction)
    path = np.zeros((t.size, 6))
    path[:, 0] = t * d1
    path[:, 1] = t * d2
    path[:, 2] = d3
    path[:, 5] = t * r3
    out = np.zeros_like(path)
    n_slip = np.zeros(t.size, dtype=np.int64)
    spring_grid.spring_grid_path(
        np.ascontiguousarray(interface.positions), path, k_n, k_s, float(law.mu),
        law.cohesion * areas, law.tensile_strength * areas, out, n_slip,
    )
    return IncrementalResult(path, out, n_slip)


# ----------------------------------------------------------------------------------------------
# static route: second-order cone program (cvxpy + Clarabel)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SocpResult:
    """Result of :func:`max_torsion_socp`.

    Parameters
    ----------
    torsion : float
        Optimal torsion [N m].
    status : str
        cvxpy status (``optimal`` or ``optimal_inaccurate``).
    spring_shear : ndarray, shape (n, 2)
        Optimal spring tangential forces [N].
    max_cone_violation : float
        ``max(|t_i| - r_i, 0)`` [N] (primal feasibility certificate).
    equality_residual : float
        Largest residual of the shear equilibrium [N].
    """

    torsion: float
    status: str
    spring_shear: np.ndarray
    max_cone_violation: float
    equality_residual: float


def coulomb_spring_constraints(spring_shear, spring_normal, areas, law: CoulombSpringLaw):
    r"""cvxpy constraints of the Coulomb spring law for a set of springs.

    .. math:: |t_i| \le A_i c - \mu\, n_i, \qquad n_i \le A_i \sigma_t.

    Parameters
    ----------
    spring_shear : cvxpy expression, shape (n, 2)
        Tangential spring forces [N].
    spring_normal : cvxpy expression or ndarray, shape (n,)
        Normal spring forces [N], negative in compression.
    areas : ndarray, shape (n,)
        Spring areas [m^2].
    law : CoulombSpringLaw
        Spring law.

    Returns
    -------
    list
        cvxpy constraints (one vectorised second-order cone plus the tension cut-off).
    """
    import cvxpy as cp

    areas = np.asarray(areas, dtype=np.float64)
    cons = [cp.SOC(areas * law.cohesion - law.mu * spring_normal, spring_shear, axis=1)]
    if isinstance(spring_normal, cp.Expression):
        cons.append(spring_normal <= areas * law.tensile_strength)
    return cons


def max_torsion_socp(
    interface: SpringInterface,
    law: CoulombSpringLaw,
    normal_force: float,
    shear: tuple[float, float] = (0.0, 0.0),
    *,
    solver: str = "CLARABEL",
) -> SocpResult:
    """Largest torsion at a given shear by a second-order cone program.

    Maximise ``m3 = sum (y1 t2 - y2 t1)`` over the spring tangential forces ``t`` subject to
    ``sum t = shear`` and :func:`coulomb_spring_constraints`, with the normal forces fixed to
    the uniform distribution of ``normal_force`` (as the elastic springs give it; leaving them
    free would let all the normal force move to the corners).

    Parameters
    ----------
    interface : SpringInterface
        The springs.
    law : CoulombSpringLaw
        Spring law.
    normal_force : float
        Normal force [N], negative in compression.
    shear : tuple of float
        ``(f1, f2)`` [N].
    solver : str
        cvxpy solver name.

    Returns
    -------
    SocpResult
        Torsion and certificates.

    Raises
    ------
    InterfaceStrengthError
        If the status is not ``optimal`` or ``optimal_inaccurate`` (the latter warns).
    """
    import cvxpy as cp

    caps = shear_capacities(interface, law, normal_force)  # checks inputs
    del caps
    n = interface.n_springs
    normal = np.full(n, normal_force) * interface.areas / interface.area
    t = cp.Variable((n, 2))
    y1 = interface.positions[:, 0]
    y2 = interface.positions[:, 1]
    objective = cp.Maximize(y1 @ t[:, 1] - y2 @ t[:, 0])
    cons = coulomb_spring_constraints(t, normal, interface.areas, law)
    cons += [cp.sum(t[:, 0]) == shear[0], cp.sum(t[:, 1]) == shear[1]]
    prob = cp.Problem(objective, cons)
    prob.solve(solver=solver)
    if prob.status == cp.OPTIMAL_INACCURATE:
        warnings.warn("max_torsion_socp: solver status optimal_inaccurate", stacklevel=2)
        logger.warning("max_torsion_socp: optimal_inaccurate")
    elif prob.status != cp.OPTIMAL:
        raise InterfaceStrengthError(f"max_torsion_socp: solver status {prob.status}")
    tv = np.asarray(t.value)
    caps = interface.areas * (law.cohesion - law.mu * normal / interface.areas)
    viol = float(np.max(np.maximum(np.hypot(tv[:, 0], tv[:, 1]) - caps, 0.0)))
    eq = float(np.max(np.abs(tv.sum(0) - np.asarray(shear, dtype=float))))
    return SocpResult(float(prob.value), str(prob.status), tv, viol, eq)
