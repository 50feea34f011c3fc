"""Indentation of a small TIS panel: scaling with k_n, checkpoint-resume, results."""

import numpy as np
import pytest

from dem.explicit import (
    ExplicitSettings,
    IndentationSettings,
    RelaxationSettings,
    curve_summary,
    simulate_indentation,
)
from dem.kernels.contact_force import ENTRY_CHUNK
from dem.kernels.integrate import quat_to_rot
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM

FAST = IndentationSettings(speed=50 * MM, max_deflection=0.15 * MM, record_interval=0.005 * MM)


def run(k_n, **kw):
    scene = tis_panel(3, 2.5)
    settings = ExplicitSettings(k_n=k_n, **{"node_spacing": 1.5 * MM, **kw})
    return simulate_indentation(scene, settings, FAST)


def test_load_proportional_to_kn():
    """Rigid blocks, penalty contact and Coulomb friction with k_t proportional to k_n: the
    quasi-static problem is homogeneous in k_n (self weight aside, 1e-4 of P here), so doubling
    E doubles P at every deflection (seed 000 Sec. 2.3)."""
    k = tis_panel_k_def(3)
    one = run(k)
    two = run(2 * k)
    assert one.load.max() > 5.0  # a real load, far above the panel's weight
    common = np.linspace(0.05, 0.15, 5) * MM
    p1 = np.interp(common, one.delta, one.load)
    p2 = np.interp(common, two.delta, two.load)
    np.testing.assert_allclose(p2 / p1, 2.0, rtol=0.03)


def test_checkpoint_resume_same_curve(tmp_path):
    """A run abandoned midway and resumed from its checkpoint gives the same curve, bit for bit,
    as the uninterrupted run."""
    k = tis_panel_k_def(3)
    scene = tis_panel(3, 2.5)
    settings = ExplicitSettings(k_n=k, node_spacing=1.5 * MM)
    whole = simulate_indentation(scene, settings, FAST)
    path = tmp_path / "run.npz"
    with pytest.raises(KeyboardInterrupt):
        simulate_indentation(scene, settings, FAST, checkpoint=path, stop_after_chunks=11)
    assert path.exists()
    resumed = simulate_indentation(scene, settings, FAST, checkpoint=path)
    np.testing.assert_array_equal(resumed.delta, whole.delta)
    np.testing.assert_array_equal(resumed.load, whole.load)
    np.testing.assert_array_equal(resumed.block_pos[-1], whole.block_pos[-1])
    # a checkpoint of other settings is not reused
    other = ExplicitSettings(k_n=k, node_spacing=1.5 * MM, kt_over_kn=0.5)
    fresh = simulate_indentation(scene, other, FAST, checkpoint=path)
    assert not np.array_equal(fresh.load, whole.load)


def test_curve_summary_triangle():
    """Closed form on a triangular curve: peak, deflection at peak, ultimate and energy."""
    delta = np.linspace(0.001, 4.0, 4000)
    load = np.where(delta <= 1.0, 100 * delta, np.maximum(0.0, 100 * (2.0 - delta)))
    s = curve_summary(delta, load, ultimate_fraction=0.05, out_confirm=0.5)
    np.testing.assert_allclose(s["peak_load"], 100.0, rtol=1e-3)
    np.testing.assert_allclose(s["deflection_at_peak"], 1.0, atol=1e-3)
    np.testing.assert_allclose(s["ultimate_deflection"], 1.95, atol=2e-3)
    # area of the triangle up to 1.95: 100 - 0.5 * 5 * 0.05
    np.testing.assert_allclose(s["loading_energy"], 100.0 - 0.125, rtol=2e-3)
    np.testing.assert_allclose(s["energy_to_peak"], 50.0, rtol=2e-3)


def test_peak_state_is_balanced():
    """The exported peak state, taken into each block's reference frame with its quaternion:
    on every free block the nodal forces and the true weight balance m a, and their moments
    about the reference centroid balance I alpha + omega x I omega, with the block's own
    closed-form mass properties (from the scene, not from the solver)."""
    res = run(tis_panel_k_def(3))
    ps = res.peak_state
    scene = tis_panel(3, 2.5)
    asm = scene.assembly
    n = asm.n_blocks
    rot = np.zeros((n, 3, 3))
    quat_to_rot(ps["quaternion"], rot)
    f_ref = np.einsum("mji,mj->mi", rot[ps["block"]], ps["force"])
    total = np.zeros((n, 3))
    np.add.at(total, ps["block"], f_ref)
    moment = np.zeros((n, 3))
    np.add.at(moment, ps["block"], np.cross(ps["point"] - asm.centroid[ps["block"]], f_ref))
    scale = np.abs(ps["force"]).max()
    for i in np.flatnonzero(~ps["fixed"]):
        m, inertia, r = asm.mass[i], asm.inertia[i], rot[i]
        lhs = total[i] + m * r.T @ ps["gravity"]
        np.testing.assert_allclose(lhs, m * r.T @ ps["acceleration"][i, :3], atol=1e-9 * scale)
        w = r.T @ ps["angular_velocity"][i]
        expected = inertia @ (r.T @ ps["acceleration"][i, 3:]) + np.cross(w, inertia @ w)
        np.testing.assert_allclose(moment[i], expected, atol=1e-11 * scale)
    assert ps["point"].shape == ps["force"].shape and ps["block"].dtype == np.int64
    assert len(ps["vert_ptr"]) == n + 1
    np.testing.assert_array_equal(ps["fixed"], scene.supports.fixed)


def test_run_stops_once_block_is_out():
    """Feeding the triangular curve record by record: the stop test fires one confirmation
    length after the closed-form ultimate deflection, and the summary then finds it."""
    from dem.explicit.indentation import _RunState

    ind = IndentationSettings(ultimate_fraction=0.05, out_confirm=0.5)
    delta = np.linspace(0.001, 4.0, 4000)
    load = np.where(delta <= 1.0, 100 * delta, np.maximum(0.0, 100 * (2.0 - delta)))
    st = _RunState(key="test")
    for d, p in zip(delta, load, strict=True):
        st.delta.append(d)
        st.load.append(p)
        st.best_load = max(st.best_load, p)
        if st.below_since(ind):
            break
    np.testing.assert_allclose(st.delta[-1], 1.95 + 0.5, atol=2e-3)
    s = curve_summary(np.array(st.delta), np.array(st.load), 0.05, 0.5)
    np.testing.assert_allclose(s["ultimate_deflection"], 1.95, atol=2e-3)


def test_parallel_node_loop_matches_serial():
    """The parallel node loop gives the serial curve bit for bit: both sum each chunk of entries
    in its own buffer and add the chunks in chunk order, whatever the number of threads."""
    k = tis_panel_k_def(3)
    serial = run(k, parallel=False, node_spacing=0.4 * MM)
    parallel = run(k, parallel=True, node_spacing=0.4 * MM)
    assert serial.info["n_nodes"] > 2 * ENTRY_CHUNK  # several chunks
    np.testing.assert_array_equal(parallel.load, serial.load)
    np.testing.assert_array_equal(parallel.block_pos, serial.block_pos)


def test_flat_panel_stays_symmetric():
    """theta = 0: the central block of a panel without clearance slides out between its
    neighbours; indented on its axis, the panel is symmetric and must stay so (no block turns
    beyond round-off), the indenter pushing only against the damping. Sliding in a slot
    without clearance is unstable under friction (an axis 1 nm off jams the block); depths of
    round-off size carry no friction, so round-off does not decide it."""
    scene = tis_panel(3, 0.0)
    settings = ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1.5 * MM)
    falling = RelaxationSettings(max_steps=2000, require_convergence=False)
    res = simulate_indentation(scene, settings, FAST, falling)
    turn = np.abs(res.block_quat[:, :, 1:]).max()
    assert turn < 1e-12
    # a jammed block carries tens of newtons after 0.1 mm (8 N at 0.12 mm, growing)
    assert res.load.max() < 2.0
