"""The cross-check on small scenes: its numbers against closed forms, its verdict against
wrong inputs, its files and pictures."""

import json
import math

import matplotlib.image
import numpy as np
import pytest

from dem.estimate import Estimate
from dem.scene import point_load
from dem.scenes import stack
from validation.crosscheck import (
    Context,
    CrosscheckSettings,
    StepResult,
    crosscheck,
)
from validation.crosscheck.run import weight_direction
from validation.crosscheck.verdict import explicit_checks, verdict


@pytest.fixture(scope="module")
def pillar_result(tmp_path_factory):
    """Two stacked blocks b = 0.4, h = 0.5 each: overturning at b / (2 h) = 0.4 < mu."""
    out = tmp_path_factory.mktemp("crosscheck")
    scene = stack(2, 0.4, 0.3, 0.5, mu=0.6)
    return crosscheck(scene, CrosscheckSettings.quick(), out), out


def test_every_method_finds_the_overturning_load(pillar_result):
    result, _ = pillar_result
    expected = 0.4 / (2 * 0.5)  # stack closed form: b / (n h)
    for name in ("limit-vertex", "limit-resultant"):
        np.testing.assert_allclose(result.step(name).values["upper"], expected, rtol=1e-6)
    for name, below in (("dem-fibre", 1e-3), ("dem-resultant", 2e-2)):
        # the resultant law approaches the rigid-block limit from below (tests/dem/test_static)
        step = result.step(name)
        assert step.values["collapsed"]
        lam = step.values["lambda_max"]
        assert expected * (1 - below) <= lam <= expected * (1 + 1e-4)
    assert result.step("dead-load").values["stands"] is True
    fem = result.step("fem").values
    assert fem["n_solved"] == 2 and fem["max_residual"] < 1e-6
    # a rocking block presses on its toe: compression exceeds tension somewhere
    assert fem["max_compression_Pa"] < 0 < fem["max_tension_Pa"]
    others = [c for c in result.checks if c.step != "explicit"]
    assert {c.status for c in others} <= {"pass", "n/a"}, [c for c in others if c.status == "fail"]


def test_explicit_bracket_of_the_stack(pillar_result):
    """A state at rest is statically admissible: lambda_stable <= b / (n h) = 0.4."""
    result, _ = pillar_result
    v = result.step("explicit").values
    assert v["collapsed"]
    assert v["lambda_stable"] <= 0.4 < 1.25 * 0.4
    assert v["lambda_stable"] < v["lambda_moving"] <= 1.25 * 0.4


def test_every_step_records_its_time_and_settings(pillar_result):
    result, _ = pillar_result
    for step in result.steps:
        assert step.wall_s >= 0
        if step.status == "ok":
            assert step.settings, step.name
    assert result.step("dem-fibre").settings["interface_model"] == "fibre"
    assert result.step("limit-resultant").settings["interface_model"] == "resultant"


def test_report_files_and_pictures(pillar_result):
    result, out = pillar_result
    data = json.loads((out / "report.json").read_text())
    assert data["consistent"] is result.consistent
    assert [s["name"] for s in data["steps"]] == [s.name for s in result.steps]
    md = (out / "report.md").read_text()
    assert "## Verdict" in md and "DEM fibre <= upper (vertex)" in md
    # the summary reads the live load as an acceleration: each block's weight along +x
    assert "at most 0.4 (proven upper bound; the lower bound 0 is the frictionless" in md
    assert "a lateral load needs shear" in md and "seismic coefficient" in md
    for key in ("scene", "interfaces", "mechanism", "stress"):
        assert (out / f"{key}.vtu").stat().st_size > 0
    for key in ("pushover", "mechanism", "interface_states", "stress"):
        image = matplotlib.image.imread(out / f"{key}.png")
        assert image.shape[0] > 100 and image.shape[1] > 100, key
        assert np.ptp(image[..., :3]) > 0.2, f"{key}.png is blank"


def test_a_scene_without_live_load_skips_the_collapse_analysis(two_block_stack):
    settings = CrosscheckSettings.quick(methods=("dead", "limit", "dem", "fem"), pictures=False)
    result = crosscheck(two_block_stack, settings)
    assert result.step("dead-load").values["stands"] is True
    for name in ("limit-vertex", "dem-fibre", "dem-resultant"):
        assert result.step(name).status == "skipped"
        assert "no live load" in result.step(name).reason
    assert result.step("fem").status == "skipped"


def test_the_report_names_blocks_that_touch_only_along_an_edge(tmp_path, caplog):
    # the top block sits a full width over: it meets the lower one along an edge only
    scene = stack(2, 0.4, 0.3, 0.5, offsets=[0.0, 0.4], mu=0.6)
    settings = CrosscheckSettings.quick(methods=("dead",), pictures=False)
    with caplog.at_level("WARNING", logger="dem.geometry.interfaces"):
        result = crosscheck(scene, settings, tmp_path)
    assert "1 pair(s) of blocks touch only along an edge or at a corner (blocks 0-1)" in (
        caplog.text
    )
    assert result.scene["edge_contacts"] == [[0, 1]]
    md = (tmp_path / "report.md").read_text()
    assert "1 pair of blocks touches only along an edge or at a corner (0-1)" in md
    assert "Under its dead load the structure FALLS" in md


def test_a_scene_that_falls_is_reported_and_not_pushed(tmp_path):
    # the top block overhangs by more than half its width: it topples under its own weight
    scene = stack(2, 0.4, 0.3, 0.5, offsets=[0.0, 0.25], mu=0.6)
    result = crosscheck(scene, CrosscheckSettings.quick(methods=("dead", "dem"), pictures=False))
    assert result.step("dead-load").values["stands"] is False
    assert result.step("dem-fibre").status == "skipped"
    assert not result.consistent
    assert result.checks[0].status == "fail"


def _ctx(**values) -> Context:
    ctx = Context(CrosscheckSettings())
    for name, v in values.items():
        ctx.results[name] = StepResult(name, name, "ok", values=v)
    return ctx


LIMIT = {
    "upper": 0.5,
    "lower": 0.1,
    "reduced_mu": 0.4,
    "iterative": 0.45,
    "iterative_admissible": True,
    "lower_note": "",
}


def _status(checks, name):
    return next(c.status for c in checks if c.name == name)


def test_verdict_rejects_inconsistent_results():
    dem = {"lambda_max": 0.45, "termination": "plateau", "collapsed": True}
    good = verdict(_ctx(**{"limit-vertex": LIMIT, "dem-fibre": dem}))
    # everything passes but the dead-load line, which did not run here
    assert [c.name for c in good if c.status != "pass"] == ["stands under its dead load"]
    # a DEM multiplier above the upper bound, a lower bound above the upper bound, an
    # estimate outside the bounds and a run that ended at max_steps must all fail
    high = {**dem, "lambda_max": 0.6}
    assert (
        _status(
            verdict(_ctx(**{"limit-vertex": LIMIT, "dem-fibre": high})),
            "DEM fibre <= upper (vertex)",
        )
        == "fail"
    )
    crossed = {**LIMIT, "lower": 0.7}
    assert _status(verdict(_ctx(**{"limit-vertex": crossed})), "lower <= upper (vertex)") == "fail"
    low = {**LIMIT, "reduced_mu": 0.05}
    checks = verdict(_ctx(**{"limit-vertex": low}))
    assert _status(checks, "estimate mu* within bounds (vertex)") == "fail"
    stalled = {**dem, "termination": "max_steps", "collapsed": False}
    checks = verdict(_ctx(**{"limit-vertex": LIMIT, "dem-fibre": stalled}))
    assert _status(checks, "DEM fibre law collapsed") == "fail"


def test_a_failed_method_is_a_failed_line():
    ctx = _ctx(**{"limit-vertex": LIMIT})
    ctx.results["dem-resultant"] = StepResult("dem-resultant", "", "failed", "no equilibrium")
    (line,) = [c for c in verdict(ctx) if c.step == "dem-resultant"]
    assert line.status == "fail" and line.detail == "no equilibrium"


def _est(value, error):
    return Estimate(value, {"test": error}).to_dict()


def _with(values, **bars):
    """``values`` with error bars for the given keys (``values["estimates"]``)."""
    return {**values, "estimates": {k: _est(values[k], e) for k, e in bars.items()}}


def test_inequalities_are_judged_by_the_error_bars():
    """A DEM multiplier 0.6 % above the upper bound passes when its bar (1 %) reaches the
    bound, fails when its bar (0.2 %) does not; without bars the slack rtol = 1e-3 decides."""
    limit = _with(LIMIT, upper=1e-9)
    dem = {"lambda_max": 0.503, "termination": "plateau", "collapsed": True}
    line = "DEM fibre <= upper (vertex)"
    wide = verdict(_ctx(**{"limit-vertex": limit, "dem-fibre": _with(dem, lambda_max=0.005)}))
    narrow = verdict(_ctx(**{"limit-vertex": limit, "dem-fibre": _with(dem, lambda_max=0.001)}))
    bare = verdict(_ctx(**{"limit-vertex": limit, "dem-fibre": dem}))
    assert (_status(wide, line), _status(narrow, line), _status(bare, line)) == (
        "pass",
        "fail",
        "fail",
    )
    (checked,) = [c for c in wide if c.name == line]
    assert checked.value_error == 0.005 and checked.bound_error == 1e-9
    (slack,) = [c for c in bare if c.name == line]
    assert "not estimated" in slack.detail and "rtol" in slack.detail


FIBRE = {"lambda_max": 0.40, "termination": "plateau", "collapsed": True}


def test_laws_agree_when_their_intervals_overlap_and_not_without_bars():
    res = {**FIBRE, "lambda_max": 0.405}
    both = {
        "dem-fibre": _with(FIBRE, lambda_max=0.003),
        "dem-resultant": _with(res, lambda_max=0.003),
    }
    assert _status(verdict(_ctx(**both)), "the two DEM laws agree") == "pass"
    apart = {**both, "dem-resultant": _with(res, lambda_max=0.001)}  # 0.403 < 0.404
    assert _status(verdict(_ctx(**apart)), "the two DEM laws agree") == "fail"
    bare = {"dem-fibre": FIBRE, "dem-resultant": res}  # no bars: cannot be judged
    (check,) = [c for c in verdict(_ctx(**bare)) if c.name == "the two DEM laws agree"]
    assert check.status == "n/a" and "cannot be judged" in check.detail


def test_the_interface_models_difference_is_measured_on_the_scene():
    """Fibre 0.50, resultant 0.45 (bars 0.005): apart, but the upper bounds of the vertex and
    resultant models differ by 0.05 too, so the gap is the models', not the solvers'."""
    fib, res = {**FIBRE, "lambda_max": 0.50}, {**FIBRE, "lambda_max": 0.45}
    ctx = _ctx(
        **{
            "limit-vertex": _with({**LIMIT, "upper": 0.55}, upper=1e-6),
            "limit-resultant": _with({**LIMIT, "upper": 0.50}, upper=1e-6),
            "dem-fibre": _with(fib, lambda_max=0.005),
            "dem-resultant": _with(res, lambda_max=0.005),
        }
    )
    (check,) = [c for c in verdict(ctx) if c.name == "the two DEM laws agree"]
    assert check.status == "pass" and "the interface models differ by 0.050000" in check.detail


def test_verdict_explains_disagreeing_laws():
    res = {"lambda_max": 0.08, "termination": "plateau", "collapsed": True}
    ctx = _ctx(
        **{
            "limit-vertex": _with(LIMIT, upper=1e-9),
            "limit-resultant": _with({**LIMIT, "upper": 0.52}, upper=1e-9),
            "dem-fibre": _with(FIBRE, lambda_max=0.01),
            "dem-resultant": _with(res, lambda_max=0.01),
        }
    )
    (check,) = [c for c in verdict(ctx) if c.name == "the two DEM laws agree"]
    assert check.status == "fail"
    assert "(-4.0% of the vertex model's upper bound)" in check.detail
    assert "15% of its upper bound" in check.detail


def test_laws_without_a_finite_pair_are_not_compared():
    fib = {"lambda_max": math.inf, "termination": "no_mechanism", "collapsed": False}
    res = {"lambda_max": 0.3, "termination": "plateau", "collapsed": True}
    checks = verdict(_ctx(**{"dem-fibre": fib, "dem-resultant": res}))
    assert _status(checks, "the two DEM laws agree") == "n/a"


def test_laws_that_both_did_not_collapse_are_not_compared():
    # tis-3x3 of crosscheck-examples: no mechanism, both laws end at max_steps; their last
    # multipliers are no collapse loads, so there is nothing to compare (before: a failed
    # "agree" line). One law collapsing while the other does not is still a failure.
    fib = {"lambda_max": 70.0, "termination": "max_steps", "collapsed": False}
    res = {"lambda_max": 6.1, "termination": "max_steps", "collapsed": False}
    checks = verdict(_ctx(**{"dem-fibre": fib, "dem-resultant": res}))
    assert _status(checks, "the two DEM laws agree") == "n/a"
    done = {**res, "termination": "plateau", "collapsed": True}
    checks = verdict(
        _ctx(
            **{
                "dem-fibre": _with(fib, lambda_max=0.1),
                "dem-resultant": _with(done, lambda_max=0.1),
            }
        )
    )
    assert _status(checks, "the two DEM laws agree") == "fail"


def test_unbounded_limit_and_no_dem_collapse_is_no_collapse_to_check():
    # a run that did not collapse does not pass "collapsed" (it showed pass, value inf, for a
    # block pushed into the ground); no mechanism exists, so the line does not apply
    stalled = {"lambda_max": 70.0, "termination": "max_steps", "collapsed": False}
    ctx = _ctx(**{"limit-vertex": {"upper": math.inf, "unbounded": True}, "dem-fibre": stalled})
    checks = verdict(ctx)
    (line,) = [c for c in checks if c.name == "DEM fibre law collapsed"]
    assert line.status == "n/a" and line.value is None
    assert "max_steps" in line.detail and "finds no mechanism" in line.detail
    assert _status(checks, "finite upper bound (vertex)") == "n/a"


def test_weight_direction_tells_a_weight_load_from_others():
    scene = stack(2, 0.4, 0.3, 0.5, live_direction=(0.0, -2.0, 0.0))
    np.testing.assert_allclose(weight_direction(scene), [0.0, -1.0, 0.0])
    point = stack(2, 0.4, 0.3, 0.5, live_direction=None).with_loads(
        live=point_load(scene.assembly, 1, (0.0, 0.0, 1.0), (100.0, 0.0, 0.0))
    )
    assert weight_direction(point) is None


def test_settings_refuse_unknown_methods():
    with pytest.raises(ValueError, match="unknown methods"):
        CrosscheckSettings(methods=("dem", "magic"))


def test_report_lists_unbalanced_and_most_stressed_blocks():
    from validation.crosscheck.files import BLOCK_ROWS, _most_stressed

    blocks = [
        {"block": i, "residual": 1e-9, "max_principal": float(i), "min_principal": -1.0}
        for i in range(30)
    ]
    blocks[3] = {"block": 3, "residual": 0.2}  # out of equilibrium, not solved
    listed = [b["block"] for b in _most_stressed(blocks, 1e-3)]
    assert len(listed) == BLOCK_ROWS and 3 in listed
    assert listed == sorted(listed) and 29 in listed and 4 not in listed


EXPLICIT = {
    "collapsed": True,
    "mechanism_confirmed": True,
    "lambda_stable": 0.245,
    "lambda_moving": 0.25,
}


@pytest.mark.parametrize("lam, status", [(0.2475, "pass"), (0.26, "fail"), (0.24, "fail")])
def test_the_explicit_value_at_material_stiffness_is_compared_by_its_bar(lam, status):
    dem = _with({"collapsed": True, "lambda_max": lam}, lambda_max=0.001)
    explicit = _with({**EXPLICIT, "lambda_c": 0.2475}, lambda_c=0.0025)
    ctx = _ctx(explicit=explicit, **{"dem-fibre": dem})
    (check,) = [c for c in explicit_checks(ctx, 1e-6) if "static DEM fibre" in c.name]
    assert check.status == status
    # the finite-stiffness hint only where the explicit run collapsed lower than the static DEM
    assert ("large displacements" in check.detail) == (lam == 0.26)


def test_the_explicit_bracket_alone_cannot_judge_agreement():
    """Without its own error estimate the explicit run gives only its load-step bracket; its
    other sources (time step, rate, node spacing) are unknown, so the line does not apply."""
    dem = _with({"collapsed": True, "lambda_max": 0.26}, lambda_max=0.001)
    ctx = _ctx(explicit=EXPLICIT, **{"dem-fibre": dem})
    (check,) = [c for c in explicit_checks(ctx, 1e-6) if "static DEM fibre" in c.name]
    assert check.status == "n/a" and "cannot be judged" in check.detail
    assert "large displacements" in check.detail  # 0.2475 below 0.26: finite stiffness named


def test_the_rigid_limit_is_compared_and_the_stiffness_effect_measured():
    """The arch of issue 28: explicit 0.242 at the material stiffness, rigid limit 0.284 ±
    0.002, static DEM 0.2843: agreement through the rigid limit, the 15 % named as finite
    stiffness."""
    dem = _with({"collapsed": True, "lambda_max": 0.2843}, lambda_max=0.0005)
    explicit = _with(
        {**EXPLICIT, "lambda_c": 0.242, "lambda_rigid": 0.284}, lambda_c=0.002, lambda_rigid=0.002
    )
    ctx = _ctx(explicit=explicit, **{"dem-fibre": dem})
    (check,) = [c for c in explicit_checks(ctx, 1e-6) if "static DEM fibre" in c.name]
    assert check.status == "pass" and check.value == 0.284
    assert "lowers it by 0.042 (14.8% of the rigid limit)" in check.detail
    # the rigid limit against the associated upper bound (0.2852 of the arch): below it by
    # the bars, and above it when the bar cannot reach it
    limit = _with({**LIMIT, "upper": 0.2852}, upper=1e-10)
    for rigid, status in ((0.284, "pass"), (0.29, "fail")):
        explicit = _with({**EXPLICIT, "lambda_rigid": rigid}, lambda_rigid=0.002)
        ctx = _ctx(explicit=explicit, **{"limit-vertex": limit})
        (line,) = [c for c in explicit_checks(ctx, 1e-6) if "rigid limit <= upper" in c.name]
        assert line.status == status, rigid


@pytest.mark.parametrize("metre", [1.0, 1e-3], ids=["m", "mm"])
def test_an_explicit_collapse_its_solver_does_not_confirm_is_no_collapse(metre):
    """One block 0.2 x 0.2 x 0.4 m on the ground, in metres and in millimetres: in mm the
    explicit DEM's motion at 0.4375 does not grow when followed and the solver says the
    mechanism is not confirmed (LateralResult.mechanism_confirmed). The verdict passed
    "explicit run collapsed" and used the bracket as agreement all the same."""
    scene = stack(1, 0.2 / metre, 0.2 / metre, 0.4 / metre, mu=0.6)
    settings = CrosscheckSettings.quick(methods=("limit", "dem", "explicit"), pictures=False)
    result = crosscheck(scene, settings)
    step = result.step("explicit")
    confirmed = step.payload.mechanism_confirmed  # the explicit solver's own word
    assert confirmed is (metre == 1.0)  # both branches are exercised
    assert step.values["collapsed"] and step.values["mechanism_confirmed"] is confirmed
    checks = {c.name: c for c in result.checks if c.step == "explicit"}
    collapsed = checks["explicit run collapsed"]
    assert collapsed.status == ("pass" if confirmed else "fail")
    assert ("not confirmed" in collapsed.detail) is not confirmed
    judged = "lambda_c" in step.values.get("estimates", {})  # the explicit DEM's own bar
    for law in ("fibre", "resultant"):
        line = checks[f"explicit DEM agrees with the static DEM {law}"]
        if confirmed and judged:
            assert line.status == "pass"
        elif confirmed:
            assert line.status == "n/a" and "cannot be judged" in line.detail
        else:
            assert line.status == "n/a" and "no agreement" in line.detail
            assert "not confirmed" in step.reason
    # a state at rest is statically admissible whatever came after it: b / h = 0.5
    assert checks["explicit lambda_stable <= upper (vertex)"].status == "pass"
    assert result.consistent is confirmed


def test_a_fem_check_that_solved_no_block_says_so(tmp_path):
    """FEM ok with no block solved (here: the only free block carries a concentrated
    moment): the summary table printed a traceback and report.md 'largest tension None MPa'."""
    from validation.crosscheck.cli import summary
    from validation.crosscheck.fem_step import _summary
    from validation.crosscheck.files import markdown
    from validation.crosscheck.run import CrosscheckResult, scene_summary

    values = _summary([], [0], 1e-3)
    settings = {"state": "dem-fibre", "lambda": 0.5, "young": 10e9}
    reason = "blocks [0] carry concentrated moments: not solved"
    fem = StepResult("fem", "FEM", "ok", reason, 0.1, settings, values)
    result = CrosscheckResult(scene_summary(stack(1, 0.2, 0.2, 0.4)), [fem], [])
    table = summary(result)
    assert "max_tension [MPa]" in table and "None" not in table
    md = markdown(result, {}, {"git_commit": "0" * 40, "date": "today"})
    assert "No block was solved at the state dem-fibre (lambda = 0.5): " + reason in md
    assert "None MPa" not in md and "largest tension" not in md


def test_the_residual_bar_bounds_the_round_off_of_a_balanced_block():
    """A block moved to an arbitrary pose, its weight carried by equal point forces at its
    vertices (balanced exactly: the centroid of a box is the mean of its vertices): the
    computed residual is round-off only and lies within its bar, also 1e4 m from the origin; an
    imbalance of 1e-8 of the load scale lies outside it (the bar is no tolerance)."""
    from fem_check.loads import BlockLoad
    from validation.cases.bars import moved_copy
    from validation.crosscheck.fem_step import block_residual, residual_round_off

    for offset in (0.37, 123.4, 1e4):
        block = moved_copy(stack(1, 0.3, 0.2, 0.5).assembly, offset).blocks[0]
        gravity = np.array([0.0, 0.0, -9.81])
        weight = 2000.0 * block.volume * gravity
        share = np.tile(-weight / len(block.vertices), (len(block.vertices), 1))
        load = BlockLoad(block.vertices, share, density=2000.0, gravity=gravity)
        bar = residual_round_off(load, block)
        assert block_residual(load, block) <= bar < 1e-8
        tilted = BlockLoad(block.vertices, share * (1 + 2e-8), density=2000.0, gravity=gravity)
        assert block_residual(tilted, block) > bar
