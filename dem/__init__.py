"""Rigid-block scenes and the DEM solvers (explicit LS-DEM style for TIS, static for masonry)."""

from dem.geometry.interfaces import Interfaces, OverlapError, find_interfaces
from dem.geometry.polyhedron import ConvexBlock, convex_block
from dem.scene import Assembly, Loads, Scene, Supports

__all__ = [
    "Assembly",
    "ConvexBlock",
    "Interfaces",
    "Loads",
    "OverlapError",
    "Scene",
    "Supports",
    "convex_block",
    "find_interfaces",
]
