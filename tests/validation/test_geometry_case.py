"""Smoke test of the `geometry` case: files written, every row equal to its closed form."""

import json

from validation.__main__ import CASES
from validation.report import write_results


def test_geometry_case_matches_every_closed_form(tmp_path):
    rows, notes = CASES["geometry"](quick=True)
    assert len(rows) == 9 * 4 + 3 and notes
    for row in rows:
        assert row.rel_error is not None and row.rel_error < 1e-12, row.quantity
    json_path, md_path = write_results("geometry", rows, quick=True, wall_s=0.0, out_dir=tmp_path)
    data = json.loads(json_path.read_text())
    assert data["rows"][0]["reference"]["source"].startswith("seed 000")
    assert "| quantity |" in md_path.read_text()
