"""Loads on one elastic block from a DEM state: point forces, surface tractions, body forces.

Everything here is in the world frame and SI units. The DEM hands over either

- :class:`BlockPointLoads`: contact node forces (the explicit TIS solver), or
- :class:`InterfaceResultants`: one force and moment per interface (the masonry solver), which
  :func:`interface_block_loads` turns into the traction distribution they stand for,

plus gravity and the rigid-body acceleration of every block. A :class:`BlockLoad` gathers what
acts on one block; :func:`check_equilibrium` checks that every traction patch lies on a face of
the block (:func:`check_patch_on_face`) and compares the resultant with zero before any solve.

Sign convention of interface resultants (this module's contract with the DEM):
``(N, V1, V2, M1, M2, M3)`` are the force and the moment about the interface centroid that
block ``a`` exerts on block ``b``, in components along the interface frame ``(n, t1, t2)``
(:class:`dem.geometry.interfaces.Interfaces`, ``n`` from a into b). Compression gives
``N > 0``. Force on b: ``N n + V1 t1 + V2 t2``; moment on b: ``M1 t1 + M2 t2 + M3 n``
(``M1, M2`` bend the interface, ``M3`` twists it). Block a receives the opposite wrench.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTri

from dem.geometry.clipping import clip_convex_polygons, counter_clockwise, polygon_properties
from dem.geometry.interfaces import Interfaces
from dem.geometry.polyhedron import ConvexBlock, clip_halfspace, plane_basis

log = logging.getLogger(__name__)

EQUILIBRIUM_REL_TOL = 1e-3
"""Default largest accepted load imbalance, relative to the load scale (see check_equilibrium)."""
PATCH_FACE_REL_TOL = 1e-5
"""Width of the band, relative to the block size, within which a traction patch may leave its
face: off the face plane, or past the face edges (area outside <= band x patch perimeter). It
admits DEM interface polygons, which may stick out of one block's face by the contact
tolerance of :func:`dem.geometry.interfaces.find_interfaces` (1e-6 of the median block size)."""


class EquilibriumError(ValueError):
    """The loads on a block are not in equilibrium (the DEM state is not balanced)."""


# -- polygons in space ------------------------------------------------------------------------
def polygon_quadrature(polygon: np.ndarray, degree: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Quadrature points and weights on a planar convex polygon in space.

    Parameters
    ----------
    polygon : (k, 3) float
        Corners in order [m], k >= 3.
    degree : int
        Polynomial degree integrated exactly.

    Returns
    -------
    points : (q, 3) float
        [m].
    weights : (q,) float
        [m^2]; they sum to the area.
    """
    poly = np.asarray(polygon, dtype=float)
    x_ref, w_ref = get_quadrature(RefTri, degree)
    a = poly[0]
    b, c = poly[1:-1], poly[2:]
    areas = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    # fan triangle (a, b, c), reference coordinates (s, t): x = a + s (b - a) + t (c - a)
    pts = (
        a
        + x_ref[0][None, :, None] * (b - a)[:, None, :]
        + x_ref[1][None, :, None] * (c - a)[:, None, :]
    )
    wts = 2.0 * areas[:, None] * w_ref[None, :]
    return pts.reshape(-1, 3), wts.reshape(-1)


def clip_polygon(polygon: np.ndarray, normal: np.ndarray, offset: float) -> np.ndarray:
    """The part ``normal . x >= offset`` of a planar convex polygon in space.

    Parameters
    ----------
    polygon : (k, 3) float
        [m].
    normal : (3,) float
    offset : float
        [m].

    Returns
    -------
    (j, 3) float
        Corners of the kept part, in the same order; ``j = 0`` when nothing is kept.
    """
    poly = np.asarray(polygon, dtype=float)
    s = poly @ normal - offset
    out = []
    for i in range(len(poly)):
        j = (i + 1) % len(poly)
        if s[i] >= 0:
            out.append(poly[i])
        if (s[i] >= 0) != (s[j] >= 0):
            w = s[i] / (s[i] - s[j])
            out.append(poly[i] + w * (poly[j] - poly[i]))
    return np.array(out).reshape(-1, 3)


def polygon_area_centroid(polygon: np.ndarray) -> tuple[float, np.ndarray]:
    """Area [m^2] and centroid (3,) [m] of a planar polygon in space."""
    pts, wts = polygon_quadrature(polygon, 1)
    area = float(wts.sum())
    return area, (wts[:, None] * pts).sum(axis=0) / area


# -- traction patches ---------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class TractionPatch:
    """A traction field that is affine in space over a planar convex polygon.

    ``t(x) = traction + spin x (x - centre)``: a uniform part plus the field of a small rotation
    about ``centre``. On a plane this is a linear normal traction (bending), a uniform shear
    and a linear shear circulating about ``centre`` (torsion).

    Attributes
    ----------
    polygon : (k, 3) float
        Corners [m], on one face of the block.
    traction : (3,) float
        [Pa].
    spin : (3,) float
        [Pa/m].
    centre : (3,) float
        [m].
    """

    polygon: np.ndarray
    traction: np.ndarray
    spin: np.ndarray
    centre: np.ndarray

    def __post_init__(self):
        poly = np.asarray(self.polygon, dtype=float)
        if poly.ndim != 2 or poly.shape[1] != 3 or len(poly) < 3:
            raise ValueError(f"patch polygon must have shape (k >= 3, 3), got {poly.shape}")
        object.__setattr__(self, "polygon", poly)
        for name in ("traction", "spin", "centre"):
            arr = np.asarray(getattr(self, name), dtype=float)
            if arr.shape != (3,) or not np.all(np.isfinite(arr)):
                raise ValueError(f"patch {name} must be a finite 3-vector, got {arr}")
            object.__setattr__(self, name, arr)

    def at(self, points: np.ndarray) -> np.ndarray:
        """(q, 3) traction [Pa] at (q, 3) points [m]."""
        return self.traction + np.cross(self.spin, np.asarray(points) - self.centre)

    def clipped(self, normal: np.ndarray, offset: float) -> TractionPatch | None:
        """The same field on the part ``normal . x >= offset`` of the polygon (or None)."""
        poly = clip_polygon(self.polygon, normal, offset)
        if len(poly) < 3:
            return None
        return TractionPatch(poly, self.traction, self.spin, self.centre)

    def resultant(self, about: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Force [N] and moment about ``about`` [N m] of the patch (exact quadrature)."""
        pts, wts = polygon_quadrature(self.polygon, 2)
        t = self.at(pts) * wts[:, None]
        return t.sum(axis=0), np.cross(pts - about, t).sum(axis=0)


def wrench_patches(
    polygons: list[np.ndarray], force: np.ndarray, moment: np.ndarray, about: np.ndarray
) -> list[TractionPatch]:
    """The smallest (L2) traction on a set of polygons that has a given force and moment.

    Parameters
    ----------
    polygons : list of (k_i, 3) float
        Planar convex polygons [m] (e.g. one interface, or the support faces of a block).
    force : (3,) float
        [N].
    moment : (3,) float
        About ``about`` [N m].
    about : (3,) float
        [m].

    Returns
    -------
    list of TractionPatch
        One per polygon, all with the same ``traction``, ``spin`` and ``centre``.

    Notes
    -----
    Minimising :math:`\\int |t|^2 dA` subject to :math:`\\int t\\,dA = F` and
    :math:`\\int (x - c) \\times t\\,dA = M_c` gives, by a Lagrange argument,
    :math:`t = \\lambda + \\mu \\times (x - c)`. Taking ``c`` as the area centroid decouples the
    two: :math:`\\lambda = F / A` and :math:`J \\mu = M_c` with the polar tensor
    :math:`J = \\int (|y|^2 I - y y^T) dA`, ``y = x - c``. On one planar interface this is the
    familiar linear normal stress of a section under bending, a uniform shear, and a torsional
    shear linear in the distance to the centroid.
    """
    pts, wts = zip(*(polygon_quadrature(p, 2) for p in polygons), strict=True)
    pts_all, wts_all = np.concatenate(pts), np.concatenate(wts)
    area = wts_all.sum()
    centre = (wts_all[:, None] * pts_all).sum(axis=0) / area
    y = pts_all - centre
    polar = np.einsum("q,q->", wts_all, np.einsum("qi,qi->q", y, y)) * np.eye(3) - np.einsum(
        "q,qi,qj->ij", wts_all, y, y
    )
    moment_c = np.asarray(moment, float) - np.cross(centre - np.asarray(about, float), force)
    spin = np.linalg.solve(polar, moment_c)
    traction = np.asarray(force, float) / area
    return [TractionPatch(p, traction, spin, centre) for p in polygons]


def patch_face(block: ConvexBlock, patch: TractionPatch) -> tuple[int, float, float, float]:
    """The face of a block that a traction patch lies on, and how far it leaves that face.

    Parameters
    ----------
    block : ConvexBlock
    patch : TractionPatch

    Returns
    -------
    face : int
        The face whose plane is nearest all the patch corners.
    off_plane : float
        Largest distance of a patch corner from that plane [m].
    area : float
        Area of the patch, projected onto the plane [m^2].
    area_outside : float
        Area of the projected patch outside the face polygon [m^2].
    """
    dev = np.abs(patch.polygon @ block.normals.T - block.offsets)  # (k, n_faces)
    face = int(np.argmin(dev.max(axis=0)))
    basis = np.stack(plane_basis(block.normals[face]))
    poly2 = counter_clockwise(patch.polygon @ basis.T)
    face2 = counter_clockwise(block.vertices[block.faces[face]] @ basis.T)
    area = polygon_properties(poly2)[0]
    inside = clip_convex_polygons(poly2, face2)
    area_inside = polygon_properties(inside)[0] if len(inside) >= 3 else 0.0
    return face, float(dev[:, face].max()), area, max(area - area_inside, 0.0)


def check_patch_on_face(block: ConvexBlock, patch: TractionPatch, label: str = "patch") -> int:
    """The face a traction patch lies on; raise if the patch leaves it (see PATCH_FACE_REL_TOL).

    Raises
    ------
    ValueError
        If the patch is off the face plane by more than the band width, or more of its area
        than a band along its edges lies outside the face: that part would act on no surface
        of the block (it would count in the resultant but not in the FE load).
    """
    face, off_plane, area, area_outside = patch_face(block, patch)
    band = PATCH_FACE_REL_TOL * block.size
    if off_plane > band:
        raise ValueError(f"{label} is {off_plane:.3e} m off the nearest block face {face}")
    poly = patch.polygon
    perimeter = float(np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1).sum())
    if area_outside > band * perimeter:
        raise ValueError(
            f"{label} extends past block face {face}: {area_outside:.3e} m^2 of its "
            f"{area:.3e} m^2 lie outside the face (tolerance {band * perimeter:.1e} m^2)"
        )
    return face


# -- everything on one block -------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class BlockLoad:
    """Loads on one block (world frame).

    Attributes
    ----------
    points : (k, 3) float
        Points of application of point forces, on (or within the DEM penetration of) the
        block surface [m].
    forces : (k, 3) float
        Point forces acting on the block [N].
    patches : tuple of TractionPatch
        Surface tractions acting on the block.
    density : float
        [kg/m^3].
    gravity : (3,) float
        [m/s^2].
    acceleration : (6,) float
        Rigid-body acceleration of the block in the DEM state: centroid acceleration [m/s^2]
        and angular acceleration [rad/s^2].
    angular_velocity : (3,) float
        [rad/s]. With it the d'Alembert body force is the full rigid-body one,
        ``-rho (a + alpha x r + omega x (omega x r))``, ``r = x - centroid``, whose moment
        ``-(I alpha + omega x I omega)`` balances Euler's equations.
    label : str
        What the loads are (for reports).
    """

    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    forces: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    patches: tuple[TractionPatch, ...] = ()
    density: float = 0.0
    gravity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    acceleration: np.ndarray = field(default_factory=lambda: np.zeros(6))
    angular_velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    label: str = ""

    def __post_init__(self):
        pts = np.asarray(self.points, dtype=float).reshape(-1, 3)
        frc = np.asarray(self.forces, dtype=float).reshape(-1, 3)
        if pts.shape != frc.shape:
            raise ValueError(f"points {pts.shape} and forces {frc.shape} must have equal shapes")
        if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(frc))):
            raise ValueError("point loads contain NaN or inf")
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "forces", frc)
        object.__setattr__(self, "patches", tuple(self.patches))
        if not np.isfinite(self.density) or self.density < 0:
            raise ValueError(f"density must be finite and >= 0 [kg/m^3], got {self.density}")
        for name, shape in (("gravity", (3,)), ("acceleration", (6,)), ("angular_velocity", (3,))):
            arr = np.asarray(getattr(self, name), dtype=float)
            if arr.shape != shape or not np.all(np.isfinite(arr)):
                raise ValueError(f"{name} must be a finite array of shape {shape}, got {arr}")
            object.__setattr__(self, name, arr)

    def with_patches(self, patches: list[TractionPatch], label: str = "") -> BlockLoad:
        """A copy with more traction patches (value semantics)."""
        return BlockLoad(
            self.points,
            self.forces,
            self.patches + tuple(patches),
            self.density,
            self.gravity,
            self.acceleration,
            self.angular_velocity,
            label or self.label,
        )

    @property
    def acceleration_gradient(self) -> np.ndarray:
        """(3, 3) ``G`` with rigid-body acceleration ``a(x) = a_c + G (x - centroid)`` [1/s^2].

        ``G = [alpha]_x + omega omega^T - |omega|^2 I``: angular plus centripetal acceleration.
        """
        al, w = self.acceleration[3:], self.angular_velocity
        skew = np.array([[0, -al[2], al[1]], [al[2], 0, -al[0]], [-al[1], al[0], 0]])
        return skew + np.outer(w, w) - np.dot(w, w) * np.eye(3)

    def body_resultant(self, block: ConvexBlock, about: np.ndarray) -> tuple[np.ndarray, ...]:
        """Force [N] and moment about ``about`` [N m] of gravity plus d'Alembert load."""
        return body_resultant_on(block, block.centroid, self, about)

    def resultant(self, block: ConvexBlock, about: np.ndarray | None = None) -> tuple:
        """Total force [N] and moment [N m] about ``about`` (default: the block centroid)."""
        about = block.centroid if about is None else np.asarray(about, dtype=float)
        force, moment = self.body_resultant(block, about)
        force = force + self.forces.sum(axis=0)
        moment = moment + np.cross(self.points - about, self.forces).sum(axis=0)
        for p in self.patches:
            f, m = p.resultant(about)
            force, moment = force + f, moment + m
        return force, moment

    def scale(self, block: ConvexBlock) -> float:
        """Load scale [N]: sum of the magnitudes of all forces acting on the block."""
        s = np.linalg.norm(self.forces, axis=1).sum()
        for p in self.patches:
            pts, wts = polygon_quadrature(p.polygon, 2)
            s += (np.linalg.norm(p.at(pts), axis=1) * wts).sum()
        # |g - a(x)| <= |g - a_c| + |G| |x - c|, with |x - c| up to half the block size
        accel = np.linalg.norm(self.gravity - self.acceleration[:3]) + 0.5 * block.size * float(
            np.linalg.norm(self.acceleration_gradient, 2)
        )
        return float(s + accel * self.density * block.volume)


def body_resultant_on(
    part: ConvexBlock, centre: np.ndarray, load: BlockLoad, about: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Gravity and d'Alembert load on a (part of a) block.

    Parameters
    ----------
    part : ConvexBlock
        The region loaded [m].
    centre : (3,) float
        Centroid of the whole block, about which ``acceleration[3:]`` rotates [m].
    load : BlockLoad
    about : (3,) float
        Moment centre [m].

    Notes
    -----
    With ``b(x) = rho (g - a_c - G (x - c))`` (``G``: :attr:`BlockLoad.acceleration_gradient`)
    and ``x = c' + y`` about the part's centroid ``c'``: force ``rho V' b0``,
    ``b0 = g - a_c - G (c' - c)``, and moment ``(c' - o) x F - rho int y x (G y) dV`` where
    :math:`\\int y \\times G y\\,dV = \\epsilon_{ijk} G_{kl} C_{jl}` with the second moment
    ``C = tr(J')/2 I - J'`` from the part's inertia ``J'`` per unit density. For
    ``G = [alpha]_x`` the last term is ``J' alpha``.
    """
    rho = load.density
    grad = load.acceleration_gradient
    b0 = load.gravity - load.acceleration[:3] - grad @ (part.centroid - centre)
    force = rho * part.volume * b0
    second = 0.5 * np.trace(part.inertia) * np.eye(3) - part.inertia
    swirl = np.einsum("ijk,kl,jl->i", _LEVI_CIVITA, grad, second)
    moment = np.cross(part.centroid - about, force) - rho * swirl
    return force, moment


_LEVI_CIVITA = np.zeros((3, 3, 3))
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _LEVI_CIVITA[_i, _j, _k], _LEVI_CIVITA[_i, _k, _j] = 1.0, -1.0


@dataclass(frozen=True)
class EquilibriumReport:
    """Resultant of the loads on one block, which a balanced DEM state makes zero.

    Attributes
    ----------
    force : (3,) float
        [N].
    moment : (3,) float
        About the block centroid [N m].
    scale : float
        Sum of the magnitudes of all loads [N].
    size : float
        Block size (bounding-box diagonal) [m].
    """

    force: np.ndarray
    moment: np.ndarray
    scale: float
    size: float

    @property
    def rel_force(self) -> float:
        """|F| / scale."""
        return _ratio(float(np.linalg.norm(self.force)), self.scale)

    @property
    def rel_moment(self) -> float:
        """|M| / (scale size)."""
        return _ratio(float(np.linalg.norm(self.moment)), self.scale * self.size)

    @property
    def rel(self) -> float:
        """The larger of the two relative imbalances."""
        return max(self.rel_force, self.rel_moment)


def _ratio(value: float, scale: float) -> float:
    """value / scale, with 0 / 0 = 0 (no load at all is balanced)."""
    if scale > 0:
        return value / scale
    return 0.0 if value == 0 else float("inf")


def check_equilibrium(
    block: ConvexBlock, load: BlockLoad, rel_tol: float = EQUILIBRIUM_REL_TOL, name: str = "block"
) -> EquilibriumReport:
    """Resultant of the loads on a block; raise if it is not (nearly) zero.

    Parameters
    ----------
    block : ConvexBlock
    load : BlockLoad
    rel_tol : float
        Largest accepted ``|F| / scale`` and ``|M| / (scale size)``.
    name : str
        Used in the error message.

    Raises
    ------
    ValueError
        If a traction patch leaves the block face it lies on (:func:`check_patch_on_face`):
        its resultant would not be the load the block carries.
    EquilibriumError
        If the imbalance exceeds ``rel_tol``: the DEM state is not an equilibrium state (or the
        accelerations / damping forces were not handed over). Nothing is fixed silently.
    """
    for i, patch in enumerate(load.patches):
        check_patch_on_face(block, patch, f"{name}: traction patch {i}")
    force, moment = load.resultant(block)
    report = EquilibriumReport(force, moment, load.scale(block), block.size)
    if not report.rel <= rel_tol:
        raise EquilibriumError(
            f"{name}: loads not in equilibrium: force imbalance {np.round(force, 12)} N "
            f"({report.rel_force:.2e} of the load scale {report.scale:.3e} N), moment imbalance "
            f"{np.round(moment, 12)} N m ({report.rel_moment:.2e}); tolerance {rel_tol:.1e}"
        )
    return report


def loads_on_side(
    block: ConvexBlock, load: BlockLoad, normal: np.ndarray, offset: float, about: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Force [N] and moment about ``about`` [N m] of the loads on the part ``n . x >= offset``.

    By Cauchy's theorem this equals the integral of ``sigma n`` over the cut ``n . x = offset``.
    Point forces count by the side their point lies on.
    """
    normal = np.asarray(normal, dtype=float)
    about = np.asarray(about, dtype=float)
    part = clip_halfspace(block, -np.asarray(normal, dtype=float), -offset)  # n . x >= offset
    force, moment = np.zeros(3), np.zeros(3)
    if part is not None:
        force, moment = body_resultant_on(part, block.centroid, load, about)
    side = load.points @ normal >= offset
    force = force + load.forces[side].sum(axis=0)
    moment = moment + np.cross(load.points[side] - about, load.forces[side]).sum(axis=0)
    for p in load.patches:
        q = p.clipped(normal, offset)
        if q is not None:
            f, m = q.resultant(about)
            force, moment = force + f, moment + m
    return force, moment


# -- DEM inputs --------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class BlockPointLoads:
    """Contact node forces of a DEM state (explicit TIS solver).

    Attributes
    ----------
    block : (k,) int64
        Block each force acts on.
    point : (k, 3) float
        Point of application [m].
    force : (k, 3) float
        Force acting on ``block`` [N].
    gravity : (3,) float
        [m/s^2].
    acceleration : (n_blocks, 6) float
        Centroid and angular acceleration of each block [m/s^2, rad/s^2].
    density : (n_blocks,) float
        [kg/m^3].
    angular_velocity : (n_blocks, 3) float or None
        [rad/s]; None means zero (then a spinning block's ``omega x I omega`` shows up as a
        moment imbalance).
    rotation : (n_blocks, 3, 3) float or None
        Rotation of each block from its reference configuration to the current one. When
        given, ``point`` lies in the reference configuration of its block (with the block
        vertices) while ``force``, ``gravity``, ``acceleration`` and ``angular_velocity`` are
        world vectors: :meth:`for_block` turns them into the block's reference frame,
        ``v_ref = R^T v``. When None, every array is in one frame already.
    """

    block: np.ndarray
    point: np.ndarray
    force: np.ndarray
    gravity: np.ndarray
    acceleration: np.ndarray
    density: np.ndarray
    angular_velocity: np.ndarray | None = None
    rotation: np.ndarray | None = None

    def __post_init__(self):
        blk = np.asarray(self.block, dtype=np.int64).reshape(-1)
        k = len(blk)
        n = len(np.asarray(self.density).reshape(-1))
        checks = {
            "point": (self.point, (k, 3)),
            "force": (self.force, (k, 3)),
            "gravity": (self.gravity, (3,)),
            "acceleration": (self.acceleration, (n, 6)),
            "density": (self.density, (n,)),
            "angular_velocity": (
                np.zeros((n, 3)) if self.angular_velocity is None else self.angular_velocity,
                (n, 3),
            ),
        }
        for name, (arr, shape) in checks.items():
            a = np.asarray(arr, dtype=float)
            if a.shape != shape or not np.all(np.isfinite(a)):
                raise ValueError(f"{name} must be finite with shape {shape}, got {a.shape}")
            object.__setattr__(self, name, a)
        if self.rotation is not None:
            rot = np.asarray(self.rotation, dtype=float)
            if rot.shape != (n, 3, 3) or not np.all(np.isfinite(rot)):
                raise ValueError(f"rotation must be finite with shape ({n}, 3, 3), got {rot.shape}")
            err = np.abs(np.einsum("nji,njk->nik", rot, rot) - np.eye(3)).max() if n else 0.0
            if err > 1e-6 or np.any(np.linalg.det(rot) < 0):
                raise ValueError(
                    f"rotation must hold proper rotation matrices (R^T R - I: {err:.1e})"
                )
            object.__setattr__(self, "rotation", rot)
        if k and (blk.min() < 0 or blk.max() >= n):
            raise ValueError(f"block index out of range 0..{n - 1}")
        object.__setattr__(self, "block", blk)

    @property
    def n_blocks(self) -> int:
        return len(self.density)

    def for_block(self, i: int) -> BlockLoad:
        """The :class:`BlockLoad` of block ``i``."""
        sel = self.block == i
        rot = np.eye(3) if self.rotation is None else self.rotation[i]
        acc = self.acceleration[i]
        return BlockLoad(
            self.point[sel],
            self.force[sel] @ rot,  # rows: v_ref = R^T v
            (),
            float(self.density[i]),
            self.gravity @ rot,
            np.concatenate([acc[:3] @ rot, acc[3:] @ rot]),
            self.angular_velocity[i] @ rot,
            "DEM node forces",
        )


def rotation_from_quaternion(quaternion: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotation matrices of (n, 4) quaternions, scalar first (normalised here)."""
    q = np.asarray(quaternion, dtype=float).reshape(-1, 4)
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def read_point_state(path: str | Path) -> tuple[BlockPointLoads, list[np.ndarray]]:
    """Read a TIS DEM state (``validation/results/tis-peak-state.npz`` layout).

    Arrays ``block``, ``point``, ``force``, ``gravity``, ``acceleration``, ``density``,
    ``block_vertices``, ``vert_ptr`` and, if present, ``angular_velocity`` (n_blocks, 3) and
    the block rotations from reference to current configuration, ``rotation``
    (n_blocks, 3, 3) or ``quaternion`` (n_blocks, 4), scalar first (see
    :class:`BlockPointLoads` for the frames).

    Returns
    -------
    loads : BlockPointLoads
    vertices : list of (v_i, 3) float
        Current corners of every block [m] (``block_vertices`` split at ``vert_ptr``).
    """
    with np.load(path) as data:
        ptr = np.asarray(data["vert_ptr"], dtype=np.int64)
        verts = np.asarray(data["block_vertices"], dtype=float).reshape(-1, 3)
        omega = data["angular_velocity"] if "angular_velocity" in data else None
        rotation = None
        if "rotation" in data:
            rotation = data["rotation"]
        elif "quaternion" in data:
            rotation = rotation_from_quaternion(data["quaternion"])
        loads = BlockPointLoads(
            data["block"], data["point"], data["force"], data["gravity"],
            data["acceleration"], data["density"], omega, rotation,
        )  # fmt: skip
    return loads, [verts[ptr[i] : ptr[i + 1]] for i in range(len(ptr) - 1)]


@dataclass(frozen=True, eq=False)
class InterfaceResultants:
    """Interface forces of a DEM state (masonry), one wrench per interface.

    Attributes
    ----------
    interfaces : Interfaces
        Geometry (polygons, frames) of the interfaces.
    resultants : (m, 6) float
        ``(N, V1, V2, M1, M2, M3)`` [N, N m]; see the module docstring for signs.
    """

    interfaces: Interfaces
    resultants: np.ndarray

    def __post_init__(self):
        r = np.asarray(self.resultants, dtype=float)
        if r.shape != (self.interfaces.n_interfaces, 6) or not np.all(np.isfinite(r)):
            raise ValueError(
                f"resultants must be finite with shape ({self.interfaces.n_interfaces}, 6), "
                f"got {r.shape}"
            )
        object.__setattr__(self, "resultants", r)

    def wrench_on_b(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """Force [N] and moment about the centroid [N m] that block a exerts on block b."""
        frame = self.interfaces.frame[k]  # rows n, t1, t2
        n_, v1, v2, m1, m2, m3 = self.resultants[k]
        force = n_ * frame[0] + v1 * frame[1] + v2 * frame[2]
        moment = m1 * frame[1] + m2 * frame[2] + m3 * frame[0]
        return force, moment

    def patches(self) -> tuple[list[TractionPatch], list[TractionPatch]]:
        """The traction patches on block a and on block b of every interface."""
        on_a, on_b = [], []
        for k in range(self.interfaces.n_interfaces):
            poly, c = self.interfaces.polygon(k), self.interfaces.centroid[k]
            f, m = self.wrench_on_b(k)
            (pb,) = wrench_patches([poly], f, m, c)
            on_b.append(pb)
            on_a.append(TractionPatch(poly, -pb.traction, -pb.spin, pb.centre))
        return on_a, on_b


def interface_block_loads(
    state: InterfaceResultants,
    n_blocks: int,
    density: np.ndarray,
    gravity: np.ndarray,
    acceleration: np.ndarray | None = None,
) -> list[BlockLoad]:
    """The :class:`BlockLoad` of every block from interface resultants.

    Parameters
    ----------
    state : InterfaceResultants
    n_blocks : int
    density : (n_blocks,) float
        [kg/m^3].
    gravity : (3,) float
        [m/s^2].
    acceleration : (n_blocks, 6) float, optional
        Zero (a static state) by default.
    """
    density = np.broadcast_to(np.asarray(density, dtype=float), (n_blocks,))
    acc = np.zeros((n_blocks, 6)) if acceleration is None else np.asarray(acceleration, float)
    on_a, on_b = state.patches()
    per_block: list[list[TractionPatch]] = [[] for _ in range(n_blocks)]
    for k in range(state.interfaces.n_interfaces):
        per_block[state.interfaces.block_a[k]].append(on_a[k])
        per_block[state.interfaces.block_b[k]].append(on_b[k])
    return [
        BlockLoad(
            patches=tuple(per_block[i]),
            density=float(density[i]),
            gravity=gravity,
            acceleration=acc[i],
            label="interface resultants",
        )
        for i in range(n_blocks)
    ]


def support_reaction_patches(
    block: ConvexBlock, load: BlockLoad, face_ids: list[int]
) -> list[TractionPatch]:
    """Tractions on a supported block's support faces that balance its other loads.

    The support reaction of a fixed block is the negative of the resultant of its contact and
    body loads; it is spread over ``face_ids`` as the smallest traction with that wrench
    (:func:`wrench_patches`). This is a modelling choice for blocks the DEM holds fixed (the
    reaction is an output there, not a contact force), reported as such.
    """
    if not face_ids:
        raise ValueError("support_reaction_patches needs at least one support face")
    force, moment = load.resultant(block)
    polys = [block.vertices[block.faces[f]] for f in face_ids]
    return wrench_patches(polys, -force, -moment, block.centroid)
