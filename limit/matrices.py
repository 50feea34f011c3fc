r"""Matrices of rigid-block limit analysis: equilibrium, vertex forces, yield blocks.

Sign conventions follow :func:`dem.geometry.compatibility.compatibility_matrix`. At interface
``k`` (normal ``n`` from block ``a`` into block ``b``, frame rows ``n, t1, t2``) the generalised
force is ``f_k = (N, V1, V2, M1, M2, M3)`` with ``N > 0`` in tension, moments about
``(t1, t2, n)`` at the interface centroid; it is the resultant of the interface traction
``sigma = sigma_n n + s_1 t1 + s_2 t2`` (``sigma_n < 0`` in compression):

.. math::

    N = \int_A \sigma_n, \quad V_i = \int_A s_i, \quad
    M_1 = \int_A y_2 \sigma_n, \quad M_2 = -\int_A y_1 \sigma_n, \quad
    M_3 = \int_A (y_1 s_2 - y_2 s_1).

Block ``b`` receives ``-f`` (as a wrench at the interface centroid), block ``a`` receives
``+f``. With the external wrenches ``F_dead + lambda F_live`` at the block centroids
[N, N m], the equilibrium of every free block is ``A_eq f + F_dead + lambda F_live = 0`` with
``A_eq = -H^T`` (``H`` the DEM compatibility matrix: virtual work). :func:`equilibrium_matrix`
builds ``A_eq`` from statics, independently of ``H``, so that the identity can be tested.

Units are SI: m, N, N m.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from dem.geometry.interfaces import Interfaces

__all__ = [
    "equilibrium_matrix",
    "vertex_force_matrix",
    "interface_vertices",
    "rocking_constraints",
    "torsion_coefficient",
    "mean_distance_polygon",
    "mean_distance_polygons",
    "interface_rectangles",
    "interface_friction",
]


def _skew(d: np.ndarray) -> np.ndarray:
    """(k, 3, 3) matrices ``[d]_x`` with ``[d]_x v = d x v``."""
    out = np.zeros((len(d), 3, 3))
    out[:, 0, 1], out[:, 0, 2] = -d[:, 2], d[:, 1]
    out[:, 1, 0], out[:, 1, 2] = d[:, 2], -d[:, 0]
    out[:, 2, 0], out[:, 2, 1] = -d[:, 1], d[:, 0]
    return out


def equilibrium_matrix(block_centroid: np.ndarray, interfaces: Interfaces) -> sp.csr_matrix:
    r"""Equilibrium matrix ``A_eq`` (6 n_blocks x 6 m) from statics.

    Parameters
    ----------
    block_centroid : (n_blocks, 3) float
        Reference points of the block wrenches [m].
    interfaces : Interfaces
        ``m`` interfaces.

    Returns
    -------
    (6 n_blocks, 6 m) csr_matrix
        ``(A_eq f)[6 i : 6 i + 6]`` is the wrench ``(F, M)`` [N, N m] that the interface
        forces ``f`` exert on block ``i`` about its centroid.

    Notes
    -----
    Block ``b`` receives the force :math:`-E^T(N, V_1, V_2)` at the interface centroid ``c``
    and the couple :math:`-R^T (M_1, M_2, M_3)`, with ``E`` the frame rows ``(n, t1, t2)`` and
    ``R`` the rows ``(t1, t2, n)``; block ``a`` receives the opposite. About the block centroid
    ``x`` the force adds the moment :math:`(c - x)\times F`. The result equals ``-H^T``
    (seed 001, Eq. A1-A3 and Sec. 2, ``K = H^T K_bar H``).
    """
    x = np.asarray(block_centroid, dtype=np.float64)
    if x.ndim != 2 or x.shape[1] != 3:
        raise ValueError(f"block_centroid must have shape (n_blocks, 3), got {x.shape}")
    m, n = interfaces.n_interfaces, len(x)
    if m == 0:
        return sp.csr_matrix((6 * n, 0))
    frame = interfaces.frame  # (m, 3, 3) rows n, t1, t2
    e_force = np.transpose(frame, (0, 2, 1))  # columns n, t1, t2: (N, V1, V2) -> global force
    e_couple = e_force[:, :, [1, 2, 0]]  # columns t1, t2, n: (M1, M2, M3) -> global couple
    rows, cols, vals = [], [], []
    k6 = 6 * np.arange(m)
    for blocks, sign in ((interfaces.block_b, -1.0), (interfaces.block_a, 1.0)):
        arm = interfaces.centroid - x[blocks]  # (m, 3)
        blk = np.zeros((m, 6, 6))
        blk[:, :3, :3] = sign * e_force
        blk[:, 3:, :3] = sign * _skew(arm) @ e_force
        blk[:, 3:, 3:] = sign * e_couple
        r = 6 * blocks[:, None, None] + np.arange(6)[None, :, None]
        c = k6[:, None, None] + np.arange(6)[None, None, :]
        rows.append(np.broadcast_to(r, blk.shape).ravel())
        cols.append(np.broadcast_to(c, blk.shape).ravel())
        vals.append(blk.ravel())
    a_eq = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(6 * n, 6 * m)
    )
    a_eq.eliminate_zeros()
    return a_eq


def interface_vertices(interfaces: Interfaces) -> tuple[np.ndarray, np.ndarray]:
    """Corners of every interface polygon in local coordinates.

    Returns
    -------
    vertex_iface : (p,) int64
        Interface of each corner.
    vertex_local : (p, 2) float
        ``(y1, y2)`` of each corner about the interface centroid [m].
    """
    p_ptr = interfaces.poly_ptr
    counts = np.diff(p_ptr)
    vertex_iface = np.repeat(np.arange(interfaces.n_interfaces), counts)
    rel = interfaces.poly_points - interfaces.centroid[vertex_iface]
    t = interfaces.frame[vertex_iface, 1:, :]  # (p, 2, 3)
    vertex_local = np.einsum("pij,pj->pi", t, rel)
    return vertex_iface.astype(np.int64), vertex_local


def vertex_force_matrix(interfaces: Interfaces) -> sp.csr_matrix:
    r"""Map ``B`` from vertex forces to interface resultants, ``f = B x``.

    Parameters
    ----------
    interfaces : Interfaces
        ``m`` interfaces with ``p`` polygon corners in all.

    Returns
    -------
    (6 m, 3 p) csr_matrix
        ``x`` stacks per corner ``(p_j, s_1j, s_2j)``: the compressive normal force
        ``p_j >= 0`` [N] and the tangential force along ``(t1, t2)`` [N].

    Notes
    -----
    With the corner at ``(y_1, y_2)``: :math:`N = -\sum p_j`, :math:`V_i = \sum s_{ij}`,
    :math:`M_1 = -\sum y_2 p_j`, :math:`M_2 = \sum y_1 p_j`,
    :math:`M_3 = \sum (y_1 s_{2j} - y_2 s_{1j})`. For a rigid no-tension Coulomb joint any
    pressure distribution on the convex polygon maps onto such corner forces (each point of the
    polygon is a convex combination of the corners and the resultants are linear in the point),
    so the vertex model is the exact interface.
    """
    vi, y = interface_vertices(interfaces)
    p = len(vi)
    j = np.arange(p)
    rows = np.concatenate(
        [6 * vi, 6 * vi + 1, 6 * vi + 2, 6 * vi + 3, 6 * vi + 4, 6 * vi + 5, 6 * vi + 5]
    )
    cols = np.concatenate([3 * j, 3 * j + 1, 3 * j + 2, 3 * j, 3 * j, 3 * j + 2, 3 * j + 1])
    vals = np.concatenate(
        [-np.ones(p), np.ones(p), np.ones(p), -y[:, 1], y[:, 0], y[:, 0], -y[:, 1]]
    )
    return sp.csr_matrix((vals, (rows, cols)), shape=(6 * interfaces.n_interfaces, 3 * p))


def rocking_constraints(interfaces: Interfaces) -> tuple[sp.csr_matrix, np.ndarray]:
    r"""Half-planes that keep the centre of pressure inside each interface polygon.

    The normal resultant ``c = -N`` acts at ``e = (M_2, -M_1) / c``; ``e`` in the polygon
    ``P = {y : nu_e . y <= h_e}`` reads :math:`\nu_1 M_2 - \nu_2 M_1 \le h\,c` for every edge.

    Returns
    -------
    G : (n_edges, 6 m) csr_matrix
        Row ``e`` holds ``(-nu_2, nu_1)`` in the ``(M1, M2)`` columns of its interface.
    h : (n_edges,) float
        Edge distances from the centroid [m] (positive).
    edge_iface : (n_edges,) int64
        Interface of each edge.
    """
    vi, y = interface_vertices(interfaces)
    # each list starts with an empty array: no interface gives empty outputs
    rows, cols, vals, hs, owner = ([np.zeros(0, dtype=np.int64)] for _ in range(5))
    e = 0
    for k in range(interfaces.n_interfaces):
        poly = y[interfaces.poly_ptr[k] : interfaces.poly_ptr[k + 1]]
        area2 = np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
        if area2 < 0:
            poly = poly[::-1]
        d = np.roll(poly, -1, axis=0) - poly
        nu = np.stack([d[:, 1], -d[:, 0]], axis=1)
        nu /= np.linalg.norm(nu, axis=1)[:, None]
        h = np.einsum("ij,ij->i", nu, poly)
        ne = len(poly)
        idx = e + np.arange(ne)
        rows += [idx, idx]
        cols += [np.full(ne, 6 * k + 3), np.full(ne, 6 * k + 4)]
        vals += [-nu[:, 1], nu[:, 0]]
        hs.append(h)
        owner.append(np.full(ne, k))
        e += ne
    g = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(e, 6 * interfaces.n_interfaces),
    )
    return g, np.concatenate(hs), np.concatenate(owner).astype(np.int64)


def _sec3_antiderivative(a: np.ndarray) -> np.ndarray:
    r""":math:`\int_0^{\arctan a} \sec^3 = (a\sqrt{1+a^2} + \operatorname{asinh} a) / 2`."""
    return 0.5 * (a * np.sqrt(1.0 + a * a) + np.arcsinh(a))


def mean_distance_polygons(
    corners: np.ndarray, ptr: np.ndarray, points: np.ndarray | None = None
) -> np.ndarray:
    r"""Mean distance :math:`\frac{1}{A}\int_P |y - y_0|\,dA` of convex polygons [m] (exact).

    Parameters
    ----------
    corners : (p, 2) float
        Corners of all polygons, polygon ``k`` in rows ``ptr[k]:ptr[k + 1]``, either
        orientation [m].
    ptr : (m + 1,) int
    points : (m, 2) float, optional
        ``y_0`` per polygon; default the centroids.

    Returns
    -------
    (m,) float

    Raises
    ------
    ValueError
        A polygon of zero area.

    Notes
    -----
    Fan of triangles from ``y_0``; on each, in polar coordinates about ``y_0`` with the edge
    at distance ``h`` and foot of the perpendicular at angle ``theta_0``,
    :math:`\int r\,dA = \frac{h^3}{3}\int \sec^3(\theta - \theta_0)\,d\theta`, integrated in
    closed form. All edges of all polygons at once.
    """
    corners = np.asarray(corners, dtype=np.float64).reshape(-1, 2)
    ptr = np.asarray(ptr, dtype=np.int64)
    m = len(ptr) - 1
    owner = np.repeat(np.arange(m), np.diff(ptr))
    nxt = np.arange(len(corners)) + 1
    nxt[ptr[1:] - 1] = ptr[:-1]  # the last corner of a polygon closes onto its first
    x, y = corners[:, 0], corners[:, 1]
    xn, yn = x[nxt], y[nxt]
    cross = x * yn - xn * y
    area = 0.5 * np.bincount(owner, cross, m)
    flat = np.flatnonzero(np.abs(area) <= 1e-300)
    if flat.size:
        raise ValueError(f"polygons {flat[:10].tolist()} have zero area (fewer than 3 corners?)")
    if points is None:
        with np.errstate(divide="ignore", invalid="ignore"):
            points = np.stack(
                [
                    np.bincount(owner, (x + xn) * cross, m),
                    np.bincount(owner, (y + yn) * cross, m),
                ],
                axis=1,
            ) / (6.0 * area[:, None])
    q0 = corners - points[owner]
    q1 = corners[nxt] - points[owner]
    d = q1 - q0
    length = np.hypot(d[:, 0], d[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        t = d / length[:, None]
        h = t[:, 1] * q0[:, 0] - t[:, 0] * q0[:, 1]  # signed distance of the edge line
        a0 = np.einsum("ij,ij->i", t, q0) / h
        a1 = np.einsum("ij,ij->i", t, q1) / h
        part = h**3 / 3.0 * (_sec3_antiderivative(a1) - _sec3_antiderivative(a0))
    part = np.where((length > 0.0) & (np.abs(h) >= 1e-300), part, 0.0)
    return np.abs(np.bincount(owner, part, m)) / np.abs(area)


def mean_distance_polygon(poly: np.ndarray, point: np.ndarray | None = None) -> float:
    """Mean distance of one convex polygon ``(k, 2)`` to ``point`` (default its centroid) [m];
    see :func:`mean_distance_polygons`."""
    poly = np.asarray(poly, dtype=np.float64).reshape(-1, 2)
    pts = None if point is None else np.asarray(point, dtype=np.float64).reshape(1, 2)
    return float(mean_distance_polygons(poly, np.array([0, len(poly)]), pts)[0])


def torsion_coefficient(interfaces: Interfaces) -> np.ndarray:
    r"""Torsion coefficient ``c_T`` of each interface under uniform pressure [m].

    :math:`c_T = \frac{1}{A}\int_A |y|\,dA` about the centroid, so that the pure-torsion
    strength of a uniformly pressed Coulomb interface is :math:`c_T \mu c` (seed 001, Eq. 11-12;
    Orduna and Lourenco 2005a).

    Returns
    -------
    (m,) float
    """
    _, y = interface_vertices(interfaces)
    return mean_distance_polygons(y, interfaces.poly_ptr)


def interface_rectangles(interfaces: Interfaces, rel_tol: float = 1e-6):
    """Sides and axes of rectangular interfaces (for the compressive-strength cone).

    Returns
    -------
    sides : (m, 2) float
        ``(l_u, l_v)`` [m].
    rot : (m, 2, 2) float
        Rows: the rectangle axes ``u, v`` in ``(t1, t2)`` components.

    Raises
    ------
    ValueError
        If an interface is not a rectangle.
    """
    _, y = interface_vertices(interfaces)
    m = interfaces.n_interfaces
    sides, rot = np.zeros((m, 2)), np.zeros((m, 2, 2))
    for k in range(m):
        poly = y[interfaces.poly_ptr[k] : interfaces.poly_ptr[k + 1]]
        d = np.roll(poly, -1, axis=0) - poly
        lengths = np.linalg.norm(d, axis=1)
        keep = lengths > rel_tol * lengths.max()
        d, lengths = d[keep], lengths[keep]
        if len(d) != 4:
            raise ValueError(f"interface {k} is not a rectangle ({len(d)} sides)")
        u = d[0] / lengths[0]
        v = np.array([-u[1], u[0]])
        lu, lv = lengths[0], lengths[1]
        if abs(d[1] @ u) > rel_tol * lengths.max() or abs(lengths[2] - lu) > rel_tol * lu:
            raise ValueError(f"interface {k} is not a rectangle")
        sides[k] = (lu, lv)
        rot[k] = np.stack([u, v])
    return sides, rot


def interface_friction(
    interfaces: Interfaces, block_mu: np.ndarray | None, mu: float | None
) -> np.ndarray:
    """Friction coefficient of each interface [-].

    ``mu`` (a number) overrides the scene; otherwise the smaller of the two blocks' values.
    ``inf`` means no sliding (the friction cone is dropped, see :mod:`limit.problems`).

    Raises
    ------
    ValueError
        If neither the scene nor ``mu`` gives a friction coefficient.
    """
    m = interfaces.n_interfaces
    if mu is not None:
        if math.isnan(mu) or mu < 0:
            raise ValueError(f"friction coefficient mu must be >= 0 (inf: no sliding), got {mu}")
        return np.full(m, float(mu))
    if block_mu is None:
        raise ValueError("no friction coefficient: the scene has none and settings.mu is None")
    return np.minimum(block_mu[interfaces.block_a], block_mu[interfaces.block_b])
