"""End of a collapse analysis on synthetic (c, lambda) paths with known answers."""

import numpy as np
import pytest

from dem.collapse_criteria import CollapseCriteria

DC0 = 1e-4  # first control increment [m]
SLOPE0 = 100.0  # initial slope d lambda / d c [1/m]: the first step reaches lambda = 0.01
NOISE = 1e-6  # error of lambda at every point


def _criteria():
    return CollapseCriteria(0.0, DC0, plateau_slope=2e-3, plateau_steps=4, softening_drop=0.2)


def _run(criteria, cs, lams):
    """Feed the path; the index of the point that ended it and the reason (or None)."""
    for i, (c, lam) in enumerate(zip(cs, lams, strict=True)):
        end = criteria.add(lam, c, NOISE)
        if end is not None:
            return i, end
    return None, None


def test_elastic_perfectly_plastic_path_ends_after_four_plateau_steps():
    # lambda = min(SLOPE0 c, 0.1): the flat part starts at step 10; steps of DC0 (the peak is
    # flat over the last tenth of the path as soon as the four plateau steps are counted)
    cs = DC0 * np.arange(1, 40)
    i, end = _run(_criteria(), cs, np.minimum(SLOPE0 * cs, 0.1))
    assert end == "plateau"
    assert i == 10 + 4 - 1


def test_short_steps_end_only_after_the_plateau_spans_four_first_steps():
    # rise to 0.1 at c = 10 DC0, flat to c = 30 DC0 in loosely converged steps (which neither
    # count towards a plateau nor reset it), then flat in steps of DC0 / 100: lambda is flat
    # since half the path, and four flat short steps are not enough, four DC0 of them are
    criteria = _criteria()
    for c in DC0 * np.arange(1, 11):
        assert criteria.add(SLOPE0 * c, c, NOISE) is None
    for c in DC0 * np.arange(11, 31):
        assert criteria.add(0.1, c, NOISE, loose=True) is None
    short = 30 * DC0 + 0.01 * DC0 * np.arange(1, 1000)
    i, end = _run(criteria, short, np.full(len(short), 0.1))
    assert end == "plateau"
    np.testing.assert_allclose(short[i] - 30 * DC0, 4 * DC0, atol=0.011 * DC0)


def test_slow_frictional_hardening_is_not_a_plateau():
    # issue 11, item 1: after the elastic start the path hardens towards LIMIT as
    # lambda = LIMIT - 0.01 exp(-(c - c1) / TAU), starting at 1.5e-3 of the initial slope,
    # i.e. below plateau_slope: judged against the initial slope alone it ended at once,
    # 9 % below the limit. Judged against its recent path (it rises at every step) it must
    # go on until the peak rose by less than plateau_rise (1e-3) of lambda over the last half
    # of the path (e^{-x} (e^{x/2} - 1) 0.01 <= 1e-3 LIMIT with x = c / TAU), or until a step
    # raises lambda by less than ten times its noise (0.6 % left here): within 1 %.
    limit, tau = 0.11, 0.01 / (1.5e-3 * SLOPE0)
    up = DC0 * np.arange(1, 11)
    hard = up[-1] + 10 * DC0 * np.arange(1, 2000)
    cs = np.concatenate([up, hard])
    lams = np.concatenate([SLOPE0 * up, limit - 0.01 * np.exp(-(hard - up[-1]) / tau)])
    criteria = _criteria()
    i, end = _run(criteria, cs, lams)
    assert end == "plateau"
    assert lams[i] >= limit * (1 - 1e-2)
    old = CollapseCriteria(0.0, DC0, 2e-3, 4, 0.2, plateau_rise=0.99)  # initial slope only
    j, _ = _run(old, cs, lams)
    assert lams[j] < 0.92 * limit  # what the old criterion took for the collapse


def test_meander_at_a_constant_peak_is_a_plateau_in_short_steps():
    # after the knee the path meanders at lambda = 0.1 - 5e-6 U(0, 1) (five times the noise)
    # in steps of DC0 / 10: not a rise at every step, so it ends once the plateau steps span
    # four DC0, not after the path has doubled its length (seed 001 S13 with a fixed column:
    # 300 more steps)
    rng = np.random.default_rng(1)
    up = DC0 * np.arange(1, 11)
    flat = up[-1] + 0.1 * DC0 * np.arange(1, 2000)
    cs = np.concatenate([up, flat])
    lams = np.concatenate([SLOPE0 * up, 0.1 - 5e-6 * rng.uniform(0, 1, len(flat))])
    i, end = _run(_criteria(), cs, lams)
    assert end == "plateau"
    assert cs[i] - up[-1] <= 6 * DC0


def test_meander_at_constant_lambda_is_not_a_snap_back():
    # back in c for 8 steps with lambda down by 1e-5 (less than a plateau may rise: 2e-3 *
    # SLOPE0 * 4 DC0 = 8e-5), then up again
    up = DC0 * np.arange(1, 11)
    back = up[-1] - 0.01 * DC0 * np.arange(1, 9)
    again = back[-1] + DC0 * np.arange(1, 6)
    cs = np.concatenate([up, back, again])
    lams = np.concatenate(
        [SLOPE0 * up, 0.1 - 1.25e-6 * np.arange(1, 9), 0.1 - 1e-5 + 0.005 * np.arange(1, 6)]
    )
    i, end = _run(_criteria(), cs, lams)
    assert end is None


def test_snap_back_past_the_peak_ends_the_analysis():
    # back in c with lambda falling by 5e-5 a step: ends once 4 steps went back and lambda is
    # below the peak by more than 8e-5
    up = DC0 * np.arange(1, 11)
    back = up[-1] - 0.1 * DC0 * np.arange(1, 10)
    cs = np.concatenate([up, back])
    lams = np.concatenate([SLOPE0 * up, 0.1 - 5e-5 * np.arange(1, 10)])
    criteria = _criteria()
    i, end = _run(criteria, cs, lams)
    assert end == "snap_back"
    assert i == 10 + 4 - 1
    assert criteria.peak == 0.1


def test_softening_ends_when_lambda_drops_by_a_fifth():
    up = DC0 * np.arange(1, 11)
    down = up[-1] + DC0 * np.arange(1, 40)
    cs = np.concatenate([up, down])
    lams = np.concatenate([SLOPE0 * up, 0.1 - 0.0075 * np.arange(1, 40)])
    i, end = _run(_criteria(), cs, lams)
    assert end == "softening"
    assert lams[i] < 0.08 < lams[i - 1]


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(dc0=0.0), "dc0"),
        (dict(dc0=float("nan")), "dc0"),
        (dict(plateau_slope=-1e-3), "plateau_slope"),
        (dict(softening_drop=1.5), "softening_drop"),
        (dict(plateau_steps=0), "plateau_steps"),
        (dict(plateau_rise=1.0), "plateau_rise"),
        (dict(plateau_rise=float("nan")), "plateau_rise"),
        (dict(plateau_window=-0.1), "plateau_window"),
    ],
)
def test_bad_settings_are_refused(kw, match):
    args = dict(c0=0.0, dc0=DC0, plateau_slope=2e-3, plateau_steps=4, softening_drop=0.2)
    with pytest.raises(ValueError, match=match):
        CollapseCriteria(**{**args, **kw})


def test_a_path_flat_at_zero_from_the_start_is_a_mechanism_at_zero():
    # a block on a frictionless floor: lambda stays within its noise of 0 while c grows. The
    # initial slope is then noise, and a plateau judged against it was never reached (the
    # fibre law ran to max_steps); four steps spanning four DC0 end it at lambda = 0
    rng = np.random.default_rng(0)
    cs = DC0 * np.arange(1, 40)
    i, end = _run(_criteria(), cs, NOISE * rng.uniform(-1, 1, len(cs)))
    assert end == "plateau"
    assert i == 4 - 1
    # a path that rises from the first step is judged as before
    j, end = _run(_criteria(), cs, np.minimum(SLOPE0 * cs, 0.1))
    assert (j, end) == (10 + 4 - 1, "plateau")
