"""Stable time step of the explicit scheme from the stiffness and masses actually present."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from dem.explicit.state import Bodies, Contacts, Indenter, Nodes


@dataclass(frozen=True)
class ContactStiffness:
    """The contact entries whose stiffness sets the highest natural frequency.

    Attributes
    ----------
    bodies, nodes, contacts : Bodies, Nodes, Contacts
        See :mod:`dem.explicit.state`.
    pos : (n_blocks, 3) float
        Centroids [m].
    k_n, k_t : float
        Penalties [Pa/m].
    indenter : Indenter, optional
        Include the indenter's nodes.
    rot : (n_blocks, 3, 3) float, optional
        Rotations of the blocks (default: the reference orientation).
    """

    bodies: Bodies
    nodes: Nodes
    contacts: Contacts
    pos: np.ndarray
    k_n: float
    k_t: float
    indenter: Indenter | None = None
    rot: np.ndarray | None = None


def highest_frequency(system: ContactStiffness) -> float:
    """Highest natural frequency with every candidate contact of ``system`` closed [rad/s].

    Each entry adds ``k A w J^T J`` with ``J`` the 3 x 12 map from the two blocks' dofs to the
    relative displacement of the node, and ``k = max(k_n, k_t)`` in every direction (an upper
    bound on the normal plus tangential stiffness); indenter nodes add their own ``k_n A`` to the
    loaded block. ``omega_max^2`` is the largest eigenvalue of ``K x = omega^2 M x`` over the free
    dofs.
    """
    bodies, pos, rot = system.bodies, system.pos, system.rot
    free = bodies.free_blocks
    nf = len(free)
    if nf == 0:
        return 0.0
    free_index = -np.ones(len(bodies.inv_mass), dtype=np.int64)
    free_index[free] = np.arange(nf)
    stiff, points, sides = _entries(system)
    jac = [(blk, sign[:, None, None] * _point_jacobian(points - pos[blk])) for blk, sign in sides]
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
    M = scipy.linalg.block_diag(*_block_masses(bodies, free, rot))
    last = 6 * nf - 1
    top = scipy.linalg.eigh(K, M, eigvals_only=True, subset_by_index=[last, last])[0]
    return float(math.sqrt(max(top, 0.0)))


def frequency_bound(system: ContactStiffness) -> np.ndarray:
    """Upper bound on :func:`highest_frequency` per free block [rad/s], in O(entries).

    An entry that moves ``s`` free blocks (1 or 2) adds ``k A w (J_a - J_b)^T (J_a - J_b)``
    to ``K``, which is at most ``s k A w (J_a^T J_a + J_b^T J_b)`` (Cauchy-Schwarz); so ``K``
    is at most the block-diagonal ``D`` of these terms, and ``omega_max^2 <= max_i
    lambda_max(D_ii, M_ii)`` over the free blocks ``i``. Since ``omega_max^2`` is at least
    ``max_i lambda_max(K_ii, M_ii) >= max_i lambda_max(D_ii, M_ii) / 2``, the bound is at most
    ``sqrt(2)`` times the exact ``omega_max``.

    Returns
    -------
    (n_blocks,) float
        The bound from each block's entries [rad/s] (0 for fixed blocks and blocks without
        entries); its maximum bounds ``omega_max``.
    """
    bodies, pos, rot = system.bodies, system.pos, system.rot
    n_blocks = len(bodies.inv_mass)
    out = np.zeros(n_blocks)
    free = bodies.free_blocks
    if len(free) == 0:
        return out
    is_free = np.zeros(n_blocks, dtype=bool)
    is_free[free] = True
    stiff, points, sides = _entries(system)
    moves = [is_free[blk] & (sign != 0.0) & (stiff > 0) for blk, sign in sides]
    weight = np.sum(moves, axis=0) * stiff
    D = np.zeros((n_blocks, 6, 6))
    for (blk, _), moved in zip(sides, moves, strict=True):
        D += _moment_blocks(blk[moved], weight[moved], (points - pos[blk])[moved], n_blocks)
    values, vectors = np.linalg.eigh(_inertia(bodies, free, rot))
    inv_sqrt = np.zeros((len(free), 6, 6))
    inv_sqrt[:, :3, :3] = np.sqrt(bodies.inv_mass[free])[:, None, None] * np.eye(3)
    inv_sqrt[:, 3:, 3:] = (vectors / np.sqrt(values)[:, None, :]) @ vectors.transpose(0, 2, 1)
    scaled = inv_sqrt @ D[free] @ inv_sqrt
    out[free] = np.sqrt(np.maximum(np.linalg.eigvalsh(scaled)[:, -1], 0.0))
    return out


def _moment_blocks(blk: np.ndarray, weight: np.ndarray, arm: np.ndarray, n: int) -> np.ndarray:
    """(n, 6, 6) sums over entries of ``weight J^T J`` per block ``blk``, ``J`` the point
    Jacobian of the ``arm`` (m, 3): from the moments ``K0 = sum w``, ``K1 = sum w r`` and
    ``K2 = sum w r r^T``, ``[[K0 I, -skew(K1)], [skew(K1), tr(K2) I - K2]]``."""
    k0 = np.bincount(blk, weight, n)
    k1 = np.stack([np.bincount(blk, weight * arm[:, i], n) for i in range(3)], axis=1)
    k2 = np.empty((n, 3, 3))
    for i in range(3):
        for j in range(i, 3):
            k2[:, i, j] = k2[:, j, i] = np.bincount(blk, weight * arm[:, i] * arm[:, j], n)
    skew = np.zeros((n, 3, 3))
    skew[:, 0, 1], skew[:, 0, 2], skew[:, 1, 2] = -k1[:, 2], k1[:, 1], -k1[:, 0]
    skew -= skew.transpose(0, 2, 1)
    out = np.zeros((n, 6, 6))
    out[:, :3, :3] = k0[:, None, None] * np.eye(3)
    out[:, :3, 3:] = -skew
    out[:, 3:, :3] = skew
    out[:, 3:, 3:] = np.trace(k2, axis1=1, axis2=2)[:, None, None] * np.eye(3) - k2
    return out


def stable_frequency(dt: float, alpha: float, beta: float) -> float:
    """Highest frequency [rad/s] the damped scheme is stable for at time step ``dt`` [s].

    With the global damping rate ``alpha`` [1/s] and the contact dashpot ``beta`` [s] (modal
    damping rate ``alpha + beta omega^2``), symplectic Euler is stable for ``(omega dt)^2 +
    2 (alpha + beta omega^2) dt <= 4`` (the condition of
    :meth:`dem.explicit.ExplicitModel._check_damping`); this is the ``omega`` where it holds
    with equality (0 if ``alpha dt >= 2``).
    """
    room = 4.0 - 2.0 * alpha * dt
    if room <= 0.0:
        return 0.0
    return math.sqrt(room / (dt * dt + 2.0 * beta * dt))


def stable_time_step(omega: float, alpha: float, beta: float) -> float:
    """Largest time step [s] at which the damped scheme is stable for the frequency
    ``omega`` [rad/s] > 0 (the inverse of :func:`stable_frequency`: the ``dt`` where
    ``(omega dt)^2 + 2 (alpha + beta omega^2) dt = 4``)."""
    damping = alpha + beta * omega * omega
    return (math.sqrt(damping * damping + 4.0 * omega * omega) - damping) / omega**2


def _entries(system: ContactStiffness):
    """Per entry of ``system``: stiffness ``k A w`` [N/m] (m,), node position [m] (m, 3) and
    the two sides as ``(block (m,), sign (m,))`` (sign 0 for the indenter's side)."""
    nodes, contacts, indenter = system.nodes, system.contacts, system.indenter
    owners = nodes.block[contacts.node]
    offsets = nodes.r0[contacts.node]
    stiff = max(system.k_n, system.k_t) * nodes.area[contacts.node] * contacts.weight
    others, signs = contacts.block, -np.ones(len(owners))
    if indenter is not None and len(indenter.block):
        offsets = np.concatenate([offsets, indenter.r0])
        stiff = np.concatenate([stiff, system.k_n * indenter.area])
        owners = np.concatenate([owners, indenter.block])
        others = np.concatenate([contacts.block, indenter.block])
        signs = np.concatenate([signs, np.zeros(len(indenter.block))])
    if system.rot is not None:
        offsets = np.einsum("mij,mj->mi", system.rot[owners], offsets)
    return stiff, system.pos[owners] + offsets, [(owners, np.ones(len(owners))), (others, signs)]


def _inertia(bodies: Bodies, free: np.ndarray, rot: np.ndarray | None) -> np.ndarray:
    """(len(free), 3, 3) inertia tensors ``R I_ref R^T`` of the ``free`` blocks [kg m^2]
    (``I_ref`` where ``rot`` is None)."""
    inertia = bodies.inertia_ref[free]
    return inertia if rot is None else rot[free] @ inertia @ rot[free].transpose(0, 2, 1)


def _block_masses(bodies: Bodies, free: np.ndarray, rot: np.ndarray | None) -> np.ndarray:
    """(len(free), 6, 6) mass matrices ``diag(m I, R I_ref R^T)`` of the ``free`` blocks."""
    M = np.zeros((len(free), 6, 6))
    M[:, :3, :3] = np.eye(3) / bodies.inv_mass[free][:, None, None]
    M[:, 3:, 3:] = _inertia(bodies, free, rot)
    return M


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
