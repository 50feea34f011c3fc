"""Torsion strength of an interface that also carries bending moments (seed 001, Fig. 10).

Bending moments ``m1, m2`` [N m] with a compressive normal force ``N`` [N] either shrink the
compressed area to a reduced rectangle [m] under uniform stress (:func:`reduced_rectangle`,
Orduna and Lourenco 2005a) or give a partialised elastic no-tension pressure
(:func:`no_tension_normal_forces`, spring forces [N]); the torsion strength [N m] follows from
the friction capacities of the compressed springs.
"""

from __future__ import annotations

import numpy as np

from dem.interface_strength.capacities import (
    InterfaceStrengthError,
    shear_capacities,
    torsion_coefficient_rectangle,
    torsion_section,
)
from dem.interface_strength.springs import CoulombSpringLaw, SpringInterface


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
    b = np.column_stack(
        [np.ones(interface.n_springs), interface.positions[:, 1], -interface.positions[:, 0]]
    )
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
