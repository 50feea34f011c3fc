r"""Torsion-shear interaction domains and the exponent alpha (seed 001, Figs. 8-9, A4, Table A1).

:func:`interaction_domain` traces the ``m3`` [N m] - shear [N] boundary of the spring grid at a
fixed normal force [N] along one shear direction [rad]; :func:`fit_alpha` fits the exponent
alpha [-] of :math:`(m_3/m_{3,u})^\alpha + (f/f_{s,u})^2 = 1` (:func:`interaction_law_torsion`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from dem.interface_strength.capacities import (
    shear_capacities,
    torsion_section,
    twist_centre_resultants,
)
from dem.interface_strength.springs import CoulombSpringLaw, SpringInterface


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

        res = minimize_scalar(misfit, bounds=(0.3, 6.0), method="bounded", options={"xatol": 1e-8})
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
