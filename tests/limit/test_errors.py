"""Infeasible and unbounded scenes end in clear structural errors; finite f_c bounds arching."""

import numpy as np
import pytest

from dem.scene import Scene, Supports
from limit.errors import LimitAnalysisError
from limit.problems import LimitSettings
from limit.solve import kinematic_analysis, limit_analysis
from tests.limit._scenes import block_on_ground, box, harmonic_stack, pressed_block


def test_no_support_is_reported():
    scene = block_on_ground(0.2, 0.2, 0.5, 0.7)
    free = scene.with_supports(Supports.none(scene.n_blocks))
    with pytest.raises(LimitAnalysisError, match="no supports"):
        limit_analysis(free)


def test_floating_block_is_reported():
    scene = block_on_ground(0.2, 0.2, 0.5, 0.7)
    far = box((5.0, 5.0, 5.0), (6.0, 6.0, 6.0))
    blocks = [b.vertices for b in scene.assembly.blocks] + [far]
    s2 = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.7)
    with pytest.raises(LimitAnalysisError, match=r"blocks \[2\] touch no other block"):
        limit_analysis(s2.with_loads(live=scene.loads.live_wrench.tolist() + [[0] * 6]))


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_falls_by_itself_is_infeasible(model):
    """A stack past the harmonic overhang has no equilibrium under its own weight."""
    with pytest.raises(LimitAnalysisError, match="falls down by itself"):
        limit_analysis(harmonic_stack(3, factor=1.05), LimitSettings(interface_model=model))


def test_too_little_friction_is_infeasible():
    """A block on a 45 degree slope with mu = 0.5 < tan 45 slides under its own weight."""
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    rot = np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])
    ground = box((-2, -2, -1), (2, 2, 0)) @ rot.T
    blk = box((-0.1, -0.1, 0), (0.1, 0.1, 0.2)) @ rot.T
    scene = Scene.from_convex_blocks([ground, blk], 2000.0, fixed=[0], mu=0.5)
    live = np.zeros((2, 6))
    live[1, 2] = -1.0
    with pytest.raises(LimitAnalysisError, match="falls down by itself"):
        limit_analysis(scene.with_loads(live=live))


def test_live_load_on_supported_dofs_only():
    scene = block_on_ground(0.2, 0.2, 0.5, 0.7)
    restrained = np.zeros((2, 6), dtype=bool)
    restrained[1, 0] = True
    held = scene.with_supports(Supports(scene.supports.fixed, restrained))
    with pytest.raises(LimitAnalysisError, match="unbounded"):
        limit_analysis(held)


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_pressed_block_is_unbounded(model):
    """Pushed onto the rigid ground with unlimited compressive strength, it never fails."""
    with pytest.raises(LimitAnalysisError, match="unbounded"):
        limit_analysis(pressed_block(), LimitSettings(interface_model=model))


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_compressive_strength_bounds_the_pressed_block(model):
    """With f_c the bed carries at most f_c A (centred load: the stress block is the whole
    face), so (1 + lambda) W = f_c A."""
    fc = 2.0e4
    scene = pressed_block()
    res = limit_analysis(scene, LimitSettings(interface_model=model, compressive_strength=fc))
    weight = scene.assembly.mass[1] * 9.81
    np.testing.assert_allclose(res.lam, fc * 0.4 * 0.3 / weight - 1.0, rtol=1e-6)


@pytest.mark.parametrize("model", ["vertex", "resultant"])
def test_compressive_strength_with_eccentricity(model):
    """A b x h block pushed sideways by lambda W on a bed of strength f_c: the stress block
    of width b - 2e with e = lambda W h / (2 W) must carry W (and mu is large):
    W = f_c d (b - lambda h), i.e. lambda = (b - W / (f_c d)) / h."""
    from tests.limit._scenes import block_on_ground

    b, d, h, fc = 0.2, 0.3, 0.5, 2.0e4
    scene = block_on_ground(b, d, h, mu=5.0)
    weight = scene.assembly.mass[1] * 9.81
    res = limit_analysis(scene, LimitSettings(interface_model=model, compressive_strength=fc))
    np.testing.assert_allclose(res.lam, (b - weight / (fc * d)) / h, rtol=1e-6)


def test_kinematic_form_reports_the_same_structural_errors():
    """By conic duality the kinematic programme is unbounded where the static one is
    infeasible, and infeasible where it is unbounded: the messages must still say which."""
    with pytest.raises(LimitAnalysisError, match=r"falls down by itself.*kinematic status"):
        kinematic_analysis(harmonic_stack(3, factor=1.05))
    with pytest.raises(LimitAnalysisError, match=r"unbounded.*kinematic status"):
        kinematic_analysis(pressed_block())


def test_corner_normal_forces_stay_compressive_without_sign_rows():
    """With mu > 0 the friction cone alone keeps every corner force compressive (p >= 0)."""
    from limit.problems import build_static_problem
    from limit.solve import solve_static

    scene = block_on_ground(0.4, 0.3, 0.8, mu=0.7)
    sp_ = build_static_problem(scene, LimitSettings())
    assert sp_.extra["implied_sign"].all()
    res = solve_static(sp_)
    assert res.lam == pytest.approx(0.5, rel=1e-6)  # overturning: b/h
    assert res.vertex_forces[:, 0].min() >= -1e-9 * sp_.weight


def test_zero_mu_after_build_is_refused():
    """Setting mu = 0 on corners whose sign row was left out would free p: refused."""
    from limit.problems import build_static_problem
    from limit.solve import solve_static

    sp_ = build_static_problem(block_on_ground(0.4, 0.3, 0.8, mu=0.7), LimitSettings())
    sp_.mu.value = np.zeros(sp_.n_cones)
    with pytest.raises(ValueError, match="mu = 0"):
        solve_static(sp_)
