r"""The error bar of a limit-analysis multiplier, as an :class:`dem.estimate.Estimate`.

A static programme is exact for its own interface set, so what separates the returned
multiplier from the optimum of that programme is the point where the solver stopped and,
where an inscribed friction polygon replaces the cone, the polygon. The sources, in the unit
of lambda:

``"duality gap"``
    :math:`|\bar\lambda - \lambda|`, the distance from the returned multiplier to the dual
    bound of the certificate (:mod:`limit.certificates`).
``"feasibility"``
    The feasibility shift of the certificate: how far the optimum may move when every
    constraint is relaxed by what the returned point violates it by (duals as sensitivities,
    first order).
``"dual stationarity"``, ``"dual cone"``
    The stationarity and dual-cone shifts of the certificate (:mod:`limit.certificates`):
    the dual objective bounds the optimum only for duals that make the Lagrangian stationary
    and lie in their dual cones; the returned duals may miss it by :math:`|r|^T|x^*|` plus
    :math:`\sum_i \operatorname{dist}(z_i, K_i^*)\lVert g_i(x^*)\rVert`, read at the
    returned point. Gap, feasibility and these two together are the solver's error, each of
    the order of Clarabel's tolerance.
``"friction polygon"``
    Where ``friction_polygon = k``: the distance to the optimum of the same programme with
    the exact (second-order) cones, plus that solve's own solver error
    (:func:`limit.solve.polygon_error`); the cones cost Clarabel about what the polygons do.
    Should the exact cones fail, the outer bracket: the inscribed ``k``-gon of the circle of
    radius :math:`\mu/\cos(\pi/k)` contains the circle of radius :math:`\mu`, so the programme
    with every friction coefficient divided by :math:`\cos(\pi/k)` has a larger admissible
    set than the exact cone (in the resultant model its torsion capacity grows too, which
    only enlarges the set further). The exact optimum then lies in
    :math:`[\lambda, \lambda_{out}]`, one-sided; the whole width (plus the outer solve's own
    solver error) is the half-width, loose where the load points near a polygon corner.
``"iteration"``
    Estimate (b) of :mod:`limit.estimates`: the geometric tail
    :math:`\rho/(1-\rho)\,|\lambda_k - \lambda_{k-1}|` of its last two steps, with
    :math:`\rho = |\lambda_k - \lambda_{k-1}| / |\lambda_{k-1} - \lambda_{k-2}|`; infinite when
    the steps do not shrink (:math:`\rho \ge 1`: no fixed point in sight). A last step within
    the solver's resolution (twice the last solve's solver error) is itself the half-width:
    the iteration no longer moves by more than its solves can tell.

The bar concerns the programme's own optimum. For non-associated (zero-dilatancy) friction
the associated optimum is an upper bound of the collapse multiplier, and the distance between
the two is a question of the model (:mod:`limit.estimates`), not part of this bar.
"""

from __future__ import annotations

import math

from dem.estimate import Estimate
from limit.certificates import Certificate

__all__ = ["iteration_tail", "outer_polygon_factor", "solver_estimate"]


def solver_estimate(lam: float, certificate: Certificate | None) -> Estimate:
    """``lam`` with the solver's sources (module notes) read from its ``certificate``.

    Parameters
    ----------
    lam : float
        The returned multiplier [unit of lambda].
    certificate : Certificate or None
        With ``dual_objective`` and the shifts (``feasibility_shift``, ``stationarity_shift``,
        ``dual_cone_shift``) in the unit of lambda; None (no certificate computed) or a shift
        not computed gives an unknown error, never a silent zero.
    """
    if certificate is None:
        return Estimate.unknown(lam, "no certificate computed (certify=False)")
    shifts = {
        "feasibility": certificate.feasibility_shift,
        "dual stationarity": certificate.stationarity_shift,
        "dual cone": certificate.dual_cone_shift,
    }
    missing = [name for name, value in shifts.items() if not math.isfinite(value)]
    if missing:
        return Estimate.unknown(lam, f"the certificate has no {', '.join(missing)} shift")
    return Estimate(
        lam,
        {"duality gap": abs(certificate.dual_objective - lam), **shifts},
        notes="solver error of the programme's optimum (duality gap, primal violations, dual "
        "stationarity and cone)",
    )


def outer_polygon_factor(sides: int) -> float:
    """``1 / cos(pi / sides)``: the factor on mu whose inscribed polygon contains the circle
    of radius mu (module notes)."""
    if sides < 3:
        raise ValueError(f"a friction polygon needs at least 3 sides, got {sides}")
    return 1.0 / math.cos(math.pi / sides)


def iteration_tail(history: list[float], resolution: float = 0.0) -> float:
    """Half-width [unit of lambda] of the distance from the last iterate to the fixed point
    of a linearly converging iteration (module notes, ``"iteration"``): the last step where
    it is within ``resolution`` (the solver's, [unit of lambda]), else the geometric tail;
    ``inf`` with fewer than three values or steps that do not shrink."""
    if len(history) >= 2 and abs(history[-1] - history[-2]) <= resolution:
        return abs(history[-1] - history[-2])
    if len(history) < 3:
        return math.inf
    last, before = abs(history[-1] - history[-2]), abs(history[-2] - history[-3])
    if before == 0 or last >= before:
        return math.inf
    rho = last / before
    return rho / (1.0 - rho) * last
