"""Small statistics of Monte Carlo samples: mean with a t confidence interval, running means,
empirical CDF, and bootstrap confidence intervals of the reported statistics (mean, standard
deviation, quantiles) as :class:`dem.estimate.Estimate`."""

from __future__ import annotations

import time
import warnings
from dataclasses import asdict, dataclass

import numpy as np
from scipy import stats

from dem.estimate import Estimate


def mean_ci(x, level: float = 0.95) -> tuple[float, float]:
    """Sample mean and the half-width of its two-sided Student-t confidence interval.

    Parameters
    ----------
    x : (n,) array_like
        Finite samples, n >= 2.
    level : float
        Confidence level in (0, 1).

    Returns
    -------
    mean, half_width : float
        ``half_width = t_{(1+level)/2, n-1} s / sqrt(n)`` with ``s`` the sample standard
        deviation (ddof 1).
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)):
        raise ValueError(f"need at least 2 finite samples, got {x.size} ({x[:5]}...)")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    half = stats.t.ppf(0.5 + level / 2, x.size - 1) * x.std(ddof=1) / np.sqrt(x.size)
    return float(x.mean()), float(half)


def running_mean_ci(x, level: float = 0.95) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(n, mean, half_width)`` of the first ``n = 2, 3, ...`` samples (in run order)."""
    x = np.asarray(x, dtype=float)
    n = np.arange(2, x.size + 1)
    out = np.array([mean_ci(x[:k], level) for k in n]).reshape(-1, 2)
    return n, out[:, 0], out[:, 1]


def ecdf(x) -> tuple[np.ndarray, np.ndarray]:
    """Sorted samples and ``F = i / n``, ``i = 1..n`` (the empirical CDF at each sample)."""
    x = np.sort(np.asarray(x, dtype=float))
    return x, np.arange(1, x.size + 1) / x.size


BOOTSTRAP_RESAMPLES = 2000
"""Bootstrap resamples of :func:`bootstrap_ci`: the Monte Carlo error of a 95 % end point is
then a few percent of the interval's width."""

STATISTICS = {
    "mean": lambda x, axis=-1: np.mean(x, axis=axis),
    "std": lambda x, axis=-1: np.std(x, ddof=1, axis=axis),
    "q05": lambda x, axis=-1: np.quantile(x, 0.05, axis=axis),
    "q50": lambda x, axis=-1: np.quantile(x, 0.50, axis=axis),
    "q95": lambda x, axis=-1: np.quantile(x, 0.95, axis=axis),
    "cov": lambda x, axis=-1: np.std(x, ddof=1, axis=axis) / np.mean(x, axis=axis),
}
"""The reported statistics of a sample, each vectorised over ``axis``."""


@dataclass(frozen=True)
class BootstrapCI:
    """A statistic of a sample and its bootstrap confidence interval.

    Attributes
    ----------
    value : float
        The statistic of the sample itself.
    lo, hi : float
        End points of the interval at ``level``.
    level : float
    method : str
        scipy's bootstrap method (``"BCa"``, or ``"percentile"`` where BCa is undefined).
    n_resamples, seed : int
    cost_s : float
        Wall time of the resampling [s].
    """

    value: float
    lo: float
    hi: float
    level: float
    method: str
    n_resamples: int
    seed: int
    cost_s: float = 0.0

    @property
    def estimate(self) -> Estimate:
        """The value with the half-width that covers the (asymmetric) interval, source
        ``"sampling"``."""
        # plus a few ulps, so that value +- half holds both end points after rounding
        ulps = 4 * np.spacing(max(abs(self.lo), abs(self.hi)))
        half = max(self.hi - self.value, self.value - self.lo, 0.0) + float(ulps)
        interval = f"[{self.lo:.6g}, {self.hi:.6g}]"
        note = f"{self.method} bootstrap {100 * self.level:g} % interval {interval}"
        return Estimate(self.value, {"sampling": half}, self.cost_s, note)

    def to_dict(self) -> dict:
        return {**asdict(self), "error": self.estimate.error}


def bootstrap_ci(
    x,
    statistic: str = "mean",
    level: float = 0.95,
    seed: int = 0,
    n_resamples: int = BOOTSTRAP_RESAMPLES,
) -> BootstrapCI:
    """Bootstrap confidence interval of one of :data:`STATISTICS` (``scipy.stats.bootstrap``,
    BCa, seeded).

    Parameters
    ----------
    x : (n,) array_like
        Finite samples, n >= 2.
    statistic : str
        A key of :data:`STATISTICS`.
    level : float
        Confidence level in (0, 1).
    seed : int
        Seed of the resampling (the interval is reproducible).

    Notes
    -----
    BCa corrects the percentile interval for bias and skew; where it is undefined (all
    resamples on one side of the statistic, as for an extreme quantile of a small sample)
    the percentile interval is used. A sample of identical values has a zero-width interval:
    resampling cannot show a spread the sample does not have.
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)):
        raise ValueError(f"need at least 2 finite samples, got {x.size} ({x[:5]}...)")
    if not 0 < level < 1:
        raise ValueError(f"level must be in (0, 1), got {level}")
    if statistic not in STATISTICS:
        raise ValueError(f"statistic must be one of {sorted(STATISTICS)}, got {statistic!r}")
    fn = STATISTICS[statistic]
    value = float(fn(x))
    if np.ptp(x) == 0:
        return BootstrapCI(value, value, value, level, "degenerate", 0, seed)
    t0 = time.perf_counter()
    for method in ("BCa", "percentile"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", stats.DegenerateDataWarning)
            res = stats.bootstrap(
                (x,), fn, confidence_level=level, n_resamples=n_resamples, method=method,
                random_state=np.random.default_rng(seed), vectorized=True,
            )  # fmt: skip
        lo, hi = float(res.confidence_interval.low), float(res.confidence_interval.high)
        if np.isfinite(lo) and np.isfinite(hi):
            cost = time.perf_counter() - t0
            return BootstrapCI(value, lo, hi, level, method, n_resamples, seed, cost)
    raise ValueError(f"no finite bootstrap interval of the {statistic} of {x.size} samples")


def sample_statistics(x, level: float = 0.95, seed: int = 0) -> dict[str, BootstrapCI]:
    """Every statistic of :data:`STATISTICS` with its bootstrap interval (one seed for all)."""
    return {name: bootstrap_ci(x, name, level, seed) for name in STATISTICS}
