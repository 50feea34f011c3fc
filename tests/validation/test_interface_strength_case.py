"""Smoke test of the `interface-strength` case (seed 001 Sec. 2.1): rows, files and curves."""

import json

import numpy as np

import validation.cases.interface_strength as case
from validation.report import staged, write_results


def test_interface_strength_case_quick(tmp_path):
    with staged(case.CASE, tmp_path):  # the curves land beside the tables when the case ends
        rows, notes = case.run(quick=True)
    assert notes and len(rows) > 30
    by_name = {r.quantity: r for r in rows}
    # the seed's two headline numbers, within their printed rounding
    assert abs(by_name["shear strength f_su, seed interface [N]"].ours - 168.0) < 1e-9
    assert abs(by_name["pure torsion strength m3u, seed interface [N m]"].ours - 16.2) < 0.07
    for r in rows:
        if r.quantity.startswith("alpha"):
            assert abs(r.ours - r.reference) <= 0.15, r.quantity
    curves = np.load(tmp_path / "interface-strength.npz")
    assert "fig8_domain_m3" in curves and "alpha_r1_f1_m" in curves
    json_path, _ = write_results(case.CASE, rows, quick=True, wall_s=0.0, out_dir=tmp_path)
    data = json.loads(json_path.read_text())
    assert data["rows"][0]["reference"]["source"].startswith("seed 001")
