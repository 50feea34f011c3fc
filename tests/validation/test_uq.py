"""Uncertainty studies: their statistics, the failure-mode rule and the TIS task function.

Expectations: scipy's Student-t interval, the definition of the empirical CDF, and the
homogeneity of the quasi-static TIS problem in k_n (P scales with k_n: rigid blocks, penalty
contact, k_t proportional to k_n, weight negligible), so the calibrated model's peak over the
perfect one is k_imp / k_def (seed 000 Eq. 4).
"""

import math

import numpy as np
import pytest
from scipy import stats

from dem.explicit import RelaxationSettings
from dem.tis_stiffness import K_GAPS_SEED_000, k_series, tis_panel_k_def
from dem.units import GPA, MM
from validation.cases.tis import QUICK
from validation.cases.uq import failure_mode, tis_gaps_task
from validation.sweep.stats import ecdf, mean_ci, running_mean_ci


def test_mean_ci_is_the_student_t_interval():
    x = np.random.default_rng(0).normal(3.0, 2.0, 12)
    lo, hi = stats.t.interval(0.95, x.size - 1, loc=x.mean(), scale=stats.sem(x))
    mean, half = mean_ci(x)
    np.testing.assert_allclose([mean - half, mean + half], [lo, hi], rtol=1e-12)
    n, means, halves = running_mean_ci(x)
    assert n[0] == 2 and n[-1] == 12
    np.testing.assert_allclose([means[-1], halves[-1]], [mean, half])


@pytest.mark.parametrize("bad", [[1.0], [1.0, math.nan], [[1.0, 2.0]]])
def test_mean_ci_rejects_too_few_or_nonfinite_samples(bad):
    with pytest.raises(ValueError, match="finite samples"):
        mean_ci(bad)


def test_ecdf_steps_by_one_over_n():
    x, f = ecdf([0.3, 0.1, 0.2, 0.4])
    np.testing.assert_array_equal(x, [0.1, 0.2, 0.3, 0.4])
    np.testing.assert_array_equal(f, [0.25, 0.5, 0.75, 1.0])


def test_failure_mode_rule():
    assert failure_mode({"central_out": True}, 3.0) == "central out"
    assert failure_mode({"central_out": False}, 3.0) == "several blocks"
    assert failure_mode({"central_out": True}, math.nan) == "not out"
    assert failure_mode({"central_out": True}, math.nan, "blocks 1 and 2 overlap") == "stopped"


@pytest.mark.slow  # three 3 x 3 panels with 20000 relaxation steps each: ~30 s idle, 90 s loaded
def test_gap_task_calibrated_over_perfect_is_the_stiffness_ratio_and_gaps_weaken():
    k_def = tis_panel_k_def(3)
    k_imp = k_series(k_def, K_GAPS_SEED_000)
    disc = {**QUICK, "node_spacing_mm": 2.0}
    base = {"n": 3, "theta_deg": 2.5, "disc": disc, "stop_below_peak_fraction": 0.85}
    unit = GPA / MM
    perfect = tis_gaps_task({**base, "k_n_gpa_mm": k_def / unit, "mean_gap_mm": 0.0}, 0)
    calibrated = tis_gaps_task({**base, "k_n_gpa_mm": k_imp / unit, "mean_gap_mm": 0.0}, 0)
    gappy = tis_gaps_task({**base, "k_n_gpa_mm": k_def / unit, "mean_gap_mm": 0.02}, 1)
    ratio = calibrated["peak_load"] / perfect["peak_load"]
    np.testing.assert_allclose(ratio, k_imp / k_def, rtol=0.05)
    assert gappy["peak_load"] < 0.9 * perfect["peak_load"]
    assert len(perfect["delta_mm"]) == len(perfect["load_n"]) > 10
    assert max(perfect["load_n"]) == pytest.approx(perfect["peak_load"], rel=0.02)


def test_a_gapped_panel_relaxed_until_settled_is_in_balance_unlike_as_built():
    """As built, the loose blocks still hang where they were built when the indenter starts
    (out of balance by their whole weight); relaxed 'viscous', every block carries its load
    within the relaxation's default tolerance."""
    disc = {**QUICK, "node_spacing_mm": 2.0}
    k_n = tis_panel_k_def(3) / (GPA / MM)
    base = {"n": 3, "theta_deg": 2.5, "disc": disc, "stop_below_peak_fraction": 0.5,
            "k_n_gpa_mm": k_n, "mean_gap_mm": 0.01, "gap_seed": 3}  # fmt: skip
    built = tis_gaps_task({**base, "settle": "as_built"}, 0)
    settled = tis_gaps_task({**base, "settle": "viscous"}, 1)  # the same gaps: gap_seed
    assert built["relax_unbalanced_ratio"] > 0.5
    assert settled["relax_unbalanced_ratio"] <= RelaxationSettings().unbalanced_tol
    assert settled["relax_steps"] > built["relax_steps"]
