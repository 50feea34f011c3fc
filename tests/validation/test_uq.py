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
from validation.sweep.stats import (
    bootstrap_ci,
    ecdf,
    mean_ci,
    running_mean_ci,
    sample_statistics,
)


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


def test_bootstrap_ci_of_the_mean_covers_at_its_level_and_matches_the_normal_width():
    """Normal samples (n = 30, mu = 3, sigma = 2), 400 seeds: the 95 % interval of the mean
    covers mu in 95 % of them (within three binomial standard deviations, +-0.033). Its width
    is, on average, the normal interval's with the plug-in deviation: the t interval times
    z_0.975 / t_0.975,29 * sqrt(29 / 30) = 0.942."""
    n, n_seeds = 30, 400
    covered, ratios = 0, []
    for seed in range(n_seeds):
        x = np.random.default_rng(10_000 + seed).normal(3.0, 2.0, n)
        ci = bootstrap_ci(x, "mean", seed=seed)
        covered += ci.lo <= 3.0 <= ci.hi
        ratios.append((ci.hi - ci.lo) / (2 * mean_ci(x)[1]))
    sigma = math.sqrt(0.95 * 0.05 / n_seeds)
    assert abs(covered / n_seeds - 0.95) <= 3 * sigma
    expected = stats.norm.ppf(0.975) / stats.t.ppf(0.975, n - 1) * math.sqrt((n - 1) / n)
    assert np.mean(ratios) == pytest.approx(expected, abs=0.02)


def test_bootstrap_statistics_are_seeded_and_carry_their_estimates():
    x = np.random.default_rng(3).normal(0.0, 1.0, 40)
    a, b = sample_statistics(x, seed=5), sample_statistics(x, seed=5)
    for name in a:  # the same interval from the same seed (only the measured cost differs)
        assert (a[name].lo, a[name].hi, a[name].value) == (b[name].lo, b[name].hi, b[name].value)
        assert a[name].estimate.cost_s > 0
    assert set(a) == {"mean", "std", "q05", "q50", "q95", "cov"}
    for ci in a.values():
        est = ci.estimate
        assert ci.lo <= ci.value <= ci.hi
        assert est.contains(ci.lo) and est.contains(ci.hi) and "sampling" in est.sources
    assert a["std"].value == pytest.approx(x.std(ddof=1))
    assert a["cov"].value == pytest.approx(x.std(ddof=1) / x.mean())
    assert bootstrap_ci(x, "mean", seed=6).lo != a["mean"].lo  # another seed, other resamples
    flat = bootstrap_ci([2.0, 2.0, 2.0], "mean")
    assert flat.lo == flat.hi == 2.0
    with pytest.raises(ValueError, match="statistic must be one of"):
        bootstrap_ci(x, "mode")
    with pytest.raises(ValueError, match="finite samples"):
        bootstrap_ci([1.0, math.nan], "mean")


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


def test_stats_rows_carry_the_bootstrap_bar_of_the_mean():
    """A uq row's ours is the mean with its bootstrap half-width (source 'sampling'), close to
    the t interval's (normal samples, n = 40: the ratio is 0.95 in expectation)."""
    from validation.cases.uq import _stats_rows

    x = np.random.default_rng(11).normal(5.0, 1.0, 40)
    (row,) = _stats_rows("x", x, "N", {})
    assert row.ours == pytest.approx(x.mean())
    assert set(row.error_sources) == {"sampling"}
    assert row.ours_error == pytest.approx(mean_ci(x)[1], rel=0.2)
    assert set(row.extra["bootstrap"]) == {"mean", "std", "q05", "q50", "q95", "cov"}


def test_a_run_without_reruns_has_a_partial_peak_bar():
    """The triangle P = 100 delta to delta = 1, then down, recorded every 1e-3: the peak's free
    bar (curve sampling, 100 h) holds the continuous peak 100, and the reruns a full budget
    would pay for are named as omitted (a partial bar, not an unknown one)."""
    from types import SimpleNamespace

    from dem.explicit import curve_summary
    from validation.cases.uq import peak_estimate

    h = 1e-3
    delta = np.arange(1, 4001) * h
    load = np.where(delta <= 1.0, 100 * delta, np.maximum(0.0, 100 * (2.0 - delta)))
    res = SimpleNamespace(delta=delta, load=load, **curve_summary(delta, load, 0.05, 0.5))
    est = peak_estimate(res, h)
    assert est.contains(100.0) and 0 < est.error <= 100 * h * (1 + 1e-9)
    assert est.omitted == ("loading rate", "time step", "node spacing") and not est.complete
    up, up_load = delta[:500], 100 * delta[:500]
    rising = SimpleNamespace(delta=up, load=up_load, **curve_summary(up, up_load, 0.05, 0.5))
    assert math.isinf(peak_estimate(rising, h).error)
