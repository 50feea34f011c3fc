"""Convex polygon clipping and area moments against closed forms."""

import numpy as np
import pytest

from dem.geometry.clipping import clip_convex_polygons, polygon_properties


def rectangle(x0, y0, x1, y1):
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], float)


def regular_polygon(n, r=1.0, phase=0.0):
    a = phase + 2 * np.pi * np.arange(n) / n
    return r * np.stack([np.cos(a), np.sin(a)], axis=1)


def test_overlapping_rectangles_give_their_intersection():
    piece = clip_convex_polygons(rectangle(0, 0, 2, 1), rectangle(1.5, -1, 4, 0.25))
    area, centroid, moments = polygon_properties(piece)
    assert area == pytest.approx(0.5 * 0.25, rel=1e-14)
    np.testing.assert_allclose(centroid, [1.75, 0.125], rtol=1e-14)
    # about the centroid: b h^3 / 12, h b^3 / 12, 0
    b, h = 0.5, 0.25
    np.testing.assert_allclose(moments, [h * b**3 / 12, b * h**3 / 12, 0.0], atol=1e-16)


def test_disjoint_polygons_give_nothing():
    assert clip_convex_polygons(rectangle(0, 0, 1, 1), rectangle(2, 0, 3, 1)).shape == (0, 2)


def test_tolerance_keeps_a_touching_edge_and_merges_repeats():
    # the clip edge at x = 1 lies 1e-12 inside the subject's edge: with tol it is kept whole
    piece = clip_convex_polygons(rectangle(0, 0, 1, 1), rectangle(-1, -1, 1 - 1e-12, 2), 1e-9)
    assert len(piece) == 4
    assert polygon_properties(piece)[0] == pytest.approx(1.0, rel=1e-9)


def test_two_rotated_squares_give_the_regular_octagon():
    """A square and the same square turned by 45 degrees overlap in a regular octagon of
    apothem 1 (area 8 tan(pi/8)), centred, with equal principal moments."""
    square = regular_polygon(4, np.sqrt(2), np.pi / 4)  # apothem 1, edges on the axes
    turned = regular_polygon(4, np.sqrt(2), 0.0)
    piece = clip_convex_polygons(square, turned)
    area, centroid, moments = polygon_properties(piece)
    assert len(piece) == 8
    assert area == pytest.approx(8 * np.tan(np.pi / 8), rel=1e-13)
    np.testing.assert_allclose(centroid, 0.0, atol=1e-14)
    assert moments[0] == pytest.approx(moments[1], rel=1e-12)
    assert moments[2] == pytest.approx(0.0, abs=1e-14)


def test_clip_is_symmetric_in_area():
    rng = np.random.default_rng(3)
    for _ in range(50):
        a = regular_polygon(int(rng.integers(3, 9)), 1.0, rng.uniform(0, 1)) + rng.normal(size=2)
        b = regular_polygon(int(rng.integers(3, 9)), 1.3, rng.uniform(0, 1))
        ab, ba = clip_convex_polygons(a, b), clip_convex_polygons(b, a)
        area_ab = polygon_properties(ab)[0] if len(ab) >= 3 else 0.0
        area_ba = polygon_properties(ba)[0] if len(ba) >= 3 else 0.0
        assert area_ab == pytest.approx(area_ba, rel=1e-12, abs=1e-14)
