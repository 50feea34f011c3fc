"""Penalty stiffness from the material, and settings for masonry scenes.

Seed 000 Eq. (3) makes the penalty reproduce the blocks' elastic deformability: ``M``
interfaces across a strip of length ``L`` give ``k_n = M E / L``. For a wall, a strip through
one block and one joint has ``M = 1`` and ``L`` the block's extent across the joint, so each
interface ``k`` has ``k_n,k = E / L_k`` with ``L_k`` the distance between the two centroids
along the interface normal (twice the free block's distance to the interface when the other
block is fixed). The solver takes one ``k_n``: the median over the interfaces. A dry or
mortared joint is softer than the block (gap closure, mortar): as for TIS gaps (seed 000
Eq. (4)) the joint stiffness ``k_j`` acts in series, ``k_n = k_def k_j / (k_def + k_j)``; the
default ``k_j`` is seed 001's joint stiffness (Sec. 2.1, 2.4 N/mm^3). The collapse load of
rigid blocks does not depend on ``k_n`` (the problem is homogeneous in it); ``k_n`` sets the
time step and the elastic deflections before collapse.
"""

from __future__ import annotations

import math

import numpy as np

from dem.explicit.settings import ExplicitSettings
from dem.scene import Scene
from dem.tis_stiffness import k_series
from dem.units import GPA, N_MM3

MASONRY_YOUNG = 10.0 * GPA
"""Default Young's modulus of masonry units [Pa] (brick and stone: a few to tens of GPa)."""
JOINT_STIFFNESS = 2.4 * N_MM3
"""Default joint stiffness per unit area, seed 001 Sec. 2.1 (2.4 N/mm^3) [Pa/m]. Under the
weight of a 1 m wall the joints then close by ``rho g H / k_j``, about 1e-5 m, below the motion
thresholds of :class:`dem.explicit.lateral.MotionCriteria` for blocks of a few cm."""
LOCAL_DAMPING = 0.7
"""Default local damping for masonry (PFC's default; 3DEC uses 0.8 for static solutions)."""
NODES_PER_EDGE = 4
"""Default node spacing for masonry: the smallest block dimension over this."""


def interface_lengths(scene: Scene) -> np.ndarray:
    """``L_k`` of every face-to-face interface of the scene (module docstring) [m].

    Raises
    ------
    OverlapError
        If blocks interpenetrate (from :meth:`dem.scene.Assembly.interfaces`).
    ValueError
        If the scene has no interface between blocks that can move.
    """
    interfaces = scene.assembly.interfaces()
    fixed = scene.supports.fixed
    centroid = scene.assembly.centroid
    a, b = interfaces.block_a, interfaces.block_b
    normal = interfaces.frame[:, 0]
    both_free = ~fixed[a] & ~fixed[b]
    span = np.abs(np.einsum("ij,ij->i", centroid[b] - centroid[a], normal))
    free_side = np.where(fixed[a], b, a)
    to_face = np.abs(np.einsum("ij,ij->i", interfaces.centroid - centroid[free_side], normal))
    lengths = np.where(both_free, span, 2.0 * to_face)
    lengths = lengths[~(fixed[a] & fixed[b])]
    if len(lengths) == 0:
        raise ValueError(
            f"scene {scene.name!r} has no face-to-face interface with a free block: give "
            "ExplicitSettings.k_n directly"
        )
    return lengths


def k_n_from_material(
    scene: Scene, young: float = MASONRY_YOUNG, joint_stiffness: float | None = JOINT_STIFFNESS
) -> float:
    """Penalty from the material: ``k_def = median_k E / L_k`` (seed 000 Eq. (3), ``M = 1``),
    in series with the joint stiffness (seed 000 Eq. (4)) [Pa/m].

    Parameters
    ----------
    scene : Scene
    young : float
        Young's modulus of the blocks [Pa].
    joint_stiffness : float or None
        Joint stiffness per unit area ``k_j`` [Pa/m]; None: rigid joints (``k_def`` alone).
    """
    if not (math.isfinite(young) and young > 0):
        raise ValueError(f"young must be finite and positive [Pa], got {young}")
    k_def = float(np.median(young / interface_lengths(scene)))
    return k_def if joint_stiffness is None else k_series(k_def, joint_stiffness)


def masonry_settings(
    scene: Scene,
    young: float = MASONRY_YOUNG,
    joint_stiffness: float | None = JOINT_STIFFNESS,
    **overrides,
) -> ExplicitSettings:
    """Explicit settings for a masonry scene, with the material's ``k_n`` and edge nodes.

    ``k_n`` from :func:`k_n_from_material`; nodes at the corners of a grid whose spacing is the
    smallest block dimension over :data:`NODES_PER_EDGE` (``node_layout="vertex"``: the outer
    nodes lie on the face edges, so a block rocks about its true edge and ``b / h`` is exact);
    penetration from the neighbour's face plane that faces the node (``contact_plane=
    "compatible"``: with the nearest plane, a node on an edge shared with an equal neighbour,
    as in a stack of equal blocks or at every joint of an arch, is about as near the
    neighbour's side plane and carries nothing where the hinge forms, so a column of three
    boxes rocked about its middle joint at half its lever arm);
    no global viscous damping (it would resist the mechanism itself) but local damping
    :data:`LOCAL_DAMPING` (it damps the vibrations of the slow modes of a wall, which the
    contact dashpots tuned to ``omega_max`` leave nearly undamped). Keyword arguments override
    any field.
    """
    extent = np.array([np.ptp(b.vertices, axis=0).min() for b in scene.assembly.blocks])
    spacing = float(extent[~scene.supports.fixed].min() if (~scene.supports.fixed).any()
                    else extent.min()) / NODES_PER_EDGE  # fmt: skip
    fields = {
        "k_n": k_n_from_material(scene, young, joint_stiffness),
        "node_spacing": spacing,
        "node_layout": "vertex",
        "contact_plane": "compatible",
        "margin": 0.5 * spacing,
        "global_damping": 0.0,
        "local_damping": LOCAL_DAMPING,
    }
    fields.update(overrides)
    return ExplicitSettings(**fields)
