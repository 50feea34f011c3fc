"""Tangents of both interface laws at the corners of their yield domains.

Newton converges at a corner of a piecewise smooth law only if the tangent there is an element
of its generalised (Bouligand) Jacobian: the limit of the Jacobians of one of the smooth
pieces that meet there (semismooth Newton, Sauter & Wieners 2011; corner tangents of
multi-surface return mapping, Lourenco & Rots 1997). Away from corners the tangents are checked
against central differences in ``test_static_kernels.py``; here the corners: the apex of the
fibre law's friction cone (springs at ``u_n = 0`` while sliding and twisting), the sliding
corner of seed 001's Eq. (A5) domain (sliding with a vanishing twist) and the seed's
shear-torsion return there. The resultant law's apex (zero shear rows next to elastic normal
rows, an element of neither side) is an open defect, not tested here.
"""

import numpy as np
import pytest

from dem.kernels.interface_law import STATE_SHEAR, resultant_law_one
from dem.kernels.shear_torsion_return import nearest_on_boundary
from tests.dem.test_static_kernels import K6, _fibre, _grid, _params

ENERGY = np.sqrt(np.outer(K6, K6))  # D / ENERGY: the tangent relative to the elastic one
SCALE = np.array([1e-6, 4e-6, 4e-6, 2e-4, 2e-4, 2e-4])  # motions of a loaded joint [m, rad]


def _resultant(q, alpha=1.5):
    f, qp, D = np.zeros(6), np.zeros(6), np.zeros((6, 6))
    _, state = resultant_law_one(q, np.zeros(6), False, _params(alpha=alpha), 0.0, f, qp, D)
    return f, D, state


def _central(law, q, h):
    """Central differences of ``law(q)[0]`` with steps ``h`` (6,)."""
    J = np.zeros((6, 6))
    for j in range(6):
        e = np.eye(6)[j] * h[j]
        J[:, j] = (law(q + e)[0] - law(q - e)[0]) / (2 * h[j])
    return J


def _apex_states(n, seed):
    """Joints at ``N = 0`` exactly (closed, unstressed), sliding and twisting."""
    rng = np.random.default_rng(seed)
    q = rng.standard_normal((n, 6)) * SCALE
    q[:, [0, 3, 4]] = 0.0
    return q


def test_fibre_apex_tangent_is_the_limit_of_sliding_under_compression():
    # the fibre law's springs at u_n = 0 take the sliding tangent of the compressed side
    pos, areas = _grid(0.21, 0.07, 4)

    def law(q):
        f, D, _ = _fibre(q, pos, areas)
        return f, D

    for q in _apex_states(20, 11):
        _, D = law(q)
        near = q.copy()
        near[0] = -1e-14
        J = _central(
            law, near, np.array([1e-16, *(1e-6 * np.abs(q[1:3])), 1e-18, 1e-18, 1e-6 * abs(q[5])])
        )
        np.testing.assert_allclose(D / ENERGY, J / ENERGY, atol=1e-5)


@pytest.mark.parametrize("alpha", [1.0, 1.43, 2.0, 2.56])
@pytest.mark.parametrize("twist", [1e-3, 1e-6, 1e-9])
def test_sliding_with_a_vanishing_twist_returns_smoothly(alpha, twist):
    # a trial 10 % beyond the Coulomb limit with a torsion of ``twist`` of the capacity M_u
    # (a sliding joint that barely twists: most joints of a wall sliding in its plane).
    # The nearest point of Eq. (A5)'s domain keeps 0 <= m <= m_t (the return never adds
    # torsion), and its derivatives are those of central differences; near the sliding
    # corner m(v) is ill-conditioned (m = M_u w^(1/alpha), w = 1 - (v/V_u)^2 loses its digits)
    v_u, m_u, a, b = 1.0, 0.3, 1.0, 0.1
    args = np.array([1.1 * v_u, twist * m_u, v_u, m_u])
    out = np.empty(10)
    nearest_on_boundary(*args, alpha, a, b, out)
    v, m = out[:2]
    assert 0.0 <= m <= args[1] and 0.0 < v <= v_u
    np.testing.assert_allclose((m / m_u) ** alpha + (v / v_u) ** 2, 1.0, atol=1e-12)
    for i in range(4):
        h = 1e-6 * args[i]
        plus, minus = np.empty(10), np.empty(10)
        nearest_on_boundary(*(args + h * np.eye(4)[i]), alpha, a, b, plus)
        nearest_on_boundary(*(args - h * np.eye(4)[i]), alpha, a, b, minus)
        fd = (plus[:2] - minus[:2]) / (2 * h)
        # (a quotient resolves v and m only to their round-off over 2 h)
        np.testing.assert_allclose([out[2 + i], out[6 + i]], fd, rtol=1e-4, atol=1e-6 + 1e-15 / h)


@pytest.mark.parametrize("alpha", [1.43, 2.0, 2.56])
def test_resultant_tangent_of_sliding_with_a_vanishing_twist(alpha):
    # the joint slides along t1 under 240 N of compression and twists by a vanishing angle:
    # its tangent against central differences (the torsion stiffness was noise there)
    rng = np.random.default_rng(3)
    for _ in range(20):
        q = np.array([-240.0 / K6[0], 1e-3, 1e-5 * rng.standard_normal(), 0, 0, 0])
        q[3:5] = 1e-9 * rng.standard_normal(2)  # closed (|M| > 0: its kink at 0 aside)
        q[5] = 10.0 ** rng.uniform(-12, -8)
        f, D, state = _resultant(q, alpha)
        assert state == STATE_SHEAR
        J = _central(lambda x: _resultant(x, alpha), q, 1e-4 * np.maximum(np.abs(q), 1e-9))
        np.testing.assert_allclose(D / ENERGY, J / ENERGY, atol=1e-5)
