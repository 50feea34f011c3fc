"""Smoke test of the seed-003 cases in quick mode: the min-energy rows meet their closed forms."""

import validation.cases.tresca as tresca
from validation.report import staged


def _check(rows):
    checked = 0
    for row in rows:
        if "min_energy" in row.quantity and row.reference is not None and row.ours is not None:
            # uniform stress / equilibrium closed forms; absolute error in Pa (references 0 or -1)
            assert abs(row.ours - row.reference) < 1e-6, row.quantity
            checked += 1
    assert checked > 10


def test_tresca_verification_quick():
    rows, notes = tresca.run_verification(quick=True)
    _check(rows)
    assert notes


def test_tresca_reconstruction_quick(tmp_path):
    with staged("tresca-reconstruction", tmp_path):
        rows, _ = tresca.run_reconstruction(quick=True)
        assert not (tmp_path / tresca.FIELDS_NPZ).exists()  # staged until the case ends
    _check(rows)
    assert (tmp_path / tresca.FIELDS_NPZ).exists()
