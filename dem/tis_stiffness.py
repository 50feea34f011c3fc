"""Penetration stiffness and imperfection models for TIS panels (seed 000, Secs. 2.3 and 5).

- Perfect panel: ``k_n = k_def = M E / L`` (seed 000 Eq. (3)): ``M`` interfaces across which
  penetrations accumulate along a strip of length ``L`` through the panel, so that ``M`` rigid
  interfaces give the elastic shortening ``sigma L / E`` of the strip. For the ``n x n`` panel the
  strip through the centre holds a half block, ``n`` internal blocks and a half block: ``M = n + 1``
  interfaces over the panel side ``L`` (seed 000 Fig. 4f).
- Gaps (seed 000 Eq. (4)): ``k_imp = k_def k_gaps / (k_def + k_gaps)``, the gap closure and the
  block deformation as springs in series; the seed calibrates ``k_gaps = 0.65 GPa/mm`` on the
  5 x 5, 5 degree panel and keeps it for every panel.
- Friction variability (seed 000 Fig. 9b): per-block coefficients drawn from a normal
  distribution; a pair's coefficient is combined by the solver's ``mu_rule``
  (:class:`dem.explicit.ExplicitSettings`, default the arithmetic mean of the two blocks).

The seed states ``k_def = 2.25 GPa/mm`` for its panels (Sec. 5.1.2) but not ``E``; with
``M = 6`` and ``L = 50 mm`` for the 5 x 5 panel that value implies ``E = 18.75 GPa``
(:data:`YOUNG_SEED_000`), which is used here for all panels so that ``k_def`` follows Eq. (3) with
the number of blocks (3 x 3: 1.5 GPa/mm, 7 x 7: 3.0 GPa/mm).
"""

from __future__ import annotations

import math

import numpy as np

from dem.units import GPA, MM

K_DEF_SEED_000 = 2.25 * GPA / MM
"""``k_def`` of the 5 x 5 panel, seed 000 Sec. 5.1.2 [Pa/m]."""
K_GAPS_SEED_000 = 0.65 * GPA / MM
"""Calibrated gap stiffness, seed 000 Sec. 5.1.2 [Pa/m]."""
YOUNG_SEED_000 = K_DEF_SEED_000 * 50.0 * MM / 6.0
"""Young's modulus implied by ``K_DEF_SEED_000`` for the 5 x 5 panel (M = 6, L = 50 mm) [Pa]."""
MU_STD_SEED_000 = 0.06
"""Standard deviation of the per-block friction coefficients, seed 000 Fig. 9b."""


def k_def(young: float, n_interfaces: int, length: float) -> float:
    """Penetration stiffness equivalent to the blocks' in-plane deformability, Eq. (3).

    Parameters
    ----------
    young : float
        Young's modulus ``E`` [Pa].
    n_interfaces : int
        ``M``, interfaces along the strip.
    length : float
        ``L``, strip length [m].

    Returns
    -------
    float
        ``M E / L`` [Pa/m].
    """
    if not (math.isfinite(young) and young > 0):
        raise ValueError(f"young must be finite and positive [Pa], got {young}")
    if int(n_interfaces) != n_interfaces or n_interfaces < 1:
        raise ValueError(f"n_interfaces must be a positive integer, got {n_interfaces}")
    if not (math.isfinite(length) and length > 0):
        raise ValueError(f"length must be finite and positive [m], got {length}")
    return n_interfaces * young / length


def tis_panel_k_def(n: int, young: float = YOUNG_SEED_000, size: float = 50.0 * MM) -> float:
    """``k_def`` of the ``n x n`` TIS panel: ``M = n + 1`` interfaces over the side ``L``."""
    return k_def(young, n + 1, size)


def k_series(k_deformation: float, k_gaps: float) -> float:
    """Gap-softened penetration stiffness, Eq. (4): ``k_def k_gaps / (k_def + k_gaps)`` [Pa/m]."""
    for name, value in (("k_deformation", k_deformation), ("k_gaps", k_gaps)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and positive [Pa/m], got {value}")
    return k_deformation * k_gaps / (k_deformation + k_gaps)


def draw_block_friction(
    n_blocks: int, mean: float, std: float, seed: int, minimum: float = 0.0
) -> np.ndarray:
    """Per-block friction coefficients from a normal distribution (seed 000 Fig. 9b).

    Parameters
    ----------
    n_blocks : int
    mean, std : float
        Of the normal distribution (seed 000: 0.23 and 0.06).
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same draw.
    minimum : float
        Values below are clipped to it (a friction coefficient cannot be negative; with the
        seed's numbers a draw below 0 has probability 6e-5 per block).

    Returns
    -------
    (n_blocks,) float
    """
    if std < 0 or not math.isfinite(std) or not math.isfinite(mean):
        raise ValueError(f"need finite mean and std >= 0, got {mean}, {std}")
    rng = np.random.default_rng(seed)
    return np.maximum(rng.normal(mean, std, size=n_blocks), minimum)
