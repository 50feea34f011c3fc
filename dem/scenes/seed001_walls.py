"""Every masonry specimen of seed 001 (Baraldi & Cecchi), Tables 1-3, from the seed's numbers.

Builders return a :class:`dem.scene.Scene` (SI inside); :data:`SPECIMENS` lists each specimen
with the seed's DEM value, its reference values (FEM, limit analysis, experiments) and where
the geometry had to be assumed because the seed leaves it open.

- Table 1, :func:`orduna_panel`: the two dry-joint panels of Orduna & Lourenco (2005b),
  ``a = 81, b = 210, s = 70`` mm, 20 kN/m^3, ``mu = 0.7``, 13 courses, 3 or 6 blocks per course;
  "block translations are fixed" along the left column (3 x 13) or both lateral columns
  (6 x 13); out-of-plane load proportional to weight (lambda dimensionless).
- Table 2, :func:`restrepo_specimen`: the dry-stone specimens of Restrepo-Velez et al. (2014),
  ``a = 28.24, b = 79.78, s = 39.68`` mm, 26.8 kN/m^3, ``mu = 0.7``, 21 courses; return walls
  either as the seed's fixed columns or built as blocks (:mod:`dem.scenes.return_walls`).
- Table 3, :func:`chee_liang_specimen`: the mortared walls of Chee Liang (1996), bricks
  ``b = 112, a = 36, s = 53`` mm, joints 10 mm, uniform pressure (lambda in Pa; the seed's
  p in kN/m^2 is lambda / 1000), simply supported on 3 or 4 sides. The interface law
  (``k_n = 25``, ``k_t = 105`` N/mm^3, ``mu = 0.57``, tensile strength 0.35 MPa) belongs to
  the solver settings: :data:`CHEE_LIANG_JOINT` holds it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dem.scene import Scene, Supports
from dem.scenes.return_walls import wall_with_returns
from dem.scenes.running_bond_wall import running_bond_wall

SOURCE = "seed 001 (Baraldi & Cecchi)"

# --- Table 1: Orduna & Lourenco (2005b) --------------------------------------------------------
ORDUNA_BLOCK_MM = (81.0, 210.0, 70.0)  # a (height), b (length), s (thickness)
ORDUNA_UNIT_WEIGHT = 20.0  # [kN/m^3]
ORDUNA_MU = 0.7
ORDUNA_COURSES = 13
ORDUNA_RETURN_BLOCKS = 2  # our alternative: return walls of blocks, length in blocks (assumed)

# --- Table 2: Restrepo-Velez, Magenes & Griffith (2014) ----------------------------------------
RESTREPO_BLOCK_MM = (28.24, 79.78, 39.68)
RESTREPO_UNIT_WEIGHT = 26.8  # [kN/m^3]
RESTREPO_MU = 0.7
RESTREPO_COURSES = 21
RESTREPO_BEAM_FORCE_N = 16.46  # each of the eleven wooden beams on S32
RESTREPO_RETURN_BLOCKS = 3  # assumed length of a return wall behind the corner, in blocks
RESTREPO_S32_TOP = "restrained"
"""S32: the wooden beams hold the top course out of plane (``uy`` restrained), assumed. With a
free top the wall would overturn as a whole at ``lambda ~ s (W + P) / (W H) = 0.084``, far
from both the seed's DEM (0.305) and the test (0.293), whose mechanism has a horizontal hinge
between courses 15 and 16: that hinge needs a restrained top."""

# --- Table 3: Chee Liang (1996) ----------------------------------------------------------------
CHEE_LIANG_BRICK_MM = (36.0, 112.0, 53.0)  # a, b, s
CHEE_LIANG_JOINT_MM = 10.0
CHEE_LIANG_UNIT_WEIGHT = 18.0  # [kN/m^3] not given by the seed: assumed (clay brickwork)


@dataclass(frozen=True)
class JointLaw:
    """Interface law of a specimen family in paper units (the solver converts).

    Attributes
    ----------
    mu : float
        Friction coefficient [-].
    tensile_strength_mpa : float
        [MPa]; 0 for dry joints.
    kn_n_mm3, kt_n_mm3 : float or None
        Normal and tangential stiffness per unit area [N/mm^3]; None where the seed gives none
        (dry joints: the solver's default penalty stiffness).
    """

    mu: float
    tensile_strength_mpa: float = 0.0
    kn_n_mm3: float | None = None
    kt_n_mm3: float | None = None


DRY_JOINT_07 = JointLaw(mu=0.7)
CHEE_LIANG_JOINT = JointLaw(mu=0.57, tensile_strength_mpa=0.35, kn_n_mm3=25.0, kt_n_mm3=105.0)


@dataclass(frozen=True)
class SeedSpecimen:
    """One specimen of seed 001 Tables 1-3 with the seed's numbers.

    Attributes
    ----------
    key : str
        Unique id, e.g. ``"orduna-3x13"``, ``"restrepo-S11"``, ``"chee-liang-2-3"``.
    table : str
        ``"Table 1"``, ``"Table 2"`` or ``"Table 3"``.
    name : str
        The specimen's name in the seed.
    quantity : str
        ``"lambda [-]"`` (live load proportional to weight) or ``"p [kN/m^2]"`` (pressure).
    seed_dem : float
        The seed's DEM collapse value.
    reference : float
        The primary reference: Table 1 FEM, Table 2 experiment, Table 3 mean of the two tests.
    references : dict
        Every reference value in the table, by name.
    source : str
    supports : str
        The supports as the seed describes them.
    assumptions : str
        What the seed leaves open and we assumed.
    joint : JointLaw
    builder : str
        ``"orduna_panel"``, ``"restrepo_specimen"`` or ``"chee_liang_specimen"``.
    args : dict
        Builder arguments in paper units.
    """

    key: str
    table: str
    name: str
    quantity: str
    seed_dem: float
    reference: float
    references: dict
    source: str
    supports: str
    assumptions: str
    joint: JointLaw
    builder: str
    args: dict = field(default_factory=dict)

    def build(self, **kwargs) -> Scene:
        """The scene of this specimen (keyword arguments go to the builder)."""
        if self.builder == "orduna_panel":
            return orduna_panel(self.args["n_per_course"], **kwargs)
        if self.builder == "restrepo_specimen":
            return restrepo_specimen(self.name, **kwargs)
        return chee_liang_specimen(self.name)


# ----------------------------------------------------------------------------------------------
# Table 1
# ----------------------------------------------------------------------------------------------


def orduna_panel(n_per_course: int | str = 3, return_walls: str = "translations") -> Scene:
    """Orduna & Lourenco's dry-joint panels (seed 001, Sec. 3.1, Fig. 12, Table 1).

    Parameters
    ----------
    n_per_course : {3, 6} or {"3x13", "6x13"}
        3: ``L = 0.630, H = 1.053`` m, restrained on the left (case 1); 6: ``L = 1.260,
        H = 1.053`` m, restrained on both sides (case 2).
    return_walls : {"translations", "blocks"}
        ``"translations"``: the seed's model, ``ux, uy, uz`` of the end block of every course
        restrained, rotations free. ``"blocks"``: the restraint built as return walls of
        blocks in corner bond, ``ORDUNA_RETURN_BLOCKS`` long (an alternative of ours, see
        :mod:`dem.scenes.return_walls`).

    Returns
    -------
    Scene
        13 courses on a fixed foundation; live load: weight along +y.
    """
    key = {"3x13": 3, "6x13": 6, 3: 3, 6: 6}.get(n_per_course)
    if key is None:
        raise ValueError(
            f"orduna_panel takes 3 (3 x 13 panel, case 1) or 6 (6 x 13 panel, case 2), "
            f"got {n_per_course!r}"
        )
    if return_walls not in ("translations", "blocks"):
        raise ValueError(f"return_walls must be 'translations' or 'blocks', got {return_walls!r}")
    a, b, s = ORDUNA_BLOCK_MM
    sides = ("left",) if key == 3 else ("left", "right")
    name = f"orduna_{key}x{ORDUNA_COURSES}"
    if return_walls == "blocks":
        scene = wall_with_returns(
            key,
            ORDUNA_COURSES,
            a,
            b,
            s,
            ORDUNA_UNIT_WEIGHT,
            ORDUNA_MU,
            returns=sides,
            return_blocks=ORDUNA_RETURN_BLOCKS,
            name=name + "_blocks",
        )
        meta = dict(scene.meta, seed001="Table 1", return_walls="blocks")
        return Scene(scene.assembly, scene.supports, scene.loads, scene.name, meta)
    scene = running_bond_wall(
        key,
        ORDUNA_COURSES,
        a,
        b,
        s,
        ORDUNA_UNIT_WEIGHT,
        ORDUNA_MU,
        base=True,
        live="weight",
        name=name,
    )
    restrained = scene.supports.restrained.copy()
    for i in _column_blocks(scene, sides):
        restrained[i, :3] = True
    meta = dict(
        scene.meta,
        seed001="Table 1",
        restrained_columns=list(sides),
        column_restraint="translations",
        return_walls="translations",
    )
    return Scene(
        scene.assembly, Supports(scene.supports.fixed, restrained), scene.loads, scene.name, meta
    )


def _column_blocks(scene: Scene, sides) -> list[int]:
    """End blocks of every course of a running-bond wall on the given sides."""
    course = np.array(scene.meta["course"])
    cx = scene.assembly.centroid[:, 0]
    out = []
    for k in range(int(course.max()) + 1):
        ids = np.flatnonzero(course == k)
        order = ids[np.argsort(cx[ids])]
        if "left" in sides:
            out.append(int(order[0]))
        if "right" in sides:
            out.append(int(order[-1]))
    return out


# ----------------------------------------------------------------------------------------------
# Table 2
# ----------------------------------------------------------------------------------------------

_B2 = RESTREPO_BLOCK_MM[1]
_A2 = RESTREPO_BLOCK_MM[0]
# Two window openings, 3 blocks wide and 7 courses high, sill on course 7: assumed (the seed
# gives no opening sizes, only "wide" (S23) and "thin" (S34) central pier).
_OPENING_Z = (7 * _A2, 14 * _A2)
RESTREPO_OPENINGS_MM = {
    "S23": (  # central pier 4 blocks wide
        (2 * _B2, _OPENING_Z[0], 5 * _B2, _OPENING_Z[1]),
        (9 * _B2, _OPENING_Z[0], 12 * _B2, _OPENING_Z[1]),
    ),
    "S34": (  # central pier 2 blocks wide
        (3 * _B2, _OPENING_Z[0], 6 * _B2, _OPENING_Z[1]),
        (8 * _B2, _OPENING_Z[0], 11 * _B2, _OPENING_Z[1]),
    ),
}

# name: (n, supports, seed DEM lambda, experimental lambda)
_RESTREPO = {
    "S11": (12, "left", 0.100, 0.097),
    "S12": (8, "left", 0.125, 0.129),
    "S13": (6, "left", 0.165, 0.181),
    "S15": (4, "left", 0.250, 0.199),
    "S6": (13, "both", 0.160, 0.208),
    "S1-S2-S3": (11, "both", 0.225, 0.208),
    "S5": (8, "both", 0.350, 0.349),
    "S32": (14, "base+beams", 0.305, 0.293),
    "S23": (14, "both+openings", 0.130, 0.144),
    "S34": (14, "both+openings", 0.140, 0.156),
}
RESTREPO_NAMES = tuple(_RESTREPO)


def restrepo_specimen(
    name: str, return_walls: str = "fixed_column", return_blocks: int = RESTREPO_RETURN_BLOCKS
) -> Scene:
    """A Restrepo-Velez et al. (2014) dry-stone specimen (seed 001, Sec. 3.2, Table 2).

    Parameters
    ----------
    name : str
        One of ``S11, S12, S13, S15`` (one return wall, left; Fig. 15), ``S6, S1-S2-S3, S5``
        (two return walls; Fig. 16), ``S32`` (no return wall, eleven beams of 16.46 N; Fig. 17),
        ``S23, S34`` (two return walls, two openings; Fig. 18; the seed's text calls the second
        one S24).
    return_walls : {"fixed_column", "blocks"}
        ``"fixed_column"``: the seed's model, translations and rotations of the end block of
        every course fixed. ``"blocks"``: the return walls built as blocks in corner bond
        (:func:`dem.scenes.return_walls.wall_with_returns`), ``RESTREPO_RETURN_BLOCKS`` long.
        Ignored for S32.
    return_blocks : int
        Length of each return wall built as blocks, in blocks behind the wall (assumed; the
        seed gives none).

    Returns
    -------
    Scene
        21 courses of ``n`` blocks on a fixed foundation, live load: weight along +y (tilting
        table, lambda = tan of the tilt angle for a rigid specimen).
    """
    if name == "S24":
        name = "S34"
    if name not in _RESTREPO:
        raise ValueError(f"unknown Restrepo-Velez specimen {name!r}; known: {RESTREPO_NAMES}")
    if return_walls not in ("fixed_column", "blocks"):
        raise ValueError(f"return_walls must be 'fixed_column' or 'blocks', got {return_walls!r}")
    n, supports, _, _ = _RESTREPO[name]
    b = RESTREPO_BLOCK_MM[1]
    wall = (n, RESTREPO_COURSES, *RESTREPO_BLOCK_MM)
    common = dict(unit_weight_kn_m3=RESTREPO_UNIT_WEIGHT, mu=RESTREPO_MU)
    openings = RESTREPO_OPENINGS_MM.get(name, ())
    tag = f"restrepo_{name}_{return_walls}"
    sides = ("left",) if supports == "left" else ("left", "right")
    if supports == "base+beams":
        beams = [((i + 0.5) * n * b / 11, RESTREPO_BEAM_FORCE_N * 1e-3) for i in range(11)]
        # The beams also hold the top course out of plane (assumed, see RESTREPO_S32_TOP)
        top = ("top",) if RESTREPO_S32_TOP == "restrained" else ()
        scene = running_bond_wall(
            *wall,
            base=True,
            beam_loads_kn=beams,
            simply_supported=top,
            live="weight",
            name=f"restrepo_{name}",
            **common,
        )
    elif return_walls == "fixed_column":
        scene = running_bond_wall(
            *wall,
            base=True,
            fixed_columns=sides,
            openings_mm=openings,
            live="weight",
            name=tag,
            **common,
        )
    else:
        scene = wall_with_returns(
            *wall,
            returns=sides,
            return_blocks=return_blocks,
            openings_mm=openings,
            name=tag,
            **common,
        )
    meta = dict(scene.meta, seed001="Table 2", specimen=name, return_walls=return_walls)
    return Scene(scene.assembly, scene.supports, scene.loads, scene.name, meta)


# ----------------------------------------------------------------------------------------------
# Table 3
# ----------------------------------------------------------------------------------------------

# wall: (L [m], H [m], restraint, seed DEM p [kN/m^2], test 1, test 2 [kN/m^2])
_CHEE_LIANG = {
    "2-3": (1.15, 1.15, "4 sides", 13.00, 12.20, 12.55),
    "8-12": (0.795, 1.190, "4 sides", 25.0, 25.0, 31.8),
    "14-15": (1.130, 0.755, "4 sides", 18.0, 20.6, 18.9),
    "4-5": (1.14, 1.14, "3 sides, free top", 10.00, 8.54, 8.55),
    "9-13": (0.795, 1.140, "3 sides, free top", 20.0, 23.5, 27.8),
    "10-11": (1.20, 1.20, "3 sides, free left", 6.5, 5.20, 4.51),
}
CHEE_LIANG_NAMES = tuple(_CHEE_LIANG)
_CHEE_LIANG_SUPPORTS = {
    "4 sides": ("bottom", "top", "left", "right"),
    "3 sides, free top": ("bottom", "left", "right"),
    "3 sides, free left": ("bottom", "top", "right"),
}


def chee_liang_layout(name: str) -> tuple[int, int, float, float]:
    """Blocks per course, courses, and block pitch ``(b', a')`` [mm] of a Chee Liang wall.

    The rigid blocks of the interface model are brick plus one joint thickness (122 x 46 mm);
    the counts are the nearest integers to ``L / 122`` and ``H / 46`` (halves rounded up) and
    the pitch is stretched so that the model has the seed's ``L`` and ``H`` exactly.
    """
    if name not in _CHEE_LIANG:
        raise ValueError(f"unknown Chee Liang wall {name!r}; known: {CHEE_LIANG_NAMES}")
    length, height = _CHEE_LIANG[name][:2]
    a, b, _ = CHEE_LIANG_BRICK_MM
    n = max(1, int(np.floor(length * 1e3 / (b + CHEE_LIANG_JOINT_MM) + 0.5)))
    nc = max(1, int(np.floor(height * 1e3 / (a + CHEE_LIANG_JOINT_MM) + 0.5)))
    return n, nc, length * 1e3 / n, height * 1e3 / nc


def chee_liang_specimen(name: str) -> Scene:
    """A Chee Liang (1996) mortared wall (seed 001, Sec. 3.3, Table 3, Figs. 19-21).

    Parameters
    ----------
    name : str
        Wall pair of Table 3: ``2-3, 8-12, 14-15`` (4 sides simply supported), ``4-5, 9-13``
        (3 sides, free top), ``10-11`` (3 sides, free left).

    Returns
    -------
    Scene
        Running-bond wall of :func:`chee_liang_layout` on a fixed foundation (the vertical
        support), ``uy`` restrained along the supported edges, live load a uniform pressure
        on the face ``y = -s/2`` (lambda in Pa).
    """
    n, nc, b, a = chee_liang_layout(name)
    _, _, restraint, *_ = _CHEE_LIANG[name]
    scene = running_bond_wall(
        n,
        nc,
        a,
        b,
        CHEE_LIANG_BRICK_MM[2],
        CHEE_LIANG_UNIT_WEIGHT,
        CHEE_LIANG_JOINT.mu,
        base=True,
        simply_supported=_CHEE_LIANG_SUPPORTS[restraint],
        live="pressure",
        name=f"chee_liang_{name}",
    )
    meta = dict(scene.meta, seed001="Table 3", specimen=name, restraint=restraint)
    return Scene(scene.assembly, scene.supports, scene.loads, scene.name, meta)


# ----------------------------------------------------------------------------------------------
# The table of specimens
# ----------------------------------------------------------------------------------------------


def _specimens() -> dict[str, SeedSpecimen]:
    out: dict[str, SeedSpecimen] = {}
    for n, dem, fem, lim in ((3, 0.175, 0.210, 0.127), (6, 0.215, 0.260, 0.193)):
        key = f"orduna-{n}x13"
        out[key] = SeedSpecimen(
            key=key,
            table="Table 1",
            name=f"{n}x13",
            quantity="lambda [-]",
            seed_dem=dem,
            reference=fem,
            references={"fem": fem, "limit": lim},
            source=f"{SOURCE} Table 1 (Orduna & Lourenco 2005b: FEM and limit analysis)",
            supports="translations of the left column fixed"
            if n == 3
            else "translations of both lateral columns fixed",
            assumptions="fixed foundation under the first course; rotations of the restrained "
            "column blocks left free (the seed fixes translations only)",
            joint=DRY_JOINT_07,
            builder="orduna_panel",
            args={"n_per_course": n},
        )
    for name, (n, sup, dem, exp) in _RESTREPO.items():
        key = f"restrepo-{name}"
        assumptions = {
            "left": "one return wall on the left",
            "both": "return walls on both ends",
            "base+beams": "no return wall; beams evenly spaced at (i + 1/2) L / 11 on the top; "
            "the beams restrain the top course out of plane (assumed: with a free top the "
            "wall overturns at 0.084)",
            "both+openings": "return walls on both ends; openings 3 blocks wide, courses 7-13 "
            "(assumed), central pier " + ("4" if name == "S23" else "2") + " blocks",
        }[sup]
        if sup != "base+beams":
            assumptions += (
                f"; n = blocks per even course including the corner block; return walls as "
                f"blocks are {RESTREPO_RETURN_BLOCKS} blocks long (assumed), behind the wall"
            )
        out[key] = SeedSpecimen(
            key=key,
            table="Table 2",
            name=name,
            quantity="lambda [-]",
            seed_dem=dem,
            reference=exp,
            references={"experiment": exp},
            source=f"{SOURCE} Table 2 (Restrepo-Velez et al. 2014, tilting-table tests)",
            supports=sup,
            assumptions=assumptions,
            joint=DRY_JOINT_07,
            builder="restrepo_specimen",
            args={"name": name, "n_per_course": n},
        )
    for name, (length, height, restraint, dem, t1, t2) in _CHEE_LIANG.items():
        key = f"chee-liang-{name}"
        n, nc, b, a = chee_liang_layout(name)
        out[key] = SeedSpecimen(
            key=key,
            table="Table 3",
            name=name,
            quantity="p [kN/m^2]",
            seed_dem=dem,
            reference=0.5 * (t1 + t2),
            references={"test_1": t1, "test_2": t2},
            source=f"{SOURCE} Table 3 (Chee Liang 1996, two tests per wall)",
            supports=restraint,
            assumptions=f"{n} x {nc} blocks of pitch {b:.1f} x {a:.1f} mm (brick + 10 mm "
            f"joint, stretched to L = {length} m, H = {height} m); unit weight "
            f"{CHEE_LIANG_UNIT_WEIGHT} kN/m^3 (not in the seed); the bottom edge rests on a "
            "fixed foundation",
            joint=CHEE_LIANG_JOINT,
            builder="chee_liang_specimen",
            args={"name": name, "length_m": length, "height_m": height},
        )
    return out


SPECIMENS: dict[str, SeedSpecimen] = _specimens()
"""Every specimen of seed 001 Tables 1-3, keyed ``orduna-3x13``, ``restrepo-S11``,
``chee-liang-2-3``, ..."""
