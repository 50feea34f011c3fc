r"""Voussoir arches, semicircular or pointed, with radial joints (SI units).

Axes: x along the span, y along the arch's depth (mid-plane ``y = 0``), z up; the springings
lie on ``z = 0``, the centre line's springing points at ``x = -/+ span / 2``.

Geometry
--------
Each half of a pointed arch is a circular arc of the centre line of radius
``r = span / 2 + e`` about the centre ``(+/- e, 0)`` (the left half about ``x = +e``), where
``e = eccentricity * span / 2`` (``0``: semicircular, one centre; ``1``: equilateral arch, each
centre on the other springing). Intrados and extrados are the arcs of radii ``r -/+ t / 2``.
A voussoir spans the angles ``[phi_k, phi_{k+1}]`` about its centre; its joints are radial
(they pass through the centre), and its intrados and extrados faces are the chords of the
arcs, so each voussoir is a convex hexahedron. The crown joint of a pointed arch is the
vertical symmetry plane ``x = 0`` (a radial joint of one arc is not radial for the other).

The springings stand on two fixed abutment blocks, ``[x_s - t/2, x_s + t/2] x depth x
[-t, 0]``.

Closed forms
------------
- A voussoir spanning ``dphi`` about its centre has, with chord faces, the volume
  ``(r_e^2 - r_i^2) sin(dphi) / 2 * depth = r t sin(dphi) depth``; the voussoirs of a
  semicircular arch add up to ``n r t sin(pi / n) depth``, which tends to the ring's
  ``pi r t depth`` as ``n`` grows.
- Rise of the centre line: ``r`` (semicircular), ``sqrt(r^2 - e^2)`` (pointed).
- Least thickness of a semicircular arch under self weight, radial joints, no sliding:
  ``t / r = 0.1075`` (Milankovitch 1907; Heyman 1969 finds 0.106 with a simpler thrust
  line); with ``n`` voussoirs the hinges can form only at joints, which can only lower it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from dem.scene import Scene
from dem.scenes.running_bond_wall import box_corners
from dem.scenes.supported import on_supports

HEYMAN_T_OVER_R = 0.1075
"""Least thickness over centre-line radius of a semicircular arch (Milankovitch 1907)."""


def arc_joint_angles(n_voussoirs: int, eccentricity: float) -> np.ndarray:
    """Angles [rad] of the left half's joints about its centre, from the springing (pi).

    A semicircular arch (``eccentricity = 0``) returns all ``n + 1`` joint angles from ``pi``
    to ``0``; a pointed arch returns the ``n / 2 + 1`` angles of its left half, the last one
    where the centre line meets ``x = 0``.
    """
    if eccentricity == 0.0:
        return np.linspace(math.pi, 0.0, n_voussoirs + 1)
    r = 1.0 + eccentricity  # in units of span / 2
    top = math.acos(-eccentricity / r)
    return np.linspace(math.pi, top, n_voussoirs // 2 + 1)


def _point(centre_x: float, radius: float, phi: float) -> tuple[float, float]:
    return centre_x + radius * math.cos(phi), radius * math.sin(phi)


def _crown_point(centre_x: float, radius: float) -> tuple[float, float]:
    """Where the circle about ``(centre_x, 0)`` meets ``x = 0`` (upper half)."""
    return 0.0, math.sqrt(radius**2 - centre_x**2)


def _prism(section: list[tuple[float, float]], depth: float) -> np.ndarray:
    """(2 k, 3) corners of the prism of an xz-section over ``-depth/2 <= y <= depth/2``."""
    return np.array([(x, y, z) for x, z in section for y in (-depth / 2, depth / 2)])


def ring_sections(
    centre_x: float, radius: float, thickness: float, phis: np.ndarray
) -> list[list[tuple[float, float]]]:
    """xz-corners ``(intrados_0, extrados_0, extrados_1, intrados_1)`` of the voussoirs
    between consecutive radial joints at angles ``phis`` [rad] about ``(centre_x, 0)`` [m]."""
    ri, re = radius - thickness / 2, radius + thickness / 2
    return [
        [
            _point(centre_x, ri, a),
            _point(centre_x, re, a),
            _point(centre_x, re, b),
            _point(centre_x, ri, b),
        ]
        for a, b in zip(phis[:-1], phis[1:], strict=True)
    ]


def voussoir_sections(
    span: float, thickness: float, n_voussoirs: int, eccentricity: float = 0.0
) -> list[list[tuple[float, float]]]:
    """xz-corners ``(intrados_0, extrados_0, extrados_1, intrados_1)`` of every voussoir [m],
    from the left springing to the right one."""
    half = span / 2.0
    e = eccentricity * half
    r = half + e
    left = ring_sections(e, r, thickness, arc_joint_angles(n_voussoirs, eccentricity))
    if eccentricity == 0.0:
        return left
    # the crown joint is the plane x = 0, not the last radial joint
    left[-1][2] = _crown_point(e, r + thickness / 2)
    left[-1][3] = _crown_point(e, r - thickness / 2)
    right = [[(-x, z) for x, z in reversed(sec)] for sec in reversed(left)]
    return left + right


def voussoir_arch(
    span: float,
    thickness: float,
    n_voussoirs: int,
    depth: float | None = None,
    eccentricity: float = 0.0,
    density: float = 2000.0,
    mu: float | None = 0.6,
    live_direction: Sequence[float] | None = (1.0, 0.0, 0.0),
    name: str = "voussoir_arch",
) -> Scene:
    """A voussoir arch on two fixed abutments (module notes give the geometry).

    Parameters
    ----------
    span : float
        Distance between the springings of the centre line [m].
    thickness : float
        Radial thickness of the ring ``t`` [m], ``0 < t < span``.
    n_voussoirs : int
        Voussoirs in the arch, >= 2 (even for a pointed arch).
    depth : float, optional
        Extent along y [m]; default ``thickness``.
    eccentricity : float
        Offset of each half's centre from midspan over ``span / 2``, in ``[0, 1]``: 0
        semicircular, 1 equilateral pointed arch.
    density : float
        [kg/m^3].
    mu : float or None
        Friction coefficient [-].
    live_direction : (3,) float or None
        Live load: each voussoir's weight along this direction (None: none).
    name : str

    Returns
    -------
    Scene
        Voussoirs ``0..n-1`` from left to right, then the left and right abutments (fixed).
    """
    if int(n_voussoirs) != n_voussoirs or n_voussoirs < 2:
        raise ValueError(f"n_voussoirs must be an integer >= 2, got {n_voussoirs!r}")
    if not (math.isfinite(eccentricity) and 0.0 <= eccentricity <= 1.0):
        raise ValueError(f"eccentricity must lie in [0, 1], got {eccentricity!r}")
    if eccentricity > 0 and n_voussoirs % 2:
        raise ValueError(f"a pointed arch needs an even n_voussoirs, got {n_voussoirs}")
    if not (math.isfinite(span) and span > 0):
        raise ValueError(f"span must be finite and positive [m], got {span!r}")
    if not (math.isfinite(thickness) and 0 < thickness < span):
        raise ValueError(f"thickness must lie in (0, span) [m], got {thickness!r}")
    depth = thickness if depth is None else depth
    if not (math.isfinite(depth) and depth > 0):
        raise ValueError(f"depth must be finite and positive [m], got {depth!r}")
    sections = voussoir_sections(span, thickness, n_voussoirs, eccentricity)
    half, t = span / 2.0, thickness
    abutments = [
        box_corners(xs - t / 2, xs + t / 2, -depth / 2, depth / 2, -t, 0.0) for xs in (-half, half)
    ]
    meta = {
        "builder": "dem.scenes.arch",
        "span": span,
        "thickness": thickness,
        "n_voussoirs": int(n_voussoirs),
        "depth": depth,
        "eccentricity": eccentricity,
    }
    voussoirs = [_prism(sec, depth) for sec in sections]
    return on_supports(voussoirs, abutments, density, mu, live_direction, name, meta)
