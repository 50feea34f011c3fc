r"""A certificate that a flat path has reached its limit: an upper bound that it meets.

The collapse multiplier of joints with non-associated (zero-dilatancy) Coulomb friction is
at most the associated limit load of any convex domain that contains the joints' domain
(Radenkovic's first theorem; e.g. de Saxce and Feng 1998), and that is at most the
multiplier of any mechanism of the associated kinematic problem. When the path's peak comes
within its stated tolerance of such a bound, the rest it may still rise is bounded by the
bound itself: ``end of path = lambda_UB - lambda_peak`` (with the bound's own bar). The bound
is the static limit analysis of :mod:`limit` with its ``"vertex"`` joints (every admissible
distribution of pressure and Coulomb friction on the joint polygon: the exact rigid
no-tension joint), computed once, when first asked.

**Which bound holds for which law** (the domain of the law's joint must lie in the bound's):

- no bound with a tensile strength: the laws' tension (per spring, or the capped stress
  field) is not inside the vertex joint's no-tension domain;
- the fibre law (its springs are points of the polygon, each with Coulomb friction and no
  tension; a compressive strength only takes away) and the resultant law with
  ``shear_torsion="exact"`` (one capped stress field with pointwise Coulomb friction) lie in
  the vertex joint with the same friction coefficient, without cohesion: the bound is the
  vertex limit analysis at the analysis' ``mu``;
- the resultant law with seed 001's Eq. (A5) (or any law with cohesion) is not inside it
  (its torsion about the centre of compression plus ``e x V`` can exceed what friction on
  the polygon carries). Every law is inside it for motions without sliding or twist: a
  rocking mechanism (gaps >= 0, no tangential motion) dissipates nothing with no tension,
  whatever the shear domain, so the vertex analysis with ``mu = inf`` (the rigid-block
  limit of rocking alone) is an upper bound for every law without tension.
"""

from __future__ import annotations

import logging
import math

from dem.collapse_criteria import Certificate
from dem.estimate import Estimate
from dem.scene import Scene
from dem.static.settings import StaticSettings
from limit import LimitAnalysisError, LimitSettings, limit_analysis

logger = logging.getLogger(__name__)


def bound_friction(settings: StaticSettings) -> float | None:
    """The friction coefficient of the vertex analysis whose multiplier bounds this
    analysis' collapse multiplier from above: ``settings.mu`` (None: the scene's) where the
    law's joint lies in the vertex joint, ``inf`` (rocking alone) where it does not; NaN
    where no such bound is known (a tensile strength). Module notes."""
    if settings.tensile_strength > 0:
        return math.nan
    law = settings.law_settings
    cohesive = settings.cohesion is not None and settings.cohesion > 0
    exact = law.name == "fibre" or getattr(law, "shear_torsion", "") == "exact"
    return settings.mu if exact and not cohesive else math.inf


class UpperBoundCertifier:
    """Certifies a peak within ``tolerance`` (relative) of the limit analysis' upper bound.

    Attributes
    ----------
    bound : Estimate or None
        The upper bound with its bar, once computed (None before, or when none is known).
    """

    def __init__(self, scene: Scene, settings: StaticSettings, tolerance: float):
        self.scene, self.settings, self.tolerance = scene, settings, tolerance
        self.mu = bound_friction(settings)
        self.bound: Estimate | None = None
        self._tried = self.mu is not None and math.isnan(self.mu)

    def _compute(self) -> None:
        self._tried = True
        limit_settings = LimitSettings(interface_model="vertex", mu=self.mu, dead_load_check=False)
        try:
            result = limit_analysis(self.scene, limit_settings)
        except LimitAnalysisError as exc:
            logger.info("no upper bound from the limit analysis: %s", exc)
            return
        self.bound = result.lambda_estimate
        logger.info("upper bound (vertex limit analysis, mu = %s): %s", self.mu, self.bound)

    def certify(self, peak: float, remaining: float) -> Certificate | None:
        """The certificate of a ``peak`` that meets the bound, or None."""
        if not self._tried:
            self._compute()
        if self.bound is None:
            return None
        high = self.bound.value + self.bound.error
        if peak < high - self.tolerance * peak:
            return None
        note = f"upper bound {self.bound.format()} (vertex limit analysis, mu = {self.mu})"
        return Certificate("upper bound", max(high - peak, 0.0), note)
