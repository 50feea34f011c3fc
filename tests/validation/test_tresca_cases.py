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


def test_admissible_range_holds_every_solvers_dual_and_the_uniform_stress():
    """The normal stress of each edge over the admissible set contains what HiGHS (a vertex),
    Clarabel (an interior point) and the min-energy rule (-p) return."""
    import numpy as np

    from limit.voronoi_packing import uniform_stress_traction, verification_packing
    from validation.cases import tresca_bars as tb

    packing = verification_packing("five-cells")
    traction = uniform_stress_traction(packing, -tresca.PRESSURE * np.eye(2))
    low, high = tb.admissible_range(packing, traction, tresca.S_VERIF, "normal")
    assert np.all(low <= -tresca.PRESSURE) and np.all(-tresca.PRESSURE <= high)
    for solver, selection in tresca._VARIANTS:
        _, res = tresca._solve(
            packing, -tresca.PRESSURE * np.eye(2), tresca.S_VERIF, solver, selection
        )
        assert np.all(low - 1e-6 <= res.normal_stress) and np.all(res.normal_stress <= high + 1e-6)
    assert np.any(high - low > 1.0)  # the five-cell graph has a self-stress: not unique
