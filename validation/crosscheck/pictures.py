"""Files of a cross-check: VTU for ParaView and PNG pictures drawn off-screen.

Every writer returns the path it wrote; a picture that cannot be drawn (no OpenGL context,
nothing to draw) is logged and left out rather than failing the report.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from dem.output import interface_triangles, write_interfaces_vtu, write_scene_vtu
from dem.scene import Scene
from fem_check.stress_output import render_png, write_vtu
from limit.mechanism import render_mechanism, write_mechanism
from validation.crosscheck.steps import Context

logger = logging.getLogger(__name__)

STATE_NAMES = "0 elastic, 1 shear, 2 flexure, 3 shear + flexure, 4 detached"


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


def render_interface_states(scene: Scene, state: np.ndarray, png: Path) -> Path:
    """Blocks (translucent) and interface polygons coloured by their DEM state."""
    import pyvista as pv

    points, tris, owner = interface_triangles(scene.assembly.interfaces())
    faces = np.hstack([np.full((len(tris), 1), 3), tris]).ravel()
    joints = pv.PolyData(points, faces)
    joints.cell_data["state"] = np.asarray(state)[owner]
    arrays = scene.assembly.arrays
    sizes = np.diff(arrays.face_vert_ptr)
    block_faces = np.insert(arrays.face_vert, arrays.face_vert_ptr[:-1], sizes)
    blocks = pv.PolyData(arrays.vertices, block_faces)
    plotter = pv.Plotter(off_screen=True, window_size=[1200, 900])
    plotter.add_mesh(blocks, color="lightgrey", opacity=0.25, show_edges=True)
    plotter.add_mesh(
        joints,
        scalars="state",
        clim=(0, 4),
        cmap="plasma",
        n_colors=5,
        scalar_bar_args={"title": f"state ({STATE_NAMES})"},
    )
    plotter.view_isometric()
    plotter.screenshot(str(png))
    plotter.close()
    return png


def render_pushover(ctx: Context, png: Path) -> Path | None:
    """The DEM pushover curves with the limit bounds and estimates drawn as horizontal lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves = [(n, ctx.ok(n)) for n in ("dem-fibre", "dem-resultant") if ctx.ok(n) is not None]
    limits = [(m, ctx.ok(f"limit-{m}")) for m in ("vertex", "resultant")]
    if not curves and not any(r for _, r in limits):
        return None
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for name, res in curves:
        c, lam = res.payload.pushover
        ax.plot(
            np.asarray(c) * 1e3,
            lam,
            marker=".",
            ms=3,
            label=f"{name} ({res.values['termination']})",
        )
    styles = {"upper": "-", "reduced_mu": ":", "iterative": "-.", "lower": "--"}
    colours = {"vertex": "tab:red", "resultant": "tab:green"}
    for model, res in limits:
        if res is None or not np.isfinite(res.values["upper"]):
            continue
        for key, ls in styles.items():
            val = res.values.get(key)
            if val is not None:
                ax.axhline(val, ls=ls, color=colours[model], lw=1.2, label=f"{key} ({model})")
    exp = ctx.ok("explicit")
    if exp is not None and exp.values["lambda_moving"] is not None:
        ax.axhspan(
            exp.values["lambda_stable"],
            exp.values["lambda_moving"],
            color="grey",
            alpha=0.2,
            label="explicit bracket"
            + ("" if exp.values["mechanism_confirmed"] else " (motion not confirmed)"),
        )
    ax.set_xlabel("control displacement (live-load weighted mean) [mm]")
    ax.set_ylabel("load multiplier lambda [-]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return png


def draw_pictures(scene: Scene, ctx: Context, out: Path, files: dict) -> dict[str, str]:
    """mechanism.png, interface_states.png, stress.png, pushover.png (those that apply)."""
    jobs = {"pushover": lambda p: render_pushover(ctx, p)}
    lim = ctx.ok("limit-vertex") or ctx.ok("limit-resultant")
    if lim is not None and lim.payload is not None:
        jobs["mechanism"] = lambda p: render_mechanism(scene, lim.payload.associated, p) and p
    dem = ctx.ok("dem-fibre") or ctx.ok("dem-resultant")
    if dem is not None:
        state = dem.payload.interface_state
        jobs["interface_states"] = lambda p: render_interface_states(scene, state, p)
    if "stress" in files:
        jobs["stress"] = lambda p: render_png(files["stress"], p, title="max principal stress")
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
