r"""Cone constraints written with second-order cones, which Clarabel treats as symmetric cones.

Clarabel's steps on the nonsymmetric 3D power cone can shrink to nothing when hundreds of
such cones sit near their apexes (it ends ``InsufficientProgress``). A bound
:math:`0 \le t \le x^p y^{1-p}` with a rational exponent of small denominator is
second-order-cone representable exactly (Ben-Tal and Nemirovski 2001, Sec. 3.3; Alizadeh and
Goldfarb 2003, Sec. 2.3): :func:`power_mean` writes it as a short tree of rotated
second-order cones and keeps the power cone for other exponents.
"""

from __future__ import annotations

from fractions import Fraction

import cvxpy as cp
import numpy as np

__all__ = ["MAX_DENOMINATOR", "power_mean", "rational_exponent", "rotated_soc"]

MAX_DENOMINATOR = 8
"""Largest denominator of an exponent written with second-order cones (at most
``MAX_DENOMINATOR - 1`` rotated cones per element)."""


def rotated_soc(x, y, z) -> cp.Constraint:
    r""":math:`x^2 \le y z` with :math:`y, z \ge 0`, elementwise (``y`` or ``z`` may be
    constant arrays), as the second-order cone :math:`\|(2x, y - z)\| \le y + z`."""
    return cp.SOC(y + z, cp.vstack([2 * x, y - z]), axis=0)


def rational_exponent(p: float) -> Fraction | None:
    """``p`` as a fraction ``r/s`` with ``0 < r < s <= MAX_DENOMINATOR`` if it is one (to
    round-off), else None."""
    frac = Fraction(p).limit_denominator(MAX_DENOMINATOR)
    if 0 < frac < 1 and abs(float(frac) - p) <= 4 * np.finfo(float).eps:
        return frac
    return None


def power_mean(t, x, y, p: float, size: int) -> list[cp.Constraint]:
    r"""Constraints for :math:`|t| \le x^p y^{1-p}` with :math:`x, y \ge 0`, elementwise.

    Parameters
    ----------
    t, x, y : cvxpy expressions or arrays of shape (size,)
        ``x`` or ``y`` may be constant arrays.
    p : float
        Exponent in (0, 1).
    size : int
        Number of elements.

    Returns
    -------
    list of cvxpy constraints
        With ``p = r/s`` (:func:`rational_exponent`) and ``n = 2^k >= s``: a new
        :math:`g \ge |t|` and :math:`g^s \le x^r y^{s-r}`, written as the geometric mean
        :math:`g \le (x^r y^{s-r} g^{n-s})^{1/n}` over a binary tree of rotated second-order
        cones on the ``n`` leaves (a pair of one expression needs no cone:
        :math:`\sqrt{a a} = a`). For ``p = 2/3``: :math:`u^2 \le y g`, :math:`g^2 \le x u`.
        Otherwise one :class:`cvxpy.PowCone3D`.
    """
    frac = rational_exponent(p)
    if frac is None:
        return [cp.PowCone3D(x, y, t, p)]
    r, s = frac.numerator, frac.denominator
    g = cp.Variable(size, name="power_mean")
    n = 1 << (s - 1).bit_length()
    level = [x] * r + [y] * (s - r) + [g] * (n - s)
    cons = [t <= g, -t <= g]
    while len(level) > 2:
        nxt = []
        for a, b in zip(level[0::2], level[1::2], strict=True):
            if a is b:
                nxt.append(a)
                continue
            node = cp.Variable(size, name="power_mean_node")
            cons.append(rotated_soc(node, a, b))
            nxt.append(node)
        level = nxt
    cons.append(rotated_soc(g, level[0], level[1]))
    return cons
