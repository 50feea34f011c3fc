"""Springs of one interface and their Mohr-Coulomb law (seed 001, Sec. 2.1, Eqs. (7)-(8)).

:class:`SpringInterface` holds the spring positions in the interface frame ``(y1, y2)`` [m] and
their tributary areas [m^2]; :class:`CoulombSpringLaw` holds the friction coefficient [-],
cohesion and tensile strength [Pa] and the stiffnesses per unit area [Pa/m]. The input checks
shared by the package (:func:`_positive`, :func:`_non_negative`) live here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a finite positive number, got {value!r}")
    return value


def _non_negative(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value < 0.0:
        raise ValueError(f"{name} must be a finite non-negative number, got {value!r}")
    return value


@dataclass(frozen=True)
class SpringInterface:
    """Springs of one planar interface, in its local frame ``(y1, y2)``.

    Parameters
    ----------
    positions : ndarray, shape (n, 2)
        Spring positions relative to the interface reference point (the centre of the
        rectangle for :meth:`rectangle`) [m].
    areas : ndarray, shape (n,)
        Tributary area of each spring [m^2].

    Notes
    -----
    Value semantics: the arrays are copied and made read-only; :meth:`restricted` returns a new
    interface.
    """

    positions: np.ndarray
    areas: np.ndarray

    def __post_init__(self) -> None:
        pos = np.array(self.positions, dtype=np.float64, order="C", copy=True)
        areas = np.array(self.areas, dtype=np.float64, copy=True)
        if pos.ndim != 2 or pos.shape[1] != 2:
            raise ValueError(f"positions must have shape (n, 2), got {pos.shape}")
        if areas.shape != (pos.shape[0],):
            raise ValueError(f"areas must have shape ({pos.shape[0]},), got {areas.shape}")
        if pos.shape[0] == 0:
            raise ValueError("an interface needs at least one spring (n_springs = 0)")
        if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(areas))):
            raise ValueError("positions and areas must be finite")
        if np.any(areas < 0.0) or not np.any(areas > 0.0):
            raise ValueError("areas must be non-negative with a positive total")
        pos.flags.writeable = False
        areas.flags.writeable = False
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "areas", areas)

    @classmethod
    def rectangle(cls, l1: float, l2: float, n1: int, n2: int | None = None) -> SpringInterface:
        """Regular grid of ``n1 x n2`` springs on a rectangle centred at the origin.

        Parameters
        ----------
        l1, l2 : float
            Sides along ``y1`` and ``y2`` [m].
        n1 : int
            Number of sub-areas along ``y1``.
        n2 : int, optional
            Number along ``y2`` (default ``n1``).

        Returns
        -------
        SpringInterface
            ``n1 * n2`` springs at the sub-area centres, each with area ``l1 l2 / (n1 n2)``.
        """
        l1 = _positive("l1 (interface side along y1) [m]", l1)
        l2 = _positive("l2 (interface side along y2) [m]", l2)
        n2 = n1 if n2 is None else n2
        for name, n in (("n1 (springs along y1)", n1), ("n2 (springs along y2)", n2)):
            if isinstance(n, bool) or int(n) != n or int(n) < 1:
                raise ValueError(f"{name} must be a positive integer, got {n!r}")
        n1, n2 = int(n1), int(n2)
        y1 = (np.arange(n1) + 0.5) * (l1 / n1) - 0.5 * l1
        y2 = (np.arange(n2) + 0.5) * (l2 / n2) - 0.5 * l2
        g1, g2 = np.meshgrid(y1, y2, indexing="ij")
        pos = np.column_stack([g1.ravel(), g2.ravel()])
        return cls(pos, np.full(n1 * n2, l1 * l2 / (n1 * n2)))

    @property
    def n_springs(self) -> int:
        """Number of springs."""
        return int(self.positions.shape[0])

    @property
    def area(self) -> float:
        """Total area [m^2]."""
        return float(self.areas.sum())

    @property
    def centroid(self) -> np.ndarray:
        """Area-weighted centroid of the springs, shape (2,) [m]."""
        return self.areas @ self.positions / self.area

    def restricted(self, mask: np.ndarray) -> SpringInterface:
        """The springs selected by a boolean ``mask`` of shape (n,), same reference point."""
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (self.n_springs,):
            raise ValueError(f"mask must have shape ({self.n_springs},), got {mask.shape}")
        if not mask.any():
            raise ValueError("mask selects no spring (n_springs = 0)")
        return SpringInterface(self.positions[mask], self.areas[mask])


@dataclass(frozen=True)
class CoulombSpringLaw:
    """Mohr-Coulomb law of the interface springs (seed 001, Eqs. (7)-(8)).

    Parameters
    ----------
    mu : float
        Friction coefficient ``tan(phi)`` [-].
    cohesion : float
        Cohesion ``c`` [Pa] (0 for a dry joint).
    tensile_strength : float
        Tensile strength ``sigma_t`` [Pa] (0 for a dry joint). The seed takes
        ``c = mu sigma_t`` (the apex of the Coulomb cone); see :meth:`from_tensile_strength`.
    normal_stiffness, shear_stiffness : float
        Stiffness per unit area ``k_n``, ``k_s`` [Pa/m], used only by the incremental analysis.
        Defaults are seed 001 Sec. 2.1: 2.4 MPa/mm and 1 MPa/mm.
    """

    mu: float
    cohesion: float = 0.0
    tensile_strength: float = 0.0
    normal_stiffness: float = 2.4e9
    shear_stiffness: float = 1.0e9

    def __post_init__(self) -> None:
        _non_negative("mu (friction coefficient)", self.mu)
        _non_negative("cohesion [Pa]", self.cohesion)
        _non_negative("tensile_strength [Pa]", self.tensile_strength)
        _positive("normal_stiffness [Pa/m]", self.normal_stiffness)
        _positive("shear_stiffness [Pa/m]", self.shear_stiffness)

    @classmethod
    def from_tensile_strength(cls, mu: float, tensile_strength: float, **kw) -> CoulombSpringLaw:
        """Law with ``c = mu sigma_t`` as in seed 001, appendix (Fig. A1)."""
        return cls(mu=mu, cohesion=mu * tensile_strength, tensile_strength=tensile_strength, **kw)
