"""Stable time step of the explicit scheme from the stiffness and masses actually present."""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg

from dem.explicit.state import Bodies, Contacts, Indenter, Nodes


def highest_frequency(
    bodies: Bodies,
    nodes: Nodes,
    contacts: Contacts,
    pos: np.ndarray,
    k_n: float,
    k_t: float,
    indenter: Indenter | None = None,
) -> float:
    """Highest natural frequency with every candidate contact closed [rad/s].

    Each entry adds ``k A w J^T J`` with ``J`` the 3 x 12 map from the two blocks' dofs to the
    relative displacement of the node, and ``k = max(k_n, k_t)`` in every direction (an upper
    bound on the normal plus tangential stiffness); indenter nodes add their own ``k_n A`` to the
    loaded block. ``omega_max^2`` is the largest eigenvalue of ``K x = omega^2 M x`` over the free
    dofs.

    Parameters
    ----------
    bodies, nodes, contacts : Bodies, Nodes, Contacts
        See :mod:`dem.explicit.state`.
    pos : (n_blocks, 3) float
        Centroids [m] (reference configuration: the nodes are placed unrotated).
    k_n, k_t : float
        Penalties [Pa/m].
    indenter : Indenter, optional
        Include the indenter's nodes.
    """
    free = bodies.free_blocks
    nf = len(free)
    if nf == 0:
        return 0.0
    n_blocks = len(bodies.inv_mass)
    free_index = -np.ones(n_blocks, dtype=np.int64)
    free_index[free] = np.arange(nf)
    owners = nodes.block[contacts.node]
    points = pos[owners] + nodes.r0[contacts.node]
    stiff = max(k_n, k_t) * nodes.area[contacts.node] * contacts.weight
    sides = [(owners, 1.0), (contacts.block, -1.0)]
    if indenter is not None and len(indenter.block):
        points = np.concatenate([points, pos[indenter.block] + indenter.r0])
        stiff = np.concatenate([stiff, k_n * indenter.area])
        owners = np.concatenate([owners, indenter.block])
        sides = [(owners, 1.0), (np.concatenate([contacts.block, indenter.block]), 0.0)]
    jac = [(blk, sign * _point_jacobian(points - pos[blk])) for blk, sign in sides]
    K = np.zeros((6 * nf, 6 * nf))
    for bi, Ji in jac:
        for bj, Jj in jac:
            fi, fj = free_index[bi], free_index[bj]
            ok = (fi >= 0) & (fj >= 0) & (stiff > 0)
            if not np.any(ok) or not np.any(Ji[ok]) or not np.any(Jj[ok]):
                continue
            blocks = np.einsum("m,mki,mkj->mij", stiff[ok], Ji[ok], Jj[ok])
            acc = np.zeros((nf * nf, 6, 6))
            np.add.at(acc, fi[ok] * nf + fj[ok], blocks)
            K += acc.reshape(nf, nf, 6, 6).transpose(0, 2, 1, 3).reshape(6 * nf, 6 * nf)
    if not np.any(K):
        return 0.0
    M = np.zeros((6 * nf, 6 * nf))
    for j, i in enumerate(free):
        M[6 * j : 6 * j + 3, 6 * j : 6 * j + 3] = np.eye(3) / bodies.inv_mass[i]
        M[6 * j + 3 : 6 * j + 6, 6 * j + 3 : 6 * j + 6] = bodies.inertia_ref[i]
    last = 6 * nf - 1
    top = scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[last, last])[0]
    return float(math.sqrt(max(top, 0.0)))


def _point_jacobian(r: np.ndarray) -> np.ndarray:
    """(m, 3, 6) map from a block's ``(u, theta)`` to the motion ``u + theta x r`` of points."""
    J = np.zeros((len(r), 3, 6))
    J[:, :, :3] = np.eye(3)
    # u + theta x r = u - skew(r) theta
    J[:, 0, 4], J[:, 0, 5] = r[:, 2], -r[:, 1]
    J[:, 1, 3], J[:, 1, 5] = -r[:, 2], r[:, 0]
    J[:, 2, 3], J[:, 2, 4] = r[:, 1], -r[:, 0]
    return J


def choose_time_step(omega_max: float, settings) -> dict:
    """Time step and damping coefficients from the highest frequency.

    Parameters
    ----------
    omega_max : float
        [rad/s].
    settings : ExplicitSettings

    Returns
    -------
    dict
        ``dt`` [s], ``dt_critical`` [s] (stable limit of the damped scheme), ``beta`` [s]
        (normal dashpot), ``alpha`` [1/s] (global damping rate).

    Raises
    ------
    ValueError
        A forced ``dt`` above the stable limit, or no stiffness and no ``dt``.
    """
    w = omega_max
    if w > 0:
        zeta = settings.contact_damping
        out = {
            "dt_critical": 2.0 / w * (math.sqrt(1.0 + zeta * zeta) - zeta),
            "beta": 2.0 * zeta / w,
            "alpha": 2.0 * settings.global_damping * w,
        }
    else:
        out = {"dt_critical": math.inf, "beta": 0.0, "alpha": 0.0}
    if settings.dt is not None:
        if settings.dt > out["dt_critical"]:
            raise ValueError(
                f"time step dt={settings.dt:.3e} s is above the stable limit "
                f"{out['dt_critical']:.3e} s (omega_max={w:.3e} rad/s)"
            )
        out["dt"] = float(settings.dt)
    elif math.isfinite(out["dt_critical"]):
        out["dt"] = settings.dt_safety * out["dt_critical"]
    else:
        raise ValueError(
            "no contact stiffness in the scene: no contact node lies within "
            "ExplicitSettings.margin of another block at the start, so no contact sets the "
            "time step; for blocks in free flight give ExplicitSettings.dt (below 2 / omega "
            "of the stiffest contact they will meet)"
        )
    return out
