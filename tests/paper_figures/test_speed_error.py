"""The speed-against-error figure sorts rows by reference and skips bounds."""

import json

from paper_figures import fig_speed_error as fig


def _case(tmp_path, name, rows):
    (tmp_path / f"{name}.json").write_text(json.dumps({"case": name, "rows": rows}))


def _row(err, wall, source):
    return {"quantity": "q", "ours": 1.0, "reference": {"value": 1.0, "source": source},
            "wall_s": wall, "rel_error": err}  # fmt: skip


def test_rows_are_sorted_by_reference_kind(tmp_path, monkeypatch):
    exact = [_row(1e-9, 0.01, "closed form s/H"), _row(0.0, 0.02, "exact")]
    _case(tmp_path, "limit-closed-forms", exact)
    _case(tmp_path, "masonry-restrepo", [
        _row(0.1, 5.0, "seed 001 (Baraldi & Cecchi) Table 2 (Restrepo-Velez et al. 2014)"),
        _row(0.3, 5.0, "associated upper bound, vertex model"),  # a bound: left out
        _row(None, 5.0, "seed 001 Table 2"),  # no error: left out
        _row(0.2, 5.0, ""),  # no named reference: left out
    ])  # fmt: skip
    monkeypatch.setattr(fig, "RESULTS", tmp_path)
    monkeypatch.setattr(fig, "OUT", tmp_path / "out")
    data = fig.collect()
    limit = data["limit analysis (cvxpy + Clarabel)"]
    assert sorted(limit["numerical"]) == [(0.01, 1e-9), (0.02, fig.FLOOR)]
    assert limit["model"] == []
    assert data["static DEM (masonry)"] == {"numerical": [], "model": [(5.0, 0.1)]}
    (png,) = fig.main()
    assert png.exists() and png.stat().st_size > 0


def test_one_figure_per_method_from_rows_and_benchmark_sweeps(tmp_path, monkeypatch):
    """Rows give points (estimated error where a finite bar is carried, true error where the
    reference is numerical, not a published value); a benchmark sweep gives a line; each
    method with data gets its own figure."""
    from paper_figures import fig_speed_error_methods as fig_m

    rows = [
        {**_row(1e-3, 0.5, "closed form b/h"), "ours": 2.0, "ours_error": 0.01},
        {**_row(0.1, 2.0, "seed 001 Table 2"), "ours": 1.0, "ours_error": "inf"},  # model error
        _row(1e-6, 0.0, "closed form"),  # no wall time: left out
    ]
    _case(tmp_path, "limit-closed-forms", rows)
    sweeps = tmp_path / "sweeps"
    sweeps.mkdir()
    (sweeps / "speed-error-fem.json").write_text(json.dumps({
        "method": "FEM check (scikit-fem)",
        "series": [{"label": "P2", "cost_s": [1.0, 2.0], "estimated": [0.1, None],
                    "true": [0.05, 0.02]}],
    }))  # fmt: skip
    monkeypatch.setattr(fig_m, "RESULTS", tmp_path)
    monkeypatch.setattr(fig_m, "SWEEPS", sweeps)
    monkeypatch.setattr(fig_m, "OUT", tmp_path / "out")
    got = fig_m.collect_rows()
    assert got == {"limit analysis (cvxpy + Clarabel)": [(0.5, 0.005, 1e-3)]}
    assert fig_m.collect_sweeps()["FEM check (scikit-fem)"][0]["label"] == "P2"
    pngs = fig_m.main()
    assert sorted(p.name for p in pngs) == [
        "fig_speed_error_fem_check.png",
        "fig_speed_error_limit_analysis.png",
    ]
    assert all(p.stat().st_size > 0 for p in pngs)
