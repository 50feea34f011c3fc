"""Every row with a numeric ``ours`` carries an error bar (issue 28), and a residual's bar is a
check that can fail.

Each case runs in quick mode; a row whose bar is unknown (``± ?``) fails the test. A row
with nothing to bound has no value (``ours`` None) and says why; a cost row (a wall time,
:attr:`validation.report.Row.cost`) is not a result and has no bar by design. The cheap cases
run in the fast suite, the others under ``-m slow``.
"""

import math

import pytest

from validation.catalogue import CASES
from validation.report import staged

FAST = (
    "geometry",
    "limit-closed-forms",
    "tresca-verification",
    "tresca-reconstruction",
    "interface-strength",
    "fem-patch",
    "fem-tis-stress",
    "fem-masonry-stress",
)
SLOW = tuple(sorted(set(CASES) - set(FAST)))


def _rows(case: str, tmp_path):
    with staged(case, tmp_path):
        out = CASES[case](quick=True)
    return out[0] if isinstance(out, tuple) else out


def _check_bars(case: str, rows) -> None:
    missing = []
    for row in rows:
        if row.cost:
            assert row.ours_error is None and "[s]" in row.quantity, row.quantity
            continue
        if row.ours is not None and not math.isfinite(row.ours_error):
            missing.append(row.quantity)
    assert not missing, f"{case}: rows without an error bar: {missing}"


@pytest.mark.parametrize("case", FAST)
def test_every_row_has_a_bar(case, tmp_path):
    _check_bars(case, _rows(case, tmp_path))


@pytest.mark.slow
@pytest.mark.parametrize("case", SLOW)
def test_every_row_has_a_bar_slow_cases(case, tmp_path):
    _check_bars(case, _rows(case, tmp_path))


def test_residual_rows_are_checks_that_can_fail(tmp_path):
    """A residual row's bar is the accuracy of its computation, so the reference 0 is inside
    it; a residual made larger than that bar falls outside (the check is not decorative)."""
    from validation.report import Row

    rows = _rows("tresca-verification", tmp_path)
    residuals = [
        r
        for r in rows
        if r.reference == 0.0 and r.ours is not None and "/solver]" not in r.quantity
    ]
    assert len(residuals) > 10
    for row in residuals:
        assert row.reference_inside, (row.quantity, row.ours, row.ours_error)
        worse = Row(
            row.quantity,
            abs(row.ours) + 2 * row.ours_error + 1e-300,
            0.0,
            row.source,
            error_sources=row.error_sources,
        )
        assert worse.reference_inside is False


def test_admissible_widths_hold_other_force_sets_and_their_reconstruction():
    """A solver's own dual is one admissible force set (seed 003 Remark 4): the widths of the
    admissible ranges around it must hold every other admissible set (another solver's dual,
    the min-energy forces), and the RT0 bars of those widths the difference between their
    reconstructed cell stresses. The five-cell mesh has a self-stress, so the sets differ."""
    import numpy as np

    from fem_check.rt_reconstruction import reconstruct_stress
    from limit.tresca import TrescaSettings, facet_tractions, solve_tresca
    from limit.voronoi_packing import uniform_stress_traction, verification_packing
    from validation.cases import tresca_bars as tb
    from validation.cases.tresca import PRESSURE, S_VERIF

    packing = verification_packing("five-cells")
    traction = uniform_stress_traction(packing, -PRESSURE * np.eye(2))
    normal = tb.admissible_range(packing, traction, S_VERIF, "normal")
    shear = tb.admissible_range(packing, traction, S_VERIF, "shear")
    sets = {
        name: solve_tresca(packing, traction, S_VERIF, TrescaSettings(solver=solver, selection=sel))
        for name, solver, sel in (
            ("clarabel", "CLARABEL", "solver"),
            ("highs", "HIGHS", "solver"),
            ("min", "CLARABEL", "min_energy"),
        )  # fmt: skip
    }
    base = sets.pop("clarabel")
    widths = tb.dual_widths(base, normal, shear)
    rec = {
        k: reconstruct_stress(
            packing.cell_ptr,
            packing.cell_xy,
            packing.centres,
            facet_tractions(packing, r, traction),
        )  # fmt: skip
        for k, r in {"clarabel": base, **sets}.items()
    }
    moved = tb.rt_bars(packing, widths).cell_stress + tb.rt_round_off(rec["clarabel"])
    tol = 1e-6 * PRESSURE  # the solves' own tolerance
    for name, other in sets.items():
        assert np.all(np.abs(other.normal_stress - base.normal_stress) <= widths + tol), name
        assert np.all(np.abs(other.shear_stress - base.shear_stress) <= widths + tol), name
        diff = np.abs(rec[name].cell_stress - rec["clarabel"].cell_stress)
        assert np.all(diff <= moved + tol), name
    assert widths.max() > 1e-3 * PRESSURE  # the forces are not unique here


def test_min_energy_force_bound_brackets_the_uniform_stress():
    """On a Voronoi packing under -p I the min-energy forces are those of the uniform stress
    (limit.tresca module notes); the certified bound must contain them, and a bound from a
    looser QP tolerance must too."""
    import numpy as np

    from limit.tresca import (
        TrescaSettings,
        forces_from_uniform_stress,
        min_energy_force_bound,
        solve_tresca,
    )
    from limit.voronoi_packing import uniform_stress_traction, voronoi_packing

    packing = voronoi_packing(30, 1.0, 1.0, seed=7)
    sigma = -np.eye(2)
    lam_exact, ft_exact = forces_from_uniform_stress(packing, sigma)
    for qp_tol in (1e-12, 1e-8):
        settings = TrescaSettings(selection="min_energy", qp_tol=qp_tol)
        res = solve_tresca(packing, uniform_stress_traction(packing, sigma), 10.0, settings)
        bound = min_energy_force_bound(packing, res, settings)
        assert np.all(np.abs(res.normal_force - lam_exact) <= bound)
        assert np.all(np.abs(res.tangential_force - ft_exact) <= bound)
