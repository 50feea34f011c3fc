"""The ratio of two indentation numbers with the bar of the interval quotient (tis cases)."""

import math

import numpy as np

from dem.estimate import Estimate
from validation.cases.tis import ratio


def test_ratio_is_the_interval_quotient():
    """(10 +- 1) / (5 +- 0.5): the quotient's interval is [9 / 5.5, 11 / 4.5], so the bar
    about 2 is 11 / 4.5 - 2 = 0.444 (first order would say 0.4); it is shared over the two
    sources in proportion to their first-order parts (0.2 each)."""
    q = ratio(Estimate(10.0, {"rate": 1.0}), Estimate(5.0, {"rate": 0.5}))
    assert q.value == 2.0
    np.testing.assert_allclose(q.error, 11 / 4.5 - 2, rtol=1e-12)
    np.testing.assert_allclose(q.sources["numerator: rate"], q.sources["denominator: rate"])
    assert q.contains(9 / 5.5) and q.contains(11 / 4.5)


def test_ratio_unbounded_where_it_must_be():
    """An unknown bar stays unknown, and a denominator whose interval holds zero gives an
    unbounded quotient."""
    unknown = ratio(Estimate.unknown(3.0), Estimate(2.0, {"rate": 0.1}))
    assert math.isinf(unknown.error) and unknown.value == 1.5
    assert math.isinf(ratio(Estimate(1.0, {"a": 0.1}), Estimate(0.5, {"b": 0.6})).error)
    assert ratio(Estimate(1.0, {"exact": 0.0}), Estimate(4.0, {"exact": 0.0})).error == 0.0


def test_mean_of_runs():
    """Three runs 9, 10, 11 with bars 0.1, 0.2, 0.3 (source "rate"): the mean 10 with the t
    interval of the mean, t_{0.975, 2} s / sqrt(3) = 4.303 / sqrt(3) (s = 1), and the mean
    bar 0.2."""
    from validation.cases.tis import mean_of_runs

    runs = [Estimate(v, {"rate": w}) for v, w in ((9.0, 0.1), (10.0, 0.2), (11.0, 0.3))]
    m = mean_of_runs(runs)
    assert m.value == 10.0
    np.testing.assert_allclose(m.sources["sampling"], 4.302652729911275 / np.sqrt(3), rtol=1e-9)
    np.testing.assert_allclose(m.sources["rate"], 0.2)


def test_ratio_and_mean_keep_what_their_parts_omit():
    """A bar that omits the time step and node spacing (the 'cheap' budget) does not become
    complete by dividing or averaging: the quotient and the mean omit them too."""
    from validation.cases.tis import mean_of_runs

    cheap = Estimate(10.0, {"rate": 1.0}, omitted=("time step", "node spacing"))
    full = Estimate(5.0, {"rate": 0.5})
    for q in (ratio(cheap, full), ratio(full, cheap), mean_of_runs([cheap, full])):
        assert q.omitted == ("time step", "node spacing") and not q.complete
    assert ratio(full, full).omitted == ()
