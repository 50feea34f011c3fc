"""Three-hinge strip of two rigid blocks between fixed abutments against its closed form."""

import math

import numpy as np

from dem.explicit import ExplicitSettings, IndentationSettings, simulate_indentation
from dem.kernels.integrate import quat_to_rot
from dem.scene import Scene

MM = 1e-3
B, T, W = 20 * MM, 5 * MM, 5 * MM  # block length, depth, width
K_N = 1e12  # [Pa/m]


def strip_load(phi: float) -> float:
    """Closed form of the centrally loaded three-hinge strip with penalty hinges.

    Each block (length b, depth t, width w) turns by phi (small), about a hinge at its bottom
    edge at the abutment and a hinge at the top edge at mid-span. A hinge whose faces turn by
    theta relative to each other with edge penetration e carries the triangular traction
    k_n (e - theta s) over s < e / theta: N = k_n w e^2 / (2 theta), acting e / (3 theta) from
    the edge (theta = phi at the abutments, 2 phi at mid-span). Equal thrust N = H at the three
    hinges gives e_c = sqrt(2) e_s; the hinge-to-hinge chord b cos(phi) + t sin(phi) over the
    half span b gives 2 e_s + e_c = 2 (phi t - phi^2 b / 2). Moments about the abutment hinge
    of one block: (P / 2) b = H (t - phi b - e_s / (3 phi) - e_c / (6 phi)).
    """
    delta = phi * B
    e_s = 2 * phi * (T - delta / 2) / (2 + math.sqrt(2))
    e_c = math.sqrt(2) * e_s
    thrust = K_N * W * e_s**2 / (2 * phi)
    arm = T - delta - e_s / (3 * phi) - e_c / (6 * phi)
    return 2 * thrust * arm / B


def test_three_hinge_strip_matches_closed_form():
    """P against the blocks' rotation within 3 % of the closed form (no sliding: mu = 1)."""

    def box(x0, x1, z0, z1):
        return np.array([[x, y, z] for x in (x0, x1) for y in (0, W) for z in (z0, z1)])

    blocks = [box(-10 * MM, 0, -T, 2 * T), box(0, B, 0, T), box(B, 2 * B, 0, T),
              box(2 * B, 2 * B + 10 * MM, -T, 2 * T)]  # fmt: skip
    scene = Scene.from_convex_blocks(blocks, 2500.0, fixed=[0, 3], mu=1.0, g=0.0)
    settings = ExplicitSettings(k_n=K_N, node_spacing=0.5 * MM, contact_plane="compatible")
    indentation = IndentationSettings(
        block=1, axis_xy=(B, W / 2), tip_radius=2 * MM, speed=10 * MM, max_deflection=1.0 * MM,
        record_interval=0.01 * MM, stop_when_out=False,
    )  # fmt: skip
    res = simulate_indentation(scene, settings, indentation)
    rot = np.zeros((4, 3, 3))
    checked = 0
    for k in range(len(res.delta)):
        quat_to_rot(res.block_quat[k], rot)
        phi = math.asin(-rot[1, 2, 0])  # block 1 turns about y, its mid-span end going down
        if 0.3 * MM < phi * B < 0.9 * MM:
            np.testing.assert_allclose(res.load[k], strip_load(phi), rtol=0.03)
            checked += 1
    assert checked > 20
