r"""A column of rectangular blocks on a fixed ground block (SI units).

Axes: x along the width, y along the depth, z up; the top of the ground is ``z = 0`` and block
``k`` (``k = 0`` at the bottom) spans ``k h <= z <= (k + 1) h``, shifted along x by
``offsets[k]``.

Closed forms (rigid blocks, no tension, friction ``mu``), for aligned blocks
(``offsets = 0``) of width ``b`` and height ``h`` under a live load equal to each block's
weight acting horizontally along +x:

- total volume ``n b d h``, centroid of the column at ``z = n h / 2``;
- the whole column overturns about the ground's edge at ``lambda = b / (n h)`` (moment of
  ``lambda W`` at ``n h / 2`` against ``W`` at ``b / 2``), and the top ``k`` blocks about their
  bed joint at ``b / (k h) >= b / (n h)``;
- a block slides at ``lambda = mu``;
- so the collapse multiplier of the associated rigid-block problem is
  ``min(b / (n h), mu)``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from dem.scene import Scene
from dem.scenes.running_bond_wall import box_corners
from dem.scenes.supported import on_supports


def stack(
    n_blocks: int,
    width: float,
    depth: float,
    height: float,
    density: float = 2000.0,
    mu: float | None = 0.6,
    offsets: Sequence[float] | None = None,
    live_direction: Sequence[float] | None = (1.0, 0.0, 0.0),
    name: str = "stack",
) -> Scene:
    """A column of ``n_blocks`` boxes on a fixed ground block (the last block).

    Parameters
    ----------
    n_blocks : int
        Blocks in the column, >= 1.
    width, depth, height : float
        Block size along x, y and z [m].
    density : float
        [kg/m^3].
    mu : float or None
        Friction coefficient [-].
    offsets : (n_blocks,) float, optional
        Shift of each block's centre along x [m] (a leaning or corbelled stack); default
        aligned.
    live_direction : (3,) float or None
        Live load: each block's weight along this direction (None: no live load).
    name : str

    Returns
    -------
    Scene
        Blocks ``0..n_blocks-1`` bottom to top, then the fixed ground
        (``3 width x 3 depth x height``, top at ``z = 0``).
    """
    if int(n_blocks) != n_blocks or n_blocks < 1:
        raise ValueError(f"n_blocks must be an integer >= 1, got {n_blocks!r}")
    for label, value in (("width", width), ("depth", depth), ("height", height)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{label} must be finite and positive [m], got {value!r}")
    shift = np.zeros(n_blocks) if offsets is None else np.asarray(offsets, dtype=float)
    if shift.shape != (n_blocks,) or not np.all(np.isfinite(shift)):
        raise ValueError(f"offsets must be {n_blocks} finite shifts [m], got {offsets!r}")
    blocks = [
        box_corners(
            s - width / 2, s + width / 2, -depth / 2, depth / 2, k * height, (k + 1) * height
        )
        for k, s in enumerate(shift)
    ]
    reach = width + float(np.abs(shift).max())
    ground = box_corners(-1.5 * reach, 1.5 * reach, -1.5 * depth, 1.5 * depth, -height, 0.0)
    meta = {
        "builder": "dem.scenes.stack",
        "n_blocks": int(n_blocks),
        "width": width,
        "depth": depth,
        "height": height,
        "offsets": shift.tolist(),
    }
    return on_supports(blocks, [ground], density, mu, live_direction, name, meta)
