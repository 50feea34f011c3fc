"""End of a collapse analysis on synthetic (c, lambda) paths with known answers."""

import math

import numpy as np
import pytest

from dem.collapse_criteria import Certificate, CollapseCriteria

DC0 = 1e-4  # first control increment [m]
SLOPE0 = 100.0  # initial slope d lambda / d c [1/m]: the first step reaches lambda = 0.01
NOISE = 1e-6  # error of lambda at every point
KNEE = 10 * DC0  # end of the elastic part of the paths below [m]


class Always:
    """Certifies every end the path's shape triggers: the tests below check the trigger."""

    def certify(self, lam, remaining):
        return Certificate("limit point", remaining)


class Never:
    """Certifies nothing (a creep whose tangent never becomes singular)."""

    def certify(self, lam, remaining):
        return None


def _criteria(certifier=None, **kw):
    args = dict(plateau_slope=2e-3, plateau_steps=4, softening_drop=0.2)
    return CollapseCriteria(0.0, DC0, **{**args, **kw}, certifier=certifier or Always())


def _run(criteria, cs, lams):
    """Feed the path; the index of the point that ended it and the reason (or None)."""
    for i, (c, lam) in enumerate(zip(cs, lams, strict=True)):
        end = criteria.add(lam, c, NOISE)
        if end is not None:
            return i, end
    return None, None


def _growing(n: int) -> np.ndarray:
    """Control points: steps of DC0 up to the knee, then growing by a quarter each step (as
    the path follower lets them grow on an approach)."""
    return np.concatenate([DC0 * np.arange(1, 11), KNEE * 1.25 ** np.arange(1, n)])


def test_elastic_perfectly_plastic_path_ends_once_flat_over_a_doubling_of_the_path():
    # lambda = min(SLOPE0 c, 0.1): flat from the knee on; once the flat part covers
    # [c/4, c] (c four times the knee) the rises over [c/4, c/2] and [c/2, c] are zero: a
    # limit point, where what may still rise is the noise
    cs = _growing(40)
    criteria = _criteria()
    i, end = _run(criteria, cs, np.minimum(SLOPE0 * cs, 0.1))
    assert end == "plateau"
    assert 4 * KNEE <= cs[i] <= 4 * 1.25 * KNEE
    assert criteria.remaining_rise() <= 20 * NOISE


def test_a_flat_path_without_a_certificate_never_ends():
    # the path of the test above, flat from the knee on, but nothing certifies a limit point:
    # it goes on, and its remaining rise stays an extrapolation
    cs = _growing(40)
    criteria = _criteria(Never())
    assert _run(criteria, cs, np.minimum(SLOPE0 * cs, 0.1)) == (None, None)
    assert criteria.certificate is None
    assert criteria.remaining_rise() <= 20 * NOISE


@pytest.mark.parametrize("shape", ["power", "exponential"])
def test_an_approach_to_a_limit_ends_within_the_stated_rise_and_bounds_it(shape):
    # after the knee lambda = LIMIT - A f(c): f = (c / KNEE)^(-1/2) (a joint rocking on a
    # shrinking strip) or exp(-(c - KNEE) / tau) (frictional hardening); the path ends once
    # what may still rise is below plateau_rise (1e-3) of lambda, and the true rest
    # LIMIT - lambda lies within that stated rise, which is at most 10 times it
    limit, a = 0.11, 0.01
    cs = _growing(120)
    if shape == "power":
        tail = limit - a * (cs / KNEE) ** -0.5
    else:
        tail = limit - a * np.exp(-(cs - KNEE) / (20 * KNEE))
    lams = np.where(cs <= KNEE, SLOPE0 * cs * (limit - a) / (SLOPE0 * KNEE), tail)
    criteria = _criteria()
    i, end = _run(criteria, cs, lams)
    assert end == "plateau"
    rest, stated = limit - lams[i], criteria.remaining_rise()
    assert rest <= stated <= max(10 * rest, 20 * NOISE)
    assert stated <= 1e-3 * lams[i]


@pytest.mark.parametrize("shape", ["linear", "logarithmic"])
def test_a_path_that_keeps_rising_never_ends_and_has_no_bound(shape):
    # linear hardening, or a creep as log(c): equal rises over each doubling of the path, no
    # limit in sight; the path is no collapse however flat it is against its start
    cs = _growing(80)
    slow = 1e-3 * SLOPE0 * (cs - KNEE) if shape == "linear" else 1e-3 * np.log(cs / KNEE)
    lams = np.where(cs <= KNEE, SLOPE0 * cs, 0.1 + slow)
    criteria = _criteria()
    assert _run(criteria, cs, lams) == (None, None)
    assert math.isinf(criteria.remaining_rise())


def test_meander_at_a_constant_peak_is_a_plateau():
    # after the knee the path meanders at lambda = 0.1 - 5e-6 U(0, 1) (five times the noise)
    # in growing steps: the envelope is flat, the path ends once the flat part spans [c/4, c]
    rng = np.random.default_rng(1)
    cs = _growing(60)
    lams = np.where(cs <= KNEE, SLOPE0 * cs, 0.1 - 5e-6 * rng.uniform(0, 1, len(cs)))
    i, end = _run(_criteria(), cs, lams)
    assert end == "plateau"
    assert cs[i] <= 4 * 1.25 * KNEE


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
        (dict(plateau_window=0.0), "plateau_window"),
    ],
)
def test_bad_settings_are_refused(kw, match):
    args = dict(c0=0.0, dc0=DC0, plateau_slope=2e-3, plateau_steps=4, softening_drop=0.2)
    with pytest.raises(ValueError, match=match):
        CollapseCriteria(**{**args, **kw}, certifier=Always())


def test_a_path_flat_at_zero_from_the_start_is_a_mechanism_at_zero():
    # a block on a frictionless floor: lambda stays within its noise of 0 while c grows. The
    # initial slope is then noise, and a plateau judged against it was never reached (the
    # fibre law ran to max_steps); four steps spanning four DC0 end it at lambda = 0
    rng = np.random.default_rng(0)
    cs = DC0 * np.arange(1, 40)
    i, end = _run(_criteria(), cs, NOISE * rng.uniform(-1, 1, len(cs)))
    assert end == "plateau"
    assert i == 4 - 1
