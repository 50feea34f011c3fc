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
from validation.report import STAGING_PREFIX, Row, output_dir, staged, write_results

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
    assert ours == side == 1.0 and "| x [-] | 1 ± ? |" in md  # no error given: unknown
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
    import validation.provenance as provenance

    monkeypatch.setattr(provenance, "git_dirty", lambda: (True, ["limit/solve.py"]))
    write_results("fake", [Row("x", 1.0)], quick=True, wall_s=0.0, out_dir=tmp_path)
    data = json.loads((tmp_path / "fake.json").read_text())
    assert data["git_clean"] is False and data["git_dirty_files"] == ["limit/solve.py"]
    assert "(dirty tree)" in (tmp_path / "fake.md").read_text()
    monkeypatch.setattr(provenance, "git_dirty", lambda: (False, []))
    write_results("fake", [Row("x", 1.0)], quick=True, wall_s=0.0, out_dir=tmp_path)
    assert json.loads((tmp_path / "fake.json").read_text())["git_clean"] is True
    assert "dirty" not in (tmp_path / "fake.md").read_text()


def test_git_dirty_sees_a_source_change_but_not_results(tmp_path):
    """On a scratch repository: a changed source file makes the tree dirty, a changed file
    under validation/results does not."""
    from validation.provenance import git_dirty

    def git(*args):
        subprocess.run(["git", *args], cwd=tmp_path, check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "validation" / "results").mkdir(parents=True)
    (tmp_path / "src.py").write_text("a = 1\n")
    (tmp_path / "validation" / "results" / "x.json").write_text("{}\n")
    git("add", "-A")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "init")
    assert git_dirty(tmp_path) == (False, [])
    (tmp_path / "validation" / "results" / "x.json").write_text('{"a": 1}\n')
    assert git_dirty(tmp_path) == (False, [])
    (tmp_path / "src.py").write_text("a = 2\n")
    assert git_dirty(tmp_path) == (True, ["src.py"])


def test_staging_is_private_to_the_run(tmp_path):
    assert output_dir() != tmp_path
    with staged("fake", tmp_path) as stage:
        assert output_dir() == stage and stage.parent == tmp_path
        (stage / "sub").mkdir()
        (stage / "sub" / "a.txt").write_text("a")
    assert (tmp_path / "sub" / "a.txt").read_text() == "a"
    assert os.listdir(tmp_path) == ["sub"]


def test_a_case_clears_only_its_own_stale_staging(tmp_path):
    """A case whose name starts another's ("tis-friction", "tis-friction-uq") removes its own
    killed run's staging directory, not the other case's live one."""
    other = tmp_path / f"{STAGING_PREFIX}fake-uq-4242"
    other.mkdir()
    (other / "runs.jsonl").write_text("{}\n")
    killed = tmp_path / f"{STAGING_PREFIX}fake-4343"
    killed.mkdir()
    with staged("fake", tmp_path):
        assert (other / "runs.jsonl").exists() and not killed.exists()


# -- rows with error bars ----------------------------------------------------------------------
def test_a_row_takes_an_estimate_and_writes_its_bar(tmp_path):
    from dem.estimate import Estimate

    est = Estimate(0.284312, {"load step": 0.0008, "end of path": 0.0004}, notes="two levels")
    row = Row("arch lambda [-]", est, 0.2843, "limit analysis")
    assert row.ours == 0.284312 and np.isclose(row.ours_error, 0.0012)
    assert row.reference_inside is True and row.error_kind is None
    write_results("fake", [row], quick=True, wall_s=0.0, out_dir=tmp_path)
    data = json.loads((tmp_path / "fake.json").read_text())["rows"][0]
    assert np.isclose(data["ours_error"], 0.0012)
    assert data["error_sources"] == {"load step": 0.0008, "end of path": 0.0004}
    assert data["error_notes"] == "two levels" and data["reference_inside"] is True
    # the error 0.0012 supports 4 decimals: 0.2843 ± 0.0012
    assert "| arch lambda [-] | 0.2843 ± 0.0012 | 0.2843 |" in (tmp_path / "fake.md").read_text()


def test_a_reference_outside_the_bar_says_which_error_it_is():
    """Outside the bar, a seed's table or experiment is a model error, a closed form or
    another method is a numerical one; an unknown bar says nothing."""
    from dem.estimate import Estimate

    seed = Row("S15 lambda [-]", Estimate(0.30, {"grid": 0.01}), 0.35, "seed 001 Table 2")
    closed = Row("tipping [-]", Estimate(0.30, {"grid": 0.01}), 0.35, "closed form b/h")
    exact = Row("count [-]", Estimate(4.0, {"exact": 0.0}), 4.0, "exact count")
    unknown = Row("no bar [-]", 0.30, 0.35, "closed form b/h")
    assert (seed.reference_inside, seed.error_kind) == (False, "model")
    assert (closed.reference_inside, closed.error_kind) == (False, "numerical")
    assert (exact.reference_inside, exact.ours_error) == (True, 0.0)
    assert unknown.ours_error == np.inf and unknown.error_sources == {"not estimated": np.inf}
    assert unknown.reference_inside is None and unknown.error_kind is None
    assert Row("n/a", None).ours_error is None and Row("n/a", None).error_sources == {}


def test_a_bound_reference_is_an_inequality():
    """A DEM multiplier far below an upper bound agrees with it (an equality test would call
    it outside); one above it by more than both bars breaks it, and the table says on which
    side of the bound ours lies."""
    from dem.estimate import Estimate
    from validation.report import _inside_cell

    def upper(value, bar, bound, bound_bar=0.0):
        return Row("lambda [-]", Estimate(value, {"step": bar}), bound, "limit analysis",
                   reference_kind="upper bound", reference_error=bound_bar)  # fmt: skip

    assert upper(0.39, 0.001, 0.79).reference_inside is True
    assert _inside_cell(upper(0.39, 0.001, 0.79)) == "yes: below the bound"
    assert upper(0.80, 0.001, 0.79).reference_inside is False
    assert _inside_cell(upper(0.80, 0.001, 0.79)) == "no (numerical): above the bound"
    assert upper(0.80, 0.005, 0.79, 0.006).reference_inside is True  # the bars overlap
    assert upper(0.80, 0.005, 0.79, np.inf).reference_inside is None
    lower = Row("p [-]", Estimate(0.5, {"step": 0.01}), 0.6, "frictionless lower bound",
                reference_kind="lower bound")  # fmt: skip
    assert lower.reference_inside is False and lower.error_kind == "numerical"
    assert _inside_cell(lower) == "no (numerical): below the bound"
    with pytest.raises(ValueError, match="reference_kind"):
        Row("x", 1.0, 1.0, reference_kind="bound")


def test_a_cost_row_has_no_bar_and_meets_its_budget_or_not(tmp_path):
    """A wall time is a cost, not a result with a converged value: no error bar (neither a
    finite one nor ``± ?``), printed as a cost, and compared with its budget as it is."""
    from dem.estimate import Estimate
    from validation.main_job import CaseSummary
    from validation.report import _inside_cell

    def cost(seconds, budget=60.0):
        return Row("wall time [s]", seconds, budget, "target", reference_kind="upper bound",
                   cost=True)  # fmt: skip

    fast, slow = cost(12.0), cost(75.0)
    assert fast.ours_error is None and fast.error_sources == {} and fast.estimate is None
    assert (fast.reference_inside, fast.error_kind) == (True, None)
    assert (slow.reference_inside, slow.error_kind) == (False, "over budget")
    assert _inside_cell(slow) == "no (over budget): above the bound"
    assert fast.ours_text() == "12 (cost)"
    assert CaseSummary.of("fake", [fast, Row("x [-]", 1.0)], 0.0).no_bar == 1
    write_results("fake", [slow], quick=True, wall_s=0.0, out_dir=tmp_path)
    data = json.loads((tmp_path / "fake.json").read_text())["rows"][0]
    assert data["cost"] is True and data["ours_error"] is None and data["error_sources"] == {}
    bad_rows = (
        dict(ours=Estimate(1.0, {"x": 0.1})),
        dict(ours=-1.0),
        dict(ours=None),
        dict(ours=1.0, reference=60.0),
        dict(ours=1.0, error_sources={"x": 0.1}),
    )
    for bad in bad_rows:
        with pytest.raises(ValueError, match="cost"):
            Row("t [s]", cost=True, **bad)
    with pytest.raises(ValueError, match="reference_error"):
        Row("x", 1.0, 1.0, reference_error=-1.0)


def test_a_row_refuses_a_nan_value():
    with pytest.raises(ValueError, match="ours is NaN; give None"):
        Row("ultimate deflection [mm]", float("nan"))


def test_a_row_rejects_a_bad_bar():
    with pytest.raises(ValueError, match="half-width"):
        Row("x", 1.0, error_sources={"grid": -1e-3})
    with pytest.raises(ValueError, match="Estimate or error_sources"):
        from dem.estimate import Estimate

        Row("x", Estimate(1.0, {"grid": 0.1}), error_sources={"grid": 0.1})


# -- the quick folder and the manifest ---------------------------------------------------------
def _porcelain(*paths: str) -> str:
    return subprocess.run(
        ["git", "status", "--porcelain", "--", *paths],
        cwd=REPO,
        capture_output=True,
        text=True,
        check=True,
    ).stdout


def test_a_quick_run_touches_no_committed_result():
    """``python -m validation run geometry --quick`` writes the git-ignored quick folder; the
    committed full ``geometry.json`` keeps its bytes and git sees no change."""
    from validation.report import QUICK_RESULTS_DIR, RESULTS_DIR

    committed = RESULTS_DIR / "geometry.json"
    before, status = committed.read_bytes(), _porcelain("validation", ".gitignore")
    done = subprocess.run(
        [sys.executable, "-m", "validation", "run", "geometry", "--quick"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    quick = json.loads((QUICK_RESULTS_DIR / "geometry.json").read_text())
    assert quick["quick"] is True and quick["case"] == "geometry"
    assert committed.read_bytes() == before
    assert _porcelain("validation", ".gitignore") == status


def _fake_result(folder: Path, case: str, commit: str, clean: bool = True, quick: bool = False):
    payload = {"case": case, "quick": quick, "git_commit": commit, "git_clean": clean}
    payload.update(date=f"d-{case}", wall_s=1.0, side_products={}, rows=[])
    (folder / f"{case}.json").write_text(json.dumps(payload))


def test_the_manifest_names_the_results_not_from_its_commit(tmp_path):
    from validation.manifest import check_manifest, write_manifest

    _fake_result(tmp_path, "a", "1" * 40)
    _fake_result(tmp_path, "b", "1" * 40)
    _fake_result(tmp_path, "c", "2" * 40, clean=False, quick=True)
    write_manifest(tmp_path)  # the commit most results share
    assert json.loads((tmp_path / "MANIFEST.json").read_text())["git_commit"] == "1" * 40
    problems = check_manifest(tmp_path, expected=["a", "b", "c", "d"])
    assert problems == [
        "d: no results file",
        "c: from commit 222222222222, not 111111111111",
        "c: written from a dirty tree",
        "c: a quick run in the full results",
    ]
    runs = tmp_path / "a-runs.jsonl"
    runs.write_text(json.dumps({"git_commit": "3" * 40}) + "\n")
    _fake_result(tmp_path, "a", "1" * 40)
    data = json.loads((tmp_path / "a.json").read_text())
    data["side_products"] = {"a-runs.jsonl": "sha"}
    (tmp_path / "a.json").write_text(json.dumps(data))
    assert "a: sweep records not from 111111111111: 1 from 333333333333" in check_manifest(tmp_path)


def test_the_command_line_is_not_in_the_middle_of_the_sweep_runner():
    """No import chain from the sweep package to ``validation.__main__``, by import statement
    or by name (an ``importlib`` call hides the circle from static tools)."""
    import grimp

    graph = grimp.build_graph("validation")
    for module in graph.find_children("validation.sweep"):
        assert not graph.chain_exists(module, "validation.__main__"), module
    for path in (REPO / "validation" / "sweep").glob("*.py"):
        assert "validation.__main__" not in path.read_text(), path


def _square(params, seed):
    return {"y": params["x"] ** 2}


def test_sweep_records_carry_the_commit_clean_flag_date_and_wall_time(tmp_path):
    from validation.provenance import git_commit
    from validation.sweep import make_tasks, run_sweep

    tasks = list(make_tasks(({"x": x} for x in (1.0, 2.0)), root_seed=3))
    summary = run_sweep(_square, tasks, tmp_path / "s", workers=0, progress=False)
    for record in summary.records():
        assert record["git_commit"] == git_commit() and record["git_clean"] in (True, False)
        assert record["date"].startswith("20") and record["wall_s"] >= 0


def test_outside_a_run_side_products_never_go_to_the_committed_results(monkeypatch):
    from validation.report import QUICK_RESULTS_DIR, RESULTS_DIR

    monkeypatch.delenv("BLOCKMECH_RESULTS", raising=False)
    assert output_dir() == QUICK_RESULTS_DIR != RESULTS_DIR


def test_a_full_run_of_every_case_refuses_a_dirty_tree(monkeypatch, capsys):
    """Full results come from one clean commit: ``validation all`` stops before any case runs
    when the tree has uncommitted changes (``--allow-dirty`` overrides)."""
    import validation.catalogue as catalogue

    monkeypatch.setattr(cli, "git_dirty", lambda: (True, ["limit/solve.py"]))
    monkeypatch.setattr(catalogue, "run_case", lambda *a, **k: pytest.fail("a case ran"))
    assert cli.main(["all"]) == 2
    assert "limit/solve.py" in capsys.readouterr().err


def test_write_stamped_records_provenance_and_wall_time(tmp_path):
    import json

    from validation.provenance import write_stamped

    path = tmp_path / "sub" / "record.json"
    data = write_stamped(path, lambda: {"series": [1, 2]})
    on_disk = json.loads(path.read_text())
    assert on_disk == data
    assert on_disk["series"] == [1, 2] and on_disk["wall_s"] >= 0.0
    assert {"git_commit", "git_clean", "date"} <= set(on_disk)


def test_a_reference_of_another_model_is_never_a_numerical_error():
    """A reference that names how its model differs from ours (an assumption our model tests,
    an approximate closed form) outside our bar is a model error, in the row, its JSON and the
    table; the same numbers from our own model's closed form are a numerical one."""
    from dem.estimate import Estimate
    from validation.report import _source_cell

    ours = Estimate(0.993, {"mesh": 0.0004})
    other = Row("E_eff / E [-]", ours, 1.0, "seed 000 Eq. (3)",
                model_difference="Eq. (3) takes the strip as a prism")  # fmt: skip
    same = Row("E_eff / E [-]", ours, 1.0, "seed 000 Eq. (3)")
    assert (other.reference_inside, other.error_kind) == (False, "model")
    assert (same.reference_inside, same.error_kind) == (False, "numerical")
    assert other.to_dict()["reference_is_model"] and not same.to_dict()["reference_is_model"]
    assert "other model: Eq. (3) takes the strip as a prism" in _source_cell(other)
    inside = Row("x [-]", Estimate(1.0, {"mesh": 0.1}), 1.05, "approx", model_difference="y")
    assert inside.error_kind is None  # agreeing rows carry no kind, whatever the model


def test_a_printed_seed_value_carries_its_last_digit():
    """One unit of the last printed digit (rounded or truncated), half a unit where the source
    rounds to nearest: 16.258 agrees with a printed 16.2, not with a printed 16.20 (rounded)."""
    from dem.estimate import Estimate
    from validation.report import printed_precision

    assert np.isclose(printed_precision("16.2"), 0.1)
    assert np.isclose(printed_precision("16.2", rounded=True), 0.05)
    assert np.isclose(printed_precision("168"), 1.0) and np.isclose(
        printed_precision("2.25e9"), 1e7
    )
    ours = Estimate(16.258, {"grid": 3e-9})
    assert Row(
        "m3u", ours, 16.2, "seed", reference_error=printed_precision("16.2")
    ).reference_inside
    tight = Row("m3u", ours, 16.2, "seed", reference_error=printed_precision("16.20", rounded=True))
    assert tight.reference_inside is False
    with pytest.raises(ValueError, match="printed_precision"):
        printed_precision("about 16")


def test_a_partial_bar_outside_its_reference_is_not_a_numerical_error():
    """A bar that omits known sources (the cheap budget) and misses a value of our own model is
    a 'partial bar', printed with what it omits; the same bar without omissions is numerical."""
    from dem.estimate import Estimate

    partial = Estimate(243.2, {"loading rate": 0.8}, omitted=("node spacing",))
    row = Row("peak [N]", partial, 256.1, "finest run")
    assert row.error_omits == ["node spacing"] and row.error_kind == "partial bar"
    assert row.ours_text() == "243.20 ± 0.80 (without node spacing)"
    assert row.to_dict()["error_omits"] == ["node spacing"]
    full = Row("peak [N]", Estimate(243.2, {"loading rate": 0.8}), 256.1, "finest run")
    assert full.error_kind == "numerical"


def test_a_cluster_run_starts_the_cases_longest_first(tmp_path):
    """The manifest's wall times order a run (longest-processing-time first), a case of
    unknown cost before all."""
    from validation.cluster import _priority
    from validation.manifest import previous_wall_times, write_manifest

    for case, wall in (("short", 2.5), ("long", 800.0), ("mid", 30.0)):
        _fake_result(tmp_path, case, "1" * 40)
        data = json.loads((tmp_path / f"{case}.json").read_text())
        data["wall_s"] = wall
        (tmp_path / f"{case}.json").write_text(json.dumps(data))
    assert previous_wall_times(tmp_path) == {}  # no manifest yet
    write_manifest(tmp_path)
    expected = previous_wall_times(tmp_path)
    assert expected == {"short": 2.5, "long": 800.0, "mid": 30.0}
    names = ["short", "new", "mid", "long"]
    order = sorted(names, key=lambda n: _priority(n, expected), reverse=True)
    assert order == ["new", "long", "mid", "short"]
