"""Files of a cross-check: VTU for ParaView and PNG pictures drawn off-screen.

Every 3D picture has an axes triad, a colour bar with its unit, a title that says what it
shows (which method, which state, which lambda) and, on request, the block numbers
(:class:`PictureOptions`). Every writer returns the path it wrote; a picture that cannot be
drawn (no OpenGL context, nothing to draw) is logged and left out rather than failing the
report.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dem.output import (
    block_polydata,
    finish_picture,
    interface_triangles,
    new_picture,
    scalar_bar,
    write_interfaces_vtu,
    write_scene_vtu,
)
from dem.scene import Scene
from fem_check.stress_output import write_vtu
from limit.mechanism import mechanism_arrays, mechanism_grid, write_mechanism
from validation.crosscheck.pushover import render_pushover
from validation.crosscheck.steps import Context, StepResult

logger = logging.getLogger(__name__)

MECHANISM_FRACTION = 0.15
"""Largest block motion in the mechanism picture, as a fraction of the structure's size [-]."""

AMBIENT = 0.35
"""Ambient light of the coloured surfaces, so that faces turned from the light keep their
colour-bar colour."""
STATES = ("elastic", "shear", "flexure", "shear + flexure", "detached", "crushed")
"""Categories of the joint-state picture (the static DEM's state bits: 1 shear, 2 flexure,
4 detached, 8 crushed)."""


@dataclass(frozen=True)
class PictureOptions:
    """What the pictures show beyond their defaults.

    Attributes
    ----------
    block_numbers : bool
        Write each block's number on it in the 3D pictures.
    pushover_tail : bool
        Draw the whole static DEM path, not only up to its collapse region.
    """

    block_numbers: bool = False
    pushover_tail: bool = False


def _interface_data(ctx: Context) -> dict[str, np.ndarray]:
    """Per-interface arrays of the DEM runs: state at the end, forces at the peak."""
    data = {}
    for name in ("dem-fibre", "dem-resultant"):
        res = ctx.ok(name)
        if res is None:
            continue
        law = name.split("-", 1)[1]
        data[f"state_{law}"] = np.asarray(res.payload.interface_state)
        data[f"forces_{law}"] = np.asarray(res.payload.interface_forces)
    return data


def write_vtus(scene: Scene, ctx: Context, out: Path) -> dict[str, str]:
    """scene.vtu, interfaces.vtu (DEM states and forces), mechanism.vtu, stress.vtu."""
    files = {"scene": write_scene_vtu(out / "scene.vtu", scene)}
    itf = scene.assembly.interfaces()
    if itf.n_interfaces:
        files["interfaces"] = write_interfaces_vtu(
            out / "interfaces.vtu", itf, _interface_data(ctx)
        )
    lim = ctx.ok("limit-vertex") or ctx.ok("limit-resultant")
    if lim is not None and lim.payload is not None:
        paths = write_mechanism(scene, lim.payload.associated, out / "mechanism")
        files["mechanism"], files["thrust"] = paths["vtu"], paths["thrust"]
    fem = ctx.ok("fem")
    if fem is not None and fem.payload is not None:
        files["stress"] = write_vtu(out / "stress.vtu", fem.payload)
    return {k: str(v) for k, v in files.items()}


def _labels(scene: Scene, options: PictureOptions, points: np.ndarray | None = None):
    """Where the block numbers go: the blocks' centroids (or ``points``), or None."""
    if not options.block_numbers:
        return None
    return scene.assembly.centroid if points is None else points


def mechanism_plotter(scene: Scene, lim: StepResult, options: PictureOptions):
    """A plotter of the collapse mechanism of the limit analysis, its title and the block
    numbers' points: blocks moved by it (exaggerated) over the structure at rest (grey wire),
    coloured by their speed relative to the fastest block; fixed blocks grey."""
    result = lim.payload.associated
    arrays = mechanism_arrays(scene, result, MECHANISM_FRACTION)
    moved = mechanism_grid(scene, result, MECHANISM_FRACTION)
    speed = moved.cell_data["speed"] / max(float(arrays["speed"].max()), 1e-300)
    moved.cell_data["relative speed"] = speed
    fixed = moved.cell_data["fixed"].astype(bool)
    plotter = new_picture()
    rest = mechanism_grid(scene, result, MECHANISM_FRACTION, displaced=False)
    plotter.add_mesh(rest, style="wireframe", color="grey", opacity=0.35)
    if fixed.any():
        plotter.add_mesh(moved.extract_cells(np.flatnonzero(fixed)), color="lightgrey")
    plotter.add_mesh(
        moved.extract_cells(np.flatnonzero(~fixed)),
        scalars="relative speed",
        clim=(0.0, 1.0),
        cmap="viridis",
        show_edges=True,
        ambient=AMBIENT,
        scalar_bar_args=scalar_bar("block speed / fastest block", "-"),
    )
    ptr, owner = arrays["face_ptr"], arrays["face_block"]
    corners = np.repeat(owner, np.diff(ptr))
    centres = np.array(
        [arrays["face_points"][corners == i].mean(axis=0) for i in range(scene.n_blocks)]
    )
    model = lim.name.split("-", 1)[1]
    title = (
        f"collapse mechanism, limit analysis ({model} model), upper bound lambda = "
        f"{lim.values['upper']:.4g}\nblock motion exaggerated (largest = "
        f"{MECHANISM_FRACTION:.0%} of the structure's size); grey wire: at rest"
    )
    return plotter, title, _labels(scene, options, centres)


def render_mechanism(scene: Scene, lim: StepResult, png: Path, options: PictureOptions) -> Path:
    """mechanism.png (see :func:`mechanism_plotter`)."""
    plotter, title, labels = mechanism_plotter(scene, lim, options)
    return finish_picture(plotter, png, title, labels)


def write_mechanism_view(
    scene: Scene, ctx: Context, path: Path, options: PictureOptions
) -> tuple[Path | None, str]:
    """``mechanism_3d.html``, the mechanism as an interactive vtk.js page, or (None, why not)."""
    from validation.crosscheck.html_report import write_mechanism_html

    lim = ctx.ok("limit-vertex") or ctx.ok("limit-resultant")
    if lim is None or lim.payload is None:
        return None, "the limit analysis found no collapse mechanism or did not run"
    try:
        plotter, _, _ = mechanism_plotter(scene, lim, options)
        plotter.add_axes(color="black")
        return write_mechanism_html(plotter, path), ""
    except Exception as exc:  # a view must never take the report down
        logger.warning("the interactive 3D view could not be written", exc_info=True)
        return None, f"its export failed ({type(exc).__name__}: {exc})"


def state_categories(state: np.ndarray) -> np.ndarray:
    """Index into :data:`STATES` of each joint's state bits (crushed wins, then detached)."""
    state = np.asarray(state, dtype=np.int64)
    out = np.minimum(state & 7, 4)
    out[state & 4 != 0] = 4
    out[state & 8 != 0] = 5
    return out


def render_interface_states(
    scene: Scene, dem: StepResult, png: Path, options: PictureOptions
) -> Path:
    """Blocks (translucent) and joints coloured by their state at the end of the static
    DEM path."""
    import pyvista as pv

    points, tris, owner = interface_triangles(scene.assembly.interfaces())
    faces = np.hstack([np.full((len(tris), 1), 3), tris]).ravel()
    joints = pv.PolyData(points, faces)
    joints.cell_data["state"] = state_categories(dem.payload.interface_state)[owner]
    plotter = new_picture()
    blocks = block_polydata(scene.assembly)
    plotter.add_mesh(blocks, color="lightgrey", opacity=0.25, show_edges=True)
    plotter.add_mesh(
        joints,
        scalars="state",
        clim=(-0.5, len(STATES) - 0.5),
        cmap="plasma",
        n_colors=len(STATES),
        annotations=dict(enumerate(STATES)),
        lighting=False,  # flat colours, as on the bar
        scalar_bar_args=scalar_bar("joint state", "category", n_labels=0, position_y=0.1),
    )
    law = dem.name.split("-", 1)[1]
    v = dem.values
    title = (
        f"joint states at the end of the static DEM path ({law} law)\n"
        f"lambda_max = {v['lambda_max']:.4g}, path ended by {v['termination']}"
    )
    return finish_picture(plotter, png, title, _labels(scene, options))


def render_stress(
    scene: Scene, fem: StepResult, vtu: str, png: Path, options: PictureOptions
) -> Path:
    """The FEM's largest principal stress over the blocks [MPa], at the DEM state it checked."""
    import pyvista as pv

    grid = pv.read(vtu)
    name = "max principal stress"
    grid.point_data[name] = np.asarray(grid.point_data["max_principal"]) / 1e6
    top = float(np.abs(grid.point_data[name]).max()) or 1.0
    plotter = new_picture()
    plotter.add_mesh(
        grid.extract_surface(algorithm="dataset_surface"),
        scalars=name,
        cmap="coolwarm",
        clim=(-top, top),
        ambient=AMBIENT,
        scalar_bar_args=scalar_bar(name + " (tension > 0)", "MPa"),
    )
    law, lam = fem.settings["state"].split("-", 1)[-1], fem.settings["lambda"]
    title = (
        "largest principal stress (FEM, elastic blocks) loaded by the joint forces\n"
        f"of the static DEM state ({law} law) at lambda = {lam:.4g}"
    )
    return finish_picture(plotter, png, title, _labels(scene, options))


def draw_pictures(
    scene: Scene, ctx: Context, out: Path, files: dict, options: PictureOptions | None = None
) -> dict[str, str]:
    """mechanism.png, interface_states.png, stress.png, pushover.png (those that apply)."""
    options = options or PictureOptions()
    jobs = {"pushover": lambda p: render_pushover(ctx, p, options.pushover_tail)}
    lim = ctx.ok("limit-vertex") or ctx.ok("limit-resultant")
    if lim is not None and lim.payload is not None:
        jobs["mechanism"] = lambda p: render_mechanism(scene, lim, p, options)
    dem = ctx.ok("dem-fibre") or ctx.ok("dem-resultant")
    if dem is not None:
        jobs["interface_states"] = lambda p: render_interface_states(scene, dem, p, options)
    fem = ctx.ok("fem")
    if "stress" in files and fem is not None:
        jobs["stress"] = lambda p: render_stress(scene, fem, files["stress"], p, options)
    pictures = {}
    for key, job in jobs.items():
        try:
            path = job(out / f"{key}.png")
        except Exception:  # a picture must never take the report down
            logger.warning("picture %s could not be drawn", key, exc_info=True)
            continue
        if path is not None:
            pictures[key] = str(path)
    return pictures
