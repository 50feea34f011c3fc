"""Bad scene files and arguments are refused with a ValueError naming the file, table and key."""

import json

import numpy as np
import pytest

from dem.scene import Assembly, Scene
from dem.scene_io import SceneSpec, read_scene
from tests.conftest import box_corners

# -- TOML -------------------------------------------------------------------------------------


def _toml(tmp_path, text):
    path = tmp_path / "spec.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[material]\ndensty = 1000.0\n", r"'densty' in \[material\] \(did you mean 'density'"),
        ("[supports]\nfixed_belw = 0.05\n", r"'fixed_belw' in \[supports\] \(did you mean 'fixed_"),
        ('[loads]\nliv = "x"\n', r"'liv' in \[loads\] \(did you mean 'live'\?\); allowed keys"),
        (
            "[[loads.point]]\nblock = 0\npoint = [0, 0, 0]\nforse = [0, 0, -1]\n",
            r"'forse' in \[loads\.point\[0\]\] \(did you mean 'force'",
        ),
        ("densty = 1000.0\n", r"'densty' in the top level; allowed keys: name, units, material"),
        ("[suports]\nfixed = [0]\n", r"'suports' in the top level \(did you mean 'supports'"),
    ],
)
def test_toml_unknown_keys_are_refused_by_name(tmp_path, text, message):
    with pytest.raises(ValueError, match=r"spec\.toml: unknown key " + message):
        SceneSpec.from_toml(_toml(tmp_path, text))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('[material]\nmu = "0.3"\n', r"material\.mu must be a finite number, got '0\.3'"),
        ("[material]\ndensity = true\n", r"material\.density must be a finite number"),
        ("[material]\ndensity = nan\n", r"material\.density must be a finite number"),
        ("[loads]\ngravity = 9.81\n", r"loads\.gravity must be a list of 3 numbers, got 9\.81"),
        ('[loads]\ngravity = [0, 0, "x"]\n', r"loads\.gravity\[2\] must be a finite number"),
        ("[supports]\nfixed = [1.7]\n", r"supports\.fixed\[0\] must be an integer block index"),
        ("[supports]\nfixed = [true]\n", r"supports\.fixed\[0\] must be an integer block index"),
        ("[supports]\nfixed = 0\n", r"supports\.fixed must be a list, got 0"),
        ("[supports]\nfixed_groups = [1]\n", r"supports\.fixed_groups\[0\] must be a string"),
        (
            "[supports]\nfixed_boxes = [[0, 0, 0, 1, 1]]\n",
            r"supports\.fixed_boxes\[0\] must be a list of 6 numbers",
        ),
        ('[loads]\nlive = "w"\n', r"loads\.live: load direction must be x, y, z"),
        ("material = 5\n", r"\[material\] must be a table, got 5"),
        ("[loads]\npoint = 3\n", r"loads\.point must be a list, got 3"),
        (
            '[[loads.point]]\nblock = 0\npoint = [0, 0, 0]\nforce = [0, 0, -1]\nkind = "wind"\n',
            r"kind 'dead' or 'live'",
        ),
        ("[material\n", r"not valid TOML"),
    ],
)
def test_toml_values_of_the_wrong_type_are_refused_by_key(tmp_path, text, message):
    with pytest.raises(ValueError, match=r"spec\.toml: .*" + message):
        SceneSpec.from_toml(_toml(tmp_path, text))


def test_toml_with_every_key_reads_as_the_spec_built_directly(tmp_path):
    text = (
        'name = "wall"\n[material]\ndensity = 2000\nmu = 0.6\n'
        '[supports]\nfixed = [0, 2]\nfixed_below = 0.05\nfixed_groups = ["base"]\n'
        "fixed_boxes = [[-1, -1, -1, 1, 1, 0]]\n"
        '[loads]\ngravity = [0, 0, -9.8]\nlive = "-y"\n'
        '[[loads.point]]\nblock = 1\npoint = [0, 0, 1.2]\nforce = [0, 0, -5000]\nkind = "live"\n'
    )
    expected = SceneSpec(
        density=2000.0,
        mu=0.6,
        fixed=(0, 2),
        fixed_below=0.05,
        fixed_groups=("base",),
        fixed_boxes=((-1.0, -1.0, -1.0, 1.0, 1.0, 0.0),),
        gravity=(0.0, 0.0, -9.8),
        live=(0.0, -1.0, 0.0),
        point_loads=(
            {"block": 1, "point": (0.0, 0.0, 1.2), "force": (0.0, 0.0, -5000.0), "kind": "live"},
        ),
        name="wall",
    )
    assert SceneSpec.from_toml(_toml(tmp_path, text)) == expected


def test_read_scene_refuses_a_misspelled_toml_key_next_to_a_json_scene(tmp_path, two_block_stack):
    """The tester's case: ``densty`` used to leave the density at the file's value."""
    path = tmp_path / "stack.json"
    two_block_stack.to_json(path)
    (tmp_path / "stack.toml").write_text("[material]\ndensty = 1000.0\nmu = 0.3\n")
    with pytest.raises(ValueError, match=r"stack\.toml: unknown key 'densty' in \[material\]"):
        read_scene(path)


# -- scene JSON -------------------------------------------------------------------------------

FIELDS = ["blocks", "density", "mu", "fixed", "restrained", "gravity", "dead_wrench", "live_wrench"]


@pytest.mark.parametrize("field", FIELDS)
def test_json_missing_field_is_named_with_the_file(tmp_path, two_block_stack, field):
    data = two_block_stack.to_dict()
    del data[field]
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=rf"scene\.json: .*missing field\(s\) \['{field}'\]"):
        Scene.from_json(path)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("mu", "0.5"),
        ("density", "1000"),
        ("gravity", 9.81),
        ("gravity", [0, 0, "-9.81"]),
        ("dead_wrench", [[0, 0, "-1", 0, 0, 0]] * 3),
        ("live_wrench", [[0, 0, True, 0, 0, 0]] * 3),
    ],
)
def test_json_field_of_the_wrong_type_is_named(tmp_path, two_block_stack, field, value):
    data = two_block_stack.to_dict()
    data[field] = value
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=rf"scene\.json: .*{field}"):
        Scene.from_json(path)


def test_json_that_is_not_an_object_is_refused(tmp_path):
    path = tmp_path / "list.json"
    path.write_text("[1, 2]")
    with pytest.raises(ValueError, match=r"list\.json: a scene must be a JSON object, got list"):
        Scene.from_json(path)


def test_crosscheck_exits_2_on_a_scene_json_missing_a_field(tmp_path, two_block_stack, capfd):
    """README: exit code 2 for unreadable input (was a KeyError traceback, code 1)."""
    from validation.crosscheck.cli import main

    data = two_block_stack.to_dict()
    del data["gravity"]
    path = tmp_path / "nogravity.json"
    path.write_text(json.dumps(data))
    assert main([str(path), "--out", str(tmp_path / "out")]) == 2
    assert "missing field(s) ['gravity']" in capfd.readouterr().err
    assert not (tmp_path / "out").exists()


# -- Scene arguments --------------------------------------------------------------------------

BLOCKS = [box_corners((0, 0, 0), (1, 1, 1)), box_corners((0, 0, 1), (1, 1, 2))]


@pytest.mark.parametrize("fixed", [0, True, np.int64(1), "0", 1.0])
def test_scalar_fixed_is_refused_asking_for_a_list(fixed):
    with pytest.raises(ValueError, match=r"fixed must be a list of block indices .* e\.g\."):
        Scene.from_convex_blocks(BLOCKS, 1000.0, fixed=fixed)


def test_zero_dimensional_fixed_array_is_refused():
    with pytest.raises(ValueError, match=r"fixed must be one-dimensional, got shape \(\)"):
        Scene.from_convex_blocks(BLOCKS, 1000.0, fixed=np.array(0))


@pytest.mark.parametrize("name", ["mu", "density"])
@pytest.mark.parametrize("value", ["0.6", ["0.6", "0.6"], True, [0.6, None]])
def test_non_numeric_mu_or_density_is_refused(name, value):
    kw = {"density": 1000.0, "mu": 0.5, name: value}
    with pytest.raises(ValueError, match=rf"^{name} must be a number or one number per block"):
        Assembly.from_convex_blocks(BLOCKS, **kw)
