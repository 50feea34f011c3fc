r"""A certificate from the mechanics that a flat path has reached its limit: a limit point.

(The other certificate, an upper bound that the path meets, is :mod:`dem.static.upper_bound`;
:class:`FirstOf` asks several in turn.)

The shape of the path ``(c, lambda)`` alone cannot tell a limit from a slow creep (a joint
whose last compressed springs are tiny, a hardening at 1e-5 of the initial slope): the end is
declared only with a certificate (:mod:`dem.collapse_criteria`). This one reads the tangent
at the last equilibrium.

**Limit point of the tangent.** The path's slope along the control is

.. math:: \frac{d\lambda}{dc} = \frac{1}{w^T K_t(\epsilon)^{-1} F_L},

with ``K_t(eps)`` the consistent tangent whose yielded and open components keep ``eps``
times their elastic stiffness (the tangent floor of :mod:`dem.static.newton`; a component
whose exact tangent is larger keeps it). Both laws are elastic-perfectly plastic: at a
mechanism the exact tangent (``eps = 0``) is singular in a direction on which the live load
works, so the compliance along ``w`` is that of the floor, ``~ 1 / eps``, and the slope
scales with ``eps``; a real stiffness (a creep on a few elastic springs, a joint still
rocking on a compressed strip, a hardening) gives a slope that does not depend on ``eps``
once ``eps`` is below it. ``K_t`` is the consistent tangent of the last step: the law
evaluated at the equilibrium from the plastic state the step started from (re-evaluated
from the state the equilibrium committed, a joint with no friction capacity, whose slip is
all plastic, would look unloaded and elastic). The slope is computed at ``FLOOR`` and at
``FLOOR / FLOOR_RATIO``: a limit point is certified when it falls by at least ``SCALING``
(at least 90 % of the compliance along the control comes from the floor), or when the
tangent already descends (a slope <= 0: the path cannot rise along it). A stiffness below
``FLOOR / FLOOR_RATIO`` of the elastic one counts as none. It is a property of the law's
tangent at a converged equilibrium, independent of the Newton floor the steps used. Cost:
two evaluations of the law and two sparse factorisations, made only when the path is
already flat and approaches a limit.

A joint rocking on the resultant law's shrinking compressed strip keeps a real (if
vanishing) stiffness until round-off stalls the path: no limit point is found there, and
the end needs the upper bound of :mod:`dem.static.upper_bound`.
"""

from __future__ import annotations

import logging
import math
from contextlib import contextmanager

import numpy as np

from dem.collapse_criteria import Certificate
from dem.static.model import Model
from dem.static.newton import factor

logger = logging.getLogger(__name__)

FLOOR = 1e-9
"""Floor of the first tangent, as a fraction of the elastic stiffness."""

FLOOR_RATIO = 100.0
"""The second tangent's floor is ``FLOOR / FLOOR_RATIO``."""

SCALING = 10.0
"""Least fall of the slope between the two floors that certifies a limit point."""


@contextmanager
def _from_state(law, plastic: tuple):
    """The law evaluates from the plastic state ``plastic`` (its committed one restored
    after)."""
    kept = law.plastic
    law.plastic = plastic
    try:
        yield
    finally:
        law.plastic = kept


def control_slope(model: Model, u: np.ndarray, plastic: tuple, floor: float) -> float:
    """``d lambda / d c`` [1/m] of the tangent at the equilibrium ``u`` (n_free,) reached
    from the plastic state ``plastic``, with the tangent floor ``floor``; NaN if the tangent
    is singular or the slope not finite."""
    with _from_state(model.law, plastic):
        ev = model.evaluate(u, floor)
    lu = factor(model.stiffness(ev.law.D))
    if isinstance(lu, Exception):
        return math.nan
    compliance = float(model.w @ lu.solve(model.F_live))
    slope = 1.0 / compliance if compliance != 0.0 else math.inf
    return slope if math.isfinite(slope) else math.nan


class LimitPointCertifier:
    """Certifies a limit point of the tangent at the last equilibrium (module notes).

    ``point()`` returns ``(u, plastic)``: the free dofs (n_free,) [m, rad] of the last
    equilibrium and the law's plastic state at the start of the step that reached it.
    """

    def __init__(self, model: Model, point):
        self.model = model
        self.point = point
        self.n_checks = 0

    def certify(self, lam: float, remaining: float) -> Certificate | None:
        """The certificate at the last equilibrium (``lam`` the path's peak, for the log),
        whose path extrapolates ``remaining`` more rise, or None."""
        self.n_checks += 1
        u, plastic = self.point()
        stiff = control_slope(self.model, u, plastic, FLOOR)
        soft = control_slope(self.model, u, plastic, FLOOR / FLOOR_RATIO)
        note = f"slope d lambda / d c {stiff:.3e} at floor {FLOOR:g}, {soft:.3e} at 1/100 of it"
        if math.isnan(stiff) or math.isnan(soft):
            logger.info("no limit point certified at lambda = %.6g (%s)", lam, note)
            return None
        if stiff <= 0.0 or soft <= stiff / SCALING:
            return Certificate("limit point", remaining, note)
        logger.info("flat path, no limit point at lambda = %.6g (%s)", lam, note)
        return None


class FirstOf:
    """The first certificate that any of ``certifiers`` gives, asked in order (the cheap
    first)."""

    def __init__(self, *certifiers):
        self.certifiers = certifiers
        self.n_checks = 0

    def certify(self, peak: float, remaining: float) -> Certificate | None:
        self.n_checks += 1
        for certifier in self.certifiers:
            found = certifier.certify(peak, remaining)
            if found is not None:
                return found
        return None
