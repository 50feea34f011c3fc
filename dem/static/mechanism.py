"""Is there a mechanism the live load can drive? A linear program before the path.

A mechanism is a motion ``U`` of the free dofs that opens no interface: the normal gap
``dn + phi1 y2 - phi2 y1`` is >= 0 at every corner of every interface polygon. Sliding is free
(zero-dilatancy friction and tensile strength only dissipate). If the live load does no
positive work on any such motion, no multiplier can make the assembly collapse (kinematic
theorem with the least restrictive joints that crush nothing): ``solve_collapse`` then ends at
once with termination ``"no_mechanism"`` instead of following an elastic path to
``max_steps``. With a compressive strength joints can crush, and the check does not apply.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

logger = logging.getLogger(__name__)

WORK_TOLERANCE = 1e-7  # relative to the largest work of the live load on the bounded motions


def gap_matrix(model, interfaces: np.ndarray | None = None) -> sp.csr_matrix:
    """(n_corners, n_free) corner gaps ``G u`` of the polygons of ``interfaces`` (default
    all) [m], one row per corner."""
    itf = model.itf
    ks = np.arange(model.m) if interfaces is None else np.asarray(interfaces, dtype=np.int64)
    counts = itf.poly_ptr[ks + 1] - itf.poly_ptr[ks]
    owner = np.repeat(ks, counts)
    corner = _corner_rows(itf.poly_ptr, ks, counts)
    local = np.einsum("pj,pij->pi", itf.poly_points[corner] - itf.centroid[owner],
                      itf.frame[owner, 1:])  # fmt: skip
    g = np.zeros((len(owner), 6))
    g[:, 0], g[:, 3], g[:, 4] = 1.0, local[:, 1], -local[:, 0]
    gb = np.einsum("pi,pij->pj", g, model.B[owner])
    dofs = np.concatenate([model.dof_index[model.a[owner]], model.dof_index[model.b[owner]]], 1)
    keep = (dofs >= 0) & (gb != 0.0)
    rows = np.broadcast_to(np.arange(len(owner))[:, None], keep.shape)[keep]
    return sp.csr_matrix((gb[keep], (rows, dofs[keep])), shape=(len(owner), model.n_free))


def _corner_rows(poly_ptr: np.ndarray, ks: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Indices into the corner list of every corner of the interfaces ``ks``, in order."""
    starts = np.repeat(poly_ptr[ks] - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)
    return starts + np.arange(int(counts.sum()))


def rigid_components(model) -> tuple[int, np.ndarray]:
    """``(n, label)``: the blocks that can move (any free dof) grouped into the ``n``
    connected parts their interfaces make; ``label`` (n_blocks,) int64, -1 for a fixed
    block."""
    movable = model.free_mask.any(axis=1)
    joined = movable[model.a] & movable[model.b]
    n_blocks = model.n_blocks
    graph = sp.coo_matrix(
        (np.ones(int(joined.sum())), (model.a[joined], model.b[joined])), shape=(n_blocks,) * 2
    )
    _, label = sp.csgraph.connected_components(graph, directed=False)
    label = np.where(movable, label, -1)
    used, label[movable] = np.unique(label[movable], return_inverse=True)
    return len(used), label


def rigid_motions(model, n_parts: int, label: np.ndarray) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """``(P, E)``: the dofs ``u = P x`` (n_free, 6 n_parts) of each part moving as one rigid
    body, ``x`` its translation at the part's mean centroid [m] and rotation [rad]; ``E x``
    the eliminated (restrained) dofs of the movable blocks, which must stay 0."""
    c = model.scene.assembly.centroid
    blocks = np.flatnonzero(label >= 0)
    part = label[blocks]
    ref = np.zeros((n_parts, 3))
    np.add.at(ref, part, c[blocks])
    ref /= np.bincount(part, minlength=n_parts)[:, None]
    r = c[blocks] - ref[part]
    # u_i = (t + omega x r_i, omega): rows (block, dof), columns 6 part + (t, omega)
    t = np.zeros((len(blocks), 6, 6))
    t[:, range(6), range(6)] = 1.0
    t[:, 0, 4], t[:, 0, 5] = r[:, 2], -r[:, 1]
    t[:, 1, 3], t[:, 1, 5] = -r[:, 2], r[:, 0]
    t[:, 2, 3], t[:, 2, 4] = r[:, 1], -r[:, 0]
    rows = np.broadcast_to((6 * blocks)[:, None, None] + np.arange(6)[None, :, None], t.shape)
    cols = np.broadcast_to((6 * part)[:, None, None] + np.arange(6)[None, None, :], t.shape)
    keep = t != 0.0
    full = sp.csr_matrix(
        (t[keep], (rows[keep], cols[keep])), shape=(6 * model.n_blocks, 6 * n_parts)
    )
    dof = model.dof_index.ravel()
    movable_dof = np.repeat(label >= 0, 6)
    P = full[np.flatnonzero(dof >= 0)][np.argsort(dof[dof >= 0])]
    E = full[np.flatnonzero(movable_dof & (dof < 0))]
    return P.tocsr(), E.tocsr()


def _max_work(model, G: sp.csr_matrix, P: sp.csr_matrix | None, E=None, size: float = 1.0):
    """Largest live-load work ``F_L . u`` over ``u = P x`` (or ``u`` itself if ``P`` is None)
    opening no corner of ``G``, translations within 1 m and rotations within 1 / size rad;
    ``(work, scale)`` with ``scale`` the work's bound, or None if HiGHS found no optimum."""
    if P is None:
        is_rot = np.broadcast_to(np.arange(6) >= 3, (model.n_blocks, 6))[model.free_mask]
        cost, A = model.F_live, G
    else:
        is_rot = np.tile(np.arange(6) >= 3, P.shape[1] // 6)
        cost, A = P.T @ model.F_live, G @ P
    bound = np.where(is_rot, 1.0 / size, 1.0)
    res = linprog(
        -cost,
        A_ub=-A,
        b_ub=np.zeros(A.shape[0]),
        A_eq=E,
        b_eq=None if E is None else np.zeros(E.shape[0]),
        bounds=np.column_stack([-bound, bound]),
        method="highs",
    )
    if res.status != 0:
        logger.debug("mechanism check inconclusive (%s)", res.message)
        return None
    return -float(res.fun), float(np.abs(cost) @ bound)


def no_mechanism_reason(model) -> str:
    """Why no collapse mechanism exists, or "" if one may (or the check is inconclusive).

    Maximises the live load's work ``F_L . u`` over the motions that open no joint, with
    translations bounded by 1 m and rotations by 1 / L rad (L the size of the assembly).
    First over the motions that move each connected part of the movable blocks as one rigid
    body (6 unknowns a part, only the joints with fixed blocks constrain them): work there
    proves a mechanism at the cost of the supports' size. Only without it is the linear
    program over every block's dofs solved.
    """
    size = float(np.ptp(model.scene.assembly.centroid, axis=0).max()) or 1.0
    n_parts, label = rigid_components(model)
    P, E = rigid_motions(model, n_parts, label)
    between = np.flatnonzero(label[model.a] != label[model.b])
    rigid = _max_work(model, gap_matrix(model, between), P, E if E.shape[0] else None, size)
    if rigid is not None and rigid[0] > WORK_TOLERANCE * rigid[1]:
        return ""
    found = _max_work(model, gap_matrix(model), None, None, size)
    if found is None:
        return ""
    work, scale = found
    if work > WORK_TOLERANCE * scale:
        return ""
    return (
        "no mechanism: the live load does no positive work on any motion that opens no joint "
        f"(largest work {work:.3e} of at most {scale:.3e}), so no multiplier makes the assembly "
        "collapse (it points into the supports or is carried by them)"
    )
