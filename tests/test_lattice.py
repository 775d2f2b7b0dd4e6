import numpy as np
import pytest

from beeoptics.eye.lattice import (conformal_map, hex_grid, kernel_mean, neighbour_counts, neighbour_edges,
                                  project_grid)
from beeoptics.eye.meshquery import MeshQuery
from conftest import cap_mesh, disc_mesh


def test_hex_grid_has_six_neighbours_at_one_pitch():
    pts = hex_grid(0.1, (0, 0), (1, 1))
    d = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    centre = np.argmin(np.linalg.norm(pts - 0.5, axis=1))
    near = np.sort(d[centre])[1:8]
    np.testing.assert_allclose(near[:6], 0.1, rtol=1e-9)
    assert near[6] == pytest.approx(0.1 * np.sqrt(3), rel=1e-9)


@pytest.mark.parametrize("lines, along", [("rows", 0.0), ("columns", 90.0)])
def test_a_grid_lines_its_adjacent_points_up_in_rows_or_in_columns(lines, along):
    pts = hex_grid(0.1, (0, 0), (1, 1), lines=lines)
    centre = np.argmin(np.linalg.norm(pts - 0.5, axis=1))
    step = pts - pts[centre]
    near = np.argsort(np.linalg.norm(step, axis=1))[1:7]
    np.testing.assert_allclose(np.linalg.norm(step[near], axis=1), 0.1, rtol=1e-9)
    # Two of the six stand along the lines, the other four 60° off them.
    off = np.abs((np.degrees(np.arctan2(step[near, 1], step[near, 0])) - along + 90.0) % 180.0 - 90.0)
    np.testing.assert_allclose(np.sort(off), [0, 0, 60, 60, 60, 60], atol=1e-6)


def test_the_count_rule_lays_the_grid_in_columns_when_asked():
    v, f = cap_mesh(0.5, 75.0)
    points, _, pitch = project_grid(MeshQuery(v, f), 1000, "columns")
    assert len(points) == 1000
    step = points[:, None, :2] - points[None, :, :2]
    # Some facet has a neighbour straight above it, one pitch away (up to the cap's slope).
    upright = (np.abs(step[..., 0]) < 1e-9) & (np.abs(step[..., 1]) > 0) & (np.abs(step[..., 1]) < 1.01 * pitch)
    assert upright.any()


@pytest.mark.parametrize("count", [300, 1000, 4752])
def test_count_rule_gives_exactly_the_count_on_the_mesh(count):
    v, f = cap_mesh(0.5, 75.0)
    q = MeshQuery(v, f)
    points, faces, pitch = project_grid(q, count)
    assert len(points) == count
    # On the mesh, under their grid point: projected along -z.
    closest, _ = q.project(points)
    np.testing.assert_allclose(closest, points, atol=1e-9)
    # The pitch is what fills the projected disc: count ≈ π r²/(√3/2 p²) for this cap.
    r = 0.5 * np.sin(np.radians(75.0))
    assert pitch == pytest.approx(np.sqrt(np.pi * r**2 / (np.sqrt(3) / 2 * count)), rel=0.05)


def test_delaunay_neighbours_of_a_hex_grid_are_six_inside():
    v, f = disc_mesh(1.0, 0.05)
    q = MeshQuery(v, f)
    uv = conformal_map(v, f)
    pts2 = hex_grid(0.08, (-0.7, -0.7), (0.7, 0.7))
    pts2 = pts2[np.linalg.norm(pts2, axis=1) < 0.7]
    points, faces = q.project(np.column_stack([pts2, np.zeros(len(pts2))]))
    edges, boundary = neighbour_edges(q.interpolate(uv, points, faces), points, np.full(len(points), 0.15))
    counts = neighbour_counts(edges, len(points))
    # Points on the rim, and those next to the ragged, circle-cut edge of the grid,
    # miss lattice neighbours; those well inside have all six.
    inside = np.linalg.norm(points[:, :2], axis=1) < 0.55
    assert boundary[np.linalg.norm(points[:, :2], axis=1) > 0.66].all()
    assert np.all(counts[inside] == 6)


def test_the_kernel_mean_keeps_a_linear_trend_and_removes_noise():
    points = hex_grid(1.0, (-20.0, -20.0), (20.0, 20.0))
    trend = 0.1 * points[:, 0]
    noise = np.random.default_rng(0).normal(0.0, 1.0, len(points))
    smooth = kernel_mean(points, trend + noise, 3.0)
    inner = np.abs(points).max(1) < 10.0
    # A symmetric kernel passes a linear trend unchanged away from the edge, and averages noise
    # over some 3·π·3² facets.
    np.testing.assert_allclose(kernel_mean(points, trend, 3.0)[inner], trend[inner], atol=1e-9)
    assert np.std((smooth - trend)[inner]) < 0.25


def test_a_particle_every_triangle_of_which_bridges_the_rim_is_on_the_rim_and_weighs_nothing():
    """A particle far from the rest keeps no Delaunay edge (each is longer than allowed): it is on the rim
    (not counted among the interior facets), and its Δφ, NaN, leaves the kernel mean of the others finite."""
    uv = np.array([[0, 0], [1, 0], [0.5, 0.9], [1.5, 0.9], [0.5, 5.0]], float)
    points = np.column_stack([uv, np.zeros(len(uv))])
    edges, boundary = neighbour_edges(uv, points, np.full(len(uv), 1.5))
    assert neighbour_counts(edges, len(uv))[4] == 0 and boundary[4]
    smooth = kernel_mean(points, np.array([1.0, 1.0, 1.0, 1.0, np.nan]), 10.0)
    assert np.allclose(smooth[:4], 1.0) and np.isclose(smooth[4], 1.0)
