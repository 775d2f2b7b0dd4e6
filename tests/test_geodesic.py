import numpy as np
import pytest
from scipy.spatial import cKDTree

from beeoptics.eye.geodesic import heat_distances, pair_distances
from beeoptics.eye.meshquery import MeshQuery
from conftest import cap_mesh


def test_geodesic_spacing_on_a_sphere_matches_great_circle_distance():
    radius = 0.5
    v, f = cap_mesh(radius, 80.0)
    rng = np.random.default_rng(3)
    p = rng.normal(size=(3000, 3))
    p[:, 2] = np.abs(p[:, 2]) + 1.0
    points, faces = MeshQuery(v, f).project(p / np.linalg.norm(p, axis=1, keepdims=True) * radius)
    pairs = cKDTree(points).query_pairs(0.03, output_type="ndarray")
    got = pair_distances(v, f, points, faces, pairs)
    unit = points / np.linalg.norm(points, axis=1, keepdims=True)
    great_circle = radius * np.arccos(np.clip((unit[pairs[:, 0]] * unit[pairs[:, 1]]).sum(1), -1, 1))
    # The mesh is a polyhedron a little inside the sphere: within 0.2 % on every pair,
    # and closer than the straight chord on average.
    np.testing.assert_allclose(got, great_circle, rtol=2e-3)
    chord = np.linalg.norm(points[pairs[:, 0]] - points[pairs[:, 1]], axis=1)
    # Every point is nudged up to 1e-4 of a face inside it before the faces are split.
    assert np.all(got >= chord * (1 - 2e-4))


def test_pairs_measured_in_batches_match_pairs_measured_alone():
    # The patches of many pairs are laid out side by side and measured a batch at a time:
    # each pair must come out as if it had its own MMP run.
    v, f = cap_mesh(0.5, 80.0)
    rng = np.random.default_rng(5)
    p = rng.normal(size=(400, 3))
    p[:, 2] = np.abs(p[:, 2]) + 1.0
    points, faces = MeshQuery(v, f).project(p / np.linalg.norm(p, axis=1, keepdims=True) * 0.5)
    pairs = cKDTree(points).query_pairs(0.08, output_type="ndarray")[:50]
    together = pair_distances(v, f, points, faces, pairs)
    alone = np.concatenate([pair_distances(v, f, points, faces, pair[None]) for pair in pairs])
    np.testing.assert_array_equal(together, alone)


def test_points_on_one_face_are_a_straight_segment_apart():
    v, f = cap_mesh(1.0, 40.0)
    tri = v[f[0]]
    points = np.array([tri.mean(0), 0.6 * tri[0] + 0.2 * tri[1] + 0.2 * tri[2]])
    d = pair_distances(v, f, points, np.array([0, 0]), np.array([[0, 1]]))
    assert d[0] == pytest.approx(np.linalg.norm(points[1] - points[0]), rel=1e-12)


def test_heat_distances_grow_with_arc_length():
    v, f = cap_mesh(1.0, 80.0)
    top = int(np.argmax(v[:, 2]))
    d = heat_distances(v, f, [top])[0]
    arc = np.arccos(np.clip(v @ v[top], -1, 1))
    assert np.corrcoef(d, arc)[0, 1] > 0.999
    np.testing.assert_allclose(d[arc > 0.3], arc[arc > 0.3], rtol=0.05)


def test_a_geodesic_round_a_notch_in_the_rim_is_measured_not_lost():
    # A flat square with a slit cut up from its lower edge: the straight segment between
    # two points either side of the slit leaves the mesh, so the patch around it falls
    # in two. The geodesic runs round the slit's top; it is not the chord, and not 0.
    n = 40
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    v = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    a = (j * (n + 1) + i).ravel()
    quads = np.column_stack([a, a + 1, a + n + 2, a + n + 1])
    centre = v[quads].mean(1)
    keep = ~((np.abs(centre[:, 0] - 0.5) < 0.05) & (centre[:, 1] < 0.7))
    f = np.vstack([quads[keep][:, [0, 1, 2]], quads[keep][:, [0, 2, 3]]])
    points, faces = MeshQuery(v, f).project(np.array([[0.4, 0.5, 0.0], [0.6, 0.5, 0.0]]))
    got = pair_distances(v, f, points, faces, np.array([[0, 1]]))[0]
    corner = np.hypot(0.05, 0.2)  # to the slit's top corner, then across it and down
    assert got == pytest.approx(2 * corner + 0.1, rel=2e-3)
