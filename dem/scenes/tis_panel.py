"""Topologically interlocked slab: the Mirkhalaf-type panel of seed 000 (Sec. 3, Fig. 4).

Construction (derived from the seed's description, checked by tests):

- Panel ``size x size x t`` occupying ``[0, size]^2 x [0, t]``, z up; grid pitch
  ``l = size / (n + 1)``; block ``(i, j)``, ``i, j = 0..n+1``, has its bottom face centred at
  ``(i l, j l, 0)``. Blocks with ``1 <= i, j <= n`` are the ``n x n`` internal blocks.
- Every block has a square bottom face of side ``l``; its four lateral faces are planes
  inclined by ``theta`` from the vertical. With ``T = tan(theta)``, a block of type A
  (``i + j`` even) has its x faces leaning out, ``x = x_c +/- (l/2 + z T)``, and its y faces
  leaning in, ``y = y_c +/- (l/2 - z T)``; type B (``i + j`` odd) is A turned by 90 degrees.
  The section at height ``z`` is ``(l + 2 z T) x (l - 2 z T)`` (A), so one block has volume
  ``l^2 t - (4/3) T^2 t^3``.
- Neighbours are of opposite type, so the +x face of one and the -x face of the next lie in
  the same plane ``x = (i + 1/2) l + z T`` (or ``- z T``): every lateral interface is planar.
- Boundary blocks (``i`` or ``j`` in ``{0, n+1}``) are cut by the vertical planes of the box:
  halves along the edges, quarters at the corners. They are fixed (the stiff frame).
- At each of the ``(n + 1)^2`` grid vertices ``((i+1/2) l, (j+1/2) l)`` the four face planes
  form a pinwheel that leaves a void of square section, side ``2 z T`` at height ``z``:
  ``(4/3) T^2 t^3`` per vertex. The block volumes add up to ``size^2 t - (n+1)^2 (4/3) T^2 t^3``.
- A lateral interface is the narrower of the two touching faces: a trapezoid with parallel
  sides ``l`` (bottom) and ``l - 2 t T`` (top) and slant height ``t / cos(theta)``; area
  ``(l - t T) t / cos(theta)``. Interfaces between two boundary blocks on the same edge are
  cut in half by the box. There are ``2 (n+1)(n+2)`` lateral interfaces.
"""

from __future__ import annotations

import math

import numpy as np

from dem.geometry.polyhedron import ConvexBlock, clip_halfspace, convex_block
from dem.scene import Assembly, Loads, Scene, Supports, check_finite
from dem.units import MM

DENSITY_SEED_000 = 2.5e-6 / MM**3  # alumina-silicate, 2.5e-6 kg/mm^3 [kg/m^3]
MU_SEED_000 = 0.23


def tis_block_corners(
    centre_x: float, centre_y: float, side: float, thickness: float, theta: float, turned: bool
) -> np.ndarray:
    """(8, 3) corners of one full block [m]; ``turned`` gives type B (x faces leaning in)."""
    lean = thickness * math.tan(theta)
    half = side / 2.0
    top_x, top_y = (half - lean, half + lean) if turned else (half + lean, half - lean)
    corners = []
    for z, hx, hy in ((0.0, half, half), (thickness, top_x, top_y)):
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                corners.append((centre_x + sx * hx, centre_y + sy * hy, z))
    return np.array(corners)


def tis_panel(
    n: int,
    theta_deg: float,
    size_mm: float = 50.0,
    thickness_mm: float = 3.18,
    density: float = DENSITY_SEED_000,
    mu: float = MU_SEED_000,
    fix_boundary: bool = True,
) -> Scene:
    """The ``n x n`` TIS panel of seed 000 with half and quarter boundary blocks.

    Parameters
    ----------
    n : int
        Internal blocks per side (seed: 3, 5, 7).
    theta_deg : float
        Inclination of the lateral faces from the vertical [deg], ``0 <= theta < 90``.
    size_mm, thickness_mm : float
        Panel side and thickness [mm] (seed: 50 and 3.18).
    density : float
        [kg/m^3] (seed: 2500).
    mu : float
        Friction coefficient (seed: 0.23).
    fix_boundary : bool
        Fix the half and quarter blocks (the seed's frame).

    Returns
    -------
    Scene
        Blocks ordered row by row, ``index = j (n + 2) + i``; ``meta`` holds the grid position
        of each block and the paper-unit parameters.
    """
    size, t, theta, side = _checked_panel(n, theta_deg, size_mm, thickness_mm, density)
    blocks, grid = _panel_blocks(n, size, side, t, theta)
    grid_arr = np.array(grid)
    boundary = (grid_arr == 0).any(axis=1) | (grid_arr == n + 1).any(axis=1)
    assembly = Assembly(tuple(blocks), density, mu)
    supports = Supports.fixed_blocks(len(blocks), np.flatnonzero(boundary) if fix_boundary else [])
    meta = {
        "builder": "tis_panel",
        "n": n,
        "theta_deg": theta_deg,
        "size_mm": size_mm,
        "thickness_mm": thickness_mm,
        "side_mm": side / MM,
        "grid": grid_arr.tolist(),
        "central_block": int((n + 1) // 2 * (n + 2) + (n + 1) // 2),
    }
    return Scene(
        assembly, supports, Loads.gravity_only(len(blocks)), f"tis_{n}x{n}_{theta_deg:g}", meta
    )


def _checked_panel(n, theta_deg, size_mm, thickness_mm, density):
    """Panel size, thickness [m], inclination [rad] and block side [m], after a
    ``ValueError`` naming a number out of range or a theta so steep the top faces vanish."""
    check_finite(
        n=n, theta_deg=theta_deg, size_mm=size_mm, thickness_mm=thickness_mm, density=density
    )
    if int(n) != n or n < 1:
        raise ValueError(f"n (internal blocks per side) must be a positive integer, got {n}")
    if not 0.0 <= theta_deg < 90.0:
        raise ValueError(f"theta_deg must be in [0, 90), got {theta_deg}")
    if size_mm <= 0 or thickness_mm <= 0:
        raise ValueError(
            f"size_mm and thickness_mm must be positive, got {size_mm}, {thickness_mm}"
        )
    size, t, theta = size_mm * MM, thickness_mm * MM, math.radians(theta_deg)
    side = size / (n + 1)
    if 2 * t * math.tan(theta) >= side:
        raise ValueError(
            f"theta_deg={theta_deg} is too steep for blocks of side {side / MM:.3g} mm and "
            f"thickness {thickness_mm} mm: the top face would vanish (need 2 t tan(theta) < l)"
        )
    return size, t, theta, side


def _panel_blocks(n: int, size: float, side: float, t: float, theta: float):
    """The (n + 2)^2 blocks row by row (boundary blocks clipped to the panel's square of side
    ``size`` [m] into halves and quarters) and their grid positions (i, j)."""
    cuts = [
        (np.array([-1.0, 0, 0]), 0.0),
        (np.array([1.0, 0, 0]), size),
        (np.array([0, -1.0, 0]), 0.0),
        (np.array([0, 1.0, 0]), size),
    ]
    blocks: list[ConvexBlock] = []
    grid = []
    for j in range(n + 2):
        for i in range(n + 2):
            block = convex_block(
                tis_block_corners(i * side, j * side, side, t, theta, (i + j) % 2 == 1)
            )
            if i in (0, n + 1) or j in (0, n + 1):
                for normal, offset in cuts:
                    block = clip_halfspace(block, normal, offset)
            blocks.append(block)
            grid.append((i, j))
    return blocks, grid


def tis_void_volume(n: int, theta: float, thickness: float) -> float:
    """Total volume of the pinwheel voids, ``(n+1)^2 (4/3) tan^2(theta) t^3`` [m^3]."""
    return (n + 1) ** 2 * 4.0 / 3.0 * math.tan(theta) ** 2 * thickness**3


def tis_interface_area(side: float, theta: float, thickness: float) -> float:
    """Area of one full lateral interface, ``(l - t tan(theta)) t / cos(theta)`` [m^2]."""
    return (side - thickness * math.tan(theta)) * thickness / math.cos(theta)
