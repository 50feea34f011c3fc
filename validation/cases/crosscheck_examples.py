"""Case `crosscheck-examples`: the cross-check on four scenes; the rows are its consistency checks.

Scenes:

- ``readme``: the README's pillar and lintel on a fixed ground, live load = weight along +x;
- ``orduna-3x13``: seed 001 Table 1's 3 x 13 dry-joint panel (:func:`dem.scenes.orduna_panel`),
  out-of-plane load proportional to weight;
- ``tis-3x3``: the seed 000 panel (3 x 3, theta = 5 deg, fixed frame) under a live load equal to
  the weight of each internal block, downwards (the seed loads it by an indenter instead);
- ``arch``: a semicircular voussoir arch from :func:`dem.scenes.voussoir_arch` (span 2 m,
  t = 0.2 m, 12 voussoirs; ``t / r = 0.2``, twice Milankovitch's least thickness), live load =
  weight along +x.

Every row is one line of a scene's verdict (:mod:`validation.crosscheck.verdict`): ``ours`` is
the checked value with the error bar its method gave (unknown where the method gives none),
``extra`` holds the bound it is compared with and the bound's bar, the outcome (pass, fail or
n/a) and why. There is no reference value: a check is an inequality between methods, not an
error. A failed line is a finding about a method (which one disagrees with the others, by how
much), not a failure of the case. Each scene's full report (``report.md``, ``report.json``;
VTU and PNG files are not committed) is written to
``validation/results/crosscheck-examples/<scene>/``. The quick run leaves out the explicit DEM
of the 3 x 13 panel (about 100 s; :func:`settings_for`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

from dem.estimate import Estimate
from dem.explicit import RigidContinuation
from dem.scene import Scene, proportional_to_weight
from dem.scenes import orduna_panel, tis_panel, voussoir_arch
from dem.scenes.running_bond_wall import box_corners
from validation.crosscheck import METHODS, CrosscheckResult, CrosscheckSettings, crosscheck
from validation.crosscheck.verdict import Check
from validation.report import Row, output_dir


def readme_scene() -> Scene:
    """The README's scene (ground, pillar, lintel; mu = 0.6), live load = weight along +x."""
    blocks = [
        box_corners(-1.0, 1.0, -1.0, 1.0, -0.2, 0.0),
        box_corners(-0.2, 0.2, -0.1, 0.1, 0.0, 0.6),
        box_corners(-0.3, 0.3, -0.1, 0.1, 0.6, 0.8),
    ]
    scene = Scene.from_convex_blocks(blocks, density=2000.0, fixed=[0], mu=0.6, name="readme")
    return scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))


def tis_scene() -> Scene:
    """The 3 x 3 TIS panel, live load = each internal block's weight downwards."""
    scene = tis_panel(3, 5.0)
    live = proportional_to_weight(scene.assembly, (0.0, 0.0, -1.0))
    live[scene.supports.fixed] = 0.0
    return Scene(scene.assembly, scene.supports, scene.loads, "tis-3x3", scene.meta).with_loads(
        live=live
    )


def scenes() -> dict[str, Scene]:
    arch = voussoir_arch(2.0, 0.2, 12)
    return {
        "readme": readme_scene(),
        "orduna-3x13": orduna_panel(3),
        "tis-3x3": tis_scene(),
        "arch": Scene(arch.assembly, arch.supports, arch.loads, "arch", arch.meta),
    }


def checked_value(check: Check) -> Estimate | None:
    """The value a check compares, with the half-width of its method's error bar (the
    sources are in the scene's ``report.json``); unknown where the method gives none."""
    if check.value is None:
        return None
    error = check.value_error
    if error is None or not math.isfinite(error):
        return Estimate.unknown(check.value, "the checked method gives no error bar")
    return Estimate(check.value, {"method's error bar": error})


def rows_of(key: str, result: CrosscheckResult) -> list[Row]:
    steps = {s.name: s.wall_s for s in result.steps}
    rows = []
    for c in result.checks:
        extra = {"outcome": c.status, "bound": c.bound, "bound_error": c.bound_error}
        rows.append(
            Row(
                f"{key}: {c.name}",
                checked_value(c),
                None,
                "consistency of the methods",
                steps.get(c.step),
                {"steps": [s.name for s in result.steps if s.ok]},
                {**extra, "detail": c.detail},
            )
        )
    return rows


def _step_table(results: dict[str, CrosscheckResult]) -> str:
    lines = ["| scene | step | status | wall [s] | note |", "|---|---|---|---|---|"]
    for key, res in results.items():
        for s in res.steps:
            lines.append(f"| {key} | {s.name} | {s.status} | {s.wall_s:.2f} | {s.reason[:160]} |")
    return "\n".join(lines)


def settings_for(key: str, quick: bool) -> CrosscheckSettings:
    """Every method; the quick run leaves out the explicit DEM of the 46-block panel (about
    100 s on a shared machine) and keeps the explicit DEM's error bar ("cheap" budget: one
    rerun at half the loading rate) and its continuation to rigid joints, without which its
    agreement with the rigid-block methods could not be judged."""
    if not quick:
        return CrosscheckSettings()
    methods = tuple(m for m in METHODS if not (key == "orduna-3x13" and m == "explicit"))
    settings = CrosscheckSettings.quick(methods=methods)
    explicit = replace(settings.explicit, error="cheap", continuation=RigidContinuation())
    return replace(settings, explicit=explicit)


def run(quick: bool = True, out_root: Path | None = None):
    out_root = output_dir() / "crosscheck-examples" if out_root is None else Path(out_root)
    results = {
        key: crosscheck(scene, settings_for(key, quick), out_root / key)
        for key, scene in scenes().items()
    }
    rows = [row for key, res in results.items() for row in rows_of(key, res)]
    verdicts = ", ".join(
        f"{k}: {'consistent' if r.consistent else 'inconsistent'}" for k, r in results.items()
    )
    failed = [f"{r.quantity}: {r.extra['detail']}" for r in rows if r.extra["outcome"] == "fail"]
    notes = (
        __doc__.split("\n\n", 1)[1]
        + f"\n\nVerdicts: {verdicts}.\n\n"
        + ("Failed checks:\n\n" + "\n".join(f"- {f}" for f in failed) + "\n\n" if failed else "")
        + "Steps (status, wall time, why skipped or failed):\n\n"
        + _step_table(results)
    )
    return rows, notes


CASES = {"crosscheck-examples": run}
MAIN_THREAD = ("crosscheck-examples",)  # the 3D view's export starts trame's server, whose
# event loop installs signal handlers: only a main thread may
