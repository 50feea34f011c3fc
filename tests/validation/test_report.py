"""The runner's writes: atomic and together, a failed or killed run leaves the previous
results whole, a dirty-tree flag beside the commit, warning filters that end with the case."""

import json
import os
import signal
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import validation.__main__ as cli
from validation.report import Row, output_dir, staged, write_results

REPO = Path(__file__).resolve().parents[2]


def _case(value: float, fail: bool = False, filters: bool = False):
    """A fake case: a side product in output_dir(), then one row (or an error)."""

    def run(quick: bool):
        np.savez(output_dir() / "fake.npz", value=np.array([value]))
        if filters:
            warnings.filterwarnings("ignore", message=".*leak.*")
        if fail:
            raise RuntimeError("the case failed half way")
        return [Row("x [-]", value, 1.0, "closed form")], "notes"

    return run


def _read(out: Path) -> tuple[float, float, str]:
    data = json.loads((out / "fake.json").read_text())
    return (
        data["rows"][0]["ours"],
        float(np.load(out / "fake.npz")["value"][0]),
        (out / "fake.md").read_text(),
    )


def test_results_and_side_products_are_written_together(tmp_path, monkeypatch):
    monkeypatch.setitem(cli.CASES, "fake", _case(1.0))
    cli.run_case("fake", quick=True, out_dir=tmp_path)
    ours, side, md = _read(tmp_path)
    assert ours == side == 1.0 and "| x [-] | 1 |" in md
    data = json.loads((tmp_path / "fake.json").read_text())
    assert list(data["side_products"]) == ["fake.npz"]
    assert len(data["side_products"]["fake.npz"]) == 64  # sha256 of the file moved with it
    assert not list(tmp_path.glob(".staging-*"))  # nothing left behind


def test_results_have_the_mode_of_every_other_output(tmp_path, monkeypatch):
    """CASE.json and CASE.md were written with mkstemp's 0600; the side product beside them
    (np.savez, an ordinary open) has 0666 less the umask."""
    monkeypatch.setitem(cli.CASES, "fake", _case(1.0))
    old = os.umask(0o022)
    try:
        cli.run_case("fake", quick=True, out_dir=tmp_path)
    finally:
        os.umask(old)
    side = (tmp_path / "fake.npz").stat().st_mode & 0o777
    assert side == 0o644
    for name in ("fake.json", "fake.md"):
        assert (tmp_path / name).stat().st_mode & 0o777 == side, name
    assert not list(tmp_path.glob(".fake.*.tmp"))


def test_a_failed_case_leaves_the_previous_results_whole(tmp_path, monkeypatch):
    monkeypatch.setitem(cli.CASES, "fake", _case(1.0))
    cli.run_case("fake", quick=True, out_dir=tmp_path)
    before = _read(tmp_path)
    monkeypatch.setitem(cli.CASES, "fake", _case(2.0, fail=True))
    with pytest.raises(RuntimeError, match="half way"):
        cli.run_case("fake", quick=True, out_dir=tmp_path)
    assert _read(tmp_path) == before  # the new .npz was written, but only in staging
    assert not list(tmp_path.glob(".staging-*"))


KILLED = """
import os, signal, sys
import numpy as np
from pathlib import Path
from validation.report import Row, output_dir, staged, write_results
out = Path(sys.argv[1])
with staged("fake", out) as stage:
    np.savez(output_dir() / "fake.npz", value=np.array([3.0]))
    write_results("fake", [Row("x [-]", 3.0)], quick=True, wall_s=0.0, out_dir=stage)
    os.kill(os.getpid(), signal.SIGKILL)  # killed before the files are moved into place
"""


def test_a_killed_run_leaves_the_previous_results_whole(tmp_path, monkeypatch):
    monkeypatch.setitem(cli.CASES, "fake", _case(1.0))
    cli.run_case("fake", quick=True, out_dir=tmp_path)
    before = _read(tmp_path)
    proc = subprocess.run([sys.executable, "-c", KILLED, str(tmp_path)], cwd=REPO, check=False)
    assert proc.returncode == -signal.SIGKILL
    assert _read(tmp_path) == before
    assert list(tmp_path.glob(".staging-fake-*"))  # the killed run's staging remains...
    cli.run_case("fake", quick=True, out_dir=tmp_path)
    assert not list(tmp_path.glob(".staging-*"))  # ...until the next run of the case


def test_warning_filters_of_a_case_do_not_leak(tmp_path, monkeypatch):
    monkeypatch.setitem(cli.CASES, "fake", _case(1.0, filters=True))
    before = list(warnings.filters)
    cli.run_case("fake", quick=True, out_dir=tmp_path)
    assert warnings.filters == before


def test_dirty_tree_flag(tmp_path, monkeypatch):
    import validation.report as report

    monkeypatch.setattr(report, "_git_dirty", lambda: (True, ["limit/solve.py"]))
    write_results("fake", [Row("x", 1.0)], quick=True, wall_s=0.0, out_dir=tmp_path)
    data = json.loads((tmp_path / "fake.json").read_text())
    assert data["git_dirty"] is True and data["git_dirty_files"] == ["limit/solve.py"]
    assert "(dirty tree)" in (tmp_path / "fake.md").read_text()
    monkeypatch.setattr(report, "_git_dirty", lambda: (False, []))
    write_results("fake", [Row("x", 1.0)], quick=True, wall_s=0.0, out_dir=tmp_path)
    assert json.loads((tmp_path / "fake.json").read_text())["git_dirty"] is False
    assert "dirty" not in (tmp_path / "fake.md").read_text()


def test_git_dirty_sees_a_source_change_but_not_results(tmp_path):
    """On a scratch repository: a changed source file makes the tree dirty, a changed file
    under validation/results does not."""
    import validation.report as report

    def git(*args):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "validation" / "results").mkdir(parents=True)
    (tmp_path / "src.py").write_text("a = 1\n")
    (tmp_path / "validation" / "results" / "x.json").write_text("{}\n")
    git("add", "-A")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "init")
    repo = report._REPO
    try:
        report._REPO = tmp_path
        assert report._git_dirty() == (False, [])
        (tmp_path / "validation" / "results" / "x.json").write_text('{"a": 1}\n')
        assert report._git_dirty() == (False, [])
        (tmp_path / "src.py").write_text("a = 2\n")
        assert report._git_dirty() == (True, ["src.py"])
    finally:
        report._REPO = repo


def test_staging_is_private_to_the_run(tmp_path):
    assert output_dir() != tmp_path
    with staged("fake", tmp_path) as stage:
        assert output_dir() == stage and stage.parent == tmp_path
        (stage / "sub").mkdir()
        (stage / "sub" / "a.txt").write_text("a")
    assert (tmp_path / "sub" / "a.txt").read_text() == "a"
    assert os.listdir(tmp_path) == ["sub"]
