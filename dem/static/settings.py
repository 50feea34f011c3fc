"""Settings of the static collapse analysis: the joints, each interface law, the path.

Plain values only: the law objects they configure are built from them in
:mod:`dem.static.laws` (:func:`dem.static.laws.build_law`), which imports this module and
never the reverse.

Each interface law owns its numerical defaults in its own settings object
(:class:`ResultantLawSettings`, :class:`FibreLawSettings`); :class:`StaticSettings` holds the
joint properties shared by both laws and the control of the path. Its fields ``alpha``,
``fibre_points``, ``tangent_floor``, ``predictor`` and ``accept_tolerance`` are shorthands
that, when given, replace the law's own value (and are refused by a law they do not apply to).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import ClassVar

ON_FAILURE = ("raise", "return")
SHEAR_TORSION_DOMAINS = ("eq_a5", "exact")


def _positive(name: str, v, allow_none: bool = False) -> None:
    if v is None and allow_none:
        return
    if isinstance(v, bool) or not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite positive number, got {v!r}")


def _fraction(name: str, v) -> None:
    if isinstance(v, bool) or not (isinstance(v, (int, float)) and math.isfinite(v)):
        raise ValueError(f"{name} must be in [0, 1), got {v!r}")
    if not 0 <= v < 1:
        raise ValueError(f"{name} must be in [0, 1), got {v!r}")


def _integer(name: str, v, low: int) -> None:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or int(v) != v or v < low:
        raise ValueError(f"{name} must be an integer >= {low}, got {v!r}")


@dataclass(frozen=True)
class ResultantLawSettings:
    """Seed 001's elastic-perfectly-plastic law on ``(N, V1, V2, M1, M2, M3)``.

    Attributes
    ----------
    shear_torsion : {"eq_a5", "exact"}
        Domain of shear and torsion. ``"eq_a5"`` (default; seed 001's tables): Eq. (A5) with
        ``c_T`` of the compressed rectangle reduced by the eccentricities. ``"exact"``: the
        joint's own domain under Coulomb friction at its capped normal stress, the limit of
        the fibre law on a fine grid (:mod:`dem.kernels.friction_domain`); about 10-100
        times the cost of Eq. (A5) per yielded joint.
    alpha : float or None
        Exponent of Eq. (A5); None: seed Table A1 (column ``f1 = f2``) at each interface's
        aspect ratio. Only with ``shear_torsion="eq_a5"``.
    tangent_floor : float
        Fraction of the elastic stiffness kept by yielded components of the iteration matrix
        (the residual uses the exact law), so that blocks held only by yielded joints keep a
        regular tangent. The law's normal part is smooth (joints open progressively), so a
        floor near the consistent tangent (the default) converges; a stiffer one can leave
        barely pressed joints that open and slide creeping without equilibrium.
    predictor : bool
        Start each step from the last increment scaled to the new one, so that the first
        iterate of a step does not unload the joints that keep yielding (which lets the path
        creep below the collapse plateau).
    accept_tolerance : float or None
        Looser residual at which a step stalled at a kink of the law is accepted; None: the
        analysis tolerance (no loose steps: loosely converged steps committed plastic states
        from which no shorter step converged).
    """

    name: ClassVar[str] = "resultant"
    shear_torsion: str = "eq_a5"
    alpha: float | None = None
    tangent_floor: float = 1e-9
    predictor: bool = True
    accept_tolerance: float | None = None

    def __post_init__(self):
        if self.shear_torsion not in SHEAR_TORSION_DOMAINS:
            raise ValueError(
                f"shear_torsion must be one of {SHEAR_TORSION_DOMAINS}, got {self.shear_torsion!r}"
            )
        if self.alpha is not None and not (math.isfinite(self.alpha) and self.alpha >= 1):
            raise ValueError(f"alpha must be None or >= 1, got {self.alpha!r}")
        if self.alpha is not None and self.shear_torsion != "eq_a5":
            raise ValueError(
                f"alpha is the exponent of Eq. (A5); shear_torsion is {self.shear_torsion!r}"
            )
        _fraction("tangent_floor", self.tangent_floor)
        _positive("accept_tolerance", self.accept_tolerance, allow_none=True)
        if not isinstance(self.predictor, bool):
            raise ValueError(f"predictor must be True or False, got {self.predictor!r}")


@dataclass(frozen=True)
class FibreLawSettings:
    """A grid of no-tension Mohr-Coulomb springs per interface.

    Attributes
    ----------
    points : int
        Gauss-Lobatto points per side of a rectangular interface (the first grid when
        ``grid_tolerance`` is set): the outer springs lie on the edges, so rocking about an
        edge is exact. Twisting, partly open and crushed joints (``compressive_strength``:
        the crushed part's lever is too long by up to half an edge cell) are only as exact as
        the grid. Other convex polygons get springs at the centres of a square grid of
        ``4 points`` cells per side (none on the edges): rocking comes out low by about half
        a cell.
    tangent_floor : float
        As for the resultant law (yielded springs are only a part of each joint); the default
        is near the consistent tangent.
    predictor : bool
        Start each step from the scaled last increment. Off by default: the fibre law
        converges from the last equilibrium in a few iterations, and the predictor's longer
        steps make its lambda_max depend on the load step.
    accept_tolerance : float or None
        Looser residual at which a step stalled at a kink (a joint at ``N -> 0``) is accepted;
        the residual is of the total equilibrium, so the error does not accumulate.
    grid_tolerance : float or None
        The analysis is repeated on grids of half the cell (``points -> 2 points - 1``) until
        ``lambda_max`` moves by less than this fraction of itself
        (:mod:`dem.static.adaptive_grid`); twice the last change bounds the ``"fibre grid"``
        error of the result; 0.005 asks for lambda to 0.5 %. None (default): one run on
        ``points``, its grid error not estimated. Each refinement quadruples the springs, so
        a refinement to 17 points costs about ten times one run on 5.
    max_points : int
        Finest grid the refinement may reach; a refinement stopped by it is flagged
        (``StaticResult.fibre_grid.converged`` False) and keeps its bound from the last change.
    """

    name: ClassVar[str] = "fibre"
    points: int = 5
    tangent_floor: float = 1e-9
    predictor: bool = False
    accept_tolerance: float | None = 1e-4
    grid_tolerance: float | None = None
    max_points: int = 17

    def __post_init__(self):
        _integer("fibre points", self.points, 2)
        _integer("max_points", self.max_points, 2)
        if self.grid_tolerance is not None:
            _fraction("grid_tolerance", self.grid_tolerance)
            _positive("grid_tolerance", self.grid_tolerance)
        _fraction("tangent_floor", self.tangent_floor)
        _positive("accept_tolerance", self.accept_tolerance, allow_none=True)
        if not isinstance(self.predictor, bool):
            raise ValueError(f"predictor must be True or False, got {self.predictor!r}")


LAWS = {law.name: law for law in (ResultantLawSettings, FibreLawSettings)}

# StaticSettings shorthand -> (law field, laws it applies to)
_LAW_SHORTHANDS = {
    "alpha": ("alpha", ("resultant",)),
    "fibre_points": ("points", ("fibre",)),
    "tangent_floor": ("tangent_floor", ("resultant", "fibre")),
    "predictor": ("predictor", ("resultant", "fibre")),
    "accept_tolerance": ("accept_tolerance", ("resultant", "fibre")),
}


@dataclass(frozen=True)
class StaticSettings:
    """Settings of :func:`dem.static.solve_collapse`.

    Attributes
    ----------
    interface_model : {"resultant", "fibre"} or None
        The interface law with its default settings; None: the name of ``law``, or
        "resultant". After construction it holds the name of the law used.
    law : ResultantLawSettings or FibreLawSettings or None
        The interface law with its own settings; None: the defaults of ``interface_model``.
        The law used, with the shorthands below applied, is :attr:`law_settings`.
    kn, kt : float
        Normal and tangential stiffness per unit area [Pa/m]. Default: seed 001 Sec. 2.1
        (2.4 MPa/mm and 1 MPa/mm). The collapse load of rigid blocks does not depend on them.
    kr : float or None
        Rotational stiffness per unit area [Pa/m]; None: ``kn`` (seed 001, ``k_r = k_n``).
    mu : float or None
        Friction coefficient; None: the smaller of the two blocks' ``Assembly.mu``.
    tensile_strength : float
        [Pa]; 0 for dry joints.
    cohesion : float or None
        [Pa]; None: ``mu * tensile_strength`` (seed 001, Sec. 2.1).
    compressive_strength : float or None
        Joint compressive strength f_c [Pa], both laws; None for unlimited. Without it,
        arching between rigid supports can grow without bound. The fibre law resolves the
        crushed zone only as finely as its grid (:class:`FibreLawSettings`, ``points``).
    tension_at_supports : bool
        Whether interfaces with a fixed block get the tensile strength and cohesion (False
        models a support as a dry hinge).
    alpha, fibre_points, tangent_floor, predictor, accept_tolerance : optional
        Shorthands for the law's ``alpha``, ``points``, ``tangent_floor``, ``predictor`` and
        ``accept_tolerance`` (None: the law's own value).
    load_step : float
        First live-load increment as a fraction of ``lambda_scale = |F_D| / |F_L|`` (total
        dead over total live force): for a live load equal to the weight, ``d lambda``.
    max_step_factor : float
        Largest control increment, in first increments, while the path is not flat (a flat
        path's steps may keep growing: :mod:`dem.static.path`).
    max_steps : int
        Live-load steps at most.
    max_iterations : int
        Newton iterations per step before the step is cut.
    target_iterations : int
        Iterations the step size adapts to.
    tolerance : float
        Relative residual ``|R| / (|F_D| + |lambda F_L|)`` for convergence.
    min_step_ratio : float
        Smallest control increment, relative to the first, before giving up a step.
    switch_after : int
        Consecutive failed steps after which the fixed control gives way to the path
        direction (:mod:`dem.static.path`): the path turns away from the control, or a local
        mechanism forms that the control hardly measures; switching early keeps the path from
        creeping at a constant lambda while the fixed control's step is halved.
    plateau_slope : float
        The end is sought only where ``d lambda / d c`` is below this fraction of the
        initial secant slope (measured back over at least the control length at which the
        residual tolerance's noise in lambda is a tenth of the allowed rise).
    plateau_steps : int
        Consecutive such steps that may end the analysis, if they also span this many first
        control increments.
    plateau_rise, plateau_window : float
        The stated tolerance of the end: the path is a collapse once lambda may still rise
        by at most ``plateau_rise`` of itself, estimated from its rises over the stretches
        ``[s (1 - w)^2, s (1 - w)]`` and ``[s (1 - w), s]`` of the travelled control ``s``,
        ``w = plateau_window`` (:mod:`dem.collapse_criteria`). It triggers the end, which
        needs a certificate from the mechanics (:mod:`dem.static.certificate`); the
        certificate states the result's "end of path" error.
    softening_drop : float
        End when lambda falls below ``(1 - softening_drop) lambda_max``.
    dead_steps : int
        The first increment of the dead load is ``1 / dead_steps`` of it; the increments
        then adapt (:mod:`dem.static.dead_load`).
    dead_min_step : float
        Smallest increment of the dead load, as a fraction of it: when one that small finds
        no equilibrium the dead load is not carried (:class:`dem.static.DeadLoadError`).
    monitor : tuple of (int, int) or None
        ``(block, dof)`` whose displacement the pushover also records; None: the free block
        with the largest live-direction translation in the mechanism.
    on_failure : {"raise", "return"}
        When the analysis ends without a collapse (no mechanism exists, ``max_steps`` reached
        while lambda still rises, or a step that converges at no increment): raise
        :class:`dem.static.NoCollapseError` (its ``result`` holds the partial path), or return
        the partial path with ``collapsed = False``, its ``termination`` and the reason in
        ``failure``.
    """

    interface_model: str | None = None
    law: ResultantLawSettings | FibreLawSettings | None = None
    kn: float = 2.4e9
    kt: float = 1.0e9
    kr: float | None = None
    mu: float | None = None
    tensile_strength: float = 0.0
    cohesion: float | None = None
    compressive_strength: float | None = None
    tension_at_supports: bool = True
    alpha: float | None = None
    fibre_points: int | None = None
    tangent_floor: float | None = None
    predictor: bool | None = None
    accept_tolerance: float | None = None
    load_step: float = 0.01
    max_step_factor: float = 200.0
    max_steps: int = 400
    max_iterations: int = 30
    target_iterations: int = 10
    tolerance: float = 1e-6
    min_step_ratio: float = 1e-4
    switch_after: int = 3
    plateau_slope: float = 2e-3
    plateau_steps: int = 4
    plateau_rise: float = 1e-3
    plateau_window: float = 0.5
    softening_drop: float = 0.2
    dead_steps: int = 1
    dead_min_step: float = 1e-3
    monitor: tuple[int, int] | None = None
    on_failure: str = "raise"

    def __post_init__(self):
        self._check_choices()
        for name in ("kn", "kt", "load_step", "tolerance", "max_step_factor"):
            _positive(name, getattr(self, name))
        _positive("kr", self.kr, allow_none=True)
        _positive("compressive_strength", self.compressive_strength, allow_none=True)
        for name in ("mu", "cohesion"):
            v = getattr(self, name)
            if v is not None and not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be None or finite and >= 0, got {v!r}")
        if not (math.isfinite(self.tensile_strength) and self.tensile_strength >= 0):
            raise ValueError(f"tensile_strength must be >= 0 [Pa], got {self.tensile_strength}")
        for name in (
            "max_steps",
            "max_iterations",
            "target_iterations",
            "plateau_steps",
            "switch_after",
        ):
            _integer(name, getattr(self, name), 1)
        _integer("dead_steps", self.dead_steps, 1)
        for name in (
            "min_step_ratio",
            "plateau_slope",
            "softening_drop",
            "plateau_rise",
            "plateau_window",
        ):
            _fraction(name, getattr(self, name))
        _positive("dead_min_step", self.dead_min_step)
        if self.dead_min_step > 1.0 / self.dead_steps:
            raise ValueError(
                f"dead_min_step {self.dead_min_step} exceeds the first dead-load increment "
                f"1 / dead_steps = {1.0 / self.dead_steps:.3g}"
            )
        law = self._resolved_law()
        object.__setattr__(self, "_law", law)
        object.__setattr__(self, "interface_model", law.name)

    @property
    def law_settings(self) -> ResultantLawSettings | FibreLawSettings:
        """The interface law used, with the shorthands applied."""
        return self._law

    def _check_choices(self):
        if self.on_failure == "stop":
            raise ValueError(
                "on_failure='stop' is no longer accepted: use 'return' to get the partial "
                "path back flagged collapsed=False, or 'raise' (default) for a NoCollapseError"
            )
        if self.on_failure not in ON_FAILURE:
            raise ValueError(f"on_failure must be one of {ON_FAILURE}, got {self.on_failure!r}")
        if self.interface_model is not None and self.interface_model not in LAWS:
            raise ValueError(
                f"interface_model must be one of {tuple(LAWS)}, got {self.interface_model!r}"
            )
        if self.law is None:
            return
        if not isinstance(self.law, tuple(LAWS.values())):
            raise ValueError(f"law must be one of {[c.__name__ for c in LAWS.values()]}")
        if self.interface_model not in (None, self.law.name):
            raise ValueError(
                f"interface_model {self.interface_model!r} contradicts law "
                f"{type(self.law).__name__}: give one of them"
            )

    def _resolved_law(self):
        """The law's settings with the shorthands given here applied."""
        law = self.law if self.law is not None else LAWS[self.interface_model or "resultant"]()
        changes = {}
        for short, (field_name, applies) in _LAW_SHORTHANDS.items():
            value = getattr(self, short)
            if value is None:
                continue
            if law.name not in applies:
                raise ValueError(f"{short} does not apply to the {law.name} law")
            changes[field_name] = value
        return replace(law, **changes) if changes else law

    def to_dict(self) -> dict:
        """The settings as plain values (the law as a dict with its name)."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        law = self.law_settings
        out["law"] = {"name": law.name, **{f.name: getattr(law, f.name) for f in fields(law)}}
        return out
