"""The command lines: ``python -m validation crosscheck`` and the quiet ``validation all``."""

import contextlib
import json
import logging
import os
import subprocess
import sys
import warnings

import matplotlib.image
import meshio
import numpy as np
import pytest

from dem.scenes import stack, voussoir_arch
from validation.__main__ import main
from validation.crosscheck.cli import main as console_main
from validation.main_job import CaseSummary, run_all
from validation.report import Row


def test_crosscheck_command_line(tmp_path, capfd):
    scene = voussoir_arch(2.0, 0.2, 12, live_direction=None)
    path = tmp_path / "arch.json"
    scene.to_json(path)
    out = tmp_path / "report"
    args = ["--live", "x", "--out", str(out), "--quick", "--methods", "dead,limit,dem,fem"]
    code = main(["crosscheck", str(path), *args])
    console = capfd.readouterr().out
    assert code == 0, console
    # one progress line per method, then the summary table and the verdict
    for step in ("dead-load", "limit-vertex", "dem-fibre", "dem-resultant", "fem"):
        assert f"{step}: " in console
    assert "verdict: consistent" in console and "step" in console and "wall [s]" in console
    assert "Warning" not in console and "optimal_inaccurate" not in console
    for name in ("pushover", "mechanism", "interface_states", "stress"):
        image = matplotlib.image.imread(out / f"{name}.png")
        assert image.ndim == 3 and min(image.shape[:2]) > 100
        assert np.ptp(image[..., :3]) > 0.2, f"{name}.png is blank"
    assert (out / "report.md").read_text().count("| pass |") >= 5
    assert (out / "crosscheck.log").exists()


def test_crosscheck_console_script_refuses_bad_input(tmp_path, capfd):
    missing = tmp_path / "cells.vtu"
    assert console_main([str(missing), "--out", str(tmp_path / "o")]) == 2
    assert "crosscheck:" in capfd.readouterr().err


def test_console_script_is_declared():
    text = open(os.path.join(os.path.dirname(__file__), "../../pyproject.toml")).read()
    assert 'blockmech-crosscheck = "validation.crosscheck.cli:main"' in text


def _noisy_case(name, quick):
    os.write(1, b"HiGHS banner straight to fd 1\n")
    os.write(2, b"numba build noise on fd 2\n")
    print("a print from a case")
    warnings.warn("a solver warning", UserWarning, stacklevel=1)
    logging.getLogger("limit.solve").warning("solver status optimal_inaccurate")
    if name == "broken":
        raise RuntimeError("this case fails")
    return [
        Row("closed form", 1.01, 1.0, "closed form"),
        Row("seed value", 0.8, 1.0, "seed 001 Table 1"),
        Row("other", 0.5, 0.5, "another method"),
    ]


def test_quiet_main_job(tmp_path, capfd):
    log = tmp_path / "validation.log"
    summaries = run_all(["first", "broken"], _noisy_case, True, log)
    console = capfd.readouterr()
    lines = console.out.splitlines()
    assert lines[1].startswith("[1/2] first ... ok, 3 rows")
    assert lines[2].startswith("[2/2] broken ... FAILED (RuntimeError")
    assert "worst numerical error" in console.out and "worst model error" in console.out
    for noise in ("HiGHS", "numba", "a print", "solver warning", "optimal_inaccurate"):
        assert noise not in console.out + console.err
        assert noise in log.read_text()
    assert "Traceback" in log.read_text()
    first, broken = summaries
    # numerical: |1.01 - 1| / 1 (closed form, other method); model: the seed table's 0.2
    assert np.isclose(first.worst_numerical, 0.01) and np.isclose(first.worst_model, 0.2)
    assert first.failed == "" and broken.failed == "RuntimeError"
    # descriptors and streams are restored
    print("after")
    assert capfd.readouterr().out == "after\n"


def test_case_summary_without_references():
    s = CaseSummary.of("c", [Row("no reference", 3.0)], 1.0)
    assert s.worst_numerical is None and s.worst_model is None and s.rows == 1
    assert s.no_bar == 1  # 3.0 came without an error bar


def test_case_summary_counts_references_outside_the_bar():
    from dem.estimate import Estimate

    rows = [
        Row("a", Estimate(1.0, {"grid": 0.01}), 1.1, "closed form"),
        Row("b", Estimate(1.0, {"grid": 0.01}), 1.1, "seed 001 Table 2"),
        Row("c", Estimate(1.0, {"grid": 0.2}), 1.1, "seed 001 Table 2"),
        Row("d", Estimate(1.0, {"grid": 0.01}, omitted=("time step",)), 1.1, "closed form"),
        Row("e", Estimate(1.0, {"grid": 0.01}), 1.1, "closed form", model_difference="approx."),
    ]
    s = CaseSummary.of("c", rows, 1.0)
    assert (s.outside_numerical, s.outside_model, s.outside_partial) == (1, 2, 1)
    assert s.no_bar == 0 and s.cells()[4] == "1/2/1"


def test_validation_all_is_quiet_end_to_end(tmp_path):
    """The real entry point in a subprocess (descriptor-level noise), with a fake case that
    solves a real limit-analysis problem and writes its files to a temporary folder."""
    code = f"""
import os, sys, warnings
from pathlib import Path
import validation.__main__ as m
import validation.catalogue as c
from dem.scenes import stack
from limit import limit_analysis
from validation.report import Row

def case(quick):
    os.write(1, b"solver banner on fd 1\\n")
    warnings.warn("a warning", UserWarning, stacklevel=1)
    lam = limit_analysis(stack(2, 0.4, 0.3, 0.5)).lam
    return [Row("overturning of a stack", lam, 0.4, "closed form b / (n h)")]

c.CASES.clear()
c.CASES["stack"] = case
m.results_dir = c.results_dir = lambda quick: Path({str(tmp_path)!r})
c.write_results = lambda *a, **k: (Path("x.json"), Path("x.md"))
sys.exit(m.main(["all", "--quick"]))
"""
    env = {**os.environ, "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.strip().splitlines()
    assert lines[1].startswith("[1/1] stack ... ok, 1 rows")
    (last,) = [line.split() for line in lines if line.split()[:1] == ["stack"]]
    assert last[-1] == "no" and float(last[2]) < 1e-6
    # then the folder's manifest, and its check (the stubbed writer left no stack.json)
    assert (tmp_path / "MANIFEST.json").exists() and lines[-1] == "stack: no results file"
    assert done.stderr == "" and "banner" not in done.stdout
    log = (tmp_path / "validation.log").read_text()
    assert "solver banner on fd 1" in log and "a warning" in log


def test_crosscheck_of_a_mesh_with_command_line_supports(tmp_path, capfd):
    """Two stacked hexahedra from a VTU (0.4 x 0.3 x 0.5 m each); density, friction, supports
    and live load from the options. The top cell overturns at b / h = 0.8 > mu: slides at 0.6."""
    corners = [(x, y, z) for z in (0.0, 0.5, 1.0) for y in (0.0, 0.3) for x in (0.0, 0.4)]
    points = np.array(corners)
    # meshio (VTK) hexahedron: bottom face counter-clockwise, then the top face
    hexes = [[0, 1, 3, 2, 4, 5, 7, 6], [4, 5, 7, 6, 8, 9, 11, 10]]
    path = tmp_path / "column.vtu"
    meshio.Mesh(points, [("hexahedron", np.array(hexes))]).write(path)
    out = tmp_path / "report"
    args = ["--density", "1500", "--mu", "0.6", "--fixed-below", "0.3", "--live", "x"]
    code = console_main(
        [str(path), *args, "--out", str(out), "--methods", "dead,limit", "--no-pictures"]
    )
    console = capfd.readouterr().out
    assert code == 0, console
    data = json.loads((out / "report.json").read_text())
    assert data["scene"]["n_blocks"] == 2 and data["scene"]["n_fixed"] == 1
    assert data["scene"]["live_weight_direction"] == [1.0, 0.0, 0.0]
    upper = next(s for s in data["steps"] if s["name"] == "limit-vertex")["values"]["upper"]
    np.testing.assert_allclose(upper, min(0.6, 0.4 / 0.5), rtol=1e-6)
    assert not list(out.glob("*.png"))


def test_a_negative_axis_after_live_is_a_direction_not_an_option(tmp_path, capfd):
    """``--live -x`` as the README writes it: the same column pushed along -x, same bound."""
    scene = stack(2, 0.4, 0.3, 0.5, mu=0.6)
    path = tmp_path / "stack.json"
    scene.to_json(path)
    out = tmp_path / "report"
    code = console_main(
        [str(path), "--live", "-x", "--out", str(out), "--methods", "dead,limit", "--no-pictures"]
    )
    assert code == 0, capfd.readouterr().out
    data = json.loads((out / "report.json").read_text())
    assert data["scene"]["live_weight_direction"] == [-1.0, 0.0, 0.0]
    assert main(["crosscheck", str(path), "--live", "-y", "--out", str(out),
                            "--methods", "dead", "--no-pictures"]) == 0  # fmt: skip
    data = json.loads((out / "report.json").read_text())
    assert data["scene"]["live_weight_direction"] == [0.0, -1.0, 0.0]
    capfd.readouterr()
    assert console_main([str(path), "--live", "-w", "--out", str(out)]) == 2
    assert "load direction must be x, y, z" in capfd.readouterr().err


def test_a_path_without_collapse_is_not_shown_as_lambda_max(tmp_path, capfd):
    """An arch pushed down by its own weight: the limit analysis finds no mechanism and the
    DEM paths end at max_steps (lambda about 700, scale-free dry joints). The summary table
    said 'lambda_max 743' for them; it now names the end of the path."""
    scene = voussoir_arch(2.0, 0.2, 12, live_direction=None)
    path = tmp_path / "arch.json"
    scene.to_json(path)
    args = ["--live", "-z", "--out", str(tmp_path / "r"), "--methods", "dead,limit,dem"]
    assert console_main([str(path), *args, "--no-pictures"]) == 0
    rows = [line for line in capfd.readouterr().out.splitlines() if line.startswith("dem-")]
    assert len(rows) == 2
    for row in rows:
        assert "no collapse" in row and "lambda_max" not in row, row


def test_a_live_load_without_mechanism_ends_with_a_summary(tmp_path, capfd):
    """A block pressed into the ground (--live -z): no mechanism. The command crashed after
    every step (the FEM step's largest tension None, divided for the summary) with rc 1, and
    the report passed "DEM ... law collapsed" (value inf) and checked a state at lambda = inf
    with no block solved, for a false reason (inf * 0 = nan read as a concentrated moment)."""
    path = tmp_path / "block.json"
    stack(1, 0.2, 0.2, 0.4, mu=0.6).to_json(path)
    out = tmp_path / "report"
    code = console_main([str(path), "--live", "-z", "--out", str(out), "--quick", "--no-pictures"])
    console = capfd.readouterr()
    assert code == 0, console.out + console.err  # nothing failed: README, exit codes
    assert "verdict: consistent" in console.out and "Traceback" not in console.err
    data = json.loads((out / "report.json").read_text())
    checks = {c["name"]: c for c in data["checks"]}
    for law in ("fibre", "resultant"):
        line = checks[f"DEM {law} law collapsed"]
        assert line["status"] == "n/a" and "no_mechanism" in line["detail"]
    fem = next(s for s in data["steps"] if s["name"] == "fem")
    assert fem["status"] == "skipped" and "no_mechanism" in fem["reason"]
    assert "concentrated moments" not in fem["reason"]
    md = (out / "report.md").read_text()
    assert "None MPa" not in md and "lambda = inf" not in md.split("## Steps")[0]


def test_an_output_folder_that_cannot_be_written_is_bad_usage(tmp_path, capfd):
    """README: rc 1 is a failed check, 2 unreadable input; --out on a file or under /proc
    gave a traceback and rc 1."""
    path = tmp_path / "block.json"
    stack(1, 0.2, 0.2, 0.4, mu=0.6).to_json(path)
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    for out, says in ((a_file, "is a file, not a folder"), ("/proc/nope", "/proc/nope")):
        assert console_main([str(path), "--live", "x", "--out", str(out), "--methods", "dead"]) == 2
        err = capfd.readouterr().err
        assert err.startswith("crosscheck: cannot write the output folder --out") and says in err
        assert len(err.strip().splitlines()) == 1
    assert a_file.read_text() == ""


def test_fixed_block_ids_that_are_not_integers_name_the_option(tmp_path, capfd):
    with pytest.raises(SystemExit) as stop:
        console_main([str(tmp_path / "x.json"), "--fixed", "0,a"])
    assert stop.value.code == 2
    err = capfd.readouterr().err
    assert "argument --fixed: block ids must be integers separated by commas, got '0,a'" in err
    assert "invalid literal" not in err


def test_a_negative_worker_count_is_refused_by_argparse(capfd):
    with pytest.raises(SystemExit) as stop:
        main(["run", "geometry", "--workers", "-1"])
    assert stop.value.code == 2
    assert "argument --workers: must be an integer >= 0" in capfd.readouterr().err


def test_a_scheduler_that_cannot_be_used_is_one_line_naming_it(monkeypatch, capfd):
    """No case runs: the address is refused by dask at once (bad usage, rc 2); a scheduler
    that does not answer is dask's OSError after its 20 s timeout, raised here (rc 1)."""
    assert main(["run", "geometry", "--scheduler", "notanaddress"]) == 2
    err = capfd.readouterr().err
    assert err == (
        "validation: cannot use the scheduler notanaddress: missing port number in address "
        "'notanaddress'\n"
    )

    @contextlib.contextmanager
    def unreachable(workers, scheduler):
        raise OSError(f"Timed out trying to connect to {scheduler} after 20 s")
        yield

    monkeypatch.setattr("validation.cluster.open_executor", unreachable)
    assert main(["run", "geometry", "--scheduler", "tcp://127.0.0.1:9"]) == 1
    err = capfd.readouterr().err
    assert err == (
        "validation: cannot use the scheduler tcp://127.0.0.1:9: Timed out trying to connect "
        "to tcp://127.0.0.1:9 after 20 s\n"
    )
