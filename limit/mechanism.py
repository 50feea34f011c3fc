r"""Collapse mechanism and forces at collapse: block motions, thrust points, VTU and pictures.

The multipliers of the equilibrium rows of the static programme are the block velocities of
the collapse mechanism (the kinematic dual, virtual work: :math:`\dot u^T(A_{eq} f + F_D +
\lambda F_L) = 0`). :class:`limit.solve.LimitResult` stores them normalised to unit live-load
power. Here they become displaced block geometry (rigid motion with the finite rotation
``exp([s omega]_x)`` for the picture) and, with the interface forces, the centres of pressure
of every compressed interface (the 3D thrust network).

``pyvista`` is imported lazily: only the writers and the renderer need it.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from dem.scene import Scene

logger = logging.getLogger(__name__)

__all__ = [
    "rotation_matrices",
    "displaced_vertices",
    "mechanism_scale",
    "thrust_points",
    "mechanism_arrays",
    "mechanism_grid",
    "write_mechanism",
    "render_mechanism",
]


def rotation_matrices(rotvec: np.ndarray) -> np.ndarray:
    """(k, 3, 3) rotation matrices of rotation vectors ``(k, 3)`` [rad] (Rodrigues)."""
    rotvec = np.atleast_2d(np.asarray(rotvec, dtype=float))
    theta = np.linalg.norm(rotvec, axis=1)
    out = np.tile(np.eye(3), (len(rotvec), 1, 1))
    nz = theta > 1e-15
    k = rotvec[nz] / theta[nz, None]
    kx = np.zeros((nz.sum(), 3, 3))
    kx[:, 0, 1], kx[:, 0, 2] = -k[:, 2], k[:, 1]
    kx[:, 1, 0], kx[:, 1, 2] = k[:, 2], -k[:, 0]
    kx[:, 2, 0], kx[:, 2, 1] = -k[:, 1], k[:, 0]
    s, c = np.sin(theta[nz])[:, None, None], np.cos(theta[nz])[:, None, None]
    out[nz] += s * kx + (1 - c) * kx @ kx
    return out


def mechanism_scale(scene: Scene, velocities: np.ndarray, fraction: float = 0.15) -> float:
    """Scale ``s`` so that the largest block-point displacement is ``fraction`` of the
    assembly size [s] (a picture scale; the mechanism's amplitude is arbitrary)."""
    pts = scene.assembly.arrays.vertices
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    biggest = 0.0
    for i, blk in enumerate(scene.assembly.blocks):
        u, w = velocities[i, :3], velocities[i, 3:]
        rel = blk.vertices - scene.assembly.centroid[i]
        v = u + np.cross(w, rel)
        biggest = max(biggest, float(np.max(np.linalg.norm(v, axis=1))))
    return fraction * size / biggest if biggest > 0 else 0.0


def displaced_vertices(scene: Scene, velocities: np.ndarray, scale: float) -> list[np.ndarray]:
    """Block corners after the rigid motion ``scale * (u, omega)`` (finite rotation).

    Parameters
    ----------
    scene : Scene
    velocities : (n_blocks, 6) float
        ``(u, omega)`` per block [m/s, rad/s].
    scale : float
        Pseudo-time [s].

    Returns
    -------
    list of (n_i, 3) float
        [m].
    """
    v = np.asarray(velocities, dtype=float) * scale
    rots = rotation_matrices(v[:, 3:])
    out = []
    for i, blk in enumerate(scene.assembly.blocks):
        c = scene.assembly.centroid[i]
        out.append(c + v[i, :3] + (blk.vertices - c) @ rots[i].T)
    return out


def thrust_points(scene: Scene, forces: np.ndarray, rel_tol: float = 1e-9) -> dict:
    r"""Centres of pressure of the compressed interfaces (the thrust network).

    The normal resultant :math:`c = -N` acts at :math:`y = (M_2, -M_1)/c` in the interface
    frame (:mod:`limit.matrices`).

    Parameters
    ----------
    scene : Scene
    forces : (m, 6) float
        Interface forces ``(N, V1, V2, M1, M2, M3)`` [N, N m].
    rel_tol : float
        Interfaces with ``c`` below ``rel_tol`` times the largest are left out.

    Returns
    -------
    dict
        ``interface`` (k,) int, ``point`` (k, 3) [m], ``compression`` (k,) [N],
        ``force`` (k, 3): the force that block a exerts on block b [N].
    """
    interfaces = scene.assembly.interfaces()
    f = np.asarray(forces, dtype=float)
    c = -f[:, 0]
    keep = np.flatnonzero(c > rel_tol * max(float(c.max(initial=0.0)), 1e-300))
    fr = interfaces.frame[keep]
    e1 = f[keep, 4] / c[keep]
    e2 = -f[keep, 3] / c[keep]
    point = interfaces.centroid[keep] + e1[:, None] * fr[:, 1] + e2[:, None] * fr[:, 2]
    force = -(
        f[keep, 0, None] * fr[:, 0] + f[keep, 1, None] * fr[:, 1] + f[keep, 2, None] * fr[:, 2]
    )
    return {"interface": keep, "point": point, "compression": c[keep], "force": force}


def mechanism_arrays(scene: Scene, result, fraction: float = 0.15) -> dict:
    """Plain arrays of the mechanism for an ``.npz`` file (figures read only these).

    Returns
    -------
    dict
        ``face_points`` (P, 3) displaced face corners, ``face_ptr`` (F + 1,), ``face_block``
        (F,), ``rest_points`` (P, 3) undisplaced corners, ``speed`` (n_blocks,) largest
        corner speed [m/s], ``fixed`` (n_blocks,) bool, ``velocities`` (n_blocks, 6),
        ``scale``, ``lam``, and the thrust points ``thrust_point`` (k, 3),
        ``thrust_compression`` (k,).
    """
    vel = result.velocities
    scale = mechanism_scale(scene, vel, fraction)
    moved = displaced_vertices(scene, vel, scale)
    pts, rest, ptr, owner = [], [], [0], []
    speed = np.zeros(scene.n_blocks)
    for i, blk in enumerate(scene.assembly.blocks):
        rel = blk.vertices - scene.assembly.centroid[i]
        speed[i] = float(np.max(np.linalg.norm(vel[i, :3] + np.cross(vel[i, 3:], rel), axis=1)))
        for face in blk.faces:
            pts.append(moved[i][face])
            rest.append(blk.vertices[face])
            ptr.append(ptr[-1] + len(face))
            owner.append(i)
    thrust = thrust_points(scene, result.interface_forces)
    return {
        "face_points": np.concatenate(pts),
        "rest_points": np.concatenate(rest),
        "face_ptr": np.array(ptr, dtype=np.int64),
        "face_block": np.array(owner, dtype=np.int64),
        "speed": speed,
        "fixed": scene.supports.fixed.copy(),
        "velocities": vel,
        "scale": scale,
        "lam": result.lam,
        "thrust_point": thrust["point"],
        "thrust_compression": thrust["compression"],
    }


def mechanism_grid(scene: Scene, result, fraction: float = 0.15, displaced: bool = True):
    """A ``pyvista.UnstructuredGrid`` of the blocks (polygonal faces) with cell data
    ``block``, ``speed`` [m/s], ``fixed``; displaced by the mechanism when asked."""
    import pyvista as pv

    arr = mechanism_arrays(scene, result, fraction)
    points = arr["face_points"] if displaced else arr["rest_points"]
    ptr = arr["face_ptr"]
    faces = np.concatenate(
        [np.r_[ptr[k + 1] - ptr[k], np.arange(ptr[k], ptr[k + 1])] for k in range(len(ptr) - 1)]
    )
    poly = pv.PolyData(points, faces=faces)
    poly.cell_data["block"] = arr["face_block"]
    poly.cell_data["speed"] = arr["speed"][arr["face_block"]]
    poly.cell_data["fixed"] = arr["fixed"][arr["face_block"]].astype(np.uint8)
    return poly.cast_to_unstructured_grid()


def write_mechanism(scene: Scene, result, path: str | Path, fraction: float = 0.15) -> dict:
    """Write ``<path>.vtu`` (displaced blocks), ``<path>_thrust.vtp`` (centres of pressure
    with their compression [N]) and ``<path>.npz`` (:func:`mechanism_arrays`).

    Returns
    -------
    dict
        The paths written.
    """
    import pyvista as pv

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    grid = mechanism_grid(scene, result, fraction)
    vtu = path.with_suffix(".vtu")
    grid.save(vtu)
    arr = mechanism_arrays(scene, result, fraction)
    cloud = pv.PolyData(arr["thrust_point"]) if len(arr["thrust_point"]) else pv.PolyData()
    if len(arr["thrust_point"]):
        cloud.point_data["compression"] = arr["thrust_compression"]
    vtp = path.with_name(path.stem + "_thrust.vtp")
    cloud.save(vtp)
    npz = path.with_suffix(".npz")
    np.savez_compressed(npz, **arr)
    return {"vtu": str(vtu), "thrust": str(vtp), "npz": str(npz)}


def render_mechanism(
    scene: Scene, result, png: str | Path, fraction: float = 0.15, window=(900, 700)
) -> str:
    """Render the mechanism off screen to ``png`` (pyvista; matplotlib if VTK cannot draw).

    Returns
    -------
    str
        The renderer used, ``"pyvista"`` or ``"matplotlib"``.
    """
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    try:
        import pyvista as pv

        grid = mechanism_grid(scene, result, fraction)
        plotter = pv.Plotter(off_screen=True, window_size=list(window))
        plotter.add_mesh(grid, scalars="speed", show_edges=True, cmap="viridis")
        plotter.view_isometric()
        plotter.screenshot(str(png))
        plotter.close()
        return "pyvista"
    except Exception as exc:  # no OpenGL context: fall back to a matplotlib drawing
        logger.info("pyvista rendering failed (%s); using matplotlib", exc)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    arr = mechanism_arrays(scene, result, fraction)
    ptr = arr["face_ptr"]
    polys = [arr["face_points"][ptr[k] : ptr[k + 1]] for k in range(len(ptr) - 1)]
    speed = arr["speed"][arr["face_block"]]
    fig = plt.figure(figsize=(window[0] / 100, window[1] / 100))
    ax = fig.add_subplot(projection="3d")
    col = Poly3DCollection(polys, cmap="viridis", edgecolor="k", linewidths=0.2)
    col.set_array(speed)
    ax.add_collection3d(col)
    allp = arr["face_points"]
    ax.auto_scale_xyz(allp[:, 0], allp[:, 1], allp[:, 2])
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return "matplotlib"
