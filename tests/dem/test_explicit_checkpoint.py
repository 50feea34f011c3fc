"""Checkpoints: the state object round-trips; damaged or foreign files are named and refused."""

import pickle

import numpy as np
import pytest

from dem.explicit import ExplicitModel, ExplicitSettings
from dem.explicit.checkpoint import CheckpointError, read_checkpoint, write_checkpoint
from dem.explicit.state import ExplicitState
from dem.scene import Scene

SIDE = 0.01


def cube(x, y, z, side=SIDE):
    return np.array(
        [[x + i * side, y + j * side, z + k * side] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    )


def moving_model():
    ground = cube(-0.01, -0.01, -0.01, side=0.03)
    scene = Scene.from_convex_blocks([cube(0, 0, 0.02), ground], 2500.0, fixed=[1], mu=0.5)
    model = ExplicitModel(scene, ExplicitSettings(k_n=1e10, node_spacing=SIDE / 4))
    model.advance(50)  # falling on the ground: a state with shear history and velocities
    return model


def test_state_round_trip_through_checkpoint_is_exact(tmp_path):
    """Write, read, restore: every array and the time equal bit for bit, and the restored model
    continues exactly as the original (same state after 200 more steps)."""
    model = moving_model()
    path = tmp_path / "state.npz"
    write_checkpoint(path, model.state.to_arrays("s."), {"note": "test"})
    arrays, meta = read_checkpoint(path)
    assert meta["note"] == "test"
    copy = ExplicitState.from_arrays(arrays, "s.")
    twin = moving_model()
    twin.restore(copy)
    for a, b in zip(model.state.to_arrays().values(), twin.state.to_arrays().values(), strict=True):
        np.testing.assert_array_equal(a, b)
    model.advance(200)
    twin.advance(200)
    np.testing.assert_array_equal(model.pos, twin.pos)
    np.testing.assert_array_equal(model.state.contacts.shear, twin.state.contacts.shear)


def test_restore_gives_back_the_snapshot():
    """After a snapshot, more steps and a restore, the model continues as from the snapshot."""
    model = moving_model()
    snap = model.snapshot()
    model.advance(300)
    after = model.pos.copy()
    model.restore(snap)
    np.testing.assert_array_equal(model.pos, snap.motion.pos)
    model.advance(300)
    np.testing.assert_array_equal(model.pos, after)


def damaged_files(tmp_path):
    good = tmp_path / "good.npz"
    write_checkpoint(good, {"x": np.arange(1000.0)}, {})
    raw = good.read_bytes()
    files = {
        "empty": b"",
        "truncated": raw[: len(raw) // 2],
        "text": b"hello, not a checkpoint\n",
        "python_object": pickle.dumps({"x": 1}),
    }
    paths = {}
    for name, content in files.items():
        paths[name] = tmp_path / f"{name}.npz"
        paths[name].write_bytes(content)
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, x=np.arange(3))
    paths["foreign"] = foreign
    return paths


@pytest.mark.parametrize("kind", ["empty", "truncated", "text", "python_object", "foreign"])
def test_damaged_checkpoint_named_never_unpickled(tmp_path, kind):
    path = damaged_files(tmp_path)[kind]
    with pytest.raises(CheckpointError) as info:
        read_checkpoint(path)
    message = str(info.value)
    assert str(path) in message
    assert "pickle" not in message.lower()
    assert "delete it" in message


def test_other_version_refused(tmp_path):
    path = tmp_path / "old.npz"
    np.savez(path, __meta__=np.array('{"format": "blockmech.explicit.checkpoint", "version": 1}'))
    with pytest.raises(CheckpointError, match="version 1"):
        read_checkpoint(path)


def test_indentation_refuses_a_damaged_checkpoint_by_name(tmp_path):
    """simulate_indentation with a truncated checkpoint stops with the file's name instead of
    starting afresh or unpickling it."""
    from dem.explicit import IndentationSettings, simulate_indentation
    from dem.scenes.tis_panel import tis_panel
    from dem.tis_stiffness import tis_panel_k_def
    from dem.units import MM

    path = damaged_files(tmp_path)["truncated"]
    with pytest.raises(CheckpointError, match="truncated.npz"):
        simulate_indentation(
            tis_panel(3, 2.5), ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1.5 * MM),
            IndentationSettings(max_deflection=0.01 * MM), checkpoint=path,
        )  # fmt: skip
