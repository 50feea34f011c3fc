r"""Path following of the live load to collapse: step control, cascades, control switch, end.

Each live step prescribes the increment of a control ``w . u`` and solves for ``(u, lambda)``
(:mod:`dem.static.newton`), which stays regular at limit points:

- **control**: first ``w = F_L / |F_L|_1``, so ``c = w . u`` is the live-load-weighted mean
  displacement [m]. After ``switch_after`` consecutive failed steps (near some peaks the
  path turns in ``c``, or a local mechanism forms that ``c`` hardly measures), ``w`` becomes
  the unit direction of the previous increment (the updated normal plane of Riks' method),
  the first step as long as that increment and the step unit the length of the first
  increment; this follows the path through limit points and snap-backs, where halving the
  fixed control's step would leave the path creeping at a constant lambda;
- **step size**: the increment adapts to the Newton iteration count (``target_iterations``),
  halves on a failed step, and stays within ``max_step_factor`` first increments unless the
  path is flat (:meth:`dem.collapse_criteria.CollapseCriteria.flat`): then it may keep
  doubling, so that the path samples its approach in a geometric progression and reaches a
  slow limit (``s^{-1/2}``) in a few dozen steps, and a creep (at 1e-5 of the initial slope,
  say) travels to its end, where a limit point certifies it, instead of ending uncertified
  at ``max_steps``;
- **cracking cascade**: when no step converges and the failed trial broke mortar joints, the
  cracks are kept and the path restarts from the last equilibrium (brittle snap-back);
- **end**: the collapse criteria of :mod:`dem.collapse_criteria`: a flat path whose
  extrapolated rise is below the stated ``plateau_rise`` ends only with a certificate from
  the mechanics (a limit point of the tangent, :mod:`dem.static.certificate`, or an upper
  bound that the peak meets, :mod:`dem.static.upper_bound`); softening,
  snap-back. Otherwise ``max_steps`` (no collapse: lambda still rising, or flat without a
  certificate, with the extrapolated rise as an estimate) or ``stalled`` (no step converges
  even at ``min_step_ratio``: no collapse either, wherever the path was).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from dem.collapse_criteria import CollapseCriteria
from dem.static.certificate import FirstOf, LimitPointCertifier
from dem.static.model import Model
from dem.static.newton import Constraint, Corrector, Iterate, Outcome, factor
from dem.static.result import StaticSolverError
from dem.static.settings import StaticSettings
from dem.static.upper_bound import UpperBoundCertifier

logger = logging.getLogger(__name__)

ROUND_OFF = 1e-12
"""Relative round-off of a residual: below it, a residual bounds lambda no better."""


@dataclass(eq=False)
class Peak:
    """The equilibrium of the largest lambda so far."""

    lam: float
    u: np.ndarray
    f: np.ndarray
    state: np.ndarray


def first_increment(model: Model, corrector: Corrector, u: np.ndarray) -> float:
    """Control increment [m] of the elastic response to ``load_step * lambda_scale``."""
    ev = model.evaluate(u, 1.0)  # floor 1: the elastic stiffness
    lu = factor(model.stiffness(ev.law.D))
    if isinstance(lu, Exception):
        corrector.check_tangent(Iterate(u, 0.0, ev, None))
        raise StaticSolverError(f"singular stiffness after the dead load: {lu}", lam=0.0)
    dlam0 = corrector.settings.load_step * model.lambda_scale
    dc0 = float(model.w @ lu.solve(model.F_live)) * dlam0
    if not (math.isfinite(dc0) and dc0 > 0):
        raise StaticSolverError(
            "the live load does no work on the elastic response (control increment "
            f"{dc0:.3e} m): the live pattern is carried without displacement",
            lam=0.0,
        )
    return dc0


class PathFollower:
    """Follows the live load from the dead-load equilibrium ``start`` (module notes).

    Attributes
    ----------
    point : Iterate
        The last equilibrium.
    peak : Peak
    criteria : CollapseCriteria
        The path ``(c, lambda)`` so far and its end.
    history : list of (n_free,) arrays
        ``u`` at every equilibrium.
    n_steps, n_iterations, n_loose, n_cascades, n_arc, n_failed_iterations : int
    """

    def __init__(self, model: Model, corrector: Corrector, start: Iterate, n_iter: int = 0):
        self.model, self.corrector = model, corrector
        settings: StaticSettings = corrector.settings
        self.settings = settings
        self.point = start
        self.peak = Peak(0.0, start.u.copy(), start.ev.law.f.copy(), model.law.state.copy())
        self.history = [start.u.copy()]
        self.dc0 = first_increment(model, corrector, start.u)
        self.upper_bound = UpperBoundCertifier(model.scene, settings, settings.plateau_rise)
        self.criteria = CollapseCriteria(
            float(model.w @ start.u),
            self.dc0,
            settings.plateau_slope,
            settings.plateau_steps,
            settings.softening_drop,
            settings.plateau_rise,
            settings.plateau_window,
            certifier=FirstOf(
                LimitPointCertifier(model, lambda: (self.point.u, self.step_plastic)),
                self.upper_bound,
            ),
        )
        # step control: the increment, its bounds, the last accepted increment
        self.dc = self.dc_ref = self.dc_cascade = self.dc0
        self.dc_max = settings.max_step_factor * self.dc0
        self.w = model.w  # constraint: the fixed control until switched to the path direction
        self.du_first = 0.0  # length of the first increment: the step unit along the path
        self.last_du = np.zeros_like(start.u)
        self.last_dlam = self.last_dc = 0.0
        self.floor = None
        self.step_plastic = model.law.plastic  # the law's plastic state at the last step's start
        self.n_steps, self.n_iterations = 0, n_iter
        self.n_loose = self.n_cascades = self.n_arc = self.n_failed_iterations = 0
        self.n_failed = 0  # consecutive failed steps

    @property
    def switched(self) -> bool:
        """Whether the constraint follows the path direction."""
        return self.w is not self.model.w

    def run(self) -> tuple[str, str]:
        """Steps until the path ends: ``(termination, reason it is no collapse or "")``."""
        while self.n_steps < self.settings.max_steps:
            out = self._step()
            end = self._accept(out) if out.converged else self._failed(out)
            if end is not None:
                return end
        return "max_steps", self._still_rising()

    @property
    def certificate(self) -> str:
        """The kind of the certificate of a ``"plateau"`` end, else ""."""
        cert = self.criteria.certificate
        return "" if cert is None else cert.kind

    def pushover(self) -> tuple[np.ndarray, np.ndarray]:
        """``(lambda, c)`` along the path so far."""
        return np.array(self.criteria.lams), np.array(self.criteria.ctrl)

    def error_sources(self, termination: str) -> dict[str, float]:
        """Half-widths of the peak of lambda [same unit] that this path gives for free.

        ``"end of path"``: how much lambda may still rise, as the end's certificate states it
        (:class:`dem.collapse_criteria.Certificate`; 0 past a peak, after softening or a
        snap-back); on a path without a certificate ``"end of path (extrapolated)"``, the
        rise extrapolated from the path's shape
        (:meth:`dem.collapse_criteria.CollapseCriteria.remaining_rise`), an estimate that
        a creep can exceed; ``"load step"``: the change of lambda over the steps next
        to the peak (the path's peak lies between its neighbours' samples; the path
        dependence of friction is measured only by a second run:
        :func:`dem.static.solve_collapse` makes it with ``error="full"``, and past a peak
        with ``"cheap"`` too);
        ``"residual"``: the error of lambda that the residual tolerance allows at the peak.
        """
        criteria = self.criteria
        lams = np.asarray(criteria.lams)
        k = int(np.argmax(lams))
        step = float(np.max(np.abs(lams[max(k - 1, 0) : k + 2] - lams[k])))
        sources = {"load step": step, "residual": criteria.error[k]}
        if termination in ("softening", "snap_back"):
            sources["end of path"] = 0.0
        elif termination == "plateau":
            sources["end of path"] = criteria.certificate.end_error
        else:
            sources["end of path (extrapolated)"] = criteria.remaining_rise()
        return sources

    def _constraint(self, dc: float) -> Constraint:
        return Constraint(w=self.w, c=float(self.w @ self.point.u) + dc, dc=dc)

    def _step(self) -> Outcome:
        """One step of the present size, from the predictor if the law uses one."""
        con = self._constraint(self.dc)
        corrector, point = self.corrector, self.point
        if self.model.law.settings.predictor and self.last_dc > 0:
            # the last increment scaled to this one; the constraint still counts from point
            scale = self.dc / self.last_dc
            guess = Iterate(
                point.u + scale * self.last_du, point.lam + scale * self.last_dlam, None, None
            )
            out = corrector.solve(
                guess, con, self.floor, max_iterations=self.settings.target_iterations
            )
            if out.converged:
                return out
            self.n_iterations += out.iterations
            self.n_failed_iterations += out.iterations
        return corrector.solve(point, con, self.floor)

    def _failed(self, out: Outcome) -> tuple[str, str] | None:
        """A step without equilibrium: shorter step, control switch, cascade, or the end."""
        self.n_iterations += out.iterations
        self.n_failed_iterations += out.iterations
        self.last_dc = 0.0
        if self.dc >= 0.5 * self.dc_cascade * (1 + 1e-12):
            self.dc_cascade = self.dc
        self.dc *= 0.5
        self.n_failed += 1
        can_switch = not self.switched and self.du_first > 0 and np.any(self.last_du)
        if can_switch and self.n_failed >= self.settings.switch_after:
            return self._switch()
        if self.dc >= self.settings.min_step_ratio * self.dc_ref:
            return None
        lam = self.point.lam
        if self.model.law.keep_breaks(out.point.ev.law):
            # brittle cascade (mortar cracking that snaps back): keep the cracks of the failed
            # trial, re-start from the last equilibrium; lambda drops
            self.n_cascades += 1
            logger.info("cracking cascade at lambda = %.6g: cracks kept", lam)
            self.dc = self.dc_cascade
            return None
        if can_switch:
            return self._switch()
        return "stalled", "stalled: " + self._stall_message(out)

    def _switch(self) -> None:
        """Follow the path along the normal plane of its last increment instead of the fixed
        control, starting with a step as long as that increment (which converged)."""
        logger.info("control switched to the path direction at lambda = %.6g", self.point.lam)
        du_norm = float(np.linalg.norm(self.last_du))
        self.w = self.last_du / du_norm
        self.dc = self.dc_cascade = du_norm
        self.dc_ref = self.du_first
        self.dc_max = self.settings.max_step_factor * self.dc_ref
        self.n_failed = 0
        return None

    def _stall_message(self, out: Outcome) -> str:
        model = self.model
        blk, dof = model.block_of_dof(int(np.argmax(np.abs(out.point.residual))))
        changing = np.flatnonzero(out.point.ev.law.state != model.law.state)
        return (
            f"no convergence at lambda = {self.point.lam:.6g} after cutting the step to "
            f"{self.dc:.3e} m (largest residual at block {blk} {dof}; {len(changing)} "
            f"interfaces changing state, e.g. {changing[:5].tolist()})"
        )

    def _accept(self, out: Outcome) -> tuple[str, str] | None:
        """Commit a converged step, record it, and size the next one."""
        new, old = out.point, self.point
        self.floor = out.floor
        self.n_loose += int(out.loose)
        self.step_plastic = self.model.law.plastic  # commit replaces it by new arrays
        self.model.law.commit(new.ev.law)
        self.n_failed = 0
        self.n_iterations += out.iterations
        self.n_steps += 1
        self.last_du = new.u - old.u
        self.last_dlam, self.last_dc = new.lam - old.lam, self.dc
        if self.n_steps == 1:
            self.du_first = float(np.linalg.norm(self.last_du))
        if self.switched:
            self.n_arc += 1
            self.w = self.last_du / np.linalg.norm(self.last_du)
        self.point = new
        self.history.append(new.u.copy())
        if new.lam > self.peak.lam:
            law = new.ev.law
            self.peak = Peak(new.lam, new.u.copy(), law.f.copy(), law.state.copy())
        # lambda is known to the residual tolerance the step met (relative to the loads), and
        # more closely to the residual it reached (down to the round-off of the loads)
        corrector, live = self.corrector, self.model.live_norm
        lam_noise = corrector.tolerance(new.lam, out.loose) / live
        loads = corrector.tolerance(new.lam) / self.settings.tolerance
        lam_error = max(new.norm, ROUND_OFF * loads) / live
        c = float(self.model.w @ new.u)
        end = self.criteria.add(new.lam, c, lam_noise, out.loose, lam_error)
        if end is not None:
            return end, ""
        # a loose step stalled at a kink of the law, which a shorter step does not remove
        target = self.settings.target_iterations
        growth = 1.0 if out.loose else math.sqrt(target / max(out.iterations, 1))
        self.dc *= min(max(growth, 0.5), 2.0)
        if not self.criteria.flat():
            self.dc = min(self.dc, self.dc_max)
        return None

    def _still_rising(self) -> str:
        """Why a path that reached ``max_steps`` is no collapse: how much lambda may still
        rise."""
        criteria = self.criteria
        slope = criteria.secant_slope(self.settings.plateau_steps * criteria.dc0)
        if slope is None:
            slope = criteria.secant_slope(0.0)
        ratio = 0.0 if slope is None or not criteria.slope0 else slope / criteria.slope0
        rise = criteria.remaining_rise()
        more = (
            "an unknown amount (it does not approach a limit yet)"
            if math.isinf(rise)
            else f"about {rise:.3g} ({100 * rise / max(criteria.peak, 1e-300):.2g} %, "
            "extrapolated from the path's shape: an estimate, not a bound)"
        )
        checks = criteria.certifier.n_checks
        bound = self.upper_bound.bound
        known = "" if bound is None else f" nor meet the upper bound {bound.format()}"
        uncertified = (
            f"; flat, but {checks} checks found no limit point of the tangent{known}"
            if checks
            else ""
        )
        reason = (
            f"still rising at {100 * ratio:.2g} % of the initial slope after max_steps = "
            f"{self.settings.max_steps}{uncertified}; lambda may still rise by {more}"
        )
        logger.warning(reason)
        return reason
