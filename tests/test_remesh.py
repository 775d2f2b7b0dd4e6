import igl
import numpy as np
import pymeshlab
import pytest

from beeoptics.eye.remesh import remesh
from conftest import cap_mesh


@pytest.fixture(scope="module")
def coarse_and_fine():
    # A low-poly cap, as a modeller would make it: a few hundred faces.
    v, f = cap_mesh(1.0, 60.0)

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(v, f))
    ms.meshing_decimation_quadric_edge_collapse(targetfacenum=300, preserveboundary=True, boundaryweight=10)
    cv, cf = ms.current_mesh().vertex_matrix(), ms.current_mesh().face_matrix().astype(np.int64)
    return (cv, cf), remesh(cv, cf, 0.02)


def test_remeshing_reaches_the_target_edge_length(coarse_and_fine):
    _, (v, f, _) = coarse_and_fine
    assert np.median(np.sqrt(igl.squared_edge_lengths(v, f))) == pytest.approx(0.02, rel=0.15)


def _distance_to_polyline(points, loop):
    a, b = loop, np.roll(loop, -1, axis=0)
    t = np.clip(((points[:, None] - a) * (b - a)).sum(2) / ((b - a) ** 2).sum(1), 0, 1)
    return np.linalg.norm(points[:, None] - (a + t[..., None] * (b - a)), axis=2).min(1)


def test_remeshing_keeps_the_rim(coarse_and_fine):
    (cv, cf), (v, f, _) = coarse_and_fine
    old, new = cv[igl.boundary_loop(cf)], v[igl.boundary_loop(f)]
    # Subdivision rounds the modeller's rim between its vertices; the remeshed rim
    # still runs through every one of them, and never strays far from the original.
    assert _distance_to_polyline(old, new).max() < 0.05 * 0.02
    assert _distance_to_polyline(new, old).max() < 0.1 * np.median(np.linalg.norm(old - np.roll(old, -1, 0), axis=1))


def test_remeshed_surface_stays_near_the_hand_made_one(coarse_and_fine):
    (cv, cf), (v, _, _) = coarse_and_fine
    d, _, _ = igl.point_mesh_squared_distance(v, cv, cf)
    # Butterfly subdivision rounds the flat faces a little; it does not move them far.
    assert np.sqrt(d).max() < 0.02


def test_normals_are_unit_and_vary_smoothly(coarse_and_fine):
    _, (v, f, n) = coarse_and_fine
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-9)
    e = igl.edges(f)
    turn = np.degrees(np.arccos(np.clip((n[e[:, 0]] * n[e[:, 1]]).sum(1), -1, 1)))
    length = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    # On a unit sphere the normal turns by 1 rad per unit length: 57°.
    assert np.median(turn / length) == pytest.approx(57.3, rel=0.15)
    assert np.percentile(turn / length, 95) < 57.3 * 2
