"""The certificates that end a flat path (dem.static.certificate, dem.static.upper_bound) on a
single block whose collapse is known in closed form: which certificate ends which path, and
that a path no certificate covers is no collapse."""

import math

import numpy as np
import pytest

from dem.scene import Scene, proportional_to_weight
from dem.static import FibreLawSettings, ResultantLawSettings, StaticSettings, solve_collapse
from dem.static.upper_bound import bound_friction

B, H = 0.4, 1.0  # base side and height of the block [m]


def _box(lo, hi):
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def _pushed_block(mu: float, direction=(1.0, 0.0, 0.0)):
    ground = _box((-1.0, -1.0, -0.2), (1.0, 1.0, 0.0))
    block = _box((-B / 2, -B / 2, 0.0), (B / 2, B / 2, H))
    scene = Scene.from_convex_blocks([ground, block], 2000.0, fixed=[0], mu=mu)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, direction))


@pytest.mark.parametrize("law", ["resultant", "fibre"])
def test_a_sliding_block_ends_at_a_limit_point_of_the_tangent(law):
    # mu = 0.3 < B / H: the block slides at lambda = mu, a perfectly plastic mechanism whose
    # tangent is singular along the push
    result = solve_collapse(_pushed_block(0.3), StaticSettings(interface_model=law))
    assert result.termination == "plateau" and result.certificate == "limit point"
    assert result.lambda_estimate.contains(0.3), result.lambda_estimate


def test_a_rocking_approach_of_the_resultant_law_ends_at_the_upper_bound():
    # mu = 0.9: the block tips at B / H; the resultant law's compressed strip shrinks without
    # end, its tangent never singular: only the rigid-block bound (rocking alone, mu = inf,
    # since Eq. A5 is not inside the vertex joint) ends the path, within plateau_rise of it
    result = solve_collapse(_pushed_block(0.9), StaticSettings(interface_model="resultant"))
    assert result.termination == "plateau" and result.certificate == "upper bound"
    assert result.lambda_estimate.contains(B / H), result.lambda_estimate
    assert B / H - result.lambda_max <= 1e-3 * B / H + 1e-9


def test_a_rocking_approach_without_a_bound_ends_only_where_its_tangent_is_singular():
    # with a tensile strength no upper bound is known (the laws' tension is outside the
    # vertex joint; here only joints between free blocks would have it, none, so the block
    # rocks as a dry one); the resultant law's compressed strip shrinks until its stiffness
    # is below the certificate's floor resolution: the path goes on that far, and ends a
    # hair below the rigid limit, inside its bar
    settings = StaticSettings(
        interface_model="resultant", tensile_strength=1e3, tension_at_supports=False
    )
    result = solve_collapse(_pushed_block(0.9), settings)
    assert result.termination == "plateau" and result.certificate == "limit point"
    assert result.lambda_estimate.contains(B / H), result.lambda_estimate
    assert B / H - result.lambda_max <= 1e-6


@pytest.mark.parametrize(
    ("settings", "expected"),
    [
        (StaticSettings(law=FibreLawSettings(), mu=0.6), 0.6),
        (StaticSettings(law=ResultantLawSettings(shear_torsion="exact"), mu=0.6), 0.6),
        (StaticSettings(law=ResultantLawSettings(), mu=0.6), math.inf),
        (StaticSettings(law=FibreLawSettings(), mu=0.6, cohesion=1e3), math.inf),
        (StaticSettings(law=FibreLawSettings(), mu=0.6, compressive_strength=1e6), 0.6),
    ],
)
def test_the_bound_uses_the_friction_only_where_the_law_lies_in_the_vertex_joint(
    settings, expected
):
    assert bound_friction(settings) == expected


def test_no_bound_with_a_tensile_strength():
    assert math.isnan(bound_friction(StaticSettings(tensile_strength=1e3)))
