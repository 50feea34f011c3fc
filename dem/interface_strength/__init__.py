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

Modules, lowest level first (each imports only the ones above it):

- :mod:`~dem.interface_strength.springs`: the springs and their Coulomb law, input checks;
- :mod:`~dem.interface_strength.capacities`: spring capacities, support and twist-centre
  resultants, shear and torsion strengths, the torsion section, ``c_T`` of a rectangle;
- :mod:`~dem.interface_strength.domains`: m3 - shear interaction domains and the alpha fit;
- :mod:`~dem.interface_strength.bending`: torsion with bending (reduced rectangle, elastic
  no-tension pressure);
- :mod:`~dem.interface_strength.incremental`: the elastic-perfectly-plastic analysis;
- :mod:`~dem.interface_strength.socp`: the second-order cone program.

Import the public names from the package: ``from dem.interface_strength import ...``.

Units are SI throughout: m, N, Pa, rad.
"""

from dem.interface_strength.bending import (
    no_tension_normal_forces,
    reduced_rectangle,
    torsion_strength_elastic_bending,
    torsion_strength_with_bending,
    torsion_strength_with_bending_closed_form,
)
from dem.interface_strength.capacities import (
    InterfaceStrengthError,
    shear_capacities,
    shear_strength,
    support_resultants,
    torsion_coefficient_rectangle,
    torsion_section,
    torsion_strength,
    twist_centre_resultants,
)
from dem.interface_strength.domains import (
    InteractionDomain,
    fit_alpha,
    interaction_domain,
    interaction_law_torsion,
)
from dem.interface_strength.incremental import (
    IncrementalResult,
    incremental_analysis,
)
from dem.interface_strength.socp import (
    SocpResult,
    coulomb_spring_constraints,
    max_torsion_socp,
)
from dem.interface_strength.springs import (
    CoulombSpringLaw,
    SpringInterface,
)

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
