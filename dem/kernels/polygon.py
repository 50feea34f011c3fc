"""Convex polygons in a plane: clipping and area moments over plain arrays (numba).

Called once per candidate face pair when interfaces or contact patches are built, i.e. tens of
thousands of times for a large wall: in Python the array overhead of these few-corner polygons
dominated interface detection. The typed wrappers are in :mod:`dem.geometry.clipping`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def clip_polygon(subject, clip, tol):
    """Sutherland-Hodgman intersection of CCW convex polygons ``(n, 2)`` and ``(m, 2)``.

    A point within ``tol`` outside a clip edge counts as inside. Consecutive corners closer
    than ``max(tol, 1e-300)`` are merged. Returns the ``(k, 2)`` CCW corners (``k = 0`` when
    the intersection is empty).
    """
    n, m = subject.shape[0], clip.shape[0]
    size = n + m  # each half-plane cut adds at most one corner to a convex polygon
    cur = np.empty((size, 2))
    nxt = np.empty((size, 2))
    side = np.empty(size)
    cur[:n] = subject
    count = n
    for i in range(m):
        if count == 0:
            break
        px, py = clip[i, 0], clip[i, 1]
        ex, ey = clip[(i + 1) % m, 0] - px, clip[(i + 1) % m, 1] - py
        length = math.hypot(ex, ey)
        for j in range(count):
            # signed distance to the left of the edge (inside for a CCW polygon)
            side[j] = (ex * (cur[j, 1] - py) - ey * (cur[j, 0] - px)) / length
        out = 0
        for j in range(count):
            k = (j + 1) % count
            in_j = side[j] >= -tol
            if in_j:
                nxt[out] = cur[j]
                out += 1
            if in_j != (side[k] >= -tol):
                w = side[j] / (side[j] - side[k])
                nxt[out, 0] = cur[j, 0] + w * (cur[k, 0] - cur[j, 0])
                nxt[out, 1] = cur[j, 1] + w * (cur[k, 1] - cur[j, 1])
                out += 1
        cur, nxt = nxt, cur
        count = out
    if count < 2:
        return cur[:count].copy()
    gap = max(tol, 1e-300)
    keep = np.empty(count, dtype=np.bool_)
    kept = 0
    for j in range(count):
        k = (j + 1) % count
        keep[j] = math.hypot(cur[j, 0] - cur[k, 0], cur[j, 1] - cur[k, 1]) > gap
        kept += keep[j]
    res = np.empty((kept, 2))
    r = 0
    for j in range(count):
        if keep[j]:
            res[r] = cur[j]
            r += 1
    return res


@njit(cache=True)
def polygon_moments(poly):
    """Shoelace sums of a CCW polygon with corners shifted to the first one.

    Returns ``(area, cx, cy, ixx, iyy, ixy)``: the area, the centroid relative to
    ``poly[0]``, and the second moments ``int x^2, int y^2, int x y dA`` about ``poly[0]``.
    """
    n = poly.shape[0]
    ox, oy = poly[0, 0], poly[0, 1]
    area = cx = cy = ixx = iyy = ixy = 0.0
    for j in range(n):
        k = (j + 1) % n
        x, y = poly[j, 0] - ox, poly[j, 1] - oy
        xn, yn = poly[k, 0] - ox, poly[k, 1] - oy
        cr = x * yn - xn * y
        area += cr
        cx += (x + xn) * cr
        cy += (y + yn) * cr
        ixx += (x * x + x * xn + xn * xn) * cr
        iyy += (y * y + y * yn + yn * yn) * cr
        ixy += (x * yn + 2.0 * x * y + 2.0 * xn * yn + xn * y) * cr
    area /= 2.0
    if area > 0.0:
        cx /= 6.0 * area
        cy /= 6.0 * area
    return area, cx, cy, ixx / 12.0, iyy / 12.0, ixy / 24.0
