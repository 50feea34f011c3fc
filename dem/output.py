"""Scenes and results to files: VTU through meshio, pictures through pyvista (off-screen).

Blocks and interface polygons are written as triangles (fans of their convex faces) so every
VTK reader takes them; each triangle carries the id and the data of its block or interface.
"""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np

from dem.geometry.interfaces import Interfaces
from dem.scene import Assembly, Scene


def posed_vertices(
    assembly: Assembly, rotation: np.ndarray | None = None, centroid: np.ndarray | None = None
) -> np.ndarray:
    """(n_vert, 3) corners of all blocks [m], in ``assembly.arrays`` order, optionally moved.

    Parameters
    ----------
    assembly : Assembly
    rotation : (n_blocks, 3, 3) float, optional
        Rotation of each block from its reference pose.
    centroid : (n_blocks, 3) float, optional
        Current centroids [m] (default: the reference centroids).
    """
    arrays = assembly.arrays
    if rotation is None and centroid is None:
        return arrays.vertices.copy()
    n = assembly.n_blocks
    if rotation is not None and np.shape(rotation) != (n, 3, 3):
        raise ValueError(
            f"rotation must have shape {(n, 3, 3)} (one rotation matrix per block), got "
            f"{np.shape(rotation)}; for quaternions q (scalar first) pass "
            "scipy.spatial.transform.Rotation.from_quat(q, scalar_first=True).as_matrix()"
        )
    if centroid is not None and np.shape(centroid) != (n, 3):
        raise ValueError(f"centroid must have shape {(n, 3)} [m], got {np.shape(centroid)}")
    ref = assembly.centroid
    rot = np.broadcast_to(np.eye(3), (n, 3, 3)) if rotation is None else rotation
    cur = ref if centroid is None else centroid
    owner = np.repeat(np.arange(assembly.n_blocks), np.diff(arrays.vert_ptr))
    return np.einsum("pij,pj->pi", rot[owner], arrays.vertices - ref[owner]) + cur[owner]


def block_surface(
    assembly: Assembly, rotation: np.ndarray | None = None, centroid: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangulated block surfaces, optionally in moved poses (see :func:`posed_vertices`).

    Returns
    -------
    points : (p, 3) float
        [m].
    triangles : (t, 3) int64
    tri_block : (t,) int64
        Block of each triangle.
    """
    arrays = assembly.arrays
    points = posed_vertices(assembly, rotation, centroid)
    tris, owner_tri = [], []
    face_block = np.repeat(np.arange(assembly.n_blocks), np.diff(arrays.face_ptr))
    for f in range(len(arrays.face_offset)):
        corners = arrays.face_vert[arrays.face_vert_ptr[f] : arrays.face_vert_ptr[f + 1]]
        for i in range(1, len(corners) - 1):
            tris.append((corners[0], corners[i], corners[i + 1]))
            owner_tri.append(face_block[f])
    return points, np.array(tris, dtype=np.int64), np.array(owner_tri, dtype=np.int64)


def _cell_data(per_item: dict[str, np.ndarray], owner: np.ndarray, n_items: int) -> dict:
    out = {}
    for name, values in per_item.items():
        arr = np.asarray(values)
        if arr.shape[0] != n_items:
            raise ValueError(f"data {name!r} has {arr.shape[0]} rows, expected {n_items}")
        out[name] = [arr[owner]]
    return out


def write_scene_vtu(
    path: str | Path,
    scene: Scene,
    block_data: dict[str, np.ndarray] | None = None,
    rotation: np.ndarray | None = None,
    centroid: np.ndarray | None = None,
) -> Path:
    """Write the blocks as a VTU surface with per-block cell data.

    Always written: ``block`` (id), ``fixed`` (0/1), ``volume`` [m^3]; ``block_data`` adds
    arrays of shape (n_blocks,) or (n_blocks, k).
    """
    points, tris, owner = block_surface(scene.assembly, rotation, centroid)
    data = {
        "block": np.arange(scene.n_blocks),
        "fixed": scene.supports.fixed.astype(np.int64),
        "volume": scene.assembly.volume,
        **(block_data or {}),
    }
    mesh = meshio.Mesh(
        points, [("triangle", tris)], cell_data=_cell_data(data, owner, scene.n_blocks)
    )
    path = Path(path)
    mesh.write(path)
    return path


def interface_triangles(interfaces: Interfaces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fan triangles of the interface polygons: points (p, 3), triangles (t, 3), owner (t,)."""
    tris, owner = [], []
    for k in range(interfaces.n_interfaces):
        start, stop = interfaces.poly_ptr[k], interfaces.poly_ptr[k + 1]
        for i in range(start + 1, stop - 1):
            tris.append((start, i, i + 1))
            owner.append(k)
    triangles = np.array(tris, dtype=np.int64).reshape(-1, 3)
    return interfaces.poly_points, triangles, np.array(owner, dtype=np.int64)


def write_interfaces_vtu(
    path: str | Path, interfaces: Interfaces, interface_data: dict[str, np.ndarray] | None = None
) -> Path:
    """Write the interface polygons as a VTU with per-interface cell data.

    Always written: ``interface`` (id), ``block_a``, ``block_b``, ``area`` [m^2], ``normal``;
    ``interface_data`` adds arrays of shape (m,) or (m, k) (forces, states). Without
    interfaces (m = 0) the file has no cells but every array (VTK readers take it; meshio
    cannot read an empty VTU back).
    """
    points, tris, owner = interface_triangles(interfaces)
    data = {
        "interface": np.arange(interfaces.n_interfaces),
        "block_a": interfaces.block_a,
        "block_b": interfaces.block_b,
        "area": interfaces.area,
        "normal": interfaces.frame[:, 0, :],
        **(interface_data or {}),
    }
    cells = _cell_data(data, owner, interfaces.n_interfaces)
    mesh = meshio.Mesh(points, [("triangle", tris)], cell_data=cells)
    path = Path(path)
    mesh.write(path)
    return path


SCALAR_BAR = {
    "vertical": False,
    "position_x": 0.2,
    "position_y": 0.03,
    "width": 0.6,
    "height": 0.05,
    "fmt": "%.3g",
    "title_font_size": 16,
    "label_font_size": 14,
}
"""Colour bar of every 3D picture: along the bottom edge, clear of the title at the top."""


def scalar_bar(title: str, unit: str, **extra) -> dict:
    """``scalar_bar_args`` of a colour bar titled ``title [unit]``."""
    return {**SCALAR_BAR, "title": f"{title} [{unit}]", **extra}


def new_picture(window_size: tuple[int, int] = (1200, 900)):
    """An off-screen pyvista plotter on a white background."""
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    return plotter


def finish_picture(
    plotter,
    path: str | Path,
    title: str,
    labels: np.ndarray | None = None,
) -> Path:
    """Add the reader's aids and save: an x-y-z axes triad in the lower left corner, the
    title along the top edge (one or two lines) and, if ``labels`` (``(n_blocks, 3)``
    points [m]) is given, each block's number at its point; isometric view."""
    plotter.add_axes(color="black", line_width=3, viewport=(0.0, 0.0, 0.16, 0.22))
    if labels is not None:
        plotter.add_point_labels(
            np.asarray(labels, dtype=float),
            [str(i) for i in range(len(labels))],
            font_size=14,
            point_size=1,
            shape_opacity=0.6,
            always_visible=True,
        )
    plotter.add_text(title, position="upper_edge", font_size=11, color="black")
    plotter.view_isometric()
    plotter.camera.zoom(0.9)
    path = Path(path)
    plotter.screenshot(str(path))
    plotter.close()
    return path


def block_polydata(assembly: Assembly, points: np.ndarray | None = None):
    """The blocks' polygonal faces as one ``pyvista.PolyData`` with cell data ``block``."""
    import pyvista as pv

    arrays = assembly.arrays
    sizes = np.diff(arrays.face_vert_ptr)
    faces = np.insert(arrays.face_vert, arrays.face_vert_ptr[:-1], sizes)
    surface = pv.PolyData(arrays.vertices if points is None else points, faces)
    surface.cell_data["block"] = np.repeat(np.arange(assembly.n_blocks), np.diff(arrays.face_ptr))
    return surface


def render_scene(
    path: str | Path,
    scene: Scene,
    scalars: np.ndarray | None = None,
    scalar_name: str = "fixed",
    rotation: np.ndarray | None = None,
    centroid: np.ndarray | None = None,
    window_size: tuple[int, int] = (1200, 900),
    unit: str = "-",
    title: str | None = None,
    block_numbers: bool = False,
) -> Path:
    """Draw the blocks off-screen to a PNG, coloured by a per-block scalar (default: fixed),
    with an axes triad, a colour bar titled ``scalar_name [unit]``, a title (default: the
    scene's name) and, if asked, the block numbers."""
    points = posed_vertices(scene.assembly, rotation, centroid)
    surface = block_polydata(scene.assembly, points)
    values = scene.supports.fixed.astype(float) if scalars is None else np.asarray(scalars)
    if values.shape[0] != scene.n_blocks:
        raise ValueError(f"scalars must have one value per block ({scene.n_blocks})")
    surface.cell_data[scalar_name] = values[surface.cell_data["block"]]
    plotter = new_picture(window_size)
    plotter.add_mesh(
        surface,
        scalars=scalar_name,
        show_edges=True,
        cmap="viridis",
        scalar_bar_args=scalar_bar(scalar_name, unit),
    )
    owner = np.repeat(np.arange(scene.n_blocks), np.diff(scene.assembly.arrays.vert_ptr))
    labels = np.array([points[owner == i].mean(axis=0) for i in range(scene.n_blocks)])
    return finish_picture(
        plotter, path, scene.name if title is None else title, labels if block_numbers else None
    )
