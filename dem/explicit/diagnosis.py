"""Which contacts carry the load: the block pairs in contact at a state, with their forces.

When the explicit DEM holds a load that a proven upper bound of the rigid-block model says no
structure of those blocks can carry, some contact resisted that the rigid-block model does not
have (two blocks that touch along an edge or at a corner only, or stand a gap apart, have no
face interface there) or carried more than its share. :func:`pair_forces` lists the pairs
with their resultant force, their gap in the reference configuration and whether they share
a face interface there, so that a report can name them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dem.explicit.model import ExplicitModel
from dem.explicit.results import interface_resultants
from dem.geometry.polyhedron import penetration_depth


@dataclass(frozen=True)
class PairForces:
    """Resultant contact force of each pair of blocks in contact at one state.

    Attributes
    ----------
    pairs : (p, 2) int64
        ``(i, j)`` with ``i < j``.
    force : (p, 3) float
        Resultant force on block ``i`` from block ``j`` [N].
    point : (p, 3) float
        Force-weighted mean of the nodal points [m].
    gap : (p,) float
        Separation of the two blocks in the reference configuration along their face
        normals [m] (0 when they touch).
    interface : (p,) bool
        The two blocks share a face interface in the reference configuration (what the
        static DEM and the limit analysis model).
    """

    pairs: np.ndarray
    force: np.ndarray
    point: np.ndarray
    gap: np.ndarray
    interface: np.ndarray

    def ranked(self) -> np.ndarray:
        """Indices of the pairs: those without a face interface first, then by force."""
        magnitude = np.linalg.norm(self.force, axis=1)
        return np.lexsort((-magnitude, self.interface))

    def describe(self, limit: int = 5) -> str:
        """The first ``limit`` pairs of :meth:`ranked` in words, e.g. ``blocks 2-4 (no face
        interface, gap 0 mm, 141 N)``."""
        parts = []
        for k in self.ranked()[:limit]:
            i, j = self.pairs[k]
            kind = "face interface" if self.interface[k] else "no face interface"
            parts.append(
                f"blocks {i}-{j} ({kind}, gap {self.gap[k] * 1e3:.3g} mm, "
                f"{np.linalg.norm(self.force[k]):.3g} N)"
            )
        more = len(self.pairs) - limit
        return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")


def pair_forces(model: ExplicitModel) -> PairForces:
    """The pairs of blocks in contact at the model's current state (state unchanged)."""
    _, _, entry_force, entry_point, _ = model.contact_wrenches()
    contacts = model.state.contacts
    pairs, resultant, point = interface_resultants(
        contacts.node, contacts.block, model.surface.block, entry_force, entry_point
    )
    asm = model.scene.assembly
    itf = asm.interfaces()
    shared = {(min(a, b), max(a, b)) for a, b in zip(itf.block_a, itf.block_b, strict=True)}
    interface = np.array([(int(i), int(j)) in shared for i, j in pairs], dtype=bool)
    gap = np.array(
        [max(0.0, -penetration_depth(asm.blocks[i], asm.blocks[j], tol=math.inf))
         for i, j in pairs]
    )  # fmt: skip
    return PairForces(pairs, resultant, point, gap, interface.reshape(-1))
