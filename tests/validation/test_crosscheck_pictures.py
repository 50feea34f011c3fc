"""Pictures and report text a reader can use: triad, title, colour bar, block numbers, the
pushover's collapse region, joint-state categories, rounded numbers, why a lower bound is 0."""

import re

import matplotlib.image
import numpy as np
import pytest

from dem.output import render_scene
from dem.scenes.running_bond_wall import running_bond_wall
from validation.crosscheck.cli import main as crosscheck_main
from validation.crosscheck.pictures import state_categories
from validation.crosscheck.pushover import NEAR_PEAK, REGION, collapse_region_end, zero_lower_note


def test_collapse_region_of_a_path_that_approaches_its_limit():
    """lambda = 1 - exp(-x) first reaches NEAR_PEAK of its largest value at
    x = -ln(1 - NEAR_PEAK * max): the picture ends REGION times further."""
    x = np.linspace(0.0, 50.0, 50001)
    lam = 1.0 - np.exp(-x)
    expected = REGION * -np.log(1.0 - NEAR_PEAK * lam.max())
    assert collapse_region_end(x, lam) == pytest.approx(expected, abs=2e-3)
    short = x <= 4.0  # a path that stops inside its collapse region is drawn whole
    assert collapse_region_end(x[short], lam[short]) == pytest.approx(4.0)


def test_joint_state_bits_become_categories():
    # bits: 1 shear, 2 flexure, 4 detached, 8 crushed (dem.static.result)
    states = np.array([0, 1, 2, 3, 4, 5, 7, 8, 9, 12])
    assert state_categories(states).tolist() == [0, 1, 2, 3, 4, 4, 4, 5, 5, 5]


def test_why_a_lower_bound_is_zero():
    assert "a lateral load needs shear" in zero_lower_note([10.0, 0.0, 0.0])
    assert "this live load needs shear" in zero_lower_note([0.0, 0.0, -10.0])


def _ink(image: np.ndarray) -> np.ndarray:
    """Pixels that are not white."""
    return np.any(image[..., :3] < 0.9, axis=-1)


def test_3d_pictures_have_a_triad_a_title_a_colour_bar_and_block_numbers(tmp_path, two_block_stack):
    plain = render_scene(tmp_path / "plain.png", two_block_stack, unit="-", title="two blocks")
    numbered = render_scene(tmp_path / "n.png", two_block_stack, unit="-", block_numbers=True)
    image = matplotlib.image.imread(plain)
    h, w = image.shape[:2]
    assert _ink(image[int(0.78 * h) :, : int(0.16 * w)]).any(), "no axes triad lower left"
    assert _ink(image[: int(0.06 * h)]).any(), "no title along the top edge"
    bar = image[int(0.9 * h) :, int(0.25 * w) : int(0.75 * w), :3]
    assert np.ptp(bar) > 0.5, "no colour bar along the bottom"
    with_numbers = matplotlib.image.imread(numbered)
    assert np.abs(with_numbers[: int(0.9 * h)] - image[: int(0.9 * h)]).max() > 0.3


def test_report_rounds_and_says_why_the_lower_bound_is_zero(tmp_path):
    """A wall under a lateral load: its frictionless lower bound is 0 (no shear without
    friction), and the report says so with the bound's bar; numbers without an error bar carry 4
    digits."""
    path = tmp_path / "wall.json"
    running_bond_wall(3, 2, 100.0, 300.0, 120.0, 18.0, mu=0.6).to_json(path)
    out = tmp_path / "out"
    args = ["--live", "x", "--methods", "limit,dem,fem", "--no-pictures", "--out", str(out)]
    assert crosscheck_main([str(path), *args]) == 0
    report = (out / "report.md").read_text()
    table = report.split("## Load multipliers")[1].split("\n## ")[0]
    lower = [row for row in table.splitlines() if row.startswith("| lower bound")]
    assert len(lower) == 2
    for row in lower:
        # 0 with the solver's bar (duality gap, feasibility), far below the scale of lambda
        bar = re.search(r"\| 0 ± ([\d.e+-]+) \|", row)
        assert bar is not None and float(bar.group(1)) < 1e-6, row
        assert "frictionless (Radenkovic) lower bound" in row
        assert "a lateral load needs shear" in row
    for number in re.findall(r"\| (\d+\.\d+) \|", table):
        assert len(number.replace(".", "").lstrip("0")) <= 4, number
    stresses = re.findall(r"largest (?:tension|compression) (-?[\d.]+)(?:e-?\d+)? MPa", report)
    assert len(stresses) >= 2
    for number in stresses:
        assert len(number.lstrip("-").replace(".", "").lstrip("0")) <= 4, number
