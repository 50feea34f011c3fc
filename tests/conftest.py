"""Shared tiny scenes; headless defaults for plotting libraries."""

import itertools
import os

import numpy as np
import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

from dem.scene import Scene  # noqa: E402


def pytest_configure(config):
    """Under pytest-xdist, compile the numba kernels in the controlling process before the
    workers start, so that they load the on-disk cache rather than write it at the same time
    (:mod:`dem.warmup`)."""
    if getattr(config.option, "numprocesses", None) and not hasattr(config, "workerinput"):
        from dem.warmup import compile_kernels

        compile_kernels()


def box_corners(lo, hi) -> np.ndarray:
    """(8, 3) corners of the axis-aligned box ``[lo, hi]``."""
    return np.array(list(itertools.product(*zip(lo, hi, strict=True))), dtype=float)


@pytest.fixture
def cube_on_ground() -> Scene:
    """A 1 m cube (density 1000) on a fixed 3 x 3 x 1 m ground block; mu = 0.5."""
    ground = box_corners((-1.0, -1.0, -1.0), (2.0, 2.0, 0.0))
    cube = box_corners((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    return Scene.from_convex_blocks([cube, ground], density=1000.0, fixed=[1], mu=0.5)


@pytest.fixture
def two_block_stack() -> Scene:
    """Two 1 x 1 x 0.5 m blocks stacked on a fixed ground block; density 1000, mu = 0.5."""
    ground = box_corners((-1.0, -1.0, -1.0), (2.0, 2.0, 0.0))
    low = box_corners((0.0, 0.0, 0.0), (1.0, 1.0, 0.5))
    high = box_corners((0.0, 0.0, 0.5), (1.0, 1.0, 1.0))
    return Scene.from_convex_blocks([low, high, ground], density=1000.0, fixed=[2], mu=0.5)
