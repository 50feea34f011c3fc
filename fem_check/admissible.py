"""Statically admissible interface forces of an assembly, for exercising the stress pipeline.

This is *not* a DEM solution: it is the smallest (least-squares) set of interface wrenches
that balances every free block under given external loads, with no friction or no-tension
condition. It gives a state in equilibrium by construction, so that the stress pipeline can be
run and checked while no DEM state is at hand. Results built on it must say so.
"""

from __future__ import annotations

import numpy as np
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTri

from dem.geometry.interfaces import Interfaces
from fem_check.loads import BlockLoad, InterfaceResultants


def equilibrium_matrix(
    interfaces: Interfaces, centroids: np.ndarray, free: np.ndarray
) -> np.ndarray:
    """Map interface wrenches to the resultants on the free blocks.

    Parameters
    ----------
    interfaces : Interfaces
    centroids : (n_blocks, 3) float
        [m].
    free : (n_free,) int64
        Blocks whose equilibrium is imposed.

    Returns
    -------
    (6 n_free, 6 m) float
        Column block ``k`` takes the world force [N] and moment about the interface centroid
        [N m] that block a exerts on block b; row block ``i`` is the wrench on free block
        ``free[i]`` about its centroid.
    """
    m = interfaces.n_interfaces
    row = {int(b): i for i, b in enumerate(free)}
    a_eq = np.zeros((6 * len(free), 6 * m))
    for k in range(m):
        c = interfaces.centroid[k]
        for blk, sign in ((interfaces.block_a[k], -1.0), (interfaces.block_b[k], 1.0)):
            i = row.get(int(blk))
            if i is None:
                continue
            r = c - centroids[blk]
            skew = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            a_eq[6 * i : 6 * i + 3, 6 * k : 6 * k + 3] = sign * np.eye(3)
            a_eq[6 * i + 3 : 6 * i + 6, 6 * k : 6 * k + 3] = sign * skew
            a_eq[6 * i + 3 : 6 * i + 6, 6 * k + 3 : 6 * k + 6] = sign * np.eye(3)
    return a_eq


def admissible_resultants(
    interfaces: Interfaces,
    centroids: np.ndarray,
    free: np.ndarray,
    external: np.ndarray,
    sizes: np.ndarray | None = None,
) -> InterfaceResultants:
    """Least-squares interface resultants that balance the external wrenches of free blocks.

    Parameters
    ----------
    interfaces : Interfaces
    centroids : (n_blocks, 3) float
        [m].
    free : (n_free,) int64
    external : (n_blocks, 6) float
        External force [N] and moment about the centroid [N m] on each block (weight, point
        loads).
    sizes : (m,) float, optional
        Length scale of each interface [m] that weighs moments against forces in the norm
        (default: the square root of its area).

    Returns
    -------
    InterfaceResultants
        ``(N, V1, V2, M1, M2, M3)`` per interface (see :mod:`fem_check.loads` for signs).

    Raises
    ------
    ValueError
        If the external loads cannot be balanced (a free block with no interface).
    """
    a_eq = equilibrium_matrix(interfaces, centroids, free)
    scale = np.sqrt(interfaces.area) if sizes is None else np.asarray(sizes, dtype=float)
    # unknowns (F, M / s): moments measured in force units keep the norm balanced
    col = np.ones((interfaces.n_interfaces, 6))
    col[:, 3:] = scale[:, None]
    a_scaled = a_eq * col.reshape(-1)
    rhs = -np.asarray(external, dtype=float)[free].reshape(-1)
    sol, *_ = np.linalg.lstsq(a_scaled, rhs, rcond=None)
    residual = np.linalg.norm(a_scaled @ sol - rhs)
    if residual > 1e-9 * max(np.linalg.norm(rhs), 1e-300):
        raise ValueError(
            f"external loads cannot be balanced by the interfaces (residual {residual:.3e} N)"
        )
    wrench = (sol * col.reshape(-1)).reshape(-1, 6)
    local = np.empty_like(wrench)
    for k in range(interfaces.n_interfaces):
        frame = interfaces.frame[k]  # rows n, t1, t2
        local[k, :3] = frame @ wrench[k, :3]
        mt = frame @ wrench[k, 3:]  # along n, t1, t2
        local[k, 3:] = (mt[1], mt[2], mt[0])  # (M1 about t1, M2 about t2, M3 about n)
    return InterfaceResultants(interfaces, local)


def nodal_forces(load: BlockLoad, spacing: float) -> BlockLoad:
    """Replace the traction patches of a load by point forces on surface nodes.

    Each patch polygon is fanned into triangles, each split uniformly into sub-triangles of
    edge about ``spacing`` [m]; the degree-2 quadrature points of every sub-triangle become
    nodes carrying ``t(x) w``. Affine tractions are integrated exactly, so the force and moment
    of the load are unchanged: the DEM-like point load is balanced whenever the patches were.
    """
    x_ref, w_ref = get_quadrature(RefTri, 2)
    points, forces = [load.points], [load.forces]
    for p in load.patches:
        for k in range(1, len(p.polygon) - 1):
            a, b, c = p.polygon[0], p.polygon[k], p.polygon[k + 1]
            m = max(1, int(np.ceil(max(np.linalg.norm(b - a), np.linalg.norm(c - a)) / spacing)))
            # sub-triangles of the m x m split in (s, t) coordinates of the triangle
            i, j = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
            i, j = i.ravel(), j.ravel()
            up = i + j <= m - 1
            down = i + j <= m - 2
            corners = (
                np.concatenate(
                    [
                        np.stack([np.c_[i, j], np.c_[i + 1, j], np.c_[i, j + 1]], axis=1)[up],
                        np.stack([np.c_[i + 1, j], np.c_[i + 1, j + 1], np.c_[i, j + 1]], axis=1)[
                            down
                        ],
                    ]
                )
                / m
            )  # (n_sub, 3, 2) in (s, t)
            st = (
                corners[:, 0, None, :]
                + x_ref[0][None, :, None] * (corners[:, 1] - corners[:, 0])[:, None, :]
                + x_ref[1][None, :, None] * (corners[:, 2] - corners[:, 0])[:, None, :]
            ).reshape(-1, 2)
            xyz = a + st[:, :1] * (b - a) + st[:, 1:] * (c - a)
            area = 0.5 * np.linalg.norm(np.cross(b - a, c - a)) / m**2
            w = np.tile(2.0 * area * w_ref, len(corners))
            points.append(xyz)
            forces.append(p.at(xyz) * w[:, None])
    return BlockLoad(
        np.concatenate(points),
        np.concatenate(forces),
        (),
        load.density,
        load.gravity,
        load.acceleration,
        load.angular_velocity,
        load.label,
    )
