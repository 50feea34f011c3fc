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
