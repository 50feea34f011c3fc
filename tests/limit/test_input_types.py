"""A scene or settings of the wrong type is refused at the entry point, by name."""

import functools

import pytest

from dem.static import StaticSettings
from limit import (
    bounds_and_estimates,
    build_static_problem,
    geometric_safety_factor,
    iterative_estimate,
    kinematic_analysis,
    limit_analysis,
    stands,
)
from limit.estimates import frictionless_lower_bound
from limit.problems import build_kinematic_problem
from tests.limit._scenes import block_on_ground

ENTRY_POINTS = [
    limit_analysis,
    kinematic_analysis,
    bounds_and_estimates,
    iterative_estimate,
    frictionless_lower_bound,
    stands,
    build_static_problem,
    build_kinematic_problem,
]


@pytest.mark.parametrize("entry", ENTRY_POINTS, ids=lambda f: f.__name__)
def test_path_instead_of_scene(entry):
    with pytest.raises(TypeError, match="scene must be a dem.scene.Scene, got str"):
        entry("scene.json")


@pytest.mark.parametrize("entry", ENTRY_POINTS, ids=lambda f: f.__name__)
def test_dem_settings_instead_of_limit_settings(entry):
    scene = block_on_ground(0.2, 0.2, 0.5, 0.7)
    with pytest.raises(TypeError, match="settings must be a limit.LimitSettings, got Static"):
        entry(scene, StaticSettings())


def test_safety_factor_refuses_dem_settings():
    build = functools.partial(block_on_ground, depth=0.2, height=0.5, mu=0.7)
    with pytest.raises(TypeError, match="settings must be a limit.LimitSettings, got Static"):
        geometric_safety_factor(build, 0.1, 0.3, settings=StaticSettings())
