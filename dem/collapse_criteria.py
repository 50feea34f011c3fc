r"""When a path-following collapse analysis is over, and how much lambda can still rise.

The path is the sequence of converged points ``(c, lambda)``: ``c = w . u`` the load-weighted
control displacement [m] (the work of the live load per unit multiplier, over ``|F_L|_1``),
``lambda`` the live-load multiplier. Each point's lambda carries an error of order the
residual tolerance its step met (``lam_noise``).

**End of the path.** The envelope ``lambda*(s) = max lambda`` up to the travelled control
``s = max (c - c0)`` rises monotonically. A limit is approached as
``lambda* = lambda_inf - A s^{-p}`` (a joint rocking on a compressed strip that narrows as
``s^{-1/2}``, the resultant law) or ``lambda_inf - A e^{-s / tau}`` (frictional hardening),
or reached at a finite ``s`` (a limit point of the tangent: the fibre law's edge springs).
Over three points in geometric progression, ``s (1 - w)^2``, ``s (1 - w)``, ``s`` with
``w = plateau_window``, the two rises ``d1, d2`` have the ratio ``q = d2 / d1``; for either
approach ``q`` does not grow along the path, so the rise still to come is at most
``d2 q / (1 - q)`` (exact for the power law, an upper bound for the exponential one). That
is the end-of-path error :meth:`CollapseCriteria.remaining_rise`; ``q > Q_CONVERGING``
(a path rising as fast as before, or faster: hardening, the elastic start) gives ``inf``.
A rise below the error of two points (from the residuals they reached) counts as that much,
and a path flat within it over both stretches as approaching at the slowest ratio allowed:
the bar of a limit point is then 18 times that error.

**A certificate.** The shape of the path says when it is flat, never that it will stay so:
a creep at 1e-5 of the initial slope after a knee (a corner tipping on the fibre law's
smallest springs) makes the ratio of rises fall, then grow again, and an extrapolation from
before the creep excludes the limit. So the shape is only the trigger: once, on
``plateau_steps`` consecutive steps spanning ``plateau_steps`` first increments and the
whole of ``[s (1 - w)^2, s]``, the secant slope is below ``plateau_slope`` of the initial
one and the extrapolated rise is at most ``plateau_rise`` of the peak (without the span, the
knee of the elastic start in the first stretch made any slow rise after it look like an
approach), the ``certifier`` is asked for a :class:`Certificate` from the mechanics (a limit
point of the tangent, :mod:`dem.static.certificate`). With one the path is a collapse
(``"plateau"``); without, it goes on (and is asked again at the next such step). A path
that reaches its last step flat but uncertified is no collapse: its remaining rise is then
an extrapolation, not a bound. A path still rising is never a collapse. Lambda falling
by ``softening_drop`` of its peak (softening) or going back in ``c`` while falling (a
snap-back) also ends it, at a peak already passed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

Q_CONVERGING = 0.9
"""Largest ratio of successive rises (over geometrically growing stretches) taken as an
approach to a limit; a ratio of 0.9 leaves 9 times the last rise to come."""

NOISE_FACTOR = 10.0
"""A rise below this many times lambda's noise is no rise."""


@dataclass(frozen=True)
class Certificate:
    """Why a flat path is a collapse.

    Attributes
    ----------
    kind : str
        ``"limit point"``: the tangent is singular in a direction the live load works on;
        ``"upper bound"``: the peak meets an upper bound of the collapse multiplier
        (:mod:`dem.static.certificate`).
    end_error : float
        Half-width of the end-of-path error of lambda that it leaves [unit of lambda].
    note : str
        What was measured.
    """

    kind: str
    end_error: float
    note: str = ""


class Certifier(Protocol):
    """What certifies the end of a flat path from the mechanics."""

    def certify(self, peak: float, remaining: float) -> Certificate | None:
        """The certificate at the last point (``peak`` the largest lambda so far, the path
        extrapolating ``remaining`` more rise), or None: the path goes on."""


class CollapseCriteria:
    """Ends a collapse analysis from its path (see :func:`dem.static.solve_collapse`).

    Parameters
    ----------
    c0 : float
        Control displacement at the start of the live load [m].
    dc0 : float
        First control increment [m]: the length unit of a plateau.
    plateau_slope : float
        The end is sought only where the secant ``d lambda / d c`` is below this fraction of
        the initial secant slope (that of the first step).
    plateau_steps : int
        Consecutive such steps needed, spanning at least this many ``dc0``.
    softening_drop : float
        End when lambda falls below ``(1 - softening_drop)`` times its peak.
    plateau_rise : float
        Stated tolerance of the end: the rise of lambda still to come, relative to its peak
        (module notes).
    plateau_window : float
        ``w`` of the geometric progression ``s (1 - w)^k`` over which the rises are compared.
    certifier : Certifier
        Asked for a certificate when the path's shape would end it (module notes).

    Attributes
    ----------
    lams, ctrl : list of float
        The path so far, from ``(c0, 0)``.
    error : list of float
        The error of each point's lambda (``lam_error``).
    peak : float
        Largest lambda so far.
    certificate : Certificate or None
        The certificate of a ``"plateau"`` end.
    """

    def __init__(
        self,
        c0: float,
        dc0: float,
        plateau_slope: float,
        plateau_steps: int,
        softening_drop: float,
        plateau_rise: float = 1e-3,
        plateau_window: float = 0.5,
        *,
        certifier: Certifier,
    ):
        if not (math.isfinite(dc0) and dc0 > 0):
            raise ValueError(f"dc0 must be a finite positive length [m], got {dc0!r}")
        if not (0 <= plateau_slope < 1 and 0 <= softening_drop < 1):
            raise ValueError(
                "plateau_slope and softening_drop must lie in [0, 1), got "
                f"{plateau_slope!r} and {softening_drop!r}"
            )
        if not (math.isfinite(plateau_rise) and 0 <= plateau_rise < 1):
            raise ValueError(f"plateau_rise must lie in [0, 1), got {plateau_rise!r}")
        if not (math.isfinite(plateau_window) and 0 < plateau_window < 1):
            raise ValueError(f"plateau_window must lie in (0, 1), got {plateau_window!r}")
        if int(plateau_steps) != plateau_steps or plateau_steps < 1:
            raise ValueError(f"plateau_steps must be an integer >= 1, got {plateau_steps!r}")
        self.dc0 = dc0
        self.plateau_slope = plateau_slope
        self.plateau_steps = plateau_steps
        self.softening_drop = softening_drop
        self.plateau_rise = plateau_rise
        self.plateau_window = plateau_window
        self.lams = [0.0]
        self.ctrl = [float(c0)]
        self.error = [0.0]
        self.peak = 0.0
        self.slope0 = None
        self.n_plateau = 0
        self.c_plateau = 0.0
        self.s_flat = math.inf
        self.n_back = 0
        self.certifier = certifier
        self.certificate: Certificate | None = None

    def secant_slope(self, window: float) -> float | None:
        """``d lambda / d c`` from the last point back to the latest one at least ``window``
        [m] of control behind it; None if the path is shorter."""
        c_end = self.ctrl[-1]
        for j in range(len(self.ctrl) - 2, -1, -1):
            if c_end - self.ctrl[j] >= window:
                return (self.lams[-1] - self.lams[j]) / (c_end - self.ctrl[j])
        return None

    def envelope(self) -> tuple[np.ndarray, np.ndarray]:
        """``(s, lambda*)``: the travelled control ``max (c - c0)`` [m] and the peak of
        lambda up to each point, both non-decreasing."""
        s = np.maximum.accumulate(np.asarray(self.ctrl) - self.ctrl[0])
        return s, np.maximum.accumulate(np.asarray(self.lams))

    def rises(self) -> tuple[float, float] | None:
        """The rises ``(d1, d2)`` of the envelope over ``[s (1-w)^2, s (1-w)]`` and
        ``[s (1-w), s]``; None while the path has no point before ``s (1-w)^2``."""
        s, env = self.envelope()
        keep = 1.0 - self.plateau_window
        marks = s[-1] * np.array([keep * keep, keep, 1.0])
        if s[-1] <= 0 or np.count_nonzero(s < marks[0]) < 2:
            return None
        at = np.interp(marks, s, env)
        return float(at[1] - at[0]), float(at[2] - at[1])

    def remaining_rise(self) -> float:
        """Upper estimate of how much lambda can still rise along the path (module notes);
        ``inf`` while the path does not approach a limit."""
        rises = self.rises()
        if rises is None:
            return math.inf
        d1, d2 = rises
        # a rise below the error of two points counts as that: the ratio stays an upper bound
        floor = 2.0 * max(self.error[-3:])
        d2 = max(d2, floor)
        if d1 <= d2 <= floor:
            q = Q_CONVERGING  # flat within the noise twice: the slowest approach allowed
        else:
            q = d2 / d1 if d1 > 0 else math.inf
        return d2 * q / (1.0 - q) if q <= Q_CONVERGING else math.inf

    def flat(self) -> bool:
        """Whether the last step counted towards a plateau (its secant slope is below
        ``plateau_slope`` of the initial one)."""
        return self.n_plateau > 0

    def approaching(self) -> bool:
        """Whether the path is flat against its start (its last step counted towards a
        plateau) and approaches a limit (its remaining rise is finite)."""
        return self.n_plateau > 0 and math.isfinite(self.remaining_rise())

    def add(
        self,
        lam: float,
        c: float,
        lam_noise: float,
        loose: bool = False,
        lam_error: float | None = None,
    ) -> str | None:
        """Record a converged point; return ``"plateau"``, ``"softening"``, ``"snap_back"``
        or None (go on).

        ``lam_noise`` is the error of lambda that the step's tolerance allows (tolerance
        times the load norms): slopes are taken over stretches that resolve it. A ``loose``
        point (converged to a looser tolerance) neither counts towards a plateau nor resets
        it. ``lam_error`` (default ``lam_noise``) is the error of lambda that the residual
        actually reached bounds, used by :meth:`remaining_rise`.
        """
        dlam = lam - self.lams[-1]
        self.lams.append(float(lam))
        self.ctrl.append(float(c))
        self.error.append(float(lam_noise if lam_error is None else lam_error))
        self.peak = max(self.peak, lam)
        if self.slope0 is None:
            if lam <= NOISE_FACTOR * lam_noise:
                # no resistance (yet): the initial slope would be noise. A path that stays
                # there for plateau_steps steps and dc0s is a mechanism at lambda = 0 (a block
                # on a frictionless floor)
                far = c - self.ctrl[0] >= (1.0 - 1e-9) * self.plateau_steps * self.dc0
                if far and len(self.lams) > self.plateau_steps:
                    return self._certified(lam_noise)
                return None
            self.slope0 = max(lam / (c - self.ctrl[0]), 1e-300)
        self._count_flat(lam_noise, loose)
        long = self.c_plateau >= (1.0 - 1e-9) * self.plateau_steps * self.dc0
        s_end = max(self.ctrl) - self.ctrl[0]
        spans = self.s_flat <= (1.0 + 1e-9) * s_end * (1.0 - self.plateau_window) ** 2
        if self.n_plateau >= self.plateau_steps and long and spans and self.peak > 0:
            rise = self.remaining_rise()
            if rise <= self.plateau_rise * self.peak and self._certified(rise):
                return "plateau"
        if lam < (1.0 - self.softening_drop) * self.peak:
            return "softening"
        # Past a limit point the path may turn back in c with lambda falling (a snap-back:
        # the failing part localises while the rest unloads). Near a kink it also meanders
        # back and forth at a nearly constant lambda (seed 001 S5 with return walls, resultant
        # law: down by 1.2e-5, then up by 8 %), so it has passed the peak only once lambda is
        # lower by more than a plateau may rise.
        backwards = self.ctrl[-1] < self.ctrl[-2] and dlam < 0.0
        self.n_back = self.n_back + 1 if backwards else 0
        limit = self.plateau_slope * self.slope0
        drop = max(NOISE_FACTOR * lam_noise, limit * self.plateau_steps * self.dc0)
        if self.n_back >= self.plateau_steps and self.peak - lam > drop:
            return "snap_back"
        return None

    def _certified(self, remaining: float) -> str | None:
        """``"plateau"`` if the certifier certifies the last point (kept in
        :attr:`certificate`), else None."""
        self.certificate = self.certifier.certify(self.peak, remaining)
        return None if self.certificate is None else "plateau"

    def _count_flat(self, lam_noise: float, loose: bool) -> None:
        """Count the steps whose secant slope is below ``plateau_slope`` of the initial one
        (over the stretch whose noise in lambda is a tenth of the rise that slope allows)."""
        limit = self.plateau_slope * self.slope0
        slope = self.secant_slope(NOISE_FACTOR * lam_noise / limit if limit > 0 else 0.0)
        if loose or slope is None:
            return
        if slope < limit:
            if self.n_plateau == 0:
                self.s_flat = max(self.ctrl[:-1]) - self.ctrl[0]
            self.n_plateau += 1
            self.c_plateau += abs(self.ctrl[-1] - self.ctrl[-2])
        else:
            self.n_plateau = 0
            self.c_plateau = 0.0
            self.s_flat = math.inf
