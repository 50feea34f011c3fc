r"""A strip of a semicircular barrel vault: rings of voussoirs side by side (SI units).

Axes as in :mod:`dem.scenes.arch`: x along the span, z up, and y along the vault's axis. Ring
``j`` spans ``j w <= y <= (j + 1) w`` (``w`` the ring width). Its voussoirs have radial joints
about the centre ``(0, 0)``; with ``bond=True`` every odd ring is shifted by half a voussoir,
so it has ``n - 1`` full voussoirs and a half one at each springing (stretcher bond along the
axis). Every ring stands on the same two fixed abutments (the length of the strip).

Closed forms
------------
- Interfaces between two neighbouring rings: ``n`` (stack bond) or ``2 n`` (bond: every
  joint of one ring falls inside a voussoir of the other, so ``n + (n + 1) - 1`` overlaps).
- Voussoir volume with chord faces: ``r t sin(dphi) w`` (:mod:`dem.scenes.arch`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from dem.scene import Scene
from dem.scenes.arch import ring_sections
from dem.scenes.running_bond_wall import box_corners
from dem.scenes.supported import on_supports


def ring_joint_angles(n_voussoirs: int, shifted: bool) -> np.ndarray:
    """Joint angles [rad] of one ring from ``pi`` to ``0``; ``shifted`` by half a voussoir."""
    step = math.pi / n_voussoirs
    if not shifted:
        return np.linspace(math.pi, 0.0, n_voussoirs + 1)
    inner = math.pi - step / 2 - step * np.arange(n_voussoirs)
    return np.concatenate([[math.pi], inner, [0.0]])


def barrel_vault(
    span: float,
    thickness: float,
    n_voussoirs: int,
    n_rings: int,
    ring_width: float,
    bond: bool = True,
    density: float = 2000.0,
    mu: float | None = 0.6,
    live_direction: Sequence[float] | None = (1.0, 0.0, 0.0),
    name: str = "barrel_vault",
) -> Scene:
    """A strip of ``n_rings`` voussoir rings of a semicircular barrel vault.

    Parameters
    ----------
    span : float
        Distance between the springings of the centre line [m].
    thickness : float
        Radial thickness [m], ``0 < thickness < span``.
    n_voussoirs : int
        Voussoirs of an unshifted ring, >= 2.
    n_rings : int
        Rings along the axis, >= 1.
    ring_width : float
        Extent of a ring along y [m].
    bond : bool
        Shift every odd ring by half a voussoir.
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
        The voussoirs ring by ring (left to right within a ring), then the left and right
        abutments (fixed).
    """
    for label, value in (("n_voussoirs", n_voussoirs), ("n_rings", n_rings)):
        low = 2 if label == "n_voussoirs" else 1
        if int(value) != value or value < low:
            raise ValueError(f"{label} must be an integer >= {low}, got {value!r}")
    if not (math.isfinite(span) and span > 0 and 0 < thickness < span):
        raise ValueError(f"need span > 0 and 0 < thickness < span [m], got {span}, {thickness}")
    if not (math.isfinite(ring_width) and ring_width > 0):
        raise ValueError(f"ring_width must be finite and positive [m], got {ring_width!r}")
    radius = span / 2.0
    blocks = []
    for j in range(n_rings):
        phis = ring_joint_angles(n_voussoirs, shifted=bond and j % 2 == 1)
        for sec in ring_sections(0.0, radius, thickness, phis):
            y0, y1 = j * ring_width, (j + 1) * ring_width
            blocks.append(np.array([(x, y, z) for x, z in sec for y in (y0, y1)]))
    length = n_rings * ring_width
    abutments = [
        box_corners(xs - thickness / 2, xs + thickness / 2, 0.0, length, -thickness, 0.0)
        for xs in (-radius, radius)
    ]
    meta = {
        "builder": "dem.scenes.vault",
        "span": span,
        "thickness": thickness,
        "n_voussoirs": int(n_voussoirs),
        "n_rings": int(n_rings),
        "ring_width": ring_width,
        "bond": bond,
    }
    return on_supports(blocks, abutments, density, mu, live_direction, name, meta)
