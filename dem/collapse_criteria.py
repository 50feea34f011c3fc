"""When a path-following collapse analysis is over: plateau, softening or snap-back.

The path is the sequence of converged points ``(c, lambda)``: ``c = w . u`` the load-weighted
control displacement [m], ``lambda`` the live-load multiplier. Each point's lambda carries an
error of order the residual tolerance its step met (``lam_noise``), so slopes are taken over
stretches of path long enough to resolve that error, not over single short steps.

A slope small against the stiff elastic start is not yet a plateau: slow frictional hardening
(joints that slide one spring after another, or whose compression grows as they slide) rises
at a small fraction of the initial slope for a long way (issue 11: a fibre-law path stopped 8 %
below its limit). The plateau is therefore also judged against the recent path: while every
step of the plateau stretch still raises lambda (beyond its noise), the peak of lambda must
also have risen by less than ``plateau_rise`` of itself over the last ``plateau_window`` of the
control displacement. For an approach ``lambda_inf - A e^{-c/tau}`` this stops once
``e^{-c/tau} (e^{w c/tau} - 1) A <= plateau_rise lambda``: with the defaults (0.5, 1e-3) about
as much is left to rise as the criterion allows. A path that meanders up and down at a
constant lambda in short steps is not hardening and ends on the slope test alone (seed 001 S13
with a fixed column, resultant law: 300 more steps otherwise).
"""

from __future__ import annotations

import math


class CollapseCriteria:
    """Ends a collapse analysis from its path (see :func:`dem.static.solve_collapse`).

    Parameters
    ----------
    c0 : float
        Control displacement at the start of the live load [m].
    dc0 : float
        First control increment [m]: the length unit of a plateau.
    plateau_slope : float
        A stretch is on the plateau when its secant ``d lambda / d c`` is below this fraction
        of the initial secant slope (that of the first step).
    plateau_steps : int
        Consecutive plateau steps that end the analysis, if they also span this many ``dc0``.
    softening_drop : float
        End when lambda falls below ``(1 - softening_drop)`` times its peak.
    plateau_rise : float
        While lambda still rises at every step, a plateau also needs its peak to have risen
        by less than this fraction of itself over the last ``plateau_window`` of the control
        displacement (module notes).
    plateau_window : float
        That stretch, as a fraction of the control displacement since ``c0``.

    Attributes
    ----------
    lams, ctrl : list of float
        The path so far, from ``(c0, 0)``.
    peak : float
        Largest lambda so far.
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
    ):
        if not (math.isfinite(dc0) and dc0 > 0):
            raise ValueError(f"dc0 must be a finite positive length [m], got {dc0!r}")
        if not (0 <= plateau_slope < 1 and 0 <= softening_drop < 1):
            raise ValueError(
                "plateau_slope and softening_drop must lie in [0, 1), got "
                f"{plateau_slope!r} and {softening_drop!r}"
            )
        for name, v in (("plateau_rise", plateau_rise), ("plateau_window", plateau_window)):
            if not (math.isfinite(v) and 0 <= v < 1):
                raise ValueError(f"{name} must lie in [0, 1), got {v!r}")
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
        self.peak = 0.0
        self.slope0 = None
        self.n_plateau = 0
        self.c_plateau = 0.0
        self.n_back = 0

    @property
    def near_plateau(self) -> bool:
        """At least half the plateau steps counted: a step that then fails is the collapse."""
        return self.n_plateau >= max(1, self.plateau_steps // 2)

    def secant_slope(self, window: float) -> float | None:
        """``d lambda / d c`` from the last point back to the latest one at least ``window``
        [m] of control behind it; None if the path is shorter."""
        c_end = self.ctrl[-1]
        for j in range(len(self.ctrl) - 2, -1, -1):
            if c_end - self.ctrl[j] >= window:
                return (self.lams[-1] - self.lams[j]) / (c_end - self.ctrl[j])
        return None

    def recent_rise(self) -> float:
        """Rise of the peak of lambda over the last ``plateau_window`` of the control
        displacement (from the start of the live load)."""
        c_end = self.ctrl[-1]
        start = c_end - self.plateau_window * (c_end - self.ctrl[0])
        before = [lam for lam, c in zip(self.lams, self.ctrl, strict=True) if c <= start]
        return self.peak - max(before) if before else self.peak - self.lams[0]

    def hardening(self, lam_noise: float) -> bool:
        """Whether lambda rose (by more than ten times its noise) at every one of the last
        ``plateau_steps`` steps: a trend, not a meander."""
        if len(self.lams) <= self.plateau_steps:
            return True
        recent = self.lams[-self.plateau_steps - 1 :]
        return all(b - a > 10.0 * lam_noise for a, b in zip(recent[:-1], recent[1:], strict=True))

    def add(self, lam: float, c: float, lam_noise: float, loose: bool = False) -> str | None:
        """Record a converged point; return ``"plateau"``, ``"softening"``, ``"snap_back"``
        or None (go on).

        ``lam_noise`` is the error of lambda at this point (tolerance times the load norms);
        a ``loose`` point (converged to a looser tolerance) neither counts towards a plateau
        nor resets it.
        """
        dlam = lam - self.lams[-1]
        self.lams.append(float(lam))
        self.ctrl.append(float(c))
        self.peak = max(self.peak, lam)
        if self.slope0 is None:
            if lam <= 10.0 * lam_noise:
                # no resistance (yet): the initial slope would be noise. A path that stays
                # there for plateau_steps steps and dc0s is a mechanism at lambda = 0 (a block
                # on a frictionless floor; the fibre law ran to max_steps on it)
                far = c - self.ctrl[0] >= (1.0 - 1e-9) * self.plateau_steps * self.dc0
                return "plateau" if far and len(self.lams) > self.plateau_steps else None
            self.slope0 = max(lam / (c - self.ctrl[0]), 1e-300)
        limit = self.plateau_slope * self.slope0
        # the stretch over which the noise in lambda is a tenth of the rise a plateau allows
        # (plateau_slope = 0: no rise is allowed, the step itself is the stretch)
        slope = self.secant_slope(10.0 * lam_noise / limit if limit > 0 else 0.0)
        if loose or slope is None:
            pass
        elif slope < limit:
            self.n_plateau += 1
            self.c_plateau += self.ctrl[-1] - self.ctrl[-2]
        else:
            self.n_plateau = 0
            self.c_plateau = 0.0
        long = self.c_plateau >= (1.0 - 1e-9) * self.plateau_steps * self.dc0
        flat = (
            not self.hardening(lam_noise)
            or self.recent_rise() <= self.plateau_rise * abs(lam) + 10.0 * lam_noise
        )
        if self.n_plateau >= self.plateau_steps and long and flat and self.peak > 0:
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
        drop = max(10.0 * lam_noise, limit * self.plateau_steps * self.dc0)
        if self.n_back >= self.plateau_steps and self.peak - lam > drop:
            return "snap_back"
        return None
