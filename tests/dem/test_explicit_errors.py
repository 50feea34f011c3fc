"""Bad input gets an error naming what is wrong: settings, unsupported blocks, indenter axis."""

import math

import numpy as np
import pytest

from dem.explicit import (
    ExplicitModel,
    ExplicitSettings,
    IndentationSettings,
    RelaxationSettings,
    SimulationError,
    TiltingTable,
    simulate_indentation,
    simulate_lateral,
)
from dem.scene import Scene

SIDE = 0.01


def cube(x, y, z, side=SIDE):
    return np.array(
        [[x + i * side, y + j * side, z + k * side] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    )


def ground():
    lo, hi = (-0.02, -0.02, -0.01), (0.03, 0.03, 0.0)
    return np.array(
        [[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])]
    )


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: RelaxationSettings(min_steps=0, max_steps=0), "max_steps"),
        (lambda: RelaxationSettings(min_steps=10, max_steps=5), "max_steps"),
        (lambda: RelaxationSettings(global_damping=-0.1), "global_damping"),
        (lambda: ExplicitSettings(k_n=1e9, global_damping=-0.1), "global_damping"),
        (lambda: ExplicitSettings(k_n=1e9, contact_damping=-1.0), "contact_damping"),
        (lambda: ExplicitSettings(k_n=1e9, chunk_steps=0), "chunk_steps"),
        (lambda: ExplicitSettings(k_n=1e9, kt_over_kn=0.0), "kt_over_kn"),
        (lambda: ExplicitSettings(k_n=-1.0), "k_n"),
        (lambda: IndentationSettings(stop_below_peak_fraction=1.5), "stop_below_peak_fraction"),
        (lambda: IndentationSettings(ultimate_fraction=0.0), "ultimate_fraction"),
        (lambda: IndentationSettings(axis_xy=(0.0, float("nan"))), "axis_xy"),
        (lambda: IndentationSettings(speed=0.0), "speed"),
        (
            lambda: ExplicitSettings(k_n=1e9, indenter_node_spacing=math.inf),
            "indenter_node_spacing",
        ),
        (lambda: RelaxationSettings(ke_speed=math.inf), "ke_speed"),
    ],
)
def test_nonsense_settings_name_the_parameter(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_indenter_axis_missing_the_block_is_refused():
    """The loaded block's plan is 0..0.01 m: an axis at x = 0.05 m misses it."""
    scene = Scene.from_convex_blocks([cube(0, 0, 0), ground()], 2500.0, fixed=[1], mu=0.5)
    with pytest.raises(ValueError, match=r"axis_xy .* misses block 0"):
        simulate_indentation(
            scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4),
            IndentationSettings(block=0, axis_xy=(0.05, 0.005)),
        )  # fmt: skip


def test_floating_block_named_not_relaxation_failure():
    """Block 1 floats 5 mm above block 0: relaxation is refused naming block 1 (it would
    otherwise fall forever and end as 'relaxation did not converge')."""
    scene = Scene.from_convex_blocks(
        [cube(0, 0, 0), cube(0, 0, 0.015), ground()], 2500.0, fixed=[2], mu=0.5
    )
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))
    with pytest.raises(SimulationError, match=r"no support.*\[1\]") as info:
        model.relax(RelaxationSettings())
    assert "did not converge" not in str(info.value)


def test_scene_without_any_support_named():
    """Two stacked blocks and nothing fixed: both are named."""
    scene = Scene.from_convex_blocks([cube(0, 0, 0), cube(0, 0, SIDE)], 2500.0, mu=0.5)
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))
    with pytest.raises(SimulationError, match=r"2 blocks .*no support.*\[0, 1\]"):
        model.relax(RelaxationSettings())


def test_relaxation_failure_names_the_block_that_keeps_moving():
    """Block 1's centre lies 1 mm beyond the ground's edge (x = 0.03 m): it tips over while
    block 0 rests. The error names block 1 first, with how far it has moved."""
    scene = Scene.from_convex_blocks(
        [cube(0.0, 0.0, 0.0), cube(0.026, 0.0, 0.0), ground()], 2500.0, fixed=[2], mu=0.5
    )
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))
    with pytest.raises(SimulationError, match="did not converge") as info:
        model.relax(RelaxationSettings(min_steps=0, max_steps=4000))
    fastest = str(info.value).split("fastest: ")[1]
    assert fastest.startswith("block 1 at") and "block 0 at" in fastest


def test_every_block_fixed_is_refused_as_such():
    """A cube fixed on a fixed ground has nothing to move: the model and the lateral driver
    say so (not "no contact stiffness" nor "no interface with a free block")."""
    scene = Scene.from_convex_blocks([cube(0, 0, 0), ground()], 2500.0, fixed=[0, 1], mu=0.5)
    settings = ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4)
    with pytest.raises(ValueError, match="every block .* is fixed"):
        ExplicitModel(scene, settings)
    with pytest.raises(ValueError, match="every block .* is fixed"):
        simulate_lateral(scene)


def test_a_scene_without_touching_faces_still_asks_for_dt():
    """A free cube 5 mm above a fixed ground has no contact stiffness: give dt."""
    scene = Scene.from_convex_blocks([cube(0, 0, 0.005), ground()], 2500.0, fixed=[1], mu=0.5)
    with pytest.raises(ValueError, match="no contact stiffness.*ExplicitSettings.dt"):
        ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))


def test_tilting_table_without_gravity_is_refused():
    """A tilting table turns gravity: with g = 0 there is nothing to turn (it used to report
    collapsed=False)."""
    scene = Scene.from_convex_blocks([cube(0, 0, 0), ground()], 2500.0, fixed=[1], mu=0.5, g=0.0)
    with pytest.raises(ValueError, match="TiltingTable.*no gravity"):
        simulate_lateral(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4), TiltingTable())
