"""Seed 001 accuracy targets of the static DEM (slow: full collapse analyses of the specimens).

Run with ``pytest -m slow tests/dem/test_static_seed001.py``. Expectations are the seed's
numbers (Tables 1-3) and the seed's own accuracy; never our earlier output.
"""

import numpy as np
import pytest

from dem.scenes.running_bond_wall import running_bond_wall
from dem.scenes.seed001_walls import CHEE_LIANG_NAMES, RESTREPO_NAMES, SPECIMENS
from dem.static import StaticSettings, solve_collapse
from dem.units import MPA, N_MM3

SEED_TABLE2_MEAN_ERROR = 0.096  # seed 001 DEM vs the Table 2 experiments


def _settings(spec, model="fibre", **kw):
    j = spec.joint
    extra = {}
    if j.tensile_strength_mpa:
        extra = dict(
            tensile_strength=j.tensile_strength_mpa * MPA,
            kn=j.kn_n_mm3 * N_MM3,
            kt=j.kt_n_mm3 * N_MM3,
            tension_at_supports=False,
            load_step=0.1,
        )
        if model == "fibre":
            extra["fibre_points"] = 4
    return StaticSettings(interface_model=model, mu=j.mu, on_failure="return", **extra, **kw)


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="open model difference: the fibre law with return walls of blocks misses Table 2's "
    "experiments by 13.2-13.3 % on average against the seed DEM's 9.6 % (measured on the "
    "committed results of 2026-11-25 and again after the end-of-path certificates); S5 alone "
    "is 36 % low (0.223 against 0.349), and its return walls as 6 blocks give 0.328",
)
def test_table2_mean_error_not_worse_than_the_seed():
    # target of issue 3: mean |lambda - lambda_exp| / lambda_exp over Table 2 <= 9.6 % (the
    # seed's own DEM) with at least one interface model; ours: fibre law, return walls of blocks
    errors = []
    for name in RESTREPO_NAMES:
        spec = SPECIMENS[f"restrepo-{name}"]
        scene = spec.build(return_walls="blocks")
        lam = solve_collapse(scene, _settings(spec)).lambda_max
        errors.append(abs(lam - spec.reference) / spec.reference)
    assert np.mean(errors) <= SEED_TABLE2_MEAN_ERROR, f"errors {np.round(errors, 3)}"


@pytest.mark.slow
@pytest.mark.parametrize(
    "key",
    [
        pytest.param(
            "orduna-3x13",
            marks=pytest.mark.xfail(
                strict=True,
                reason="open model difference: both laws give 0.245-0.247 with return walls "
                "of blocks, above 1.1 x the seed's largest value (FEM 0.21); the 6x13 panel "
                "ends at the same lambda to 6 digits (fibre 0.246914), which points to a "
                "mechanism both panels share; it lies inside the 6x13 spread",
            ),
        ),
        "orduna-6x13",
    ],
)
def test_table1_within_the_seed_spread(key):
    # between the seed's DEM, FEM and limit analysis, with 10 % slack (the seed's DEM is itself
    # 17 % below the FEM)
    spec = SPECIMENS[key]
    values = [spec.seed_dem, *spec.references.values()]
    lam = solve_collapse(spec.build(return_walls="blocks"), _settings(spec)).lambda_max
    assert 0.9 * min(values) <= lam <= 1.1 * max(values)


@pytest.mark.slow
@pytest.mark.parametrize("name", CHEE_LIANG_NAMES)
def test_table3_within_the_seed_spread(name):
    # between the seed's DEM and the two tests of the wall pair, with 10 % slack
    spec = SPECIMENS[f"chee-liang-{name}"]
    values = [spec.seed_dem, *spec.references.values()]
    p = solve_collapse(spec.build(), _settings(spec)).lambda_max * 1e-3  # [kN/m^2]
    assert 0.9 * min(values) <= p <= 1.1 * max(values)


@pytest.mark.slow
@pytest.mark.parametrize("step", [0.005, 0.02])
def test_collapse_load_independent_of_the_load_step(step):
    # halving or doubling the load step changes lambda_max by less than 1 %
    spec = SPECIMENS["restrepo-S15"]
    scene = spec.build(return_walls="blocks")
    ref = solve_collapse(scene, _settings(spec, load_step=0.01)).lambda_max
    lam = solve_collapse(scene, _settings(spec, load_step=step)).lambda_max
    np.testing.assert_allclose(lam, ref, rtol=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("step", [0.005, 0.02])
def test_seed_model_collapse_independent_of_the_load_step(step):
    # the seed's own model (resultant law, end column fixed), S11: halving or doubling the
    # load step changes lambda_max by less than 1 %, and every path ends on the plateau
    spec = SPECIMENS["restrepo-S11"]
    scene = spec.build(return_walls="fixed_column")
    ref = solve_collapse(scene, _settings(spec, "resultant", load_step=0.01))
    res = solve_collapse(scene, _settings(spec, "resultant", load_step=step))
    assert ref.termination == res.termination == "plateau"
    np.testing.assert_allclose(res.lambda_max, ref.lambda_max, rtol=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("case", ["masonry-orduna", "masonry-restrepo", "masonry-chee-liang"])
def test_quick_validation_case_runs(case):
    from validation.cases import masonry

    rows, notes = masonry.CASES[case](quick=True)
    assert rows and notes
    assert all(r.reference is not None for r in rows)
    assert any(r.ours is not None for r in rows)


@pytest.mark.parametrize(
    ("build", "grid_free"),
    [
        (lambda: running_bond_wall(3, 5, 100, 200, 100, 18, 0.5, live="weight"), True),
        (lambda: running_bond_wall(4, 6, 81, 210, 70, 20, 0.6, fixed_columns=("left",)), False),
    ],
)
def test_fibre_grid_check_records_the_finer_grid(build, grid_free):
    # a free-standing wall overturns about the edge of its base joint, where the Lobatto
    # grid has its outer springs on any grid: lambda = b / h = 0.2 on both grids. A wall
    # held by a column twists its joints, and the finer grid moves it: the check must record
    # that lambda and its change against the row's own run
    from validation.cases.masonry import FIBRE_CHECK_POINTS, _fibre_grid_check
    from validation.report import Row

    scene = build()
    settings = StaticSettings(interface_model="fibre", mu=0.6, on_failure="return")
    result = solve_collapse(scene, settings)
    row = Row("wall", result.lambda_max)
    _fibre_grid_check(row, result, scene, settings)
    finer = solve_collapse(
        scene,
        StaticSettings(
            interface_model="fibre", mu=0.6, on_failure="return", fibre_points=FIBRE_CHECK_POINTS
        ),
    )
    assert row.extra["fibre_check_points"] == FIBRE_CHECK_POINTS == 7
    assert row.extra["lambda_fibre_check"] == finer.lambda_max
    change = finer.lambda_max / result.lambda_max - 1.0
    assert row.extra["fibre_grid_change"] == pytest.approx(change, rel=1e-12)
    if grid_free:
        np.testing.assert_allclose(finer.lambda_max, 0.2, rtol=1e-3)
        assert abs(change) < 1e-3
    else:
        assert abs(change) > 2e-3
