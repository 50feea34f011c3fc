"""Rigid-block scenes and the DEM solvers (explicit LS-DEM style for TIS, static for masonry)."""

import os

import numpy as np

from dem.geometry import polyhedron as _polyhedron
from dem.geometry.interfaces import Interfaces, OverlapError, find_interfaces
from dem.geometry.polyhedron import ConvexBlock
from dem.scene import Assembly, Loads, MixedUnitsWarning, Scene, Supports

# numba's parallel kernels (the explicit DEM's node loop, the static DEM's interface laws) run
# on its "omp" threading layer, one OpenMP region per call. Worker threads that spin between
# regions (libgomp's default) starve on a shared machine, where they made the parallel calls
# slower than serial ones many times over; sleeping workers cost one wake-up per region. Set
# before numba starts its threads (its first parallel call); the user's setting wins.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

__all__ = [
    "Assembly",
    "ConvexBlock",
    "Interfaces",
    "Loads",
    "MixedUnitsWarning",
    "OverlapError",
    "Scene",
    "Supports",
    "convex_block",
    "find_interfaces",
]


def convex_block(points: np.ndarray, *, exact: bool = True) -> ConvexBlock:
    """A convex block whose corners are ``points`` (n, 3) [m]: exact by default, like
    :class:`Scene` and :class:`Assembly`, so that a point inside the hull, on a face or edge,
    or a non-convex block raises; ``exact=False`` takes the convex hull of the points
    (:func:`dem.geometry.polyhedron.convex_block`)."""
    return _polyhedron.convex_block(points, exact=exact)
