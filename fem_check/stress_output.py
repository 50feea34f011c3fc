"""Recovered block stresses to VTU (meshio) and to off-screen pictures (pyvista).

Every block contributes its own corner nodes (stresses are not continuous across contacts), so
the VTU file holds the assembly as disjoint tetrahedral meshes with a ``block`` cell tag.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import meshio
import numpy as np

from fem_check.elastic import BlockSolution
from fem_check.recovery import principal_stresses, recover_nodal_stress, von_mises

log = logging.getLogger(__name__)

VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
"""Order of the six stress components written: xx, yy, zz, yz, xz, xy."""


@dataclass(frozen=True, eq=False)
class StressField:
    """Recovered stress of an assembly on disjoint block meshes (world frame).

    Attributes
    ----------
    points : (n, 3) float
        Mesh corners of all blocks [m].
    tets : (n_tets, 4) int64
        Corner indices into ``points``.
    block : (n_tets,) int64
        Block index of every tetrahedron.
    displacement : (n, 3) float
        [m].
    stress : (n, 3, 3) float
        Recovered (continuous P1 per block) stress [Pa].
    """

    points: np.ndarray
    tets: np.ndarray
    block: np.ndarray
    displacement: np.ndarray
    stress: np.ndarray

    @property
    def von_mises(self) -> np.ndarray:
        """(n,) [Pa]."""
        return von_mises(self.stress)

    @property
    def principal(self) -> np.ndarray:
        """(n, 3) principal stresses, most tensile first [Pa]."""
        return principal_stresses(self.stress)


def stress_field(
    solutions: Sequence[BlockSolution],
    block_ids: Sequence[int] | None = None,
    nodal: Sequence[np.ndarray] | None = None,
) -> StressField:
    """Gather the recovered stresses of solved blocks into one field.

    Parameters
    ----------
    solutions : sequence of BlockSolution
    block_ids : sequence of int, optional
        Block index of each solution (default ``0..``).
    nodal : sequence of (n_i, 3, 3) float, optional
        Already recovered nodal stresses (world frame) to reuse.
    """
    block_ids = list(range(len(solutions))) if block_ids is None else list(block_ids)
    pts, tets, tag, disp, sig = [], [], [], [], []
    offset = 0
    for k, (sol, i_block) in enumerate(zip(solutions, block_ids, strict=True)):
        p = sol.block_mesh.world_points()
        t = sol.operator.tet_mesh.tets
        pts.append(p)
        tets.append(t + offset)
        tag.append(np.full(len(t), i_block, dtype=np.int64))
        disp.append(sol.displacement_world())
        sig.append(recover_nodal_stress(sol) if nodal is None else nodal[k])
        offset += len(p)
    return StressField(
        np.concatenate(pts),
        np.concatenate(tets),
        np.concatenate(tag),
        np.concatenate(disp),
        np.concatenate(sig),
    )


def to_meshio(field: StressField) -> meshio.Mesh:
    """The field as a meshio mesh with point data (Voigt stress, invariants) and block tags."""
    voigt = np.stack([field.stress[:, i, j] for i, j in VOIGT], axis=1)
    pr = field.principal
    return meshio.Mesh(
        field.points,
        [("tetra", field.tets)],
        point_data={
            "displacement": field.displacement,
            "stress": voigt,
            "von_mises": field.von_mises,
            "principal": pr,
            "max_principal": pr[:, 0],
        },
        cell_data={"block": [field.block]},
    )


def write_vtu(path: str | Path, field: StressField) -> Path:
    """Write the field to a VTU file (binary) and return its path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write(path, to_meshio(field), binary=True)
    log.info("wrote %s (%d points)", path, len(field.points))
    return path


def render_png(
    vtu_path: str | Path,
    png_path: str | Path,
    scalar: str = "max_principal",
    scale: float = 1e-6,
    unit: str = "MPa",
    clim: tuple[float, float] | None = None,
    view: str = "iso",
    cmap: str = "coolwarm",
    title: str = "",
) -> Path:
    """Draw one scalar of a VTU file off-screen with pyvista and save a PNG.

    Parameters
    ----------
    vtu_path, png_path : path
    scalar : str
        Point data name.
    scale : float
        Factor applied to the scalar before drawing (1e-6: Pa to MPa).
    unit : str
        Colour-bar unit label.
    clim : (float, float), optional
        Colour range in drawn units (default: symmetric about zero for signed data).
    view : {"iso", "top", "bottom"}
    """
    import pyvista as pv

    pv.OFF_SCREEN = True
    grid = pv.read(str(vtu_path))
    data = np.asarray(grid.point_data[scalar]) * scale
    name = f"{scalar} [{unit}]"
    grid.point_data[name] = data
    if clim is None:
        top = float(np.abs(data).max()) or 1.0
        clim = (-top, top) if data.min() < 0 else (0.0, top)
    plotter = pv.Plotter(off_screen=True, window_size=(1200, 900))
    plotter.add_mesh(
        grid.extract_surface(algorithm="dataset_surface"),
        scalars=name,
        cmap=cmap,
        clim=clim,
        show_edges=False,
    )
    if view == "top":
        plotter.view_xy()
    elif view == "bottom":
        plotter.view_xy(negative=True)
    else:
        plotter.view_isometric()
    if title:
        plotter.add_text(title, font_size=10)
    png_path = Path(png_path)
    png_path.parent.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(png_path))
    plotter.close()
    return png_path
