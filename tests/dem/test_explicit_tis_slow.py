"""Quick-mode TIS validation cases as smoke tests with their independent expectations (slow)."""

import pytest

pytestmark = pytest.mark.slow


def _rows(out):
    rows, notes = out
    assert notes
    return {r.quantity: r for r in rows}


@pytest.fixture
def tis_case(tmp_path, monkeypatch):
    """The case module writing its npz files to a temporary directory (not the results)."""
    import validation.cases.tis as tis

    monkeypatch.setenv("BLOCKMECH_RESULTS", str(tmp_path))  # output_dir() outside a run
    return tis


def test_tis_panels_quick(tis_case, tmp_path):
    rows = _rows(tis_case.run_panels(quick=True))
    assert (tmp_path / "tis-peak-state.npz").exists()
    # P scales exactly with k_n (homogeneity), no interlock means no load; the ratios' error
    # bars (the runs' own, cheap budget) hold the exact ratios
    stiff = rows["3x3 theta=2.5: P_max(10 E) / P_max(E)"]
    assert stiff.rel_error < 0.05
    assert stiff.estimate.contains(10.0), stiff.estimate
    assert rows["3x3 theta=0 (no interlock): P_max / P_max(theta=2.5)"].ours < 0.05
    ratio = rows["3x3 theta=2.5: P_calibrated / P_perfect"]
    assert abs(ratio.extra["rel_to_k_ratio"]) < 0.03
    assert ratio.estimate.contains(ratio.extra["k_imp_over_k_def"]), ratio.estimate
    for q, r in rows.items():
        if q.endswith("peak load [N]"):
            assert r.extra["central_out"], q  # the central block slips out (seed 000 Fig. 5b)
            assert r.extra["energy_over_work_max"] <= 1.0, q  # no energy created


def test_tis_friction_quick(tis_case):
    rows = _rows(tis_case.run_friction(quick=True))
    # smaller friction, lower peak (seed 000 Fig. 9a)
    assert rows["P_max(mu=0.21) / P_max(mu=0.23)"].ours < 1.0
    assert rows["P_max(mu=0.19) / P_max(mu=0.23)"].ours < 1.0
