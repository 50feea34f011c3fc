"""The time step against the contacts present at each neighbour-list rebuild.

The time step is chosen once, from the entries at the start; contacts that appear later (a
block landing on another, faces meeting after large motions) can raise the highest frequency
above the scheme's stable limit, where the run would gain energy or blow up. At each rebuild
a per-block bound (:func:`dem.explicit.timestep.frequency_bound`, O(entries)) is compared with
the stable frequency of the run's ``dt``; only where it is above, the exact highest frequency
of the present entries decides.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from dem.explicit.settings import SimulationError
from dem.explicit.timestep import (
    ContactStiffness,
    frequency_bound,
    highest_frequency,
    stable_frequency,
    stable_time_step,
)

logger = logging.getLogger(__name__)


@dataclass
class StepCheck:
    """Record of the checks of one run.

    Attributes
    ----------
    omega_start : float
        Highest frequency of the entries at the start [rad/s] (0: none).
    omega_upper : float
        Largest upper bound on the present entries' highest frequency over the checks [rad/s]
        (the exact value where it was computed, else the per-block bound).
    omega_exact : float
        Largest exact highest frequency computed at a check [rad/s] (0: none computed).
    n_checks, n_exact : int
        Checks made, and those that needed the exact eigenvalue.
    """

    omega_start: float
    omega_upper: float = 0.0
    omega_exact: float = 0.0
    n_checks: int = 0
    n_exact: int = 0

    def check(
        self, system: ContactStiffness, dt: float, alpha: float, beta: float, t: float
    ) -> None:
        """Check the present entries ``system`` against ``dt`` [s] with damping ``alpha``
        [1/s] and ``beta`` [s] at the time ``t`` [s].

        Raises
        ------
        SimulationError
            The present entries' highest frequency is above the stable one of ``dt``.
        """
        self.n_checks += 1
        limit = stable_frequency(dt, alpha, beta)
        bound = frequency_bound(system)
        top = float(bound.max(initial=0.0))
        if top > limit:
            top = highest_frequency(system)
            self.n_exact += 1
            self.omega_exact = max(self.omega_exact, top)
        self.omega_upper = max(self.omega_upper, top)
        if top > limit:
            raise SimulationError(self._message(system, bound, top, limit, dt, alpha, beta, t))

    def _message(self, system, bound, omega, limit, dt, alpha, beta, t) -> str:
        nodes, contacts = system.nodes, system.contacts
        block = int(np.argmax(bound))
        owners = nodes.block[contacts.node]
        partners = np.unique(np.concatenate([contacts.block[owners == block],
                                             owners[contacts.block == block]]))  # fmt: skip
        dt_stable = stable_time_step(omega, alpha, beta)
        start = (f"{omega / self.omega_start:.3g} times the {self.omega_start:.3e} rad/s of the "
                 "contacts at the start" if self.omega_start > 0
                 else "no contact set the time step at the start")  # fmt: skip
        return (
            f"at t = {t:.6e} s the contacts present have the highest frequency omega_max = "
            f"{omega:.3e} rad/s ({start}; stiffest: block {block} against blocks "
            f"{partners.tolist()}): the time step dt = {dt:.3e} s is stable only up to "
            f"{limit:.3e} rad/s, and this omega needs dt <= {dt_stable:.3e} s. The run stops "
            "here: from this point it would gain energy or blow up. Give a smaller "
            "ExplicitSettings.dt_safety (the time step is chosen from the contacts at the "
            "start) or a smaller ExplicitSettings.dt"
        )

    def as_dict(self) -> dict:
        """The record for a run's info; ratios to ``omega_start`` (None without it)."""
        ratio = (lambda w: w / self.omega_start) if self.omega_start > 0 else (lambda w: None)
        return {
            "omega_start": self.omega_start,
            "omega_upper": self.omega_upper,
            "omega_exact": self.omega_exact,
            "omega_upper_ratio": ratio(self.omega_upper),
            "omega_exact_ratio": ratio(self.omega_exact) if self.n_exact else None,
            "n_checks": self.n_checks,
            "n_exact": self.n_exact,
        }
