"""The common end of the generic builders: free blocks on fixed supports, with a live load."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from dem.scene import Scene, proportional_to_weight


def on_supports(
    free: list[np.ndarray],
    supports: list[np.ndarray],
    density: float,
    mu: float | None,
    live_direction: Sequence[float] | None,
    name: str,
    meta: dict,
) -> Scene:
    """A scene of ``free`` blocks followed by fixed ``supports`` blocks.

    Parameters
    ----------
    free, supports : list of (k, 3) float
        Corners of the blocks [m]; the supports get the indices after the free blocks.
    density : float
        [kg/m^3].
    mu : float or None
        Friction coefficient [-].
    live_direction : (3,) float or None
        Live load: each free block's weight along this direction (None: none).
    name : str
    meta : dict
        The builder's parameters, for the record.
    """
    n = len(free)
    fixed = range(n, n + len(supports))
    scene = Scene.from_convex_blocks(free + supports, density, fixed=fixed, mu=mu, name=name)
    scene = Scene(scene.assembly, scene.supports, scene.loads, name, meta)
    if live_direction is None:
        return scene
    live = proportional_to_weight(scene.assembly, live_direction)
    live[n:] = 0.0  # the supports carry no live load
    return scene.with_loads(live=live)
