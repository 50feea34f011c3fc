"""A closed-form task for trying the sweep machinery (tests, benchmark, README).

A rigid block of width ``b`` and height ``h`` stands on a tilting table; its friction
coefficient is drawn from ``N(mu_mean, mu_std)`` with the task's seed. The table tilts until the
block slides (``tan(alpha) = mu``) or overturns about its lower edge (``tan(alpha) = b / h``),
whichever comes first (Coulomb friction, rigid block, no bouncing).
"""

from __future__ import annotations

import math
import time

import numpy as np


def tilting_block(params: dict, seed: int) -> dict:
    """Tilt angle at which a block with random friction slides or overturns.

    Parameters
    ----------
    params : dict
        ``b``, ``h`` [m] (positive), ``mu_mean``, ``mu_std`` [-]; optional ``hold_s`` [s]: wait
        this long before answering, to stand in for a longer solve.
    seed : int
        Seed of ``numpy.random.default_rng`` for the friction draw.

    Returns
    -------
    dict
        ``mu`` [-], ``lam = tan(alpha)`` [-], ``alpha_deg`` [deg], ``mode`` ("sliding" or
        "overturning").
    """
    b, h = float(params["b"]), float(params["h"])
    if not (b > 0 and h > 0):
        raise ValueError(f"block width b and height h must be positive, got b={b}, h={h}")
    rng = np.random.default_rng(seed)
    mu = max(0.0, float(rng.normal(params["mu_mean"], params["mu_std"])))
    time.sleep(float(params.get("hold_s", 0.0)))
    lam = min(mu, b / h)
    return {
        "mu": mu,
        "lam": lam,
        "alpha_deg": math.degrees(math.atan(lam)),
        "mode": "sliding" if mu < b / h else "overturning",
    }
