"""Every LimitSettings field is checked at construction, and the error names it."""

import math

import pytest

from limit.problems import LimitSettings

BAD = [
    ("interface_model", "vertices"),
    ("interface_model", None),
    ("mu", -0.1),
    ("mu", math.nan),
    ("mu", "0.6"),
    ("torsion", "both"),
    ("torsion_alpha", 0.5),
    ("torsion_alpha", math.inf),
    ("torsion_alpha", math.nan),
    ("friction_polygon", 3.5),
    ("friction_polygon", 2),
    ("friction_polygon", True),
    ("friction_polygon", "8"),
    ("tensile_strength", -1.0),
    ("tensile_strength", math.nan),
    ("tensile_strength", math.inf),
    ("compressive_strength", math.inf),
    ("compressive_strength", math.nan),
    ("compressive_strength", 0.0),
    ("tol", 0.0),
    ("tol", math.nan),
    ("tol", 1e-2),
    ("max_iter", -5),
    ("max_iter", 0),
    ("max_iter", 10.5),
    ("max_iter", True),
    ("cert_tol", math.nan),
    ("cert_tol", -1e-6),
    ("cert_tol", math.inf),
    ("cert_tol", 0.5),
    ("clarabel", "qdldl"),
    ("clarabel", {1: 2}),
    ("torsion_bending", "yes"),
    ("torsion_bending", 1),
]


@pytest.mark.parametrize(("name", "value"), BAD)
def test_bad_setting_is_refused_by_name(name, value):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        LimitSettings(**{name: value})


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("mu", math.inf),  # no sliding
        ("mu", 0),
        ("friction_polygon", 8),
        ("compressive_strength", 5e6),
        ("tensile_strength", 0),
        ("max_iter", 50),
        ("cert_tol", 1e-4),
        ("torsion_bending", True),
    ],
)
def test_good_setting_is_kept(name, value):
    assert getattr(LimitSettings(**{name: value}), name) == value


def test_with_is_validated_too():
    with pytest.raises(ValueError, match="^max_iter"):
        LimitSettings().with_(max_iter=-5)
