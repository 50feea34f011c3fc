"""Small statistics of Monte Carlo samples: mean with a t confidence interval, running means,
empirical CDF."""

from __future__ import annotations

import numpy as np
from scipy import stats


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
