"""Tiny scenes with closed-form collapse multipliers for the limit-analysis tests, and the
seed 001 walls with their joints."""

import numpy as np

from dem.scene import Scene, proportional_to_weight


def box(lo, hi) -> np.ndarray:
    """(8, 3) corners of the axis-aligned box ``[lo, hi]`` [m]."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)], float)


GROUND = box((-2.0, -2.0, -1.0), (2.0, 2.0, 0.0))


def block_on_ground(width: float, depth: float, height: float, mu: float, density=2000.0):
    """One block ``width`` (along x) by ``depth`` by ``height`` on a fixed ground; live load
    = its weight along +x."""
    blk = box((-width / 2, -depth / 2, 0.0), (width / 2, depth / 2, height))
    scene = Scene.from_convex_blocks([GROUND, blk], density, fixed=[0], mu=mu)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def torsion_pair(l1=0.3, l2=0.2, height=0.2, weight=240.0, mu=0.7):
    """Seed 001 Sec. 2.1 interface: a block ``l1 x l2 x height`` of weight 240 N on a fixed
    block, live load a unit torque about the vertical axis."""
    density = weight / 9.81 / (l1 * l2 * height)
    blk = box((-l1 / 2, -l2 / 2, 0.0), (l1 / 2, l2 / 2, height))
    scene = Scene.from_convex_blocks([GROUND, blk], density, fixed=[0], mu=mu)
    live = np.zeros((2, 6))
    live[1, 5] = 1.0
    return scene.with_loads(live=live)


def harmonic_stack(n: int, length=1.0, height=0.2, depth=0.5, factor=1.0, mu=2.0):
    """``n`` blocks stacked with the harmonic overhangs ``factor * length / (2k)``.

    Block ``k`` from the top (k = 1..n) overhangs the block below it by
    ``factor * length / (2 k)`` along +x; the bottom block sits flush on the fixed ground
    edge at x = 0 (so the ground also acts as the n-th step). Total overhang
    ``factor * (length / 2) * H_n``. Live load: weights along +x (tiny pushes outward).
    """
    shifts = [factor * length / (2 * k) for k in range(1, n + 1)]  # top ... bottom
    # x of the right edge of each block, from the bottom: ground edge at 0
    right = []
    x = 0.0
    for k in range(n, 0, -1):
        x += shifts[k - 1]
        right.append(x)
    blocks = [box((-3.0, -depth, -height), (0.0, depth, 0.0))]
    for i, xr in enumerate(right):
        blocks.append(box((xr - length, -depth / 2, i * height), (xr, depth / 2, (i + 1) * height)))
    scene = Scene.from_convex_blocks(blocks, 1000.0, fixed=[0], mu=mu)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def pressed_block(width=0.4, depth=0.3, height=0.2, density=2000.0):
    """A block on the fixed ground pushed down by lambda times its weight (mu = 0.8): with
    unlimited compressive strength the ground carries any lambda."""
    blk = box((-width / 2, -depth / 2, 0.0), (width / 2, depth / 2, height))
    scene = Scene.from_convex_blocks([GROUND, blk], density, fixed=[0], mu=0.8)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (0.0, 0.0, -1.0)))


def tilted_block(width: float, height: float, theta: float, mu: float, depth=0.2, density=2000.0):
    """A ``width x depth x height`` block on a fixed ground tilted by ``theta`` [rad] about y
    (downhill towards -x); no live load. It stands iff ``tan(theta) <= mu`` (no sliding) and
    ``tan(theta) <= width / height`` (its centroid above the base: no toppling)."""
    c, s = np.cos(theta), np.sin(theta)
    rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
    blk = box((-width / 2, -depth / 2, 0.0), (width / 2, depth / 2, height))
    return Scene.from_convex_blocks([GROUND @ rot.T, blk @ rot.T], density, fixed=[0], mu=mu)


def seed_wall(key: str, model: str):
    """``(scene, settings)`` of a seed 001 specimen with its joints (mu, tensile strength)."""
    from dem.scenes.seed001_walls import SPECIMENS
    from limit.problems import LimitSettings

    spec = SPECIMENS[key]
    settings = LimitSettings(
        interface_model=model,
        mu=spec.joint.mu,
        tensile_strength=spec.joint.tensile_strength_mpa * 1e6,
    )
    return spec.build(), settings
