"""A path that creeps on after a knee (the fibre law's springs opening one by one under a
tipping corner, tests/dem/test_static_adaptive_grid.py) against the end of
dem.collapse_criteria: the path's shape makes the rise still to come look 100 times smaller
than it is, so the end must wait for a certificate from the mechanics. Here the certificate
is that of the tangent (dem.static.certificate): a limit point once the path's own slope is
below what the tangent floor resolves, which the creep's slope (1e-5 of the initial one)
is not."""

import numpy as np
import pytest

from dem.collapse_criteria import Certificate, CollapseCriteria


class TangentOf:
    """Certifies a limit point where the slope of the path ``lam(c)`` at the last point is
    below 1e-11 of the initial one (a stiffness below the tangent certificate's floor)."""

    def __init__(self, lam):
        self.lam = lam
        self.criteria = None

    def certify(self, lam, remaining):
        c = self.criteria.ctrl[-1]
        h = 1e-6 * c
        slope = (self.lam(c + h) - self.lam(c - h)) / (2 * h)
        return Certificate("limit point", remaining) if slope <= 1e-11 * SLOPE0 else None


DC0 = 1e-4  # first control increment [m]
SLOPE0 = 100.0  # initial slope [1/m]
KNEE = 10 * DC0  # end of the elastic part [m]
NOISE = 1e-6


C1 = 50 * KNEE  # end of the approach, start of the creep [m]
LAM1 = 0.11 - 0.01 * (C1 / KNEE) ** -0.5
TOP = 1.05 * LAM1  # where the creep stops


def creeping_path(c):
    """lambda = 0.11 - 0.01 (c / KNEE)^(-1/2) after a linear knee, up to C1; then a straight
    creep at 1e-5 of the initial slope that rises 5 % more, to TOP, and stays."""
    c = np.asarray(c, dtype=float)
    approach = 0.11 - 0.01 * (np.maximum(c, KNEE) / KNEE) ** -0.5
    creep = np.minimum(LAM1 + 1e-5 * SLOPE0 * (c - C1), TOP)
    return np.where(c <= KNEE, 0.1 * c / KNEE, np.where(c <= C1, approach, creep))


def _ends(certifier, n_points=120):
    """Feed the creeping path; ``(c, lambda)`` where it ended as a plateau, or None."""
    cs = np.concatenate([DC0 * np.arange(1, 11), KNEE * 1.25 ** np.arange(1, n_points)])
    criteria = CollapseCriteria(
        0.0, DC0, plateau_slope=2e-3, plateau_steps=4, softening_drop=0.2, certifier=certifier
    )
    certifier.criteria = criteria
    for c, lam in zip(cs, creeping_path(cs), strict=True):
        if criteria.add(lam, c, NOISE) == "plateau":
            assert TOP - lam <= criteria.certificate.end_error, (c, lam, criteria.certificate)
            return c, lam
    return None


def test_a_creep_after_a_knee_ends_at_its_top_with_the_tangent_certificate():
    # the path's shape alone triggers the end at c = 0.087 claiming 4e-5 still to rise where
    # 5.4e-3 (5 %) does; the tangent certifies only once the creep has stopped
    end = _ends(TangentOf(creeping_path))
    assert end is not None, "the path never ended, although it is flat after the creep"
    assert end[0] >= C1 + (TOP - LAM1) / (1e-5 * SLOPE0)
    assert end[1] == pytest.approx(TOP, rel=1e-12)


class Never:
    """A creep that never becomes a mechanism: nothing certifies a limit point."""

    criteria = None

    def certify(self, lam, remaining):
        return None


def test_a_creep_that_never_becomes_a_mechanism_is_no_collapse():
    assert _ends(Never()) is None
