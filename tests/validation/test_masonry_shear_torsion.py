"""The Table 2 case's record of the shear-torsion domain as a modelling choice
(validation.cases.masonry._shear_torsion_check) on a single block whose answer the fibre
law gives on a fine grid."""

import numpy as np
import pytest

from dem.scene import Scene
from dem.static import FibreLawSettings, StaticSettings, solve_collapse
from validation.cases.masonry import _shear_torsion_check, _shear_torsion_note
from validation.report import Row


def _box(lo, hi):
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def test_the_exact_domain_is_recorded_as_a_modelling_choice():
    """A block (mu 0.3) pushed by its weight and twisted by 0.2 m times it: the check records
    the exact domain's lambda (the 33-point fibre law's, to 1e-4) and its change from Eq. A5,
    in the row's notes and the case notes, and leaves the row's value and bar alone."""
    blocks = [_box((-1, -1, -0.2), (1, 1, 0)), _box((-0.2, -0.2, 0), (0.2, 0.2, 1))]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.3)
    live = np.zeros((2, 6))
    live[1, 0] = scene.assembly.mass[1] * 9.81
    live[1, 5] = 0.2 * live[1, 0]
    scene = scene.with_loads(live=live)
    settings = StaticSettings()
    result = solve_collapse(scene, settings)
    row = Row("block (resultant, none)", result.lambda_estimate, reference=None)
    sources = dict(row.error_sources)
    _shear_torsion_check(row, result, scene, settings)
    fine = solve_collapse(scene, StaticSettings(law=FibreLawSettings(points=33))).lambda_max
    assert row.extra["lambda_exact_shear_torsion"] == pytest.approx(fine, rel=1e-4)
    change = row.extra["lambda_exact_shear_torsion"] / result.lambda_max - 1
    assert row.extra["shear_torsion_change"] == pytest.approx(change)
    assert abs(change) > 0.01  # Eq. A5 is 2 % low on this joint
    assert "modelling choice" in row.error_notes and row.error_sources == sources
    assert "block (resultant, none)" in _shear_torsion_note([row])
