"""Penalty stiffness from the material, and settings for masonry scenes.

Seed 000 Eq. (3) makes the penalty reproduce the blocks' elastic deformability: ``M``
interfaces across a strip of length ``L`` give ``k_n = M E / L``. For a wall, a strip through
one block and one joint has ``M = 1`` and ``L`` the block's extent across the joint, so each
interface ``k`` has ``k_n,k = E / L_k`` with ``L_k`` the distance between the two centroids
along the interface normal (twice the free block's distance to the interface when the other
block is fixed). The solver takes one ``k_n``: the median over the interfaces. The collapse
load of rigid blocks does not depend on ``k_n`` (the problem is homogeneous in it); ``k_n``
sets the time step and the elastic deflections before collapse.
"""

from __future__ import annotations

import math

import numpy as np

from dem.explicit.settings import ExplicitSettings
from dem.scene import Scene
from dem.units import GPA

MASONRY_YOUNG = 1.0 * GPA
"""Default Young's modulus for masonry scenes [Pa]: low for stone or brick (a few to tens of
GPa) but of the order of dry-joint masonry as a whole, and it keeps the time step long. The
penetration under the weight of a 1 m wall is then ``rho g H L / E``, about 1e-6 of a 50 mm
block, far below the motion thresholds of :class:`dem.explicit.lateral.MotionCriteria`."""
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


def k_n_from_material(scene: Scene, young: float = MASONRY_YOUNG) -> float:
    """Median over the interfaces of ``E / L_k`` [Pa/m] (seed 000 Eq. (3) with ``M = 1``).

    Parameters
    ----------
    scene : Scene
    young : float
        Young's modulus of the blocks [Pa].
    """
    if not (math.isfinite(young) and young > 0):
        raise ValueError(f"young must be finite and positive [Pa], got {young}")
    return float(np.median(young / interface_lengths(scene)))


def masonry_settings(scene: Scene, young: float = MASONRY_YOUNG, **overrides) -> ExplicitSettings:
    """Explicit settings for a masonry scene, with the material's ``k_n`` and edge nodes.

    ``k_n`` from :func:`k_n_from_material`; nodes at the corners of a grid whose spacing is the
    smallest block dimension over :data:`NODES_PER_EDGE` (``node_layout="vertex"``: the outer
    nodes lie on the face edges, so a block rocks about its true edge and ``b / h`` is exact);
    no global viscous damping (it would resist the mechanism itself; the contact dashpots damp
    the vibrations). Keyword arguments override any field.
    """
    extent = np.array([np.ptp(b.vertices, axis=0).min() for b in scene.assembly.blocks])
    spacing = float(extent[~scene.supports.fixed].min() if (~scene.supports.fixed).any()
                    else extent.min()) / NODES_PER_EDGE  # fmt: skip
    fields = {
        "k_n": k_n_from_material(scene, young),
        "node_spacing": spacing,
        "node_layout": "vertex",
        "margin": 0.5 * spacing,
        "global_damping": 0.0,
    }
    fields.update(overrides)
    return ExplicitSettings(**fields)
