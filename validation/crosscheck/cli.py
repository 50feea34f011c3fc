"""Command line of the cross-check.

``python -m validation crosscheck SCENE [--live x] [--out DIR] [--methods ...] [--quick]``, or
the console script ``blockmech-crosscheck`` with the same arguments. The terminal shows a
progress line per method (with a running clock on a terminal) and a summary table; solver
output and warnings go to ``DIR/crosscheck.log``.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import threading
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import TextIO

from dem.units import LENGTH_UNITS
from validation.crosscheck.pictures import PictureOptions
from validation.crosscheck.run import METHODS, CrosscheckResult, CrosscheckSettings, crosscheck
from validation.crosscheck.steps import Step, StepResult
from validation.quiet import quiet, table

SUMMARY_KEYS = ("upper", "lambda_max", "lambda_stable", "stands", "max_tension_Pa")
BAR = 20


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """The cross-check's arguments (shared by the subcommand and the console script)."""
    parser.add_argument(
        "scene", type=Path, help="scene JSON, volume mesh (.msh, .vtu, ...), OBJ/STL file or folder"
    )
    parser.add_argument(
        "--live",
        help="live load: every free block's weight along x, -x, y, "
        "-y, z or -z (replaces the scene's live load)",
    )
    parser.add_argument("--out", type=Path, help="output folder (default crosscheck-SCENE)")
    parser.add_argument(
        "--methods",
        default=",".join(METHODS),
        help=f"comma-separated subset of {','.join(METHODS)}",
    )
    parser.add_argument("--quick", action="store_true", help="fewer iterations, coarser FEM")
    parser.add_argument("--toml", type=Path, help="supports and loads (default SCENE.toml)")
    parser.add_argument("--density", type=float, help="block density [kg/m^3]")
    parser.add_argument("--mu", type=float, help="friction coefficient [-]")
    parser.add_argument("--fixed", type=block_ids, help="comma-separated ids of fixed blocks")
    parser.add_argument("--fixed-group", help="comma-separated named cell groups to fix")
    parser.add_argument(
        "--fixed-below",
        type=float,
        help="fix every block whose centroid lies below this z [--units, default m]",
    )
    parser.add_argument(
        "--units",
        choices=sorted(LENGTH_UNITS),
        help="length unit of the mesh or surface file and of the lengths given with it "
        "(default m; a scene that looks like mm read as m is refused without it)",
    )
    parser.add_argument("--no-pictures", action="store_true", help="write no PNG pictures")
    parser.add_argument(
        "--block-numbers", action="store_true", help="write the block numbers in the 3D pictures"
    )
    parser.add_argument(
        "--pushover-tail",
        action="store_true",
        help="draw the whole static DEM path (default: up to its collapse region)",
    )
    return parser


def block_ids(text: str) -> tuple[int, ...]:
    """``"0,3"`` as ``(0, 3)``; argparse names the option when it is not such a list."""
    try:
        return tuple(int(i) for i in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"block ids must be integers separated by commas, got {text!r}"
        ) from None


def join_signed_values(argv: Sequence[str]) -> list[str]:
    """``--live -y`` as ``--live=-y``: argparse takes a value that starts with ``-`` for an
    option of its own, so a negative axis after ``--live`` would be refused."""
    out: list[str] = []
    for arg in argv:
        # any "-<letter>" but -h, so that a wrong axis (-w) meets the direction's own error
        if out and out[-1] == "--live" and len(arg) == 2 and arg[1].isalpha() and arg != "-h":
            out[-1] = f"--live={arg}"
        else:
            out.append(arg)
    return out


def load_scene(args: argparse.Namespace):
    """The scene named on the command line, with the options' supports and loads."""
    from dem.scene_io import SceneSpec, read_scene

    spec = SceneSpec(
        density=args.density,
        mu=args.mu,
        fixed=args.fixed or (),
        fixed_below=args.fixed_below,
        fixed_groups=tuple(args.fixed_group.split(",")) if args.fixed_group else (),
        live=SceneSpec.direction(args.live) if args.live else None,
        units=args.units,
    )
    return read_scene(args.scene, spec, args.toml)


def check_usable(scene, fixed_below: float | None = None) -> None:
    """Refuse a scene no method can check: overlapping blocks, no supports, no free block.

    Raises
    ------
    ValueError
        One sentence naming what was found (an :class:`~dem.geometry.interfaces.OverlapError`
        names the pairs).
    """
    scene.assembly.interfaces()  # raises OverlapError (a ValueError) on overlapping blocks
    fixed = scene.supports.fixed
    if not fixed.any() and not scene.supports.restrained.any():
        units = scene.meta.get("units", "m")  # the user's lengths, as --fixed-below takes them
        z = scene.assembly.centroid[:, 2] / LENGTH_UNITS[units]
        below = "" if fixed_below is None else f" (--fixed-below {fixed_below:g} fixes none)"
        raise ValueError(
            f"no supports: no block is fixed and no dof restrained{below}; block centroids "
            f"lie at z = {z.min():.4g} .. {z.max():.4g} {units}. Fix blocks with --fixed, "
            "--fixed-below, --fixed-group or [supports] in the TOML"
        )
    if fixed.all():
        raise ValueError(f"every one of the {scene.n_blocks} blocks is fixed: nothing to check")


def read_input(args: argparse.Namespace):
    """The scene and the warnings raised while reading it (each message once).

    Raises
    ------
    ValueError, OSError
        Input no method can use (see :func:`check_usable`).
    """
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        scene = load_scene(args)
        check_usable(scene, args.fixed_below)
    messages = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in seen))
    meta = {**scene.meta, "warnings": messages}
    return dataclasses.replace(scene, meta=meta), messages


class Progress:
    """Prints ``[k/n] step ...`` when a step starts and its outcome when it ends; on a
    terminal a bar of the steps done and a running clock are redrawn every second."""

    def __init__(self, console: TextIO, n_steps: int):
        self.console, self.n, self.k = console, n_steps, 0
        self.tty = console.isatty()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def _bar(self) -> str:
        done = BAR * self.k // max(self.n, 1)
        return f"[{'#' * done}{'.' * (BAR - done)}] {self.k}/{self.n}"

    def _tick(self, step: Step, start: float):
        while not self._stop.wait(1.0):
            elapsed = time.perf_counter() - start
            self.console.write(f"\r{self._bar()} {step.name}: {step.method} ... {elapsed:.0f} s")

    def __call__(self, event: str, step: Step, result: StepResult | None):
        if event == "start":
            self.console.write(f"{self._bar()} {step.name}: {step.method} ... ")
            if self.tty:
                self._stop.clear()
                self._thread = threading.Thread(
                    target=self._tick, args=(step, time.perf_counter()), daemon=True
                )
                self._thread.start()
            return
        if self._thread is not None:
            self._stop.set()
            self._thread.join()
            self._thread = None
        self.k += 1
        note = f" ({result.reason})" if result.reason and result.status != "ok" else ""
        outcome = f"{result.status}, {result.wall_s:.1f} s{note}\n"
        if self.tty:  # redraw the whole line with the bar advanced
            self.console.write(f"\r{self._bar()} {step.name}: {outcome}")
        else:
            self.console.write(outcome)


def _main_value(res: StepResult):
    for key in SUMMARY_KEYS:
        if key in res.values:
            value = res.values[key]
            if key == "lambda_max" and res.values.get("collapsed") is False:
                # the end of a path, not a collapse multiplier
                key = f"lambda reached ({res.values['termination']}, no collapse)"
            return key, value / 1e6 if key.endswith("_Pa") and value is not None else value
    return "", None


def summary(result: CrosscheckResult) -> str:
    """Steps (status, main value, wall time), then the failed checks and the verdict."""
    rows = []
    for s in result.steps:
        key, value = _main_value(s)
        rows.append([s.name, s.status, key.replace("_Pa", " [MPa]"), value, round(s.wall_s, 2)])
    lines = [table(("step", "status", "quantity", "value", "wall [s]"), rows), ""]
    counts = {k: sum(c.status == k for c in result.checks) for k in ("pass", "fail", "n/a")}
    for c in result.checks:
        if c.status == "fail":
            lines.append(f"FAILED: {c.name}: {c.detail}")
    verdict = "consistent" if result.consistent else "INCONSISTENT"
    lines.append(
        f"verdict: {verdict} ({counts['pass']} pass, {counts['fail']} fail, "
        f"{counts['n/a']} not applicable)"
    )
    if "report_md" in result.files:
        lines.append(f"report: {result.files['report_md']}")
    return "\n".join(lines)


def settings_from(args: argparse.Namespace) -> CrosscheckSettings:
    methods = tuple(m.strip() for m in args.methods.split(",") if m.strip())
    pictures = PictureOptions(args.block_numbers, args.pushover_tail)
    kw = {"methods": methods, "pictures": False if args.no_pictures else pictures}
    return CrosscheckSettings.quick(**kw) if args.quick else CrosscheckSettings(**kw)


def run(args: argparse.Namespace) -> int:
    """Run a cross-check from parsed arguments; 0 if consistent, 1 if a check failed, 2 on
    bad input or an output folder that cannot be written."""
    out = args.out or Path(f"crosscheck-{args.scene.stem}")
    try:
        settings = settings_from(args)
        scene, messages = read_input(args)
    except (ValueError, OSError) as exc:
        print(f"crosscheck: {_one_line(exc)}", file=sys.stderr)
        return 2
    for message in messages:
        print(f"crosscheck: warning: {_one_line(message)}", file=sys.stderr)
    log = out / "crosscheck.log"
    try:
        if out.exists() and not out.is_dir():
            raise NotADirectoryError(f"{out} is a file, not a folder")
        out.mkdir(parents=True, exist_ok=True)
        log.touch()
    except OSError as exc:
        print(f"crosscheck: cannot write the output folder --out {out}: {exc}", file=sys.stderr)
        return 2
    with quiet(log) as console:
        console.write(f"{scene.name}: {scene.n_blocks} blocks -> {out}\n")
        progress = Progress(console, len(settings.steps()))
        result = crosscheck(scene, settings, out, progress)
        console.write("\n" + summary(result) + f"\ntotal {result.wall_s:.1f} s\n")
    return 0 if result.consistent else 1


def _one_line(message) -> str:
    return " ".join(str(message).split())


def main(argv: list[str] | None = None) -> int:
    """Console script ``blockmech-crosscheck``."""
    parser = add_arguments(
        argparse.ArgumentParser(prog="blockmech-crosscheck", description=__doc__.splitlines()[0])
    )
    return run(parser.parse_args(join_signed_values(sys.argv[1:] if argv is None else argv)))


if __name__ == "__main__":
    sys.exit(main())
