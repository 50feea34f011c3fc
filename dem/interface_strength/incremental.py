"""Elastic-perfectly-plastic incremental analysis of the spring grid (seed 001, Sec. 2.1).

The springs (stiffness per unit area [Pa/m]) are driven along a proportional relative motion
``(d1, d2, delta3)`` [m, m, rad] at a fixed normal force [N] by the numba return mapping of
:mod:`dem.kernels.spring_grid`; the history of the resultants is returned in [N, N m].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dem.interface_strength.capacities import shear_capacities
from dem.interface_strength.springs import CoulombSpringLaw, SpringInterface, _positive
from dem.kernels import spring_grid


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
        np.ascontiguousarray(interface.positions),
        path,
        k_n,
        k_s,
        float(law.mu),
        law.cohesion * areas,
        law.tensile_strength * areas,
        out,
        n_slip,
    )
    return IncrementalResult(path, out, n_slip)
