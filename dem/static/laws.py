"""Interface laws as objects with one small protocol.

Every law takes the relative motions ``q`` (m, 6) of all interfaces and returns their actions,
tangents and states for a trial (:meth:`InterfaceLaw.evaluate`), keeps the plastic state of
the last equilibrium (:meth:`InterfaceLaw.commit`), and can keep only the tensile failures of
a failed trial (:meth:`InterfaceLaw.keep_breaks`, the cracking cascade). Its numerical
defaults (tangent floor, predictor, loose tolerance, fibre grid) live in its settings
(:mod:`dem.static.settings`).

- :class:`ResultantLaw`: seed 001's law on ``(N, V1, V2, M1, M2, M3)``, its normal stress
  integrated over each joint polygon (:mod:`dem.kernels.interface_law`);
- :class:`FibreLaw`: a grid of no-tension Mohr-Coulomb springs per interface
  (:mod:`dem.kernels.fibre_law`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from dem.geometry.clipping import counter_clockwise
from dem.geometry.interfaces import Interfaces
from dem.kernels import fibre_law as fk
from dem.kernels import interface_law as rk
from dem.kernels.contact_stress import MAX_VERTICES
from dem.static.settings import FibreLawSettings, ResultantLawSettings

ALPHA_TABLE_A1 = np.array(
    [
        # l1/l2, alpha(f1 only), alpha(f1 = f2), alpha(f2 only)   -- seed 001 Table A1
        [0.1, 1.00, 2.00, 2.56],
        [0.2, 1.05, 1.90, 2.44],
        [0.5, 1.25, 1.70, 1.92],
        [1.0, 1.43, 1.43, 1.43],
        [2.0, 1.92, 1.70, 1.25],
        [5.0, 2.44, 1.90, 1.05],
        [10.0, 2.56, 2.00, 1.00],
    ]
)
"""Exponents of seed 001 Eq. (A5) by interface aspect ratio and shear direction."""


@dataclass(frozen=True, eq=False)
class JointArrays:
    """Geometry and strength of the ``m`` joints, shared by every law.

    Attributes
    ----------
    area : (m,) float
        [m^2].
    second_moments : (m, 2) float
        ``(J11, J22)`` about the centroid [m^4].
    dims : (m, 2) float
        Extents ``(l1, l2)`` along ``t1, t2`` [m].
    mu : (m,) float
        Friction coefficient [-].
    tensile, cohesion : (m,) float
        Tensile strength and cohesion [Pa].
    compressive : float
        Compressive strength [Pa]; inf for none.
    kn, kt, kr : float
        Stiffness per unit area [Pa/m].
    extent : float
        Largest side of the model's bounding box [m]: the scale of its round-off in gaps.
    """

    area: np.ndarray
    second_moments: np.ndarray
    dims: np.ndarray
    mu: np.ndarray
    tensile: np.ndarray
    cohesion: np.ndarray
    compressive: float
    kn: float
    kt: float
    kr: float
    extent: float

    @property
    def n(self) -> int:
        return len(self.area)


@dataclass(eq=False)
class LawResponse:
    """Actions of a trial motion.

    Attributes
    ----------
    f : (m, 6) float
        ``(N, V1, V2, M1, M2, M3)`` [N, N m].
    D : (m, 6, 6) float
        Tangent ``df/dq`` with the law's floor on yielded components.
    state : (m,) int64
        Bits ``STATE_*`` of :mod:`dem.kernels.interface_law`.
    plastic : tuple of arrays
        The law's plastic state at this trial (what :meth:`InterfaceLaw.commit` keeps).
    """

    f: np.ndarray
    D: np.ndarray
    state: np.ndarray
    plastic: tuple


class InterfaceLaw(Protocol):
    """What the model needs of an interface law."""

    settings: ResultantLawSettings | FibreLawSettings
    state: np.ndarray  # (m,) int64, at the last equilibrium
    plastic: tuple  # the plastic state evaluate starts from (arrays replaced, never mutated)

    def evaluate(self, q: np.ndarray, floor: float) -> LawResponse:
        """Actions and tangents for the relative motions ``q`` (m, 6) [m, rad]."""

    def commit(self, response: LawResponse) -> None:
        """Keep the plastic state of an equilibrium."""

    def keep_breaks(self, response: LawResponse) -> bool:
        """Keep only the tensile failures of a failed trial; True if there are new ones."""


def interface_alpha(l1: np.ndarray, l2: np.ndarray, alpha: float | None = None) -> np.ndarray:
    """Exponent of seed 001 Eq. (A5) per interface.

    ``alpha`` if given, else seed Table A1, column ``f1 = f2`` (between the two single-shear
    columns; 1.43 for square interfaces), interpolated in ``log(l1 / l2)``.
    """
    if alpha is not None:
        return np.full(len(l1), float(alpha))
    ratio = np.clip(l1 / l2, ALPHA_TABLE_A1[0, 0], ALPHA_TABLE_A1[-1, 0])
    return np.interp(np.log(ratio), np.log(ALPHA_TABLE_A1[:, 0]), ALPHA_TABLE_A1[:, 2])


class _Committed:
    """The committed part of a law: ``plastic`` (its arrays, the tensile-failure flags last)
    and ``state`` (m,)."""

    plastic: tuple
    state: np.ndarray

    def commit(self, response: LawResponse) -> None:
        self.plastic = tuple(a.copy() for a in response.plastic)
        self.state = response.state.copy()

    def keep_breaks(self, response: LawResponse) -> bool:
        broken = response.plastic[-1]
        new = broken & ~self.plastic[-1]
        self.plastic = (*self.plastic[:-1], self.plastic[-1] | broken)
        return bool(new.any())


SHEAR_TORSION_CODES = {"eq_a5": rk.DOMAIN_EQ_A5, "exact": rk.DOMAIN_EXACT}
"""The kernel's code of each shear-torsion domain of :class:`ResultantLawSettings`."""


class ResultantLaw(_Committed):
    """Seed 001's resultant law (:mod:`dem.kernels.interface_law`) on every joint; the
    parameter rows hold each joint's polygon (at most ``MAX_VERTICES`` corners)."""

    def __init__(self, joints: JointArrays, interfaces: Interfaces, settings: ResultantLawSettings):
        self.settings = settings
        m = joints.n
        j11, j22 = joints.second_moments[:, 0], joints.second_moments[:, 1]
        params = np.zeros((m, rk.N_PARAMS))
        params[:, rk.P_K : rk.P_K + 6] = np.column_stack(
            [
                joints.kn * joints.area,
                joints.kt * joints.area,
                joints.kt * joints.area,
                joints.kr * j22,
                joints.kr * j11,
                joints.kt * (j11 + j22),
            ]
        )
        params[:, rk.P_FT] = joints.tensile * joints.area
        params[:, rk.P_COHESION] = joints.cohesion * joints.area
        params[:, rk.P_MU] = joints.mu
        params[:, rk.P_DIMS : rk.P_DIMS + 2] = joints.dims
        params[:, rk.P_ALPHA] = interface_alpha(
            joints.dims[:, 0], joints.dims[:, 1], settings.alpha
        )
        params[:, rk.P_FC] = joints.compressive
        params[:, rk.P_AREA] = joints.area
        params[:, rk.P_STIFF : rk.P_STIFF + 2] = joints.kn, joints.kr
        params[:, rk.P_TOUCH] = rk.TOUCH * joints.extent
        params[:, rk.P_DOMAIN] = SHEAR_TORSION_CODES[settings.shear_torsion]
        for k in range(m):
            params[k, rk.P_N_CORNERS :] = _corner_row(interfaces.local_polygon(k), k)
        self.params = np.ascontiguousarray(params)
        # plastic motions q_p (m, 6), broken flags (m,)
        self.plastic = (np.zeros((m, 6)), np.zeros(m, dtype=np.bool_))
        self.state = np.zeros(m, dtype=np.int64)

    def evaluate(self, q: np.ndarray, floor: float) -> LawResponse:
        m = len(q)
        f, qp, D = np.empty((m, 6)), np.empty((m, 6)), np.empty((m, 6, 6))
        broken, state = np.empty(m, dtype=np.bool_), np.empty(m, dtype=np.int64)
        rk.resultant_law(q, self.plastic, self.params, floor, (qp, broken), state, f, D)
        return LawResponse(f, D, state, (qp, broken))


def _corner_row(poly: np.ndarray, k: int) -> np.ndarray:
    """``(n, y1, y2, ...)`` of interface ``k``'s polygon, CCW, padded to ``MAX_VERTICES``."""
    n = len(poly)
    if n > MAX_VERTICES:
        raise ValueError(
            f"interface {k} has {n} corners; the resultant law holds at most {MAX_VERTICES} "
            "(use the fibre law, or raise dem.kernels.contact_stress.MAX_VERTICES)"
        )
    poly = counter_clockwise(poly)
    row = np.zeros(1 + 2 * MAX_VERTICES)
    row[0] = n
    row[1 : 1 + 2 * n] = poly.ravel()
    return row


def lobatto(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Lobatto points and weights on [-1, 1] (``n >= 2``)."""
    if n == 2:
        return np.array([-1.0, 1.0]), np.array([1.0, 1.0])
    inner = np.polynomial.legendre.Legendre.basis(n - 1).deriv().roots()
    x = np.concatenate([[-1.0], np.sort(inner.real), [1.0]])
    p = np.polynomial.legendre.Legendre.basis(n - 1)(x)
    w = 2.0 / (n * (n - 1) * p**2)
    return x, w


def _polygon_springs(poly: np.ndarray, area: float, n_pts: int) -> np.ndarray:
    """(n, 3) spring positions and areas on one interface polygon (about its centroid)."""
    lo, hi = poly.min(0), poly.max(0)
    size = hi - lo
    if abs(size[0] * size[1] - area) <= 1e-6 * area:
        # a rectangle: Lobatto grid, outer springs on the edges
        x, w = lobatto(n_pts)
        c = 0.5 * (lo + hi)
        g1, g2 = np.meshgrid(c[0] + 0.5 * size[0] * x, c[1] + 0.5 * size[1] * x, indexing="ij")
        wa = np.outer(w, w).ravel() * 0.25 * size[0] * size[1]
        return np.column_stack([g1.ravel(), g2.ravel(), wa])
    # general convex polygon: midpoint cells of the bounding box inside the polygon
    n_cells = 4 * n_pts
    t = (np.arange(n_cells) + 0.5) / n_cells
    g1, g2 = np.meshgrid(lo[0] + size[0] * t, lo[1] + size[1] * t, indexing="ij")
    pts = np.column_stack([g1.ravel(), g2.ravel()])
    inside = np.ones(len(pts), dtype=bool)
    for i in range(len(poly)):
        e = poly[(i + 1) % len(poly)] - poly[i]
        r = pts - poly[i]
        inside &= e[0] * r[:, 1] - e[1] * r[:, 0] >= -1e-12 * size.max() ** 2
    pos = pts[inside]
    return np.column_stack([pos, np.full(len(pos), area / max(len(pos), 1))])


def fibre_grid(interfaces: Interfaces, n_pts: int) -> tuple[np.ndarray, np.ndarray]:
    """Springs of every interface: ``(spring_ptr (m + 1,), springs (n_springs, 3))`` with
    rows ``(y1, y2, area)`` [m, m^2] (Lobatto grid on rectangles)."""
    grids = [
        _polygon_springs(interfaces.local_polygon(k), interfaces.area[k], n_pts)
        for k in range(interfaces.n_interfaces)
    ]
    ptr = np.concatenate([[0], np.cumsum([len(g) for g in grids])]).astype(np.int64)
    return ptr, np.ascontiguousarray(np.concatenate(grids))


class FibreLaw(_Committed):
    """A grid of Mohr-Coulomb springs per joint (:mod:`dem.kernels.fibre_law`)."""

    def __init__(self, joints: JointArrays, interfaces: Interfaces, settings: FibreLawSettings):
        self.settings = settings
        m = joints.n
        self.spring_ptr, self.springs = fibre_grid(interfaces, settings.points)
        params = np.empty((m, fk.N_FIBRE_PARAMS))
        params[:, fk.F_KN] = joints.kn
        params[:, fk.F_KS] = joints.kt
        params[:, fk.F_MU] = joints.mu
        params[:, fk.F_COHESION] = joints.cohesion
        params[:, fk.F_TENSILE] = joints.tensile
        params[:, fk.F_FC] = joints.compressive
        params[:, fk.F_TOUCH] = rk.TOUCH * joints.extent
        self.params = np.ascontiguousarray(params)
        n_springs = len(self.springs)
        # slips and crushing closures (n_springs, 3), broken flags (n_springs,)
        self.plastic = (np.zeros((n_springs, 3)), np.zeros(n_springs, dtype=np.bool_))
        self.state = np.zeros(m, dtype=np.int64)

    def evaluate(self, q: np.ndarray, floor: float) -> LawResponse:
        m = len(q)
        f, D = np.empty((m, 6)), np.empty((m, 6, 6))
        slip, broken = np.empty_like(self.plastic[0]), np.empty_like(self.plastic[1])
        state = fk.fibre_law(
            q, self.spring_ptr, self.springs, self.params, self.plastic, floor, (slip, broken), f, D
        )
        return LawResponse(f, D, state, (slip, broken))


def build_law(
    settings: ResultantLawSettings | FibreLawSettings, joints: JointArrays, interfaces: Interfaces
) -> InterfaceLaw:
    """The law object that ``settings`` configure, on the joints of one scene."""
    law = LAW_OF_SETTINGS.get(type(settings))
    if law is None:
        raise ValueError(f"no interface law is configured by {type(settings).__name__}")
    return law(joints, interfaces, settings)


LAW_OF_SETTINGS = {ResultantLawSettings: ResultantLaw, FibreLawSettings: FibreLaw}
"""The law class that each settings class configures."""
