"""Static route: the largest torsion [N m] at a given shear [N] as a second-order cone program.

The Coulomb law of each spring (forces [N], areas [m^2], stresses [Pa]) becomes a second-order
cone (:func:`coulomb_spring_constraints`); :func:`max_torsion_socp` solves with cvxpy + Clarabel
and returns the optimum with its feasibility certificates.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass

import numpy as np

from dem.interface_strength.capacities import InterfaceStrengthError, shear_capacities
from dem.interface_strength.springs import CoulombSpringLaw, SpringInterface

logger = logging.getLogger(__name__)


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

    shear_capacities(interface, law, normal_force)  # checks inputs
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
