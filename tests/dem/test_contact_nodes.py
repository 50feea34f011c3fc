"""Surface nodes, signed distances, the nodal contact law and the neighbour-list merge."""

import logging
import math
import tracemalloc

import numpy as np
import pytest

from dem.contact_nodes import MIN_REACH, build_level_sets, seed_contact_nodes, seed_face
from dem.explicit import ExplicitModel, TiltingTable, masonry_settings, simulate_lateral
from dem.geometry.polyhedron import convex_block
from dem.kernels.broadphase import carry_history
from dem.kernels.contact_force import traction_one
from dem.kernels.signed_distance import convex_sdf_many, level_set_sdf_one
from dem.scene import Scene
from dem.scenes import stack
from dem.scenes.tis_panel import tis_interface_area, tis_panel
from dem.units import MM


@pytest.mark.parametrize("layout", ["centroid", "vertex"])
@pytest.mark.parametrize("spacing", [0.7, 0.31, 0.05])
def test_tributary_areas_sum_to_face_area(spacing, layout):
    """Cells clipped exactly to the face: the areas add up to the polygon area (shoelace)."""
    angle = np.sort(np.random.default_rng(3).uniform(0, 2 * np.pi, 7))
    xy = np.column_stack([2.0 * np.cos(angle), 1.3 * np.sin(angle)])
    area = 0.5 * abs(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]))
    # tilt the polygon into a plane with normal n
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    u = np.cross(n, [0.0, 0.0, 1.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    poly = 0.3 * n + xy[:, :1] * u + xy[:, 1:] * v
    points, areas = seed_face(poly, n, spacing, layout)
    np.testing.assert_allclose(areas.sum(), area, rtol=1e-12)
    if layout == "centroid":
        # first moment: each node sits at its clipped cell's centroid, so the nodes reproduce
        # the polygon centroid exactly (shoelace formula)
        cross = xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]
        cxy = ((xy + np.roll(xy, -1, axis=0)) * cross[:, None]).sum(axis=0) / (6 * area)
        expected = 0.3 * n + cxy[0] * u + cxy[1] * v
        centroid = (areas[:, None] * points).sum(axis=0) / areas.sum()
        np.testing.assert_allclose(centroid, expected, atol=1e-12)
    np.testing.assert_allclose((points - poly[0]) @ n, 0.0, atol=1e-12)  # on the face
    assert np.all(areas <= spacing**2 * (1 + 1e-12))


def test_tis_interfaces_counted_once():
    """Weight-1 node areas of each free pair equal the exact interface area (clipping)."""
    scene = tis_panel(3, 5.0)
    fixed = scene.supports.fixed
    nodes = seed_contact_nodes(scene.assembly, fixed, 0.4 * MM, 0.05 * MM)
    itf = scene.assembly.interfaces()
    for a, b, area in zip(itf.block_a, itf.block_b, itf.area, strict=True):
        if fixed[a] and fixed[b]:
            assert nodes.weight[a, b] == 0 and nodes.weight[b, a] == 0
            continue
        assert {nodes.weight[a, b], nodes.weight[b, a]} == {0.0, 1.0}
        owner = a if nodes.weight[a, b] == 1 else b
        # nodes of the owner on the face towards the other block
        other = b if owner == a else a
        on = nodes.block == owner
        normal = scene.assembly.centroid[other] - scene.assembly.centroid[owner]
        facing = on & (nodes.normal @ normal > 0.9 * np.linalg.norm(normal))
        np.testing.assert_allclose(nodes.area[facing].sum(), area, rtol=1e-9)
    # every full internal interface has the closed-form area of the builder
    side = 50 * MM / 4
    full = tis_interface_area(side, math.radians(5.0), 3.18 * MM)
    assert np.isclose(itf.area, full, rtol=1e-9).sum() >= 2 * 3 * 4


def test_convex_signed_distance_matches_numpy():
    blk = convex_block(np.random.default_rng(0).normal(size=(20, 3)))
    pts = np.random.default_rng(1).normal(size=(200, 3))
    out = np.zeros(len(pts))
    convex_sdf_many(pts, blk.normals, blk.offsets, 0, len(blk.offsets), out)
    np.testing.assert_allclose(out, blk.signed_distance(pts), rtol=0, atol=1e-15)


def test_level_set_trilinear_matches_planes_inside_faces():
    """Trilinear interpolation reproduces a linear field exactly: away from edges (one active
    face plane in the whole grid cell) the level set equals the plane distance and its gradient
    is the face normal."""
    scene = tis_panel(1, 5.0)
    asm = scene.assembly
    h = 0.1 * MM
    ls = build_level_sets(asm, h, 0.3 * MM)
    blk = asm.blocks[4]  # the internal block
    rng = np.random.default_rng(2)
    checked = 0
    for f, normal in enumerate(blk.normals):
        poly = blk.vertices[blk.faces[f]]
        centre = poly.mean(axis=0)
        for _ in range(10):
            p = (
                centre
                + 0.2 * (poly[rng.integers(len(poly))] - centre)
                - rng.uniform(0, 2) * h * normal
            )
            phi_exact = blk.signed_distance(p)[0]
            # skip points whose grid cell sees another face (near edges)
            corners = np.floor((p - ls.origin[4]) / h)[None, :] + np.array(
                [[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
            )
            cell = ls.origin[4] + corners * h
            active = np.argmax(cell @ blk.normals.T - blk.offsets, axis=1)
            if np.any(active != f):
                continue
            phi, g0, g1, g2 = level_set_sdf_one(*p, ls.origin[4], h, ls.dims[4], ls.values,
                                                ls.ptr[4])  # fmt: skip
            np.testing.assert_allclose(phi, phi_exact, atol=1e-12)
            np.testing.assert_allclose([g0, g1, g2], normal, atol=1e-9)
            checked += 1
    assert checked > 20


def test_traction_law_stick_slip_closed_form():
    """Eq. (1): elastic shear k_t |s| below mu sigma, capped at mu sigma above; normal k_n d."""
    k_n, k_t, mu, dt = 1e12, 5e11, 0.3, 1e-6
    d = 1e-6
    n = (0.0, 0.0, 1.0)
    # stick: sliding speed v for one step gives s = v dt
    v = 1e-2
    law = (k_n, k_t, mu, 0.0, 0.0)
    t, _ = traction_one(d, n, (v, 0.0, 0.0), (0.0, 0.0, 0.0), law, dt)
    np.testing.assert_allclose(t, [-k_t * v * dt, 0.0, k_n * d])
    # slip: a large step is capped at mu sigma, along the slip
    v = 10.0
    t, s = traction_one(d, n, (v, 0.0, 0.0), (0.0, 0.0, 0.0), law, dt)
    np.testing.assert_allclose([t[0], t[2]], [-mu * k_n * d, k_n * d])
    np.testing.assert_allclose(k_t * s[0], mu * k_n * d)
    # history is rotated into a new tangent plane with its length kept
    s = np.array([1e-7, 0.0, 0.0])
    tilt = math.radians(10)
    n2 = (math.sin(tilt), 0.0, math.cos(tilt))
    _, r = traction_one(d, n2, (0.0, 0.0, 0.0), tuple(s), (k_n, k_t, 10.0, 0.0, 0.0), dt)
    np.testing.assert_allclose(np.linalg.norm(r), 1e-7, rtol=1e-12)
    np.testing.assert_allclose(np.dot(r, n2), 0.0, atol=1e-20)
    # separation-free rate damping never pulls: sigma clipped at 0
    t, _ = traction_one(d, n, (0.0, 0.0, 1e3), (0.0, 0.0, 0.0), (k_n, k_t, mu, 1e-6, 0.0), dt)
    assert t[2] == 0.0


def test_carry_history_merge():
    rng = np.random.default_rng(5)
    keys_old = sorted({(int(a), int(b)) for a, b in rng.integers(0, 30, size=(60, 2))})
    keys_new = sorted({(int(a), int(b)) for a, b in rng.integers(0, 30, size=(60, 2))})
    old_n, old_b = (np.array(x, dtype=np.int64) for x in zip(*keys_old, strict=True))
    new_n, new_b = (np.array(x, dtype=np.int64) for x in zip(*keys_new, strict=True))
    old_s = rng.normal(size=(len(keys_old), 3))
    out = np.zeros((len(keys_new), 3))
    carried = carry_history(old_n, old_b, old_s, new_n, new_b, out)
    ref = {k: old_s[i] for i, k in enumerate(keys_old)}
    expected = np.array([ref.get(k, np.zeros(3)) for k in keys_new])
    np.testing.assert_array_equal(out, expected)
    assert carried == len(set(keys_old) & set(keys_new))


@pytest.mark.parametrize("cells", [2, 4])
def test_a_block_tips_over_at_the_lever_its_contact_nodes_reach(cells, caplog):
    """Centroid nodes on a ``b x b`` base, ``n`` cells across, reach ``1 - 1 / n`` of it: a
    block of height ``h`` tilted on the ground tips at ``lambda = (1 - 1 / n) b / h`` (closed
    form of a rigid block rocking on its outermost nodes), not at ``b / h``; a reach under
    ``MIN_REACH`` is logged."""
    b, h = 0.2, 0.4
    scene = stack(1, b, b, h, mu=0.9)
    settings = masonry_settings(scene, node_spacing=b / cells, node_layout="centroid",
                                contact_plane="nearest")  # fmt: skip
    with caplog.at_level(logging.WARNING, logger="dem.contact_nodes"):
        result = simulate_lateral(scene, settings=settings, driver=TiltingTable(step=0.05))
    reach = 1 - 1 / cells
    assert result.collapsed
    assert result.lambda_stable - 0.01 <= reach * b / h <= result.lambda_moving + 0.01
    assert ("fall short of their edges" in caplog.text) == (reach < MIN_REACH)


def test_a_contact_face_with_a_single_node_is_refused():
    """One node on the base would make the contact a hinge: the block tipped at lambda = 0."""
    scene = stack(1, 0.2, 0.2, 0.4, mu=0.9)
    settings = masonry_settings(scene, node_spacing=0.2, node_layout="centroid")
    with pytest.raises(ValueError, match="block 0 face .* hinge .*node_layout='vertex'"):
        ExplicitModel(scene, settings)


def test_indenter_nodes_seeded_near_the_axis_only():
    """A 0.1 m square top face under a 1 mm tip with 0.1 mm indenter spacing: the whole face
    would be 10^6 grid cells (hundreds of MB of scratch); seeding only about the axis keeps
    memory to a few MB. The nodes are the centres ``((i + 1/2) h, (j + 1/2) h)`` of the face's
    grid within ``R + margin + h`` of the axis (count by brute force), each of area ``h^2``."""
    side, tip, margin, h = 0.1, 1e-3, 1e-4, 1e-4
    corners = [[x, y, z] for x in (0.0, side) for y in (0.0, side) for z in (0.0, 0.02)]
    scene = Scene.from_convex_blocks([np.array(corners)], 2000.0)
    axis = np.array([0.05012, 0.05037])
    centres = (np.arange(round(side / h)) + 0.5) * h
    dist = np.hypot(centres[:, None] - axis[0], centres[None, :] - axis[1])
    expected = int(np.count_nonzero(dist <= tip + margin + h))

    def seed():
        return seed_contact_nodes(scene.assembly, [False], 0.01, margin, axis, tip, h)

    seed()  # compile the clipping kernel outside the measurement
    tracemalloc.start()
    try:
        nodes = seed()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert len(nodes.indenter_area) == expected
    np.testing.assert_allclose(nodes.indenter_area, h * h, rtol=1e-9)
    assert peak < 5e6  # [bytes]; the whole face's grid needs over 200 MB


def test_a_face_grid_beyond_the_cell_limit_is_refused():
    """A 0.1 m square at 10 um spacing is 10^8 cells (> MAX_GRID_CELLS): refused up front,
    naming the count and the spacing, rather than exhausting memory."""
    square = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.1, 0.1, 0.0], [0.0, 0.1, 0.0]])
    with pytest.raises(ValueError, match=r"node spacing 1e-05 m gives 1e\+08 grid cells"):
        seed_face(square, np.array([0.0, 0.0, 1.0]), 1e-5)


def test_traction_law_touching_depth_carries_no_friction():
    """The part of a penetration within the touching depth carries no friction: a depth of
    round-off size gives its normal penalty and no shear; a real depth ``d`` slips at
    ``mu k_n (d - touch)`` (module docstring of :mod:`dem.kernels.contact_force`)."""
    k_n, k_t, mu, dt, touch = 1e12, 5e11, 0.3, 1e-6, 1e-14
    n = (0.0, 0.0, 1.0)
    law = (k_n, k_t, mu, 0.0, touch)
    t, s = traction_one(1e-19, n, (10.0, 0.0, 0.0), (0.0, 0.0, 0.0), law, dt)
    np.testing.assert_array_equal([t[0], t[1], *s], 0.0)
    np.testing.assert_allclose(t[2], k_n * 1e-19)
    d = 1e-9
    t, _ = traction_one(d, n, (10.0, 0.0, 0.0), (0.0, 0.0, 0.0), law, dt)
    np.testing.assert_allclose([t[0], t[2]], [-mu * k_n * (d - touch), k_n * d], rtol=1e-14)


def test_pull_inside_moves_edge_nodes_by_the_inset_only():
    """Square face [0, 1]^2 tilted into 3D: a node on an edge moves the inset along the edge's
    inward normal, a corner node to the shrunk square's corner, an interior node stays; a face
    narrower than twice the inset sends its nodes to its centroid."""
    from dem.contact_nodes import pull_inside

    n = np.array([1.0, 2.0, 2.0]) / 3.0
    u = np.cross(n, [0.0, 0.0, 1.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    to3 = lambda p: 0.2 * n + p[:, :1] * u + p[:, 1:] * v  # noqa: E731
    nodes = np.array([[0.5, 0.0], [1.0, 0.3], [0.0, 0.0], [0.5, 0.5], [0.95, 0.5]])
    moved = pull_inside(to3(square), n, to3(nodes), 0.1)
    expected = np.array([[0.5, 0.1], [0.9, 0.3], [0.1, 0.1], [0.5, 0.5], [0.9, 0.5]])
    np.testing.assert_allclose(moved, to3(expected), atol=1e-12)
    strip = np.array([[0, 0], [1, 0], [1, 0.1], [0, 0.1]], dtype=float)
    np.testing.assert_allclose(pull_inside(to3(strip), n, to3(nodes[:2]), 0.1),
                               to3(np.array([[0.5, 0.05]] * 2)), atol=1e-12)  # fmt: skip
