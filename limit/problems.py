r"""Static (lower-bound form) limit-analysis programs of rigid-block assemblies, in cvxpy.

The static problem of every free block (seed 001, Sec. 2 and Eq. 6 with
``F_ext = F_D + lambda F_L``; Livesley 1978; Orduna and Lourenco 2005a):

.. math::

    \max_{\lambda, f}\ \lambda \quad \text{s.t.} \quad
    A_{eq} f + F_D + \lambda F_L = 0, \qquad f_k \in \mathcal{Y}_k \ \ \forall k,
    \qquad \lambda \ge 0,

with ``A_eq = -H^T`` (:mod:`limit.matrices`) and one convex admissible set
:math:`\mathcal{Y}_k` per interface. Two parametrisations of :math:`\mathcal{Y}_k`:

``"vertex"``
    forces :math:`(p_j, s_j)` at each corner of the interface polygon with
    :math:`p_j \ge 0` and the exact Coulomb cone :math:`\|s_j\| \le \mu p_j`; ``f = B x``. For
    a rigid no-tension Coulomb joint this is the exact interface.
``"resultant"``
    uniform-pressure resultants (Orduna and Lourenco 2005a; seed 001, Eq. 9-14) with
    :math:`c = -N + f_t \ge 0`, the centre of pressure :math:`(M_2, -M_1)/c` inside the polygon,
    and the torsion-shear interaction (seed 001, Eq. 14 and A5)

    .. math::

        \left(\frac{|M_3|}{c_T \mu c}\right)^{\alpha}
        + \frac{V_1^2 + V_2^2}{(\mu c)^2} \le 1,

    which is convex for :math:`\alpha \ge 1` and is written exactly as
    :math:`|M_3| \le (c_T\mu\tau_1)^{1/\alpha}(c_T\mu c)^{1-1/\alpha}`, one rotated
    second-order cone :math:`\|V\|^2 \le \mu^2 \tau_2 c` and :math:`\tau_1 + \tau_2 \le c`;
    the first is a few rotated second-order cones where ``1/alpha`` is a fraction of small
    denominator, as the seed's 1.5, and one power cone otherwise
    (:func:`limit.cones.power_mean`; Clarabel's symmetric-cone steps stall less).
    It contains the Coulomb circle and :math:`|M_3| \le c_T \mu c`. ``torsion="independent"``
    keeps only these two (no interaction: a larger set). Like the seed's law it measures the
    torsion about the interface centroid, whereas with an eccentric normal force the friction
    acts about the centre of pressure ``e``; the shear then carries the torque
    :math:`e \times V` for free. That coupling is bilinear, so this model is not contained in
    the exact (vertex) set and can exceed it on walls whose rocking joints also slide.

A tensile strength :math:`\bar\sigma_t` shifts the Coulomb cone apex (seed 001, Eq. 8-10,
:math:`c = \bar\sigma_t \mu`): both models carry it exactly by shifting the normal force by
:math:`f_t = \bar\sigma_t A`. An optional compressive strength :math:`f_c` (rectangular
interfaces) bounds the uniform stress block on the reduced rectangle,
:math:`c \le f_c (l_u - 2|e_u|)(l_v - 2|e_v|)`, i.e. :math:`c^3 \le f_c\,a\,b` with ``a, b``
affine in ``(c, M_1, M_2)``: three rotated second-order cones (convex, exact).

The programme is scaled (forces by the total dead weight ``W``, moments by ``W L`` with ``L``
the median interface size, lambda by ``W / |F_L|``) so that Clarabel's tolerances are relative
to the structure. The friction coefficients (and, for the fixed-capacity estimates, the
friction capacities) are cvxpy Parameters: sweeps re-solve without re-compiling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from dem.scene import Scene
from limit.cones import power_mean, rotated_soc
from limit.matrices import (
    equilibrium_matrix,
    interface_friction,
    interface_rectangles,
    interface_vertices,
    mean_distance_polygons,
    rocking_constraints,
    torsion_coefficient,
    vertex_force_matrix,
)

__all__ = [
    "LimitSettings",
    "checked_inputs",
    "checked_settings",
    "StaticProblem",
    "KinematicProblem",
    "build_static_problem",
    "build_kinematic_problem",
    "MODELS",
]

MODELS = ("vertex", "resultant")
_TORSION = ("interaction", "independent")
_FRICTION = ("coulomb", "fixed_capacity")


def _choice(name: str, value, options: tuple) -> None:
    if not isinstance(value, str) or value not in options:
        raise ValueError(f"{name} must be one of {options}, got {value!r}")


def _real(
    name: str,
    value,
    low: float,
    high: float = math.inf,
    strict: bool = False,
    allow_inf: bool = False,
    note: str = "",
) -> None:
    """A real number (not a bool) with ``low <(=) value <(=) high``, finite unless
    ``allow_inf`` (then ``+inf`` only)."""
    ok = isinstance(value, int | float | np.integer | np.floating) and not isinstance(
        value, bool | np.bool_
    )
    if ok:
        v = float(value)
        ok = not math.isnan(v) and (math.isfinite(v) or allow_inf and v > 0)
        ok = ok and (v > low if strict else v >= low) and (v < high if strict else v <= high)
    if not ok:
        lo = f"> {low:g}" if strict else f">= {low:g}"
        hi = "" if math.isinf(high) else f" and {'<' if strict else '<='} {high:g}"
        fin = "" if allow_inf else " and finite"
        what = " ".join(x for x in (f"a number {lo}{hi}{fin}", note) if x)
        raise ValueError(f"{name} must be {what}, got {value!r}")


def _integer(name: str, value, low: int, note: str = "") -> None:
    if not isinstance(value, int | np.integer) or isinstance(value, bool | np.bool_) or value < low:
        raise ValueError(f"{name} must be an integer >= {low} ({note}), got {value!r}")


@dataclass(frozen=True)
class LimitSettings:
    """Settings of the static limit-analysis programme.

    Parameters
    ----------
    interface_model : {"vertex", "resultant"}
        Interface parametrisation (module notes). Default ``"vertex"`` (exact rigid joint).
    mu : float, optional
        Friction coefficient of every interface [-], ``inf`` for no sliding; default the
        scene's (smaller of the two blocks).
    torsion : {"interaction", "independent"}
        Resultant model only: the torsion-shear interaction cone (default) or the Coulomb
        circle and the pure-torsion bound without interaction.
    torsion_alpha : float
        Exponent alpha of the interaction (seed 001, Eq. 14: 1.5 for masonry joints) [-], >= 1.
    friction_polygon : int, optional
        If given, replace every friction circle by the inscribed regular polygon with this
        many sides, corners at the angles ``2 pi j / k`` from the interface axis ``t1`` (a
        smaller set: lambda can only decrease; doubling ``k`` can only raise it back towards
        the exact value). Default None: exact cones. A
        circumscribed polygon (facets tangent to the circle, as some public codes use)
        enlarges the set and is never safe; it is deliberately not offered.
    tensile_strength : float
        Joint tensile strength [Pa] (0 for dry joints).
    compressive_strength : float, optional
        Joint compressive strength [Pa]; None for unlimited.
    tol : float
        Clarabel's gap and feasibility tolerances (absolute and relative) [-].
    max_iter : int
        Clarabel iteration limit.
    cert_tol : float
        Largest accepted relative certificate residual (equilibrium, cones, gap) [-].
    clarabel : dict
        Further Clarabel settings (e.g. ``{"direct_solve_method": "qdldl"}``).
    torsion_bending : bool
        Resultant model, associated problem only: reduce the torsion capacity with bending,
        ``|M3|`` below the tangent plane at ``e = 0`` of ``mu c c_T(l_u - 2|e_u|, l_v -
        2|e_v|)``, the capacity of the reduced rectangle (rectangular interfaces; seed 001
        Fig. 10, Orduna and Lourenco 2005a). Default False.
    dead_load_check : bool
        Before a multiplier is returned, prove that the dead load alone is carried
        (:func:`limit.stands`: one more solve of the same size). Without it, a structure that
        stands only while some live load props it would get the largest admissible
        multiplier of that interval, which is no collapse multiplier. Default True; switch it
        off only for a scene already known to stand.
    """

    interface_model: str = "vertex"
    mu: float | None = None
    torsion: str = "interaction"
    torsion_alpha: float = 1.5
    friction_polygon: int | None = None
    tensile_strength: float = 0.0
    compressive_strength: float | None = None
    tol: float = 1e-9
    max_iter: int = 400
    cert_tol: float = 1e-6
    clarabel: dict = field(default_factory=lambda: {"direct_solve_method": "qdldl"})
    torsion_bending: bool = False
    dead_load_check: bool = True

    def __post_init__(self) -> None:
        _choice("interface_model", self.interface_model, MODELS)
        _choice("torsion", self.torsion, _TORSION)
        if self.mu is not None:
            _real("mu", self.mu, low=0.0, allow_inf=True, note="(inf: no sliding)")
        _real("torsion_alpha", self.torsion_alpha, low=1.0, note="(convexity)")
        if self.friction_polygon is not None:
            _integer("friction_polygon", self.friction_polygon, low=3, note="sides")
        _real("tensile_strength", self.tensile_strength, low=0.0, note="[Pa]")
        if self.compressive_strength is not None:
            _real(
                "compressive_strength",
                self.compressive_strength,
                low=0.0,
                strict=True,
                note="[Pa] (None for unlimited)",
            )
        _real("tol", self.tol, low=0.0, high=1e-3, strict=True)
        _integer("max_iter", self.max_iter, low=1, note="Clarabel iterations")
        _real("cert_tol", self.cert_tol, low=0.0, high=1e-1, strict=True)
        if not isinstance(self.clarabel, dict) or not all(
            isinstance(k, str) for k in self.clarabel
        ):
            raise ValueError(
                f"clarabel must be a dict of Clarabel settings by name, got {self.clarabel!r}"
            )
        for name in ("torsion_bending", "dead_load_check"):
            if not isinstance(getattr(self, name), bool | np.bool_):
                raise ValueError(f"{name} must be True or False, got {getattr(self, name)!r}")

    def with_(self, **kw) -> LimitSettings:
        """A copy with some fields changed."""
        return replace(self, **kw)

    def to_dict(self) -> dict:
        """Every setting by name (for results and JSON)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def checked_settings(settings) -> LimitSettings:
    """``settings``, or the defaults for None; a TypeError naming any other type."""
    if settings is None:
        return LimitSettings()
    if not isinstance(settings, LimitSettings):
        raise TypeError(f"settings must be a limit.LimitSettings, got {type(settings).__name__}")
    return settings


def checked_inputs(scene, settings) -> LimitSettings:
    """:func:`checked_settings`, after a TypeError naming a scene that is no Scene."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a dem.scene.Scene, got {type(scene).__name__}")
    return checked_settings(settings)


@dataclass(eq=False)
class StaticProblem:
    """A compiled static programme and what is needed to read its solution in SI.

    Attributes
    ----------
    problem : cvxpy.Problem
    lam : cvxpy.Variable
        Scaled multiplier; ``lambda = lam_scale * lam``.
    equilibrium : cvxpy.Constraint
        ``A x + F_D + lam F_L == 0`` over the free dofs; its dual gives the block velocities.
    mu : cvxpy.Parameter
        Friction coefficient per friction cone (per corner or per interface).
    capacity : dict of cvxpy.Parameter
        Fixed friction capacities (``friction="fixed_capacity"`` only), scaled.
    model, friction : str
    scene : Scene
    settings : LimitSettings
    free : (6 n_blocks,) bool
        Free dofs (rows kept).
    a_eq : (n_free, 6 m) csr_matrix
        ``A_eq`` restricted to the free dofs, SI.
    f_map : (6 m, n_x) csr_matrix
        ``f = f_map x + f_offset`` in SI from the stacked unknowns ``x`` (scaled).
    f_offset : (6 m,) float
        Tension shift ``(f_t, 0, ...)`` per interface [N] (vertex model; zero for the
        resultant model, whose ``N`` is the full normal force).
    x_vars : list of cvxpy.Variable
        The unknowns stacked in ``x`` (in this order).
    dead, live : (n_free,) float
        SI loads on the free dofs.
    weight, length, lam_scale : float
        Scales ``W`` [N], ``L`` [m] and ``W/|F_L|``.
    row_scale : (n_free,) float
        Equilibrium row ``i`` is multiplied by ``row_scale[i]``.
    interfaces, vertex_iface, vertex_local, mu_interface, c_t
        Geometry and strength data for post-processing.
    """

    problem: cp.Problem
    lam: cp.Variable
    equilibrium: cp.Constraint
    mu: cp.Parameter
    capacity: dict
    model: str
    friction: str
    scene: Scene
    settings: LimitSettings
    free: np.ndarray
    a_eq: sp.csr_matrix
    f_map: sp.csr_matrix
    f_offset: np.ndarray
    x_vars: list
    dead: np.ndarray
    live: np.ndarray
    weight: float
    length: float
    lam_scale: float
    row_scale: np.ndarray
    interfaces: object
    vertex_iface: np.ndarray
    vertex_local: np.ndarray
    mu_interface: np.ndarray
    c_t: np.ndarray
    extra: dict = field(default_factory=dict)

    @property
    def n_cones(self) -> int:
        return int(self.mu.size)

    def x_value(self) -> np.ndarray:
        """Stacked scaled unknowns at the solution."""
        return np.concatenate([np.ravel(v.value) for v in self.x_vars])

    def interface_forces(self) -> np.ndarray:
        """(m, 6) ``(N, V1, V2, M1, M2, M3)`` [N, N m] at the solution."""
        return (self.f_map @ self.x_value() + self.f_offset).reshape(-1, 6)

    def set_friction(self, mu_interface: np.ndarray) -> None:
        """Set the friction coefficient of every interface [-] without re-compiling (one
        value per cone: per corner in the vertex model). ``inf`` (and the interfaces built
        with ``mu = inf``) keep no cone: the Parameter holds 0 there."""
        mu = np.where(np.isfinite(mu_interface) & np.isfinite(self.mu_interface), mu_interface, 0.0)
        self.mu.value = mu[self.vertex_iface] if self.model == "vertex" else mu


def _scales(scene: Scene, free: np.ndarray, interfaces) -> tuple[float, float, np.ndarray]:
    dead = scene.dead_wrench.reshape(-1, 6)
    fr = free.reshape(-1, 6)
    weight = float(np.sum(np.linalg.norm(np.where(fr[:, :3], dead[:, :3], 0.0), axis=1)))
    if weight <= 0:
        live = scene.loads.live_wrench
        weight = float(np.sum(np.linalg.norm(np.where(fr[:, :3], live[:, :3], 0.0), axis=1)))
    if weight <= 0:
        weight = 1.0
    length = float(np.median(np.sqrt(interfaces.area))) if interfaces.n_interfaces else 1.0
    rs = np.empty((len(dead), 6))
    rs[:, :3] = 1.0 / weight
    rs[:, 3:] = 1.0 / (weight * length)
    return weight, length, rs.ravel()[free]


def _subset(finite: np.ndarray):
    """Selector of the friction cones with finite mu: the identity when all are finite (no
    index atom in the programme), an index otherwise, None when none is."""
    if not finite.any():  # also no cone at all (a scene without interfaces)
        return None
    if finite.all():
        return lambda e: e
    idx = np.flatnonzero(finite)
    return lambda e: e[idx]


def _polygon_directions(k: int) -> tuple[np.ndarray, float]:
    """Facet normals and apothem (circle radius 1) of the inscribed regular ``k``-gon whose
    corners lie at the angles ``2 pi j / k`` from ``t1``: a ``k``-gon lies inside the
    ``2k``-gon, so refining the polygon can only raise lambda."""
    ang = 2 * np.pi * (np.arange(k) + 0.5) / k
    return np.stack([np.cos(ang), np.sin(ang)], axis=1), math.cos(math.pi / k)


@dataclass(eq=False)
class _ScaledData:
    """The scene's data of a static programme, SI and scaled (see :class:`StaticProblem`).

    ``d_dead`` and ``d_live`` are the scaled dead load (with the vertex model's tension shift)
    and live load on the free dofs; ``s_rows`` the row scaling; ``f_t`` (m,) the tension
    capacity ``sigma_t A`` [N] per interface; ``mu_interface`` (m,) the friction coefficients."""

    interfaces: object
    free: np.ndarray
    a_eq: sp.csr_matrix
    dead: np.ndarray
    live: np.ndarray
    weight: float
    length: float
    row_scale: np.ndarray
    lam_scale: float
    mu_interface: np.ndarray
    c_t: np.ndarray
    vertex_iface: np.ndarray
    vertex_local: np.ndarray
    f_t: np.ndarray
    f_offset: np.ndarray
    s_rows: sp.spmatrix
    d_dead: np.ndarray
    d_live: np.ndarray


@dataclass(eq=False)
class _Programme:
    """The model-specific part of a static programme: its equilibrium, its other constraints
    (in order), the unknowns ``x_vars`` with their map ``f_map`` to SI interface forces, the
    friction Parameter, the fixed-capacity Parameters and model notes."""

    equilibrium: cp.Constraint
    constraints: list
    x_vars: list
    f_map: sp.spmatrix
    mu: cp.Parameter
    capacity: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)


def build_static_problem(
    scene: Scene, settings: LimitSettings | None = None, friction: str = "coulomb"
) -> StaticProblem:
    """Compile the static programme of a scene.

    Parameters
    ----------
    scene : Scene
        Blocks, supports, dead load ``scene.dead_wrench`` and live pattern
        ``scene.loads.live_wrench`` [N, N m].
    settings : LimitSettings, optional
    friction : {"coulomb", "fixed_capacity"}
        ``"coulomb"``: capacities ``mu c`` (the associated problem). ``"fixed_capacity"``:
        capacities are Parameters set by the caller (the non-associated iteration of
        :mod:`limit.estimates`); each starts at zero.

    Returns
    -------
    StaticProblem
    """
    settings = checked_inputs(scene, settings)
    if friction not in _FRICTION:
        raise ValueError(f"friction must be one of {_FRICTION}, got {friction!r}")
    data = _scaled_data(scene, settings)
    lam = cp.Variable(name="lam")
    build = _vertex_programme if settings.interface_model == "vertex" else _resultant_programme
    prog = build(data, settings, friction, lam)
    prog.f_map = sp.csr_matrix(prog.f_map)
    return StaticProblem(
        problem=cp.Problem(cp.Maximize(lam), [lam >= 0, *prog.constraints]),
        lam=lam,
        model=settings.interface_model,
        friction=friction,
        scene=scene,
        settings=settings,
        **_shared_fields(data, StaticProblem),
        **_shared_fields(prog, StaticProblem),
    )


def _shared_fields(part, cls) -> dict:
    """The attributes of ``part`` that are fields of the dataclass ``cls``, by name."""
    return {k: v for k, v in vars(part).items() if k in cls.__dataclass_fields__}


def _scaled_data(scene: Scene, settings: LimitSettings) -> _ScaledData:
    """Interfaces, equilibrium matrix, loads and strengths of a scene, with the scales."""
    interfaces = scene.assembly.interfaces()
    interfaces.warn_edge_contacts()
    free = scene.supports.free_dofs.ravel()
    a_eq = equilibrium_matrix(scene.assembly.centroid, interfaces)[free]
    dead = scene.dead_wrench.ravel()[free]
    live = scene.loads.live_wrench.ravel()[free]
    weight, length, row_scale = _scales(scene, free, interfaces)
    live_norm = float(np.sum(np.abs(live * row_scale)))
    lam_scale = 1.0 / live_norm if live_norm > 0 else 1.0
    vi, y = interface_vertices(interfaces)
    f_t = settings.tensile_strength * interfaces.area  # [N]
    f_offset = np.zeros(6 * interfaces.n_interfaces)
    if settings.interface_model == "vertex":
        # corner forces carry the shifted pressure p + sigma_t: N = f_t - sum p
        f_offset[0::6] = f_t
    return _ScaledData(
        interfaces=interfaces,
        free=free,
        a_eq=a_eq,
        dead=dead,
        live=live,
        weight=weight,
        length=length,
        row_scale=row_scale,
        lam_scale=lam_scale,
        mu_interface=interface_friction(interfaces, scene.assembly.mu, settings.mu),
        c_t=torsion_coefficient(interfaces),
        vertex_iface=vi,
        vertex_local=y,
        f_t=f_t,
        f_offset=f_offset,
        s_rows=sp.diags(row_scale),
        d_dead=row_scale * (dead + a_eq @ f_offset),
        d_live=row_scale * live * lam_scale,
    )


def _vertex_programme(data: _ScaledData, settings, friction: str, lam) -> _Programme:
    """Corner forces ``(p, s1, s2)`` scaled by W: equilibrium, ``p >= 0`` where no cone
    implies it, the friction cone (or inscribed polygon) and the compressive strength."""
    vi, mu_k = data.vertex_iface, data.mu_interface
    nv = len(vi)
    b = vertex_force_matrix(data.interfaces)
    f_map = b * data.weight  # x scaled by W
    a_x = (data.s_rows @ data.a_eq @ f_map).tocsc()
    p = cp.Variable(nv, name="p")
    s1 = cp.Variable(nv, name="s1")
    s2 = cp.Variable(nv, name="s2")
    # columns of a_x are interleaved (p, s1, s2) per corner
    eq = (
        a_x[:, 0::3] @ p + a_x[:, 1::3] @ s1 + a_x[:, 2::3] @ s2 + data.d_dead + lam * data.d_live
        == 0
    )
    order = np.concatenate(
        [np.arange(0, 3 * nv, 3), np.arange(1, 3 * nv, 3), np.arange(2, 3 * nv, 3)]
    )
    finite = np.isfinite(mu_k[vi])
    mu_par = cp.Parameter(nv, nonneg=True, name="mu", value=np.where(finite, mu_k[vi], 0.0))
    # mu p >= |s| implies p >= 0 where mu > 0: a sign row is kept only where it is not
    # implied (mu = 0 or inf, or fixed capacities, which may vanish)
    signed = np.ones(nv, bool) if friction != "coulomb" else (mu_k[vi] <= 0) | ~finite
    prog = _Programme(eq, [eq], [p, s1, s2], f_map[:, order], mu_par)
    prog.extra["implied_sign"] = ~signed
    cons = prog.constraints
    if signed.any():
        cons.append(p[np.flatnonzero(signed)] >= 0)
    if friction == "coulomb":
        cap = cp.multiply(mu_par, p)
    else:
        cap = prog.capacity["shear"] = cp.Parameter(
            nv, nonneg=True, name="capacity", value=np.zeros(nv)
        )
    sel = _subset(finite)
    if sel is None:
        pass  # mu = inf everywhere: no friction cone
    elif settings.friction_polygon is None:
        cons.append(cp.SOC(sel(cap), cp.vstack([sel(s1), sel(s2)]), axis=0))
    else:
        dirs, cosk = _polygon_directions(settings.friction_polygon)
        for d in dirs:
            cons.append(sel(d[0] * s1 + d[1] * s2) <= cosk * sel(cap))
    if settings.compressive_strength is not None:
        # resultants (scaled by W and W L) of the corner forces
        length, weight = data.length, data.weight
        n_hat = b[0::6][:, 0::3] @ p
        m1_hat = (b[3::6][:, 0::3] / length) @ p
        m2_hat = (b[4::6][:, 0::3] / length) @ p
        c_hat = -n_hat + data.f_t / weight
        _compressive_cone(cons, data.interfaces, settings, weight, length, c_hat, m1_hat, m2_hat)
    return prog


def _resultant_programme(data: _ScaledData, settings, friction: str, lam) -> _Programme:
    """Resultants ``(N, V1, V2, M1, M2, M3)`` scaled by W and W L: equilibrium, no tension
    beyond ``f_t``, the centre of pressure inside the polygon, then friction and torsion
    (:func:`_resultant_friction`), torsion with bending and compressive strength."""
    m, weight, length = data.interfaces.n_interfaces, data.weight, data.length
    cols = np.concatenate([np.arange(j, 6 * m, 6) for j in range(6)])
    scale_cols = np.tile(np.repeat([weight, length * weight], 3), m)
    f_map = sp.diags(scale_cols).tocsr()[:, cols]
    a_x = (data.s_rows @ data.a_eq @ f_map).tocsc()
    fv = [cp.Variable(m, name=nm) for nm in ("N", "V1", "V2", "M1", "M2", "M3")]
    n_, v1, v2, m1, m2, _ = fv
    eq = (
        sum(a_x[:, j * m : (j + 1) * m] @ fv[j] for j in range(6)) + data.d_dead + lam * data.d_live
        == 0
    )
    c_hat = -n_ + data.f_t / weight
    finite = np.isfinite(data.mu_interface)
    mu_par = cp.Parameter(m, nonneg=True, name="mu", value=np.where(finite, data.mu_interface, 0.0))
    g, h, owner = rocking_constraints(data.interfaces)
    own = sp.csr_matrix((h / length, (np.arange(len(h)), owner)), shape=(len(h), m))
    rocking = g[:, 3::6] @ m1 + g[:, 4::6] @ m2 <= own @ c_hat
    prog = _Programme(eq, [eq, c_hat >= 0, rocking], list(fv), f_map, mu_par)
    _resultant_friction(prog, data, settings, friction, fv, c_hat, finite)
    if settings.torsion_bending:
        if friction != "coulomb":
            raise ValueError("torsion_bending is available for the associated problem only")
        _bending_torsion(
            prog.constraints, data.interfaces, length, c_hat, m1, m2, fv[5], mu_par, finite
        )
    if settings.compressive_strength is not None:
        _compressive_cone(
            prog.constraints, data.interfaces, settings, weight, length, c_hat, m1, m2
        )
    return prog


def _resultant_friction(prog, data, settings, friction, fv, c_hat, finite) -> None:
    """Friction and torsion of the resultant model on the interfaces with finite mu (mu = inf:
    no sliding, no torsion slip): the Coulomb circle (or the polygon of its gauge, module
    notes) and ``|M3| <= c_T mu c`` (``torsion="independent"``), or the exact torsion-shear
    interaction of seed 001 Eq. 14 (module notes).

    With fixed capacities the cones bound ``V / cap_s`` and ``M3 / cap_t`` (new variables,
    ``V = cap_s V'``, ``M3 = cap_t M3'``) by one: a capacity that vanishes (an open joint of
    the previous iterate) or nearly does then leaves every cone with an interior of unit
    size, where a cone of radius ``cap`` would have almost none."""
    m = data.interfaces.n_interfaces
    sel = _subset(finite) or (lambda e: e[np.zeros(0, dtype=np.int64)])
    n_f = int(finite.sum())
    ct_hat = (data.c_t / data.length)[finite]
    c_f, mu_f = sel(c_hat), sel(prog.mu)
    v1, v2, m3 = sel(fv[1]), sel(fv[2]), sel(fv[5])
    if friction == "coulomb":
        cap_s = cp.multiply(mu_f, c_f)
        cap_t = cp.multiply(cp.multiply(ct_hat, mu_f), c_f)
    else:
        cap_s_par = cp.Parameter(m, nonneg=True, name="capacity_shear", value=np.zeros(m))
        cap_t_par = cp.Parameter(m, nonneg=True, name="capacity_torsion", value=np.zeros(m))
        prog.capacity["shear"], prog.capacity["torsion"] = cap_s_par, cap_t_par
        if n_f:
            caps = (sel(cap_s_par), sel(cap_s_par), sel(cap_t_par))
            v1, v2, m3 = _per_capacity(prog, (v1, v2, m3), caps, n_f)
        cap_s = cap_t = np.ones(n_f)
    cons = prog.constraints
    if n_f == 0:
        return
    shear, r = cp.vstack([v1, v2]), None
    if settings.friction_polygon is not None:
        r = cp.Variable(n_f, name="shear_gauge")
        dirs, cosk = _polygon_directions(settings.friction_polygon)
        cons += [d[0] * v1 + d[1] * v2 <= cosk * r for d in dirs]
        _append_unknowns(prog, [r])
    if settings.torsion == "independent":
        cons.append(cp.SOC(cap_s, shear, axis=0) if r is None else r <= cap_s)
        cons += [m3 <= cap_t, -m3 <= cap_t]
        return
    alpha = settings.torsion_alpha
    # explicit (not nonneg=True) so that their duals enter the certificate
    tau1 = cp.Variable(n_f, name="tau_torsion")
    tau2 = cp.Variable(n_f, name="tau_shear")
    cons += [tau1 >= 0, tau2 >= 0]
    _append_unknowns(prog, [tau1, tau2])
    if friction == "coulomb":
        # |M3| <= (cT mu tau1)^(1/alpha) (cT mu c)^(1 - 1/alpha); |V|^2 <= mu^2 tau2 c
        k_t = cp.multiply(ct_hat, mu_f)
        cons += power_mean(m3, cp.multiply(k_t, tau1), cap_t, 1.0 / alpha, n_f)
        u, w = cp.multiply(mu_f, tau2), cap_s
        cons.append(tau1 + tau2 <= c_f)
    else:
        # per capacity: tau1 + tau2 <= 1, |M3'| <= tau1^(1/alpha), |V'|^2 <= tau2
        cons += power_mean(m3, tau1, cap_t, 1.0 / alpha, n_f)
        u, w = tau2, cap_s
        cons.append(tau1 + tau2 <= 1)
    if r is None:
        cons.append(cp.SOC(u + w, cp.vstack([2 * v1, 2 * v2, u - w]), axis=0))
    else:
        cons.append(cp.SOC(u + w, cp.vstack([2 * r, u - w]), axis=0))


def _append_unknowns(prog, variables: list) -> None:
    """Stack auxiliary unknowns (no force of their own) after the others in ``x``."""
    prog.x_vars += variables
    n = sum(v.size for v in variables)
    prog.f_map = sp.hstack([prog.f_map, sp.csr_matrix((prog.f_map.shape[0], n))]).tocsr()


def _per_capacity(prog, values: tuple, caps: tuple, n: int) -> list:
    """Unknowns ``q'`` with ``q = cap q'`` for each (value, capacity) pair, all of size ``n``
    (the equalities join the programme)."""
    unit = [cp.Variable(n, name=f"per_capacity_{i}") for i in range(len(values))]
    prog.constraints += [q == cp.multiply(c, u) for q, c, u in zip(values, caps, unit, strict=True)]
    _append_unknowns(prog, unit)
    return unit


def _rectangle_ct(l1: np.ndarray, l2: np.ndarray) -> np.ndarray:
    """Mean distance to the centre of ``l1 x l2`` rectangles [m]."""
    half = np.stack([l1, l2], axis=1) / 2.0
    signs = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    corners = (half[:, None, :] * signs).reshape(-1, 2)
    return mean_distance_polygons(corners, 4 * np.arange(len(half) + 1), np.zeros_like(half))


def _bending_torsion(cons, interfaces, length, c_hat, m1_hat, m2_hat, m3_hat, mu_par, finite):
    """Append the tangent-plane torsion bound of ``torsion_bending`` (scaled units) where
    ``finite`` (mu < inf)."""
    sides, rot = interface_rectangles(interfaces)
    m = interfaces.n_interfaces
    lu, lv = sides[:, 0], sides[:, 1]
    h_u, h_v = 1e-6 * lu, 1e-6 * lv
    d_u = (_rectangle_ct(lu + h_u, lv) - _rectangle_ct(lu - h_u, lv)) / (2 * h_u)
    d_v = (_rectangle_ct(lu, lv + h_v) - _rectangle_ct(lu, lv - h_v)) / (2 * h_v)
    ct_hat = _rectangle_ct(lu, lv) / length
    ceu = cp.multiply(rot[:, 0, 0], m2_hat) - cp.multiply(rot[:, 0, 1], m1_hat)
    cev = cp.multiply(rot[:, 1, 0], m2_hat) - cp.multiply(rot[:, 1, 1], m1_hat)
    a_u = cp.Variable(m, name="abs_ceu")
    a_v = cp.Variable(m, name="abs_cev")
    cap = cp.multiply(ct_hat, c_hat) - 2 * cp.multiply(d_u, a_u) - 2 * cp.multiply(d_v, a_v)
    cons += [
        a_u >= ceu,
        a_u >= -ceu,
        a_v >= cev,
        a_v >= -cev,
    ]
    idx = np.flatnonzero(finite)
    if idx.size:
        bound = cp.multiply(mu_par, cap)[idx]
        cons += [m3_hat[idx] <= bound, -m3_hat[idx] <= bound]


def _compressive_cone(cons, interfaces, settings, weight, length, c_hat, m1_hat, m2_hat):
    r"""Append the uniform stress block :math:`c \le f_c (l_u - 2|e_u|)(l_v - 2|e_v|)`.

    With :math:`a = c(l_u - 2|e_u|)`, :math:`b = c(l_v - 2|e_v|)` (affine in ``c`` and
    ``c e = (M_2, -M_1)``) the condition is :math:`c^3 \le f_c\,a\,b`: the geometric mean
    :math:`w^2 \le a b`, then :math:`c^{3/2} \le \sqrt{f_c}\,w` as :math:`s^2 \le c` and
    :math:`c^2 \le \sqrt{f_c}\,w\,s` (exact: take :math:`s = \sqrt{c}`). All three are
    rotated second-order cones. The one 3D power cone :math:`c \le f_c^{1/3} w^{2/3}` states
    the same set, but Clarabel's nonsymmetric-cone steps stall on it (``InsufficientProgress``
    on a wall with hundreds of such joints, most far from crushing), while the symmetric
    second-order cones converge. All in scaled units (``s^2 <= c`` in them): ``c`` by ``W``,
    ``a, b, w`` by ``W L``, ``kappa = f_c L^2 / W`` in place of ``f_c``.
    """
    m = interfaces.n_interfaces
    if m == 0:  # no joint to bound (and cvxpy's cones cannot be empty)
        return
    sides, rot = interface_rectangles(interfaces)
    kappa = settings.compressive_strength * length**2 / weight
    lu, lv = sides[:, 0] / length, sides[:, 1] / length
    # c e_u = u1 M2 - u2 M1 (scaled moments are already divided by W L)
    ceu = cp.multiply(rot[:, 0, 0], m2_hat) - cp.multiply(rot[:, 0, 1], m1_hat)
    cev = cp.multiply(rot[:, 1, 0], m2_hat) - cp.multiply(rot[:, 1, 1], m1_hat)
    a = cp.Variable(m, name="reduced_u")
    b = cp.Variable(m, name="reduced_v")
    w = cp.Variable(m, name="reduced_mean")
    root = cp.Variable(m, name="sqrt_c")
    cons += [
        a <= cp.multiply(lu, c_hat) - 2 * ceu,
        a <= cp.multiply(lu, c_hat) + 2 * ceu,
        b <= cp.multiply(lv, c_hat) - 2 * cev,
        b <= cp.multiply(lv, c_hat) + 2 * cev,
        rotated_soc(w, a, b),
        rotated_soc(root, c_hat, np.ones(m)),
        rotated_soc(c_hat, math.sqrt(kappa) * w, root),
    ]


@dataclass(eq=False)
class KinematicProblem:
    """The kinematic (mechanism) programme of the vertex model, dual to the static one.

    Attributes
    ----------
    problem : cvxpy.Problem
    velocity : cvxpy.Variable
        Scaled velocities of the free dofs (row ``i`` divided by ``row_scale[i]``).
    lam_scale : float
        ``lambda = lam_scale * problem.value``.
    row_scale : (n_free,) float
    free : (6 n_blocks,) bool
    """

    problem: cp.Problem
    velocity: cp.Variable
    lam_scale: float
    row_scale: np.ndarray
    free: np.ndarray


def build_kinematic_problem(scene: Scene, settings: LimitSettings | None = None):
    r"""Kinematic programme of the vertex model (upper-bound theorem, associated flow).

    .. math::

        \lambda^+ = \min_{\dot u}\ -F_D^T \dot u \quad \text{s.t.} \quad F_L^T \dot u \ge 1,
        \qquad (A_{eq} B)^T \dot u \in K^*,

    with :math:`K^* = \{(a, b) : a \ge \mu \|b\|\}` per corner: every corner opens at least
    :math:`\mu` times its slip (normality of the Coulomb cone, i.e. dilatancy). It is the
    conic dual of :func:`build_static_problem` (vertex model), written independently, so that
    both theorems can be checked against each other.

    Raises
    ------
    ValueError
        For the resultant model, inscribed polygons or a compressive strength (not written
        in kinematic form here).
    """
    settings = checked_inputs(scene, settings)
    if settings.interface_model != "vertex" or settings.friction_polygon is not None:
        raise ValueError("the kinematic programme is written for the exact vertex model only")
    if settings.compressive_strength is not None:
        raise ValueError("the kinematic programme has no compressive strength")
    data = _scaled_data(scene, settings)  # vertex model: f_offset holds the tension shift
    mu = data.mu_interface[data.vertex_iface]
    b = vertex_force_matrix(data.interfaces)
    # scaled: rows by row_scale, corner forces by W (as in the static programme)
    ab = (data.s_rows @ data.a_eq @ b * data.weight).T.tocsr()  # (3 p, n_free)
    v = cp.Variable(len(data.dead), name="velocity")
    w_p, w_1, w_2 = ab[0::3] @ v, ab[1::3] @ v, ab[2::3] @ v
    cons = [data.d_live @ v >= 1]
    finite = np.isfinite(mu)
    sel = _subset(finite)
    if sel is not None:
        mu_f = mu[finite]
        cons.append(
            cp.SOC(
                sel(w_p),
                cp.vstack([cp.multiply(mu_f, sel(w_1)), cp.multiply(mu_f, sel(w_2))]),
                axis=0,
            )
        )
    if not finite.all():  # mu = inf: the corner cannot slip, it only opens
        stuck = np.flatnonzero(~finite)
        cons += [w_p[stuck] >= 0, w_1[stuck] == 0, w_2[stuck] == 0]
    problem = cp.Problem(cp.Minimize(-data.d_dead @ v), cons)
    return KinematicProblem(problem, v, data.lam_scale, data.row_scale, data.free)
