"""The time step is checked against the contacts present at each neighbour-list rebuild.

A cube of side ``L`` (mass ``m``) on a fixed slab, its base of area ``A = L^2`` in contact:
the vertical translation's Rayleigh quotient is ``k A / m``, so ``omega_max >= omega_v =
sqrt(k A / m)`` whatever the other modes. With ``k`` in every direction over the base (plane
``L / 2`` below the centroid), sliding along x couples with rocking about y: per unit ``k A /
m`` the stiffness over the mass is ``[[1, sqrt(6) / 2], [sqrt(6) / 2, 2]]`` (``I = m L^2 / 6``,
``int x^2 dA = A L^2 / 12``), whose top eigenvalue ``(3 + sqrt(7)) / 2`` gives ``omega_max =
1.681 omega_v`` (torsion gives ``omega_v``); the nodes sum the base's second moment by a rule
on a grid inset from its edges, within a few per cent of the integral.
"""

import math

import numpy as np
import pytest

from dem.explicit import ExplicitModel, ExplicitSettings, SimulationError
from dem.explicit.timestep import (
    ContactStiffness,
    choose_time_step,
    frequency_bound,
    highest_frequency,
    stable_frequency,
    stable_time_step,
)
from dem.scene import Scene
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM
from validation.cases.tis import QUICK, run_panel

SIDE, K_N, DENSITY, MARGIN = 0.01, 1e10, 2500.0, 0.1 * MM
OMEGA_V = math.sqrt(K_N * SIDE**2 / (DENSITY * SIDE**3))  # [rad/s]
ROCKING = math.sqrt((3.0 + math.sqrt(7.0)) / 2.0)


def drop_scene(gap: float) -> Scene:
    """A free cube of side SIDE, ``gap`` [m] above a fixed slab, under gravity."""
    cube = np.array([[i * SIDE, j * SIDE, gap + k * SIDE]
                     for i in (0, 1) for j in (0, 1) for k in (0, 1)])  # fmt: skip
    slab = np.array([[x, y, z] for x in (-0.01, 0.02) for y in (-0.01, 0.02)
                     for z in (-0.005, 0.0)])  # fmt: skip
    return Scene.from_convex_blocks([cube, slab], DENSITY, fixed=[1], mu=0.5)


def drop_model(dt: float) -> ExplicitModel:
    settings = ExplicitSettings(k_n=K_N, node_spacing=SIDE / 5, margin=MARGIN, dt=dt,
                                local_damping=0.7)  # fmt: skip
    return ExplicitModel(drop_scene(3 * MARGIN), settings)


def test_a_step_stable_in_free_flight_but_not_on_landing_stops_the_run():
    """dt = 2.2 / omega_v is above 2 / omega_max of the cube on the slab (module docstring):
    the run stops when the cube comes within the margin, naming the pair and a stable dt
    (it used to run on, ending still moving under the local damping)."""
    model = drop_model(2.2 / OMEGA_V)
    with pytest.raises(SimulationError, match=r"block 0 against blocks \[1\]") as err:
        model.advance(3000)
    assert "dt_safety" in str(err.value)
    assert model.t < 0.1  # stopped at the landing (a 0.3 mm fall takes 7.8 ms)
    dt_stable = float(str(err.value).split("needs dt <= ")[1].split(" s")[0])
    assert dt_stable == pytest.approx(2.0 / (ROCKING * OMEGA_V), rel=0.03)


def test_the_same_drop_with_a_stable_step_lands_and_records_the_frequency():
    """dt = 0.5 / omega_v (2 / omega_max = 1.19 / omega_v): the cube lands and comes to rest;
    the record's highest frequency is the cube's on its base."""
    model = drop_model(0.5 / OMEGA_V)
    model.advance(3000)
    assert abs(model.vel[0, 2]) < 1e-6
    record = model.step_check.as_dict()
    assert record["omega_start"] == 0.0 and record["omega_upper_ratio"] is None
    assert record["omega_upper"] == pytest.approx(ROCKING * OMEGA_V, rel=0.03)


def test_the_per_block_bound_is_within_sqrt2_above_the_exact_frequency():
    """TIS 3 x 3 panel moved off its reference pose (blocks shifted and turned): the bound's
    maximum lies in ``[omega_max, sqrt(2) omega_max]`` (``frequency_bound``'s proof)."""
    scene = tis_panel(3, 5.0)
    settings = ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1.5 * MM)
    model = ExplicitModel(scene, settings, scene.meta["central_block"], 1.25 * MM)
    rng = np.random.default_rng(3)
    model.pos[:] += rng.normal(scale=0.02 * MM, size=model.pos.shape)
    model.quat[:, 1:] = rng.normal(scale=0.002, size=(model.n_blocks, 3))
    model.quat[:] /= np.linalg.norm(model.quat, axis=1, keepdims=True)
    model.rebuild()
    system = ContactStiffness(model.bodies, model.surface, model.state.contacts, model.pos,
                              K_N, 0.5 * K_N, model.indenter, model.rotations())  # fmt: skip
    exact = highest_frequency(system)
    bound = frequency_bound(system).max()
    assert exact > 0
    assert exact * (1 - 1e-9) <= bound <= math.sqrt(2.0) * exact * (1 + 1e-9)


def test_the_stable_frequency_of_the_chosen_critical_step_is_the_start_frequency():
    """``choose_time_step``'s ``dt_critical`` (root of ``h^2 + 4 zeta h = 4``) is stable up
    to exactly ``omega_max`` with the contact dashpot it sets; undamped, ``2 / dt``."""
    settings = ExplicitSettings(k_n=K_N, contact_damping=0.3)
    step = choose_time_step(1e5, settings)
    assert stable_frequency(step["dt_critical"], 0.0, step["beta"]) == pytest.approx(1e5)
    assert stable_frequency(1e-3, 0.0, 0.0) == pytest.approx(2e3)
    assert stable_frequency(1e-3, 2.5e3, 0.0) == 0.0
    # the step the stop message names is the one whose stable frequency is omega
    assert stable_time_step(1e5, 0.0, step["beta"]) == pytest.approx(step["dt_critical"])
    for alpha, beta in ((0.0, 0.0), (300.0, 2e-6), (1e3, 0.0)):
        dt = stable_time_step(1e5, alpha, beta)
        assert stable_frequency(dt, alpha, beta) == pytest.approx(1e5)


def test_the_quick_tis_panel_run_passes_every_check():
    """3 x 3 panel at 5 degrees, quick discretisation: the present entries stay within the
    damped scheme's limit at every rebuild (omega_upper below the stable frequency of dt)."""
    res, _ = run_panel(3, 5.0, tis_panel_k_def(3), QUICK, max_deflection_mm=2.0)
    record, info = res.info["step_check"], res.info
    assert record["n_checks"] > 10
    assert record["omega_upper"] <= stable_frequency(info["dt"], info["alpha"], info["beta"])
