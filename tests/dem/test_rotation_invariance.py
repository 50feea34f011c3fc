"""A scene turned about the vertical gives the same answers: the interface frame of a
rectangular contact lies along its sides whatever the scene's orientation."""

import numpy as np
import pytest

import limit
from dem.scene import Scene, proportional_to_weight
from dem.static import NoCollapseError, StaticSettings, solve_collapse


def _box(lo, hi) -> np.ndarray:
    return np.array(
        [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    )


def _arch_on_piers(turn_deg: float) -> Scene:
    """A semicircular arch of 11 voussoirs (radius 1 m, 0.25 m thick, 0.3 m deep) on two
    piers of two 0.6 x 0.3 x 0.5 m blocks, on a fixed slab; pushed horizontally by its weight
    along the arch's plane. Turned by ``turn_deg`` about z and moved off the origin."""
    r, t, d = 1.0, 0.25, 0.3
    blocks = [_box((-2.0, -0.5, -0.3), (2.0, 0.5, 0.0))]
    for x0 in (-r - t - 0.35, r):
        blocks += [_box((x0, -d / 2, z), (x0 + t + 0.35, d / 2, z + 0.5)) for z in (0.0, 0.5)]
    angles = np.pi * (1 - np.arange(12) / 11)
    for a0, a1 in zip(angles[:-1], angles[1:], strict=True):
        blocks.append(
            np.array([(rr * np.cos(a), y, 1.0 + rr * np.sin(a))
                      for a in (a0, a1) for rr in (r, r + t) for y in (-d / 2, d / 2)])
        )  # fmt: skip
    c, s = np.cos(np.radians(turn_deg)), np.sin(np.radians(turn_deg))
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    moved = [b @ rot.T + np.array([5.0, -3.0, 2.0]) for b in blocks]
    scene = Scene.from_convex_blocks(moved, 2000.0, fixed=[0], mu=0.6)
    return scene.with_loads(live=proportional_to_weight(scene.assembly, tuple(rot[:, 0])))


def test_contact_frames_lie_along_the_sides_of_turned_rectangles():
    scene = _arch_on_piers(30.0)
    itf = scene.assembly.interfaces()
    for k in range(itf.n_interfaces):
        size = np.ptp(itf.local_polygon(k), axis=0)
        assert size[0] * size[1] == pytest.approx(itf.area[k], rel=1e-9)
    frame = itf.frame
    np.testing.assert_allclose(np.cross(frame[:, 0], frame[:, 1]), frame[:, 2], atol=1e-12)


def test_a_turned_arch_collapses_at_the_same_multiplier():
    """Upper bound 0.29568 for any turn; the fibre law reached it unturned but 2 % lower turned
    by 30 and 137 degrees (its springs missed the edges of the turned pier joints)."""
    base = _arch_on_piers(0.0)
    upper = limit.limit_analysis(base).lam
    fibre = solve_collapse(base, StaticSettings(interface_model="fibre")).lambda_max
    resultant = solve_collapse(base, StaticSettings(interface_model="resultant")).lambda_max
    assert fibre == pytest.approx(upper, rel=1e-4)
    for turn in (30.0, 137.0):
        scene = _arch_on_piers(turn)
        assert limit.limit_analysis(scene).lam == pytest.approx(upper, rel=1e-6)
        turned = solve_collapse(scene, StaticSettings(interface_model="fibre")).lambda_max
        assert turned == pytest.approx(fibre, rel=1e-4)
        # the resultant law's plateau moves with round-off along its path by 0.15 % here
        res = solve_collapse(scene, StaticSettings(interface_model="resultant")).lambda_max
        assert res == pytest.approx(resultant, rel=1e-2)


@pytest.mark.parametrize(
    "law",
    [
        pytest.param(
            "resultant",
            marks=pytest.mark.xfail(
                strict=True,
                raises=NoCollapseError,
                reason="the end needs a certificate (dem.static.certificate): the wall along x "
                "used to end at 0.2140 from the path's shape, but its path rises on to "
                "0.217068 and stalls with neither a limit point nor an upper bound (rocking "
                "alone is unbounded with the fixed column; Eq. A5 is not inside the vertex "
                "joint); the turned wall ends at a limit point at 0.213978",
            ),
        ),
        "fibre",
    ],
)
def test_a_wall_built_along_a_diagonal_collapses_as_along_x(law):
    """A dry running-bond wall (8 courses of 6 blocks, one fixed end column) pushed out of
    plane, turned 45 degrees about z: the resultant law gave 0.2212 instead of 0.2140 (+3.4 %:
    its reduced rectangle was the bounding box of the turned joints), the fibre law -1.3 %."""
    from dem.scenes.running_bond_wall import running_bond_wall

    base = running_bond_wall(6, 8, 100.0, 200.0, 100.0, 20.0, mu=0.6, fixed_columns=("left",))
    c = s = np.sqrt(0.5)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    turned = Scene.from_convex_blocks(
        [b.vertices @ rot.T for b in base.assembly.blocks],
        base.assembly.density,
        fixed=np.flatnonzero(base.supports.fixed),
        mu=0.6,
    )
    turned = turned.with_loads(live=proportional_to_weight(turned.assembly, tuple(rot[:, 1])))
    settings = StaticSettings(interface_model=law)
    lam = solve_collapse(base, settings).lambda_max
    assert solve_collapse(turned, settings).lambda_max == pytest.approx(lam, rel=1e-3)
