"""The value-with-error type: interval arithmetic, rounding to the supported digits, and
Richardson extrapolation against a closed-form sequence."""

import math

import pytest

from dem.estimate import Estimate, check_error_budget, format_estimate, richardson


def test_error_is_the_sum_of_the_sources_and_overlap_is_interval_overlap():
    a = Estimate(1.0, {"step": 0.01, "grid": 0.02})
    assert a.error == pytest.approx(0.03)
    assert a.contains(1.03) and not a.contains(1.031)
    assert a.overlaps(Estimate(1.05, {"x": 0.02}))
    assert not a.overlaps(Estimate(1.05, {"x": 0.019}))


def test_unknown_error_is_infinite_and_round_trips_through_json_types():
    e = Estimate.unknown(0.3)
    assert math.isinf(e.error) and e.contains(1e9)
    d = e.to_dict()
    assert d["error"] == "inf"
    assert math.isinf(Estimate.from_dict(d).error)


@pytest.mark.parametrize("bad", [-1e-3, float("nan")])
def test_negative_or_nan_half_width_is_refused(bad):
    with pytest.raises(ValueError, match="half-width"):
        Estimate(1.0, {"step": bad})


def test_nan_value_and_unknown_budget_are_refused():
    with pytest.raises(ValueError, match="NaN"):
        Estimate(float("nan"))
    with pytest.raises(ValueError, match="error budget"):
        check_error_budget("some")


@pytest.mark.parametrize(
    ("value", "error", "text"),
    [
        (0.014945566619567587, 0.00012, "0.01495 ± 0.00012"),
        (0.28431, 0.0, "0.28431"),
        (123.456, 2.3, "123.5 ± 2.3"),
        (0.3, math.inf, "0.3 ± ?"),
        (0.285158842223, 3.5e-11, "0.2851588 ± 3.5e-11"),
        (0.0, 7.1e-07, "0 ± 7.1e-07"),
        (0.0, 0.25, "0.00 ± 0.25"),
    ],
)
def test_format_keeps_the_digits_the_error_supports(value, error, text):
    assert format_estimate(value, error) == text


def test_richardson_recovers_the_limit_of_a_second_order_sequence():
    # f(h) = 2 + 3 h^2: levels h = 0.2 and 0.1 extrapolate exactly to 2
    est = richardson(2 + 3 * 0.04, 2 + 3 * 0.01, ratio=2.0, order=2.0)
    assert est.value == pytest.approx(2.0)
    assert est.contains(2 + 3 * 0.01)


def test_sweep_errors_hold_the_limit_of_pre_asymptotic_and_asymptotic_sweeps():
    """Sequences s(h) = 1 + a h + b h^2 + c h^3 on uneven steps (ratios 4/3, 3/2, 2, 2) whose
    finest pair is asymptotic at order >= 1: every level's bar at the assumed order 1 contains
    the limit 1, also where the differences grow on refinement (the last two cases: 0.69,
    1.19, 1.94 before 0.90), which a bar from the next finer level alone misses; a level that
    is the model itself has no error; bad sweeps are refused."""
    from dem.estimate import sweep_errors

    steps = [2.0, 1.5, 1.0, 0.5, 0.25]
    for a, b, c in [(1, 0, 0), (1, 5, 0), (0, 2, 0), (1, 2, -1), (2, 3, -1.5)]:
        values = [1.0 + a * h + b * h**2 + c * h**3 for h in steps]
        for h, s, e in zip(steps, values, sweep_errors(steps, values, 1.0), strict=True):
            assert abs(s - 1.0) <= e + 1e-12, (a, b, c, h, s, e)
    values = [1.0 + 2 * h + 3 * h**2 - 1.5 * h**3 for h in steps]
    assert abs(values[0] - 1.0) > abs(values[0] - values[1]) * 4  # next-finer bar at r = 4/3
    assert sweep_errors([2.0, 1.0], [3.0, 2.0], 1.0) == [2.0, 1.0]
    assert sweep_errors([4.0, 1.0], [3.0, 2.0], 0.5, exact_last=True) == [1.0, 0.0]
    assert sweep_errors([2.0, 1.0, 0.5], [math.nan, 2.0, 1.5], 1.0)[0] == math.inf
    with pytest.raises(ValueError, match="decrease"):
        sweep_errors([1.0, 2.0], [1.0, 1.0], 1.0)
    with pytest.raises(ValueError, match=">= 2 levels"):
        sweep_errors([1.0], [1.0], 1.0)


def test_a_bar_that_omits_known_sources_says_so():
    """An estimate that lists the sources its budget did not pay for is not complete, prints
    them, keeps them through JSON, and loses one when that source is added."""
    e = Estimate(243.2, {"loading rate": 0.8}, omitted=("time step", "node spacing"))
    assert not e.complete and Estimate(1.0, {"grid": 0.1}).complete
    assert not Estimate.unknown(1.0).complete
    assert e.format("N") == "243.20 ± 0.80 N (without time step, node spacing)"
    assert Estimate.from_dict(e.to_dict()) == e
    assert e.with_source("time step", 0.1).omitted == ("node spacing",)
    with pytest.raises(ValueError, match="omitted"):
        Estimate(1.0, omitted="time step")
