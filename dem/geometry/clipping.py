"""Convex polygons in a plane: exact clipping, area, centroid and second moments."""

from __future__ import annotations

import numpy as np

from dem.kernels.polygon import clip_polygon, polygon_moments


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
    subject = np.ascontiguousarray(subject, dtype=float).reshape(-1, 2)
    clip = np.ascontiguousarray(clip, dtype=float).reshape(-1, 2)
    return clip_polygon(subject, clip, float(tol))


def counter_clockwise(poly: np.ndarray) -> np.ndarray:
    """(k, 2) corners of a simple polygon, reversed if they run clockwise."""
    nxt = np.roll(poly, -1, axis=0)
    if (poly[:, 0] * nxt[:, 1] - poly[:, 1] * nxt[:, 0]).sum() < 0.0:
        return poly[::-1]
    return poly


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
    p = np.ascontiguousarray(poly, dtype=float).reshape(-1, 2)
    area, cx, cy, ixx, iyy, ixy = polygon_moments(p)
    if area <= 0.0:
        return 0.0, p.mean(axis=0), np.zeros(3)
    moments = np.array([ixx - area * cx * cx, iyy - area * cy * cy, ixy - area * cx * cy])
    return float(area), np.array([cx, cy]) + p[0], moments
