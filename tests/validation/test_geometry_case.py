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


def test_the_round_off_bar_of_a_closed_form_holds_on_random_panels():
    """On random panels (n, theta drawn from a seeded generator), the counted round-off bar of
    the summed interface area and block volume contains the closed form (both bars), and stays
    at round-off: below 1e-10 of the value."""
    import numpy as np

    from validation.cases.geometry import tis_rows

    rng = np.random.default_rng(28)
    for n, theta in zip(rng.integers(2, 7, 4), rng.uniform(0.5, 12.0, 4), strict=True):
        rows = {r.quantity.split(": ")[1]: r for r in tis_rows(int(n), float(theta))}
        for name in ("interface area [mm^2]", "block volume + voids [mm^3]"):
            row = rows[name]
            assert row.reference_inside is True, (n, theta, name, row.ours, row.reference)
            assert 0 < row.ours_error < 1e-10 * row.ours, (n, theta, name, row.ours_error)
