"""The command lines: ``python -m validation crosscheck`` and the quiet ``validation all``."""

import logging
import os
import subprocess
import sys
import warnings

import matplotlib.image
import numpy as np

from dem.scenes import voussoir_arch
from validation.__main__ import main
from validation.crosscheck.cli import main as console_main
from validation.main_job import CaseSummary, run_all
from validation.report import Row


def test_crosscheck_command_line(tmp_path, capfd):
    scene = voussoir_arch(2.0, 0.2, 12, live_direction=None)
    path = tmp_path / "arch.json"
    scene.to_json(path)
    out = tmp_path / "report"
    code = main(["crosscheck", str(path), "--live", "x", "--out", str(out), "--quick"])
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


def test_validation_all_is_quiet_end_to_end(tmp_path):
    """The real entry point with one fast case, in a subprocess (descriptor-level noise)."""
    code = (
        "import sys, validation.__main__ as m;"
        "m.CASES = {k: v for k, v in m.CASES.items() if k == 'limit-closed-forms'};"
        "sys.exit(m.main(['all', '--quick']))"
    )
    env = {**os.environ, "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.strip().splitlines()
    assert lines[1].startswith("[1/1] limit-closed-forms ... ok")
    assert lines[-1].split()[0] == "limit-closed-forms" and lines[-1].split()[-1] == "no"
    assert done.stderr == ""
