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


def test_a_fitted_order_carries_its_pre_asymptotic_drift():
    """Errors C h^p (1 + a h + b h^2) on halved grids (p = 1, 2, 3): the order's bar, the
    geometric tail of the local orders' drift, contains p and stays below 0.1; an error
    sequence whose local orders do not settle has an unknown bar."""
    import math

    import pytest

    for p, a, b in [(2.0, 3.0, 0.0), (2.0, -1.5, 4.0), (1.0, 0.8, 0.0), (3.0, 2.0, 1.0)]:
        h = 0.5 ** np.arange(2, 8)
        est = case.asymptotic_order(h**p * np.abs(1 + a * h + b * h * h))
        assert est.contains(p), (p, a, b, est)
        assert est.error < 0.1, (p, a, b, est)
    assert math.isinf(case.asymptotic_order([1.0, 0.3, 0.2, 0.01, 0.009]).error)
    with pytest.raises(ValueError, match="asymptotic_order"):
        case.asymptotic_order([1.0, 0.5, 0.0, 0.1])
