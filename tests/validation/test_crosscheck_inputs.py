"""A user's own files through ``blockmech-crosscheck``: a one-file OBJ wall of blocks that
share corners is read and checked; every unusable input gives one line and exit code 2.

The wall is the builder's running-bond wall written out as OBJ objects, so the expectation is
the limit analysis of the builder's own scene (another path to the same blocks).
"""

import json

import numpy as np
import pytest

from dem.scene_io import SceneSpec, read_scene
from dem.scenes.running_bond_wall import running_bond_wall
from limit import LimitSettings, limit_analysis
from validation.crosscheck.cli import main as crosscheck_main

DENSITY = 18.0e3 / 9.81  # [kg/m^3] of the builder's 18 kN/m^3


def _wall():
    """3 courses of bricks 100 x 300 x 120 mm (3, 4 with halves, 3) and the foundation (last)."""
    return running_bond_wall(3, 3, 100.0, 300.0, 120.0, 18.0, mu=0.6)


def _write_obj(path, blocks, scale=1.0, objects=True, skip=None):
    """Blocks as OBJ ``o`` objects (corners times ``scale``); ``skip = (block, face)`` leaves
    one face out."""
    lines, offset = [], 0
    for k, b in enumerate(blocks):
        if objects:
            lines.append(f"o brick_{k}")
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in b.vertices * scale]
        lines += [
            "f " + " ".join(str(offset + i + 1) for i in face)
            for j, face in enumerate(b.faces)
            if (k, j) != skip
        ]
        offset += len(b.vertices)
    path.write_text("\n".join(lines) + "\n")
    return path


def test_one_file_obj_wall_is_read_and_checked(tmp_path):
    """The wall's bricks share corners and head-joint faces in one OBJ file: the cross-check
    reads 11 blocks and finds the upper bound of the builder's own scene."""
    built = _wall()
    path = _write_obj(tmp_path / "wall.obj", built.assembly.blocks)
    out = tmp_path / "out"
    args = ["--density", str(DENSITY), "--mu", "0.6", "--fixed-below", "0", "--live", "x"]
    code = crosscheck_main([str(path), *args, "--out", str(out), "--methods", "dead,limit"])
    assert code == 0
    report = json.loads((out / "report.json").read_text())
    assert report["scene"]["n_blocks"] == built.n_blocks == 11
    upper = next(s for s in report["steps"] if s["name"] == "limit-vertex")["values"]["upper"]
    scene = read_scene(path, SceneSpec(density=DENSITY, mu=0.6, fixed_below=0.0, live=(1, 0, 0)))
    expected = limit_analysis(scene, LimitSettings(interface_model="vertex")).lam
    reference = limit_analysis(
        SceneSpec(live=(1.0, 0.0, 0.0)).apply(built), LimitSettings(interface_model="vertex")
    ).lam
    np.testing.assert_allclose(expected, reference, rtol=1e-6)
    np.testing.assert_allclose(upper, reference, rtol=1e-6)


def test_units_mm_convert_at_the_door(tmp_path):
    """The same wall typed in mm: refused without units, equal to the metre wall with
    ``--units mm`` or ``units = "mm"`` in the TOML (the TOML's lengths in mm too)."""
    blocks = _wall().assembly.blocks
    metres = read_scene(
        _write_obj(tmp_path / "m.obj", blocks), SceneSpec(density=DENSITY, fixed_below=-0.01)
    )
    mm = _write_obj(tmp_path / "mm.obj", blocks, scale=1e3)
    with pytest.raises(ValueError, match=r"median block is .* m across .*--units mm"):
        read_scene(mm, SceneSpec(density=DENSITY))
    (tmp_path / "mm.toml").write_text('units = "mm"\n[supports]\nfixed_below = -10.0\n')
    for spec in (SceneSpec(density=DENSITY), SceneSpec(density=DENSITY, units="mm")):
        scene = read_scene(mm, spec)
        np.testing.assert_allclose(scene.assembly.volume, metres.assembly.volume, rtol=1e-12)
        np.testing.assert_allclose(scene.assembly.centroid, metres.assembly.centroid, atol=1e-12)
        assert (scene.supports.fixed == metres.supports.fixed).all()
        assert scene.supports.fixed.sum() == 1


def _overlapping(tmp_path):
    blocks = list(_wall().assembly.blocks)
    moved = type(blocks[0])(**{**blocks[0].__dict__, "vertices": blocks[0].vertices + 0.05})
    return _write_obj(tmp_path / "s.obj", [moved, *blocks[1:]]), ["--fixed-below", "0"]


def _open(tmp_path):
    return _write_obj(tmp_path / "s.obj", _wall().assembly.blocks, skip=(4, 0)), []


def _non_convex(tmp_path):
    """An L-shaped prism: its inner corner is not a corner of its hull."""
    pts = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    lines = [f"v {x} {y} {z}" for z in (0, 1) for x, y in pts]
    lines += ["f 6 5 4 3 2 1", "f 7 8 9 10 11 12"]
    lines += [f"f {i + 1} {(i + 1) % 6 + 1} {(i + 1) % 6 + 7} {i + 7}" for i in range(6)]
    path = tmp_path / "s.obj"
    path.write_text("\n".join(lines) + "\n")
    return path, []


def _no_supports(tmp_path):
    return _write_obj(tmp_path / "s.obj", _wall().assembly.blocks), ["--fixed-below", "-5"]


def _no_supports_mm(tmp_path):
    path = _write_obj(tmp_path / "s.obj", _wall().assembly.blocks, scale=1e3)
    return path, ["--units", "mm", "--fixed-below", "-100"]


def _empty(tmp_path):
    path = tmp_path / "s.obj"
    path.write_text("# nothing but a comment\nv 0 0 0\n")
    return path, []


def _in_mm(tmp_path):
    return _write_obj(tmp_path / "s.obj", _wall().assembly.blocks, scale=1e3), []


def _light(tmp_path):
    path = _write_obj(tmp_path / "s.obj", _wall().assembly.blocks)
    return path, ["--density", "2.4", "--fixed-below", "0"]


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (_overlapping, "pairs of blocks overlap: blocks 0 and"),
        (_open, "body 4 of s.obj (object 'brick_4') is open: 4 edges"),
        (_non_convex, "body 0 of s.obj is not a convex block"),
        (_no_supports, "no supports: no block is fixed and no dof restrained (--fixed-below -5"),
        # centroids of the 100 mm courses and the foundation: -50 .. 250 mm
        (_no_supports_mm, "fixes none); block centroids lie at z = -50 .. 250 mm"),
        (_empty, "no surface polygons"),
        (_in_mm, "m across (over 100 m): is the file in mm? give --units mm"),
        (_light, "the median density is 2.4 kg/m^3 (below 10)"),
    ],
    ids=["overlap", "open", "non-convex", "no-supports", "no-supports-mm", "empty", "mm", "t/m3"],
)
def test_unusable_input_is_one_line_and_exit_2(tmp_path, capfd, make, message):
    path, extra = make(tmp_path)
    args = ["--density", str(DENSITY), "--live", "x", "--out", str(tmp_path / "out"), *extra]
    assert crosscheck_main([str(path), *args]) == 2
    captured = capfd.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("crosscheck: "), captured.err
    assert message in lines[0]
    assert "Traceback" not in captured.out + captured.err
    assert not (tmp_path / "out" / "report.md").exists()


def test_warnings_that_do_not_stop_a_run_are_in_the_report(tmp_path, capfd):
    """The wall in mm read with ``--units m`` (meant so): the units warning is one line on
    the console and repeated in report.md."""
    path = _write_obj(tmp_path / "big.obj", _wall().assembly.blocks, scale=1e3)
    out = tmp_path / "out"
    args = ["--density", str(DENSITY), "--fixed-below", "0", "--units", "m", "--out", str(out)]
    crosscheck_main([str(path), *args, "--methods", "dead", "--no-pictures"])
    err = capfd.readouterr().err.splitlines()
    assert len([x for x in err if "MixedUnitsWarning" in x]) == 1, err
    report = (out / "report.md").read_text()
    assert "## Warnings" in report and "MixedUnitsWarning: the median block is" in report
