"""Scenes and inputs of a new user against closed forms and clear errors (explicit DEM).

The indenter, a rigid sphere of radius ``R`` and centre ``c``, pushes each node ``x`` it covers
with the traction ``k_n (R - |x - c|)`` along ``x - c``. Pressed ``d`` into a flat face (centre
``h = R - d`` above it), the vertical load is
``P = 2 pi k_n int_0^a (R - s) (h / s) rho d rho`` with ``s = sqrt(rho^2 + h^2)``, ``a^2 = R^2 -
h^2``; with ``s d s = rho d rho`` it is ``pi k_n h (R - h)^2 = k_n pi d^2 (R - d)``, largest at
``d = 2 R / 3``. On a block held by a wide, much stiffer support the block barely moves, so
``d`` is the indenter's travel.
"""

import itertools
import math

import numpy as np
import pytest

from dem.explicit import (
    ExplicitModel,
    ExplicitSettings,
    IndentationSettings,
    UnmodelledContactError,
    curve_summary,
    simulate_indentation,
)
from dem.explicit.unmodelled import INDENTER_DEPTH_LIMIT
from dem.scene import Scene
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM

SIDE = 0.01  # [m]
TIP = 1e-3  # [m]
K_N = 1e11  # [Pa/m]


def box(lo, hi):
    return np.array(list(itertools.product(*zip(lo, hi, strict=True))), dtype=float)


def ground():
    return box((-0.02, -0.02, -0.01), (0.03, 0.03, 0.0))


def sphere_load(depth, radius=TIP, k_n=K_N):
    """Load of a sphere pressed ``depth`` into a flat face [N]."""
    return k_n * math.pi * depth**2 * (radius - depth)


def indent(scene, block=0, axis_xy=None, max_deflection=1.5 * TIP):
    settings = ExplicitSettings(k_n=K_N, node_spacing=SIDE / 4)
    indentation = IndentationSettings(
        block=block, axis_xy=axis_xy, tip_radius=TIP, speed=0.05,
        max_deflection=max_deflection, record_interval=1e-5,
    )  # fmt: skip
    return simulate_indentation(scene, settings, indentation)


def test_sphere_on_a_held_block_follows_its_law_and_stops_before_sinking_through():
    """A cube on the ground under a sphere driven 1.5 R down: the load follows the sphere's
    law; the run stops once the tip is half its radius deep (it used to go on: the load peaked
    at 2 R / 3, the law's maximum, and turned negative, a frictionless sphere pulling the block
    up, and that peak was reported as the block's)."""
    res = indent(held_cube())
    assert "indenter" in res.info["stopped_by"]
    assert not res.peak_reached  # stopped on the rising branch of the law
    assert np.all(res.load >= 0.0)
    # each recorded load is the mean over its interval: the law at the interval's middle
    middle = res.delta - 0.5 * 1e-5
    shallow = (res.delta > 0.1 * TIP) & (res.delta < 0.45 * TIP)
    np.testing.assert_allclose(res.load[shallow], sphere_load(middle[shallow]), rtol=0.03)
    limit = INDENTER_DEPTH_LIMIT * TIP
    assert res.info["indenter_overlap_max"] <= limit
    assert res.delta[-1] <= limit + 2e-5
    assert res.peak_load <= 1.05 * sphere_load(limit)


def test_tip_starting_inside_another_block_is_refused():
    """Indenting the lower of two stacked cubes puts the tip inside the upper one (it used to
    push the lower cube through the upper one, with a load of 900 N)."""
    blocks = [box((0, 0, 0), (SIDE,) * 3), box((0, 0, SIDE), (SIDE, SIDE, 2 * SIDE)), ground()]
    scene = Scene.from_convex_blocks(blocks, 2500.0, fixed=[2], mu=0.5)
    with pytest.raises(UnmodelledContactError, match=r"overlaps block 1 .*start"):
        indent(scene, block=0)


def test_tip_sinking_into_a_block_without_indenter_nodes_stops_the_run():
    """The tip straddles a free cube and a fixed block of the same height: fixed blocks carry
    no indenter nodes, so the tip's contact with it used to be skipped. The run stops naming
    the fixed block."""
    blocks = [box((0, 0, 0), (SIDE,) * 3), box((SIDE, 0, 0), (2 * SIDE, SIDE, SIDE)), ground()]
    scene = Scene.from_convex_blocks(blocks, 2500.0, fixed=[1, 2], mu=0.5)
    res = indent(scene, axis_xy=(SIDE - 0.2 * TIP, 0.5 * SIDE))
    assert "overlaps block 1" in res.info["stopped_by"]
    assert "no indenter node of that block feels it" in res.info["stopped_by"]
    assert res.delta[-1] < 0.3 * TIP  # margin plus indenter node spacing: 0.2 TIP


def held_cube():
    return Scene.from_convex_blocks([box((0, 0, 0), (SIDE,) * 3), ground()], 2500.0,
                                    fixed=[1], mu=0.5)  # fmt: skip


def test_run_ending_while_the_load_rises_says_the_peak_was_not_reached(caplog):
    """Driven 0.2 R into a held cube, the tip is on the rising branch of its law (up to
    2 R / 3): the largest load is the last one, a lower bound, and the result says so (it used
    to report it as the peak load, with nothing to tell it from a real peak)."""
    res = indent(held_cube(), max_deflection=0.2 * TIP)
    assert res.info["stopped_by"] == ""
    assert not res.peak_reached
    assert res.deflection_at_peak == res.delta[-1]
    assert "peak was not reached" in caplog.text


@pytest.mark.parametrize(
    ("after_peak", "reached"),
    [([], False), ([0.95, 0.9], False), ([0.95, 0.8, 0.9], True), ([0.5], True)],
)
def test_peak_reached_once_the_load_fell_below_the_drop_fraction(after_peak, reached):
    """A load rising to 1 N, then the given loads: the peak is reached once a later load is
    at most 0.85 of it (the default drop fraction); a curve with no positive load has none."""
    load = np.concatenate([np.linspace(0.1, 1.0, 10), after_peak])
    delta = np.arange(1, len(load) + 1) * 1e-5
    assert curve_summary(delta, load, 0.1, 3e-5)["peak_reached"] is reached
    assert curve_summary(delta, -load, 0.1, 3e-5)["peak_reached"] is False


def test_cube_standing_on_an_edge_is_told_no_node_is_near_the_ground():
    """A cube turned 45 deg about x rests on one edge: no two faces touch, and the cube's
    nodes lie off its edges, so no node is within the margin of the ground. The error names
    that cause (it used to ask for a time step only, and with one the cube would have been
    called unsupported while it stands on the ground)."""
    turn = (
        np.array([[1.0, 0.0, 0.0], [0.0, 1.0, -1.0], [0.0, 1.0, 1.0]]) / np.array([1, 2, 2]) ** 0.5
    )
    cube = box((-0.05, -0.05, -0.05), (0.05, 0.05, 0.05)) @ turn.T + (0.0, 0.0, 0.05 * 2**0.5)
    scene = Scene.from_convex_blocks([cube, box((-1, -1, -0.1), (1, 1, 0))], 2000.0,
                                     fixed=[1], mu=0.5)  # fmt: skip
    with pytest.raises(ValueError, match="no contact node lies within .*margin"):
        ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=0.01))


def test_tip_slipping_into_the_gap_beside_the_loaded_tile_stops_the_run():
    """3 x 3 panel, theta = 5 deg, the tip 0.05 of a tile (half its radius) from the edge to
    block 13: once the loaded tile has been pushed 3 mm down the tip meets block 13's side face
    below its top, where no indenter node is (it used to sink 0.47 mm into it unseen, a load
    missing from the curve after the peak). The peak itself (1.83 mm) comes first."""
    side = 50 * MM / 4
    settings = ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1.0 * MM)
    indentation = IndentationSettings(axis_xy=(2.45 * side, 2.0 * side), speed=50 * MM)
    res = simulate_indentation(tis_panel(3, 5), settings, indentation)
    assert "overlaps block 13" in res.info["stopped_by"]
    assert "no indenter node of that block feels it" in res.info["stopped_by"]
    assert res.peak_reached and res.deflection_at_peak < res.delta[-1] < 4 * MM


def test_free_travel_above_an_inclined_top_is_reported(caplog):
    """A block whose top rises at 20 deg along x: the tip starts with its lowest point level
    with the highest vertex, so above the axis (x = L / 2) it travels
    ``L tan(20) / 2 + R - R / cos(20)`` = 1.756 mm before it touches the inclined face (delta
    used to be documented as counting from the contact, with nothing to tell this travel)."""
    rise = math.tan(math.radians(20.0))
    top = [(x, y, SIDE + rise * x) for x in (0, SIDE) for y in (0, SIDE)]
    wedge = np.array([(x, y, 0.0) for x in (0, SIDE) for y in (0, SIDE)] + top)
    scene = Scene.from_convex_blocks([wedge, ground()], 2500.0, fixed=[1], mu=0.5)
    res = indent(scene, max_deflection=2e-3)
    expected = 0.5 * SIDE * rise + TIP - TIP / math.cos(math.radians(20.0))
    assert expected - 1e-5 < res.info["delta_first_contact"] <= expected + 2e-5
    assert "first touched after 1.767 mm" in caplog.text
