"""Is there a mechanism the live load can drive? A linear program before the path.

A mechanism is a motion ``U`` of the free dofs that opens no interface: the normal gap
``dn + phi1 y2 - phi2 y1`` is >= 0 at every corner of every interface polygon. Sliding is free
(zero-dilatancy friction and tensile strength only dissipate). If the live load does no
positive work on any such motion, no multiplier can make the assembly collapse (kinematic
theorem with the least restrictive joints that crush nothing): ``solve_collapse`` then ends at
once with termination ``"no_mechanism"`` instead of following an elastic path to
``max_steps`` (issue 11, item 3: a downward live load reached lambda = 787). With a
compressive strength joints can crush, and the check does not apply.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

logger = logging.getLogger(__name__)

WORK_TOLERANCE = 1e-7  # relative to the largest work of the live load on the bounded motions


def gap_matrix(model) -> sp.csr_matrix:
    """(n_corners, n_free) corner gaps ``G u`` of every interface polygon [m]."""
    r_idx, c_idx, vals = [], [], []
    n_rows = 0
    for k in range(model.m):
        poly = model.itf.local_polygon(k)
        g = np.zeros((len(poly), 6))
        g[:, 0] = 1.0
        g[:, 3] = poly[:, 1]
        g[:, 4] = -poly[:, 0]
        gb = g @ model.B[k]
        dofs = np.concatenate([model.dof_index[model.a[k]], model.dof_index[model.b[k]]])
        keep = dofs >= 0
        for row in gb:
            nz = keep & (row != 0.0)
            r_idx.append(np.full(int(nz.sum()), n_rows))
            c_idx.append(dofs[nz])
            vals.append(row[nz])
            n_rows += 1
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(r_idx), np.concatenate(c_idx))),
        shape=(n_rows, model.n_free),
    )


def no_mechanism_reason(model) -> str:
    """Why no collapse mechanism exists, or "" if one may (or the check is inconclusive).

    Maximises the live load's work ``F_L . u`` over the motions that open no joint, with
    translations bounded by 1 m and rotations by 1 / L rad (L the size of the assembly).
    """
    G = gap_matrix(model)
    size = float(np.ptp(model.scene.assembly.centroid, axis=0).max()) or 1.0
    is_rot = np.broadcast_to(np.arange(6) >= 3, (model.n_blocks, 6))[model.free_mask]
    bound = np.where(is_rot, 1.0 / size, 1.0)
    res = linprog(
        -model.F_live,
        A_ub=-G,
        b_ub=np.zeros(G.shape[0]),
        bounds=np.column_stack([-bound, bound]),
        method="highs",
    )
    if res.status != 0:
        logger.debug("mechanism check inconclusive (%s): the path decides", res.message)
        return ""
    work = -float(res.fun)
    scale = float(np.abs(model.F_live) @ bound)
    if work > WORK_TOLERANCE * scale:
        return ""
    return (
        "no mechanism: the live load does no positive work on any motion that opens no joint "
        f"(largest work {work:.3e} of at most {scale:.3e}), so no multiplier makes the assembly "
        "collapse (it points into the supports or is carried by them)"
    )
