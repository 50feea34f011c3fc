r"""Certificates of a solved static programme: feasibility, stationarity, gap.

For the conic programme :math:`\max c^T x` s.t. :math:`g_i(x) = G_i x + h_i \in K_i`, any
:math:`z_i \in K_i^*` with :math:`c + \sum_i G_i^T z_i = 0` gives the bound
:math:`\sum_i z_i^T h_i \ge c^T x` and the gap :math:`\sum_i z_i^T g_i(x)` (complementarity).
The checks below use only the returned primal point, cvxpy's dual values and the constraint
expressions, evaluated by us:

- primal feasibility: the largest constraint violation of the scaled programme, the
  equilibrium residual recomputed in SI from the interface forces, and the yield residual of
  every interface recomputed in SI from the model's definition;
- dual feasibility: membership of every dual in its dual cone, and stationarity probed at
  random points (the Lagrangian is affine, so its linear part must vanish);
- the duality gap :math:`\sum_i z_i^T h_i - c^T x`, relative to ``max(1, |c^T x|)``;
- the feasibility shift :math:`\sum_i |z_i|^T \operatorname{dist}(g_i(x), K_i)`: relaxing every
  constraint by its violation makes the returned point feasible, and moves the optimum by
  :math:`z_i^T \delta_i` to first order (the duals are the sensitivities of the optimum), so
  this is how far the objective of an infeasible point may lie from the optimum beyond the
  gap. Elementwise for zero and nonnegative cones, cone by cone (norm of the dual times the
  distance) for second-order cones, norm times distance for a power-cone constraint;
- the stationarity and dual-cone shifts: for any feasible :math:`x^*`,
  :math:`c^T x^* = \sum_i z_i^T h_i + r^T x^* - \sum_i z_i^T g_i(x^*)` with the Lagrangian's
  linear part :math:`r = c + \sum_i G_i^T z_i`, and :math:`-z_i^T g_i(x^*) \le
  \operatorname{dist}(z_i, K_i^*) \lVert g_i(x^*) \rVert`, so a dual off stationarity or off
  its cone lifts the optimum above the dual bound by at most :math:`|r|^T |x^*|` (the
  stationarity shift) plus :math:`\sum_i \operatorname{dist}(z_i, K_i^*) \lVert g_i(x^*)
  \rVert` (the dual-cone shift). Both are read at the returned point (first order, as the
  feasibility shift; it is the best estimate of :math:`x^*` there is), :math:`r` exactly (the
  gradient of the affine Lagrangian), each distance bounded by a correction that puts the
  dual into its cone.

cvxpy's conventions (checked in the tests on a catalogue of tiny problems): an ``Equality``
``a == b`` has :math:`g = a - b` and :math:`z = -y`; an ``Inequality`` ``a <= b`` has
:math:`g = b - a \ge 0` and :math:`z = y \ge 0`; ``SOC`` and ``PowCone3D`` have ``g`` = their
arguments and ``z`` = the dual value.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import cvxpy as cp
import numpy as np

__all__ = [
    "LOCAL_TOL",
    "Certificate",
    "conic_certificate",
    "yield_residual",
    "yield_violations",
    "equilibrium_residual",
    "local_residual",
]

LOCAL_TOL = 1e-3
"""Largest accepted residual of a block or interface relative to its own blocks' loads [-]
(:func:`local_residual`): a solution off by more than 0.1 % of a light block's load is
refused, whatever the total weight."""


@dataclass(frozen=True)
class Certificate:
    """Residuals of a solution (all relative, dimensionless).

    Attributes
    ----------
    primal_residual : float
        Largest constraint violation of the scaled programme.
    equilibrium_residual : float
        Largest ``|A_eq f + F_D + lambda F_L|`` over the free dofs, divided by the total
        weight ``W`` (forces) or ``W L`` (moments), recomputed in SI.
    yield_residual : float
        Largest violation of the interface strength, recomputed in SI from the forces,
        divided by ``W`` (``nan`` where not applicable).
    dual_cone_residual : float
        Largest violation of dual-cone membership, relative to the largest dual.
    stationarity : float
        Relative size of the linear part of the Lagrangian at random probes.
    duality_gap : float
        (dual bound - primal objective) / max(1, |primal objective|), scaled programme.
    complementarity : float
        Sum of ``z_i . g_i(x)``, relative as the gap.
    dual_objective : float
        The dual bound of the scaled programme.
    local_residual : float
        Equilibrium and strength residuals relative to the loads of the blocks concerned
        (:func:`local_residual`); not in :meth:`worst`, it has its own tolerance
        (:data:`LOCAL_TOL`). ``nan`` where not computed.
    feasibility_shift : float
        First-order change of the optimum that the primal violations can hide (module
        notes), in the unit of ``dual_objective``; ``nan`` where not computed.
    stationarity_shift : float
        ``|r|^T |x|``, how far the optimum may lie above ``dual_objective`` for duals that
        are not exactly stationary (module notes), in the unit of ``dual_objective``; ``nan``
        where not computed.
    dual_cone_shift : float
        The same for duals outside their dual cones (module notes); ``nan`` where not
        computed.
    """

    primal_residual: float
    equilibrium_residual: float
    yield_residual: float
    dual_cone_residual: float
    stationarity: float
    duality_gap: float
    complementarity: float
    dual_objective: float
    local_residual: float = float("nan")
    feasibility_shift: float = float("nan")
    stationarity_shift: float = float("nan")
    dual_cone_shift: float = float("nan")

    def worst(self, feasibility: bool = False) -> float:
        """Largest residual; with ``feasibility`` only the primal ones (for a programme whose
        multiplier is fixed, a point is proved by its own residuals, whatever its duals)."""
        vals = [self.primal_residual, self.equilibrium_residual, self.yield_residual]
        if not feasibility:
            vals += [self.dual_cone_residual, self.stationarity, abs(self.duality_gap)]
        return float(max(v for v in vals if np.isfinite(v)))

    def to_dict(self) -> dict:
        return asdict(self)


def _pairs(constraint) -> list[tuple[np.ndarray, list, str]]:
    """(dual z, list of argument expressions, cone kind) of one cvxpy constraint."""
    dv = constraint.dual_value
    if isinstance(constraint, cp.constraints.Equality):
        return [
            (
                -np.atleast_1d(np.asarray(dv, float)),
                [constraint.args[0] - constraint.args[1]],
                "zero",
            )
        ]
    if isinstance(constraint, cp.constraints.Inequality):
        return [
            (
                np.atleast_1d(np.asarray(dv, float)),
                [constraint.args[1] - constraint.args[0]],
                "nonneg",
            )
        ]
    if isinstance(constraint, cp.constraints.SOC):
        return [(dv, list(constraint.args[:2]), "soc")]
    if isinstance(constraint, cp.constraints.PowCone3D):
        return [(dv, list(constraint.args[:3]), "pow")]
    raise TypeError(f"no certificate rule for constraint type {type(constraint).__name__}")


def _flat(values) -> np.ndarray:
    return np.concatenate([np.ravel(np.asarray(v, float)) for v in values])


def _soc_parts(constraint, values) -> tuple[np.ndarray, np.ndarray]:
    """Cone-wise (t, X) with X as (n_cones, k)."""
    t = np.ravel(np.asarray(values[0], float))
    x = np.asarray(values[1], float)
    if constraint.axis == 0:
        x = x.reshape(-1, len(t)).T if x.ndim > 1 or len(t) > 1 else x.reshape(1, -1)
    else:
        x = x.reshape(len(t), -1)
    return t, x


def _dual_cone_violation(constraint, kind, z) -> tuple[np.ndarray, float]:
    """Per cone, a bound on the distance of the dual ``z`` from its dual cone (the size of a
    correction that puts it in; 0 inside), and the size of the dual."""
    if kind == "zero":
        return np.zeros(0), float(np.max(np.abs(z), initial=0.0))
    if kind == "nonneg":
        return np.maximum(-z, 0.0), float(np.max(np.abs(z), initial=0.0))
    if kind == "soc":
        # (t, x) -> (max(t, |x|), x) is in the cone and moves z by (|x| - t)+
        t, x = _soc_parts(constraint, z)
        viol = np.linalg.norm(x, axis=1) - t
        return np.maximum(viol, 0.0), float(np.max(np.abs(t), initial=0.0))
    a = constraint.alpha.value if hasattr(constraint.alpha, "value") else constraint.alpha
    a = np.ravel(np.asarray(a, float))
    u, v, w = (np.ravel(np.asarray(zz, float)) for zz in z)
    u_, v_ = np.maximum(u, 0), np.maximum(v, 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        gm = (u_ / a) ** a * (v_ / (1 - a)) ** (1 - a)
    viol = np.maximum.reduce([np.abs(w) - gm, -u, -v])
    scale = max(np.max(np.abs(u), initial=0.0), np.max(np.abs(v), initial=0.0))
    # shrinking |w| to gm, or (u, v, w) -> (u+, v+, 0), each move by at most sqrt(3) viol
    return np.sqrt(3.0) * np.maximum(viol, 0.0), float(scale)


def conic_certificate(problem: cp.Problem, n_probes: int = 2, seed: int = 0) -> dict:
    """Gap, complementarity, dual-cone and stationarity residuals of a solved maximisation.

    Parameters
    ----------
    problem : cvxpy.Problem
        Solved, with ``Maximize`` objective and constraint types Equality, Inequality, SOC,
        PowCone3D.
    n_probes : int
        Random points at which stationarity is probed.

    Returns
    -------
    dict
        Keys ``primal_residual``, ``dual_cone_residual``, ``stationarity``, ``duality_gap``,
        ``complementarity``, ``dual_objective``, ``feasibility_shift``,
        ``stationarity_shift`` and ``dual_cone_shift`` (module notes; the last four in the
        unit of the objective).
    """
    variables = problem.variables()
    saved = [v.value for v in variables]
    objective = float(problem.objective.value)
    pairs = [(c, z, args, kind) for c in problem.constraints for z, args, kind in _pairs(c)]
    comp, _ = _pairing(pairs, _g_values(pairs))
    for v in variables:
        v.save_value(np.zeros(v.shape))
    g_0 = _g_values(pairs)
    dual_obj, _ = _pairing(pairs, g_0)
    stat = _stationarity(problem, variables, pairs, g_0, n_probes, np.random.default_rng(seed))
    for v, val in zip(variables, saved, strict=True):
        v.save_value(val)
    primal, shift = _primal_residual_and_shift(pairs)
    denom = max(1.0, abs(objective))
    return {
        "primal_residual": primal,
        "dual_cone_residual": _dual_cone_residual(pairs),
        "stationarity": stat,
        "duality_gap": (dual_obj - objective) / denom,
        "complementarity": comp / max(denom, 1e-300),
        "dual_objective": dual_obj,
        "feasibility_shift": float(shift),
        "stationarity_shift": _stationarity_shift(problem, pairs),
        "dual_cone_shift": _dual_cone_shift(pairs),
    }


def _g_values(pairs: list) -> list[list[np.ndarray]]:
    """The constraint arguments ``g`` of every (constraint, dual, args, kind) pair at the
    variables' present values."""
    return [[np.asarray(a.value, float) for a in args] for _, _, args, _ in pairs]


def _pairing(pairs: list, gs: list) -> tuple[float, float]:
    """``(sum z . g, sum |z| . |g|)`` over the pairs, a scalar dual broadcast over its
    argument."""
    total = 0.0
    mags = 0.0
    for (_c, z, _, _kind), g in zip(pairs, gs, strict=True):
        zf = _flat(z if isinstance(z, list) else [z])
        gf = _flat(g)
        if zf.size == 1 and gf.size > 1:
            zf = np.full(gf.size, zf[0])
        total += float(zf @ gf)
        mags += float(np.abs(zf) @ np.abs(gf))
    return total, mags


def _stationarity(problem, variables, pairs, g_0, n_probes: int, rng) -> float:
    """Largest relative residual of ``f(x) + sum z . (g(x) - g(0)) = 0`` (the Lagrangian's
    linear part vanishes) over ``n_probes`` random points ``x``; leaves the variables at the
    last probe."""
    stat = 0.0
    for _ in range(n_probes):
        probes = [rng.standard_normal(v.shape) for v in variables]
        for v, pv in zip(variables, probes, strict=True):
            v.save_value(pv)
        obj_r = float(problem.objective.expr.value)
        g_r = _g_values(pairs)
        diff = [
            [a - b for a, b in zip(gr, g0, strict=True)] for gr, g0 in zip(g_r, g_0, strict=True)
        ]
        lin, mag = _pairing(pairs, diff)
        stat = max(stat, abs(obj_r + lin) / max(mag + abs(obj_r), 1e-300))
    return stat


def _dual_cone_residual(pairs: list) -> float:
    """Largest distance of a dual from its dual cone, relative to the largest dual."""
    cone_viol, zmax = 0.0, 0.0
    for c, z, _, kind in pairs:
        viol, scale = _dual_cone_violation(c, kind, z)
        cone_viol = max(cone_viol, float(np.max(viol, initial=0.0)))
        zmax = max(zmax, scale)
    return cone_viol / max(zmax, 1e-300)


def _stationarity_shift(problem: cp.Problem, pairs: list) -> float:
    """``|r|^T |x|`` at the returned point, ``r`` the gradient of the Lagrangian
    ``c^T x + sum z . g(x)`` (affine, so exact at any point; module notes)."""
    terms = [problem.objective.expr]
    for _c, z, args, _kind in pairs:
        zs = z if isinstance(z, list) else [z] * len(args)
        for zz, a in zip(zs, args, strict=True):
            zz = np.asarray(zz, float)
            weight = zz.reshape(a.shape) if zz.size == a.size else float(np.ravel(zz)[0])
            terms.append(cp.sum(cp.multiply(weight, a)))
    grad = cp.sum(cp.hstack(terms)).grad
    total = 0.0
    for v in problem.variables():
        r = grad.get(v)
        if r is None:
            continue
        r = np.ravel(r.toarray() if hasattr(r, "toarray") else np.asarray(r, float))
        total += float(np.abs(r) @ np.abs(np.ravel(v.value, order="F")))
    return total


def _dual_cone_shift(pairs: list) -> float:
    """``sum_i dist(z_i, K_i*) |g_i(x)|`` at the returned point (module notes), the distance
    bounded cone by cone (:func:`_dual_cone_violation`) and paired by Cauchy-Schwarz."""
    total = 0.0
    for c, z, args, kind in pairs:
        viol, _ = _dual_cone_violation(c, kind, z)
        if np.any(viol > 0):
            total += float(np.linalg.norm(viol) * np.linalg.norm(_flat([a.value for a in args])))
    return total


def _primal_residual_and_shift(pairs: list) -> tuple[float, float]:
    """Largest constraint violation at the solution, and the feasibility shift ``sum |z|
    dist(g, K)`` (module notes)."""
    # cvxpy's cone projection divides by |x| = 0 before masking those entries out
    with np.errstate(divide="ignore", invalid="ignore"):
        violations = [np.ravel(np.asarray(c.violation(), float)) for c, _, _, _ in pairs]
    primal = max((float(np.max(v, initial=0.0)) for v in violations), default=0.0)
    shift = sum(_shift(c, kind, z, v) for (c, z, _, kind), v in zip(pairs, violations, strict=True))
    return primal, shift


def _shift(constraint, kind: str, z, violation: np.ndarray) -> float:
    """``sum |z| dist(g, K)`` of one constraint (module notes): elementwise where the
    violation has one entry per dual entry, cone by cone for second-order cones, and by
    Cauchy-Schwarz (norm times norm) otherwise."""
    if kind == "soc":
        t, x = _soc_parts(constraint, z)
        dual_norm = np.sqrt(t**2 + np.sum(x**2, axis=1))
        if dual_norm.size == violation.size:
            return float(dual_norm @ violation)
    zf = _flat(z if isinstance(z, list) else [z])
    if zf.size == 1:  # one dual for every entry (a broadcast scalar)
        return float(abs(zf[0]) * np.sum(violation))
    if zf.size == violation.size:
        return float(np.abs(zf) @ violation)
    return float(np.linalg.norm(zf) * np.linalg.norm(violation))


def equilibrium_residual(a_eq, f, dead, live, lam, row_scale) -> float:
    """``max |row_scale * (A_eq f + F_D + lambda F_L)|`` over the free dofs [-].

    Parameters
    ----------
    a_eq : (n_free, 6 m) sparse
    f : (6 m,) float
        Interface forces [N, N m].
    dead, live : (n_free,) float
        [N, N m].
    lam : float
    row_scale : (n_free,) float
        ``1/W`` on force rows, ``1/(W L)`` on moment rows.
    """
    r = a_eq @ f + dead + lam * live
    return float(np.max(np.abs(r * row_scale), initial=0.0))


def yield_residual(model: str, forces: np.ndarray, mu, c_t, tensile, weight: float, **kw) -> float:
    """Largest violation of the interface strength in SI (:func:`yield_violations`), divided
    by ``W`` [-]."""
    viol = yield_violations(model, forces, mu, c_t, tensile, **kw)
    return float(np.max(viol, initial=0.0)) / weight


def yield_violations(
    model: str,
    forces: np.ndarray,
    mu: np.ndarray,
    c_t: np.ndarray,
    tensile: np.ndarray,
    vertex_forces: np.ndarray | None = None,
    vertex_mu: np.ndarray | None = None,
    alpha: float | None = None,
    rocking: tuple | None = None,
) -> np.ndarray:
    r"""Violation of the interface strength in SI [N], per corner (vertex model) or per
    interface (resultant model); <= 0 where it holds.

    Vertex model: :math:`p_j \ge 0`, :math:`\|s_j\| \le \mu p_j`. Where ``mu`` is inf (no
    sliding) only the sign of the normal force is checked. Resultant model:
    :math:`c = f_t - N \ge 0`, :math:`\|V\| \le \mu c`, :math:`|M_3| \le c_T\mu c`, the
    interaction :math:`(|M_3|/c_T\mu c)^\alpha + \|V\|^2/(\mu c)^2 \le 1` (as a force:
    :math:`\mu c` times the excess of the left side's root), and the centre of pressure in the
    polygon (``rocking = (G, h, owner)`` of :func:`limit.matrices.rocking_constraints`).
    """
    if model == "vertex":
        p, s = vertex_forces[:, 0], vertex_forces[:, 1:]
        fin = np.isfinite(vertex_mu)
        slip = np.where(fin, np.linalg.norm(s, axis=1) - np.where(fin, vertex_mu, 0.0) * p, 0.0)
        return np.maximum(-p, slip)
    n, v, m = forces[:, 0], forces[:, 1:3], forces[:, 3:]
    c = tensile - n
    vn = np.linalg.norm(v, axis=1)
    fin = np.isfinite(mu)  # mu = inf: no sliding, nothing to check but c >= 0
    mu = np.where(fin, mu, 0.0)
    viol = [-c, np.where(fin, vn - mu * c, 0.0), np.where(fin, np.abs(m[:, 2]) - c_t * mu * c, 0.0)]
    if alpha is not None:
        cap = np.where(fin, mu * c, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            lhs = (np.abs(m[:, 2]) / (c_t * cap)) ** alpha + (vn / cap) ** 2
        lhs = np.where(cap > 0, lhs, 0.0)
        viol.append(cap * (np.sqrt(np.maximum(lhs, 0)) - 1.0))
    if rocking is not None:
        g, h, owner = rocking
        ge = g @ forces.ravel() - h * c[owner]
        ln = np.max(h, initial=0.0)  # no edge at all without interfaces
        viol.append(np.bincount(owner, weights=np.maximum(ge, 0) / ln, minlength=len(c)))
    return np.maximum.reduce(viol)


def local_residual(
    block_residual: np.ndarray,
    interface_violation: np.ndarray,
    block_a: np.ndarray,
    block_b: np.ndarray,
    block_load: np.ndarray,
) -> float:
    """Residuals relative to the loads of the blocks concerned, not to the total weight [-].

    The certificate's residuals are relative to the total weight ``W``, so a block much
    lighter than ``W`` (a chip of 1e-7 W) can be out of equilibrium or overload its joint by
    a large part of its own weight unseen. Here each free block's equilibrium residual
    (force rows, and moment rows divided by its size) is divided by its own load, and each
    interface's strength violation by the load of the lighter of its two free blocks.

    Parameters
    ----------
    block_residual : (n_blocks,) float
        Largest equilibrium residual of each block [N] (0 for fixed blocks).
    interface_violation : (m,) float
        Largest strength violation of each interface [N].
    block_a, block_b : (m,) int
    block_load : (n_blocks,) float
        Size of each block's own loads ``|F_D| + lambda |F_L|`` [N]; inf for fixed blocks
        (never the lighter one) and 0 for unloaded blocks (not checked).
    """
    load = np.where(block_load > 0, block_load, np.inf)
    worst = float(np.max(block_residual / load, initial=0.0))
    lighter = np.minimum(load[block_a], load[block_b]) if len(block_a) else np.zeros(0)
    return max(worst, float(np.max(interface_violation / lighter, initial=0.0)))
