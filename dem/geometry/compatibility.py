"""Interface kinematics: the compatibility matrix H between block dofs and interface motions."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from dem.geometry.interfaces import Interfaces
from dem.kernels.triplets import compatibility_triplets


def compatibility_matrix(block_centroid: np.ndarray, interfaces: Interfaces) -> sp.csr_matrix:
    """Sparse ``H`` with ``q = H U`` (seed 001, Eq. 3 and A1-A3 in general form).

    Parameters
    ----------
    block_centroid : (n_blocks, 3) float
        Reference points of the block dofs [m].
    interfaces : Interfaces

    Returns
    -------
    (6 m, 6 n_blocks) csr_matrix
        ``U`` stacks ``(ux, uy, uz, rx, ry, rz)`` per block; ``q`` stacks per interface the
        relative translation of b w.r.t. a at the interface centroid in the frame
        ``(n, t1, t2)`` and the relative rotation about ``(t1, t2, n)``: opening ``dn > 0``,
        sliding ``dt1, dt2``, rocking ``phi1, phi2`` and twisting ``phi3``.

    Notes
    -----
    By virtual work the generalised interface forces ``f = (N, V1, V2, M1, M2, M3)`` (``N > 0``
    in tension) act on the blocks as ``H^T f``: equilibrium of the blocks is
    ``H^T f = F_ext``, so the equilibrium matrix of limit analysis is ``A_eq = H^T``.
    """
    centroids = np.ascontiguousarray(block_centroid, dtype=np.float64)
    if centroids.ndim != 2 or centroids.shape[1] != 3:
        raise ValueError(f"block_centroid must have shape (n_blocks, 3), got {centroids.shape}")
    m, n = interfaces.n_interfaces, len(centroids)
    if m and max(interfaces.block_a.max(), interfaces.block_b.max()) >= n:
        raise ValueError("interfaces refer to blocks beyond block_centroid")
    rows, cols, vals = compatibility_triplets(
        interfaces.block_a,
        interfaces.block_b,
        np.ascontiguousarray(interfaces.centroid),
        centroids,
        np.ascontiguousarray(interfaces.frame),
    )
    return sp.csr_matrix((vals, (rows, cols)), shape=(6 * m, 6 * n))
