"""mu = inf is "no sliding": joints only rock or open, in the scene and in every programme.

A ``b x h`` block pushed sideways by lambda times its weight cannot slide, so it overturns at
``lambda = b / h`` (moments about the toe), however squat it is.
"""

import math

import numpy as np
import pytest

import limit
from limit.problems import LimitSettings
from limit.solve import kinematic_analysis, limit_analysis
from tests.limit._scenes import block_on_ground, tilted_block

SQUAT = (1.0, 0.5, 0.2)  # width, depth, height: b / h = 5, slides first at any finite mu < 5


@pytest.mark.parametrize("model", ["vertex", "resultant"])
@pytest.mark.parametrize("where", ["scene", "settings"])
def test_a_block_that_cannot_slide_overturns(model, where):
    b, d, h = SQUAT
    mu = math.inf if where == "scene" else 0.6
    scene = block_on_ground(b, d, h, mu)
    settings = LimitSettings(interface_model=model, mu=math.inf if where == "settings" else None)
    res = limit_analysis(scene, settings)
    np.testing.assert_allclose(res.lam, b / h, rtol=1e-6)
    assert res.certificate.worst() <= settings.cert_tol
    # the same block with a finite mu slides at lambda = mu
    np.testing.assert_allclose(limit_analysis(block_on_ground(b, d, h, 0.6)).lam, 0.6, rtol=1e-6)


def test_kinematic_programme_with_no_sliding():
    b, d, h = SQUAT
    lam, vel, _ = kinematic_analysis(block_on_ground(b, d, h, math.inf))
    np.testing.assert_allclose(lam, b / h, rtol=1e-6)
    assert abs(vel[1, 4]) > 0  # rocks about y


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_estimates_with_no_sliding(model):
    """No sliding, no dilatancy question: both estimates equal the upper bound b / h; the
    frictionless lower bound (mu = 0 everywhere) is 0."""
    b, d, h = SQUAT
    bounds = limit.bounds_and_estimates(
        block_on_ground(b, d, h, math.inf), LimitSettings(interface_model=model)
    )
    np.testing.assert_allclose([bounds.upper, bounds.reduced_mu], b / h, rtol=1e-6)
    np.testing.assert_allclose(bounds.iterative.lam, b / h, rtol=1e-5)
    assert bounds.lower == 0.0 and bounds.consistent


def test_stands_on_a_steep_slope_without_sliding():
    """tan 60 = 1.73 > any usual mu, but < b / h = 2: with mu = inf it stands."""
    assert limit.stands(tilted_block(0.4, 0.2, math.radians(60), math.inf)).stands
    assert not limit.stands(tilted_block(0.4, 0.2, math.radians(60), 1.0)).stands
