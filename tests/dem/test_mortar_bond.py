"""A mortared joint of the resultant law loses its bond for good once it cracks.

The law caps the joint's normal stress at the tensile strength. Kept at that cap for ever, a
mortared joint that rocks carries the uniform tensile block of seed 001 Eq. (9) and hardens
towards it without end: on seed 001's Chee Liang walls the path rose at 0.04-0.26 % of its
initial slope after 400 steps on 4 walls of 6. A joint whose tensile cap covers half its area
(rocking, ``STATE_FLEXURE``) has cracked: it becomes a dry no-tension Coulomb joint, in that
trial already and for the rest of the path, as the fibre law's brittle springs do.
Expectations: closed forms of the dry joint, the rigid block's rocking limit, and a 1-D
quadrature of the capped stress for the cracking moment.
"""

import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from dem.kernels import interface_law as rk
from dem.kernels.interface_law import STATE_FLEXURE, resultant_law_one
from dem.scene import Scene, proportional_to_weight
from dem.static import StaticSettings, solve_collapse

KN = 2.4e9  # [Pa/m]
DIMS = np.array([0.2, 0.3])  # joint extents (l1, l2) [m]
AREA = DIMS[0] * DIMS[1]
J11, J22 = DIMS[1] * DIMS[0] ** 3 / 12, DIMS[0] * DIMS[1] ** 3 / 12


def _params(ft, c, mu=0.6):
    p = np.zeros(rk.N_PARAMS)
    p[rk.P_K : rk.P_K + 6] = [KN * AREA, KN * AREA, KN * AREA, KN * J22, KN * J11, KN * (J11 + J22)]
    p[rk.P_FT], p[rk.P_COHESION], p[rk.P_MU] = ft, c, mu
    p[rk.P_DIMS : rk.P_DIMS + 2] = DIMS
    p[rk.P_ALPHA], p[rk.P_FC], p[rk.P_AREA] = 1.5, np.inf, AREA
    p[rk.P_STIFF : rk.P_STIFF + 2] = KN, KN
    p[rk.P_N_CORNERS] = 4
    corners = 0.5 * DIMS * np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)])  # CCW
    p[rk.P_POLY : rk.P_POLY + 8] = corners.ravel()
    return p


def _law(q, broken, ft, c):
    f, qp, D = np.zeros(6), np.zeros(6), np.zeros((6, 6))
    brk, st = resultant_law_one(
        np.asarray(q, float), np.zeros(6), broken, _params(ft, c), 0.0, f, qp, D
    )
    return f, brk, st


def test_cracked_joint_is_dry_from_that_trial_on():
    sigma_t = 2e5
    ft, c = sigma_t * AREA, 0.6 * sigma_t * AREA
    # a rotation about t2 at a closed centroid, 3 times the elastic cracking rotation: the
    # tensile cap covers |y| > y_c = sigma_t / (k_n theta) = l / 6 on one side, less than half
    # the joint, so it stays bonded. Closed form: the compressed half's linear stress, the
    # tensile half's linear part and its capped block,
    # |M2| = k_n theta w (l/2)^3 / 3 + k_n theta w y_c^3 / 3 + sigma_t w ((l/2)^2 - y_c^2) / 2
    half, w = DIMS[0] / 2, DIMS[1]
    theta = 3.0 * sigma_t / (KN * half)
    y_c = sigma_t / (KN * theta)
    f, brk, st = _law([0, 0, 0, 0, theta, 0], False, ft, c)
    assert not brk and not st & STATE_FLEXURE
    m_expect = KN * theta * w * (half**3 + y_c**3) / 3 + sigma_t * w * (half**2 - y_c**2) / 2
    np.testing.assert_allclose(abs(f[4]), m_expect, rtol=1e-9)
    # rocked well beyond: the joint cracks and answers as the dry joint at the same motion,
    # closed form: a stress triangle over the contact length a from the compressed edge,
    # N = -k_n w theta a^2 / 2, |M2| = |N| (l / 2 - a / 3), with the centroid open by
    # dn = theta (l / 2 - a)
    theta, n_force = 0.05, -500.0
    a = math.sqrt(2 * abs(n_force) / (KN * DIMS[1] * theta))
    q = [theta * (DIMS[0] / 2 - a), 0, 0, 0, theta, 0]
    f, brk, st = _law(q, False, ft, c)
    assert brk and st & STATE_FLEXURE
    np.testing.assert_allclose(f[0], n_force, rtol=1e-9)
    np.testing.assert_allclose(abs(f[4]), abs(n_force) * (DIMS[0] / 2 - a / 3), rtol=1e-9)


def test_bond_does_not_come_back_on_unloading():
    sigma_t = 2e5
    ft, c = sigma_t * AREA, 0.6 * sigma_t * AREA
    # crack the joint by rocking about an edge (centroid open), keep the flag (what a commit
    # keeps), then load it back in
    _, brk, _ = _law([0.05 * 0.09, 0, 0, 0, 0.05, 0], False, ft, c)
    assert brk
    # an opening of half the cracking strain: the intact joint pulls back, the cracked one not
    dn = 0.5 * sigma_t / KN
    f_intact, *_ = _law([dn, 0, 0, 0, 0, 0], False, ft, c)
    np.testing.assert_allclose(f_intact[0], 0.5 * ft, rtol=1e-12)
    f_cracked, *_ = _law([dn, 0, 0, 0, 0, 0], brk, ft, c)
    np.testing.assert_allclose(f_cracked[:], 0.0, atol=1e-12 * ft)
    # sliding under compression: Coulomb without cohesion, V = mu |N|
    n_force = -1000.0
    f, *_ = _law([n_force / (KN * AREA), 1e-3, 0, 0, 0, 0], brk, ft, c)
    np.testing.assert_allclose(f[1], 0.6 * abs(n_force), rtol=1e-12)


def _box(x0, x1, z0, z1, depth=0.3):
    return np.array(
        [(x, y, z) for x in (x0, x1) for y in (-depth / 2, depth / 2) for z in (z0, z1)]
    )


def _cracking_multiplier(weight, sigma_t, b, depth, h):
    """lambda at which the base joint (b x depth, N = -weight) is capped over half its area:
    the linear stress sigma = s (y - y0) along the lever, capped at sigma_t from y = 0 on."""

    def force(t):  # N and M with the cap line at the centroid: y0 = -t, s = sigma_t / t
        s = sigma_t / t
        sig = lambda y: min(s * (y + t), sigma_t)  # noqa: E731
        n = depth * quad(sig, -b / 2, b / 2, points=[-t, 0.0])[0]
        m = depth * quad(lambda y: sig(y) * y, -b / 2, b / 2, points=[-t, 0.0])[0]
        return n, m

    t = brentq(lambda t: force(t)[0] + weight, 1e-6 * b, 0.5 * b - 1e-9, xtol=1e-14)
    return force(t)[1] / (weight * h / 2)


def test_mortared_block_drops_to_the_dry_rocking_limit():
    # a block (b / h = 0.4) on a fixed base through a mortared joint, pushed at its centroid
    # by lambda times its weight. Bonded, it carries more than the rigid block's b / h; it
    # cracks at the load of the capped stress field (the peak, found to within a step), and
    # from there the dry joint's rocking limit b / h (closed form, an upper bound of the dry
    # joint at every rotation) is all it has: lambda drops below it and creeps up to its
    # plateau. Before the fix the bond stayed and lambda rose on towards the tensile block's
    # (f_t A + W) b / (W h) = 1.22: 1.195 at the end, no drop.
    b, h, depth, sigma_t = 0.2, 0.5, 0.3, 2e4
    blocks = [_box(-1, 1, -0.2, 0), _box(-b / 2, b / 2, 0, h)]
    scene = Scene.from_convex_blocks(blocks, 2000.0, fixed=[0], mu=0.6)
    scene = scene.with_loads(live=proportional_to_weight(scene.assembly, (1.0, 0.0, 0.0)))
    weight = 2000.0 * 9.81 * b * depth * h
    # short steps to locate the brittle peak; no end on softening, a flat dry plateau
    settings = StaticSettings(
        interface_model="resultant",
        tensile_strength=sigma_t,
        load_step=0.002,
        max_step_factor=100.0,
        softening_drop=0.9,
        plateau_slope=1e-4,
        on_failure="return",
    )
    result = solve_collapse(scene, settings)
    lam_crack = _cracking_multiplier(weight, sigma_t, b, depth, h)
    assert lam_crack > 1.5 * b / h
    assert 0.97 * lam_crack <= result.lambda_max <= lam_crack * (1 + 1e-6)
    lams = result.pushover_lambda
    after = lams[int(np.argmax(lams)) + 1 :]
    assert len(after) > 10 and after.max() <= b / h * (1 + 1e-6)
    # on the dry rocking plateau: a few % below the rigid block (the compressed strip's width)
    assert result.collapsed and lams[-1] >= 0.95 * b / h
