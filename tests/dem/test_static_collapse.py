"""A static analysis says whether it collapsed: no-mechanism scenes, partial paths, errors.

Issue 11, items 2-3: a run that did not reach a collapse must never look like one that did.
"""

import numpy as np
import pytest

from dem.scene import proportional_to_weight
from dem.scenes.running_bond_wall import running_bond_wall
from dem.static import NoCollapseError, StaticSettings, solve_collapse

MODELS = ("resultant", "fibre")


def _wall_loaded_downwards():
    """A dry 3 x 3 running-bond wall on a base, live load = its weight pointing down."""
    scene = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="none")
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (0.0, 0.0, -1.0)))


def _wall_with_one_fixed_column():
    """A dry 8 x 6 running-bond wall held by its fixed left column, out-of-plane load."""
    return running_bond_wall(8, 6, 65, 210, 150, 18, 0.4, fixed_columns=("left",))


@pytest.mark.parametrize("model", MODELS)
def test_downward_live_load_has_no_mechanism(model):
    # a live load pointing into the foundation does no work on any motion that opens no joint:
    # no multiplier collapses the wall (before the fix: lambda_max = 787 at max_steps, with
    # only a log line). The limit analysis of the same scene says "unbounded" independently.
    from limit.problems import LimitSettings
    from limit.solve import LimitAnalysisError, limit_analysis

    scene = _wall_loaded_downwards()
    with pytest.raises(NoCollapseError, match="no mechanism") as info:
        solve_collapse(scene, StaticSettings(interface_model=model))
    assert info.value.reason.startswith("no mechanism")
    partial = info.value.result
    assert not partial.collapsed and partial.termination == "no_mechanism"
    assert partial.n_steps == 0
    result = solve_collapse(scene, StaticSettings(interface_model=model, on_failure="return"))
    assert not result.collapsed and result.termination == "no_mechanism"
    assert result.lambda_max == np.inf
    with pytest.raises(LimitAnalysisError, match="unbounded"):
        limit_analysis(scene, LimitSettings())


def test_a_mechanism_is_not_mistaken_for_none():
    # the same wall loaded sideways out of plane overturns at s / H (closed form): the
    # mechanism check must let it through
    scene = running_bond_wall(3, 3, 81, 210, 70, 20, 0.7, live="weight")
    result = solve_collapse(scene)
    assert result.collapsed and result.termination == "plateau"
    np.testing.assert_allclose(result.lambda_max, 70 / (3 * 81), rtol=1e-3)


def test_run_cut_short_raises_and_says_it_still_rises():
    # 10 steps are far too few to reach the mechanism of the wall: by default an error naming
    # how fast lambda still rises, with the partial path; with on_failure="return" the path
    # flagged as not collapsed (before: a StaticResult that looked like an answer)
    scene = _wall_with_one_fixed_column()
    with pytest.raises(NoCollapseError, match="still rising at") as info:
        solve_collapse(scene, StaticSettings(max_steps=10))
    partial = info.value.result
    assert not partial.collapsed and partial.termination == "max_steps"
    assert partial.n_steps == 10 and len(partial.pushover_lambda) == 11
    assert "initial slope" in info.value.reason
    result = solve_collapse(scene, StaticSettings(max_steps=10, on_failure="return"))
    assert not result.collapsed and "still rising" in result.failure
    np.testing.assert_allclose(result.lambda_max, partial.lambda_max, rtol=1e-12)


def test_on_failure_values():
    with pytest.raises(ValueError, match="'stop' is no longer accepted"):
        StaticSettings(on_failure="stop")
    with pytest.raises(ValueError, match="on_failure"):
        StaticSettings(on_failure="ignore")
