"""Return walls built as blocks: every block stands on its own, with a margin."""

import numpy as np
import pytest

from dem.scenes.return_walls import wall_with_returns


def _boxes(scene):
    """Axis-aligned extents of every block, shape (n_blocks, 2, 3): [min, max] x xyz."""
    return np.array([[b.vertices.min(0), b.vertices.max(0)] for b in scene.assembly.blocks])


def _support_margin(boxes, i, tol):
    """How far [m] block ``i``'s centre of mass lies inside the bounding rectangle of the
    areas where it rests on blocks right below it (negative: outside, it tips over)."""
    lo, hi = boxes[i]
    below = np.abs(boxes[:, 1, 2] - lo[2]) < tol
    x0 = np.maximum(boxes[below, 0, 0], lo[0])
    x1 = np.minimum(boxes[below, 1, 0], hi[0])
    y0 = np.maximum(boxes[below, 0, 1], lo[1])
    y1 = np.minimum(boxes[below, 1, 1], hi[1])
    touch = (x1 - x0 > tol) & (y1 - y0 > tol)
    centre = (lo + hi) / 2  # prisms of uniform density
    return min(centre[0] - x0[touch].min(), x1[touch].max() - centre[0],
               centre[1] - y0[touch].min(), y1[touch].max() - centre[1])  # fmt: skip


@pytest.mark.parametrize("n_courses", [4, 5])
@pytest.mark.parametrize("returns", [("left",), ("left", "right")])
def test_every_block_rests_with_its_centre_well_inside_its_support(n_courses, returns):
    # Restrepo-Velez blocks: s = 39.68 mm is just under b / 2 = 39.89 mm, so a return wall
    # whose courses end staggered leaves an end block cantilevered with its centre 0.21 mm
    # inside the edge of the block below: a scene on the verge of toppling under dead load
    b = 79.78
    scene = wall_with_returns(4, n_courses, 28.24, b, 39.68, 26.8, mu=0.6, returns=returns)
    boxes = _boxes(scene)
    free = np.flatnonzero(~scene.supports.fixed)
    margins = np.array([_support_margin(boxes, i, 1e-9) for i in free])
    assert margins.min() >= 0.25 * 39.68e-3, (
        f"block {free[margins.argmin()]} has its centre {1e3 * margins.min():.2f} mm inside "
        "the edge of its support"
    )


def test_return_wall_courses_end_flush():
    scene = wall_with_returns(4, 4, 28.24, 79.78, 39.68, 26.8, returns=("left",),
                              return_blocks=3)  # fmt: skip
    boxes = _boxes(scene)
    wall, course = np.array(scene.meta["wall"]), np.array(scene.meta["course"])
    ends = [boxes[(wall == 1) & (course == k), 0, 1].min() for k in range(4)]
    np.testing.assert_allclose(ends, -39.68e-3 / 2 - 3 * 79.78e-3, rtol=1e-12)
