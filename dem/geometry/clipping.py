"""Convex polygons in a plane: exact clipping, area, centroid and second moments."""

from __future__ import annotations

import numpy as np


def clip_convex_polygons(subject: np.ndarray, clip: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """Intersection of two convex polygons (Sutherland-Hodgman).

    Parameters
    ----------
    subject, clip : (n, 2), (m, 2) float
        Counter-clockwise corners.
    tol : float
        A point within ``tol`` outside a clip edge counts as inside (same unit as the points).

    Returns
    -------
    (k, 2) float
        Counter-clockwise corners of the intersection; ``k = 0`` when it is empty.
    """
    out = np.asarray(subject, dtype=float)
    clip = np.asarray(clip, dtype=float)
    for i in range(len(clip)):
        if len(out) == 0:
            break
        p, q = clip[i], clip[(i + 1) % len(clip)]
        edge = q - p
        length = np.hypot(*edge)
        # signed distance to the left of the edge (inside for a CCW polygon)
        side = (edge[0] * (out[:, 1] - p[1]) - edge[1] * (out[:, 0] - p[0])) / length
        inside = side >= -tol
        nxt = np.roll(np.arange(len(out)), -1)
        pts = []
        for j in range(len(out)):
            k = nxt[j]
            if inside[j]:
                pts.append(out[j])
            if inside[j] != inside[k]:
                w = side[j] / (side[j] - side[k])
                pts.append(out[j] + w * (out[k] - out[j]))
        out = np.array(pts).reshape(-1, 2)
    return _drop_repeats(out, tol)


def _drop_repeats(poly: np.ndarray, tol: float) -> np.ndarray:
    if len(poly) < 2:
        return poly
    keep = np.linalg.norm(poly - np.roll(poly, -1, axis=0), axis=1) > max(tol, 1e-300)
    return poly[keep]


def polygon_properties(poly: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Area, centroid and second moments of a simple CCW polygon.

    Parameters
    ----------
    poly : (n, 2) float
        Corners, counter-clockwise [m].

    Returns
    -------
    area : float
        [m^2].
    centroid : (2,) float
        [m].
    second_moments : (3,) float
        ``(J11, J22, J12)`` = ``int y1^2, int y2^2, int y1 y2 dA`` about the centroid [m^4].

    Notes
    -----
    Green's theorem over the edges (shoelace sums); coordinates are shifted to the first
    corner to limit round-off.
    """
    p = np.asarray(poly, dtype=float)
    o = p[0]
    x, y = (p - o).T
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    area = cr.sum() / 2.0
    if area <= 0.0:
        return 0.0, p.mean(axis=0), np.zeros(3)
    cx = ((x + xn) * cr).sum() / (6.0 * area)
    cy = ((y + yn) * cr).sum() / (6.0 * area)
    ixx = ((x * x + x * xn + xn * xn) * cr).sum() / 12.0  # int x^2 dA
    iyy = ((y * y + y * yn + yn * yn) * cr).sum() / 12.0
    ixy = ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * cr).sum() / 24.0
    moments = np.array([ixx - area * cx * cx, iyy - area * cy * cy, ixy - area * cx * cy])
    return float(area), np.array([cx, cy]) + o, moments
