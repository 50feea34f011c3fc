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

import numpy as np

from dem.explicit.model import ExplicitModel
from dem.explicit.results import PairForces, interface_resultants
from dem.geometry.polyhedron import penetration_depth


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
