import numpy as np

from beeoptics.eye.facetmap import anchor_vertices, diameter_map
from beeoptics.headframe import eye_direction
from conftest import cap_mesh


def test_map_takes_the_anchor_values_at_the_anchors_and_stays_between_them():
    v, f = cap_mesh(1.0, 80.0)
    normals = v / np.linalg.norm(v, axis=1, keepdims=True)
    # Treat the cap's normals as head-frame directions of a right eye.
    # The cap spans directions within 80° of +z: put the anchors 60° either side of it.
    anchors = [{"azimuth_deg": 0.0, "elevation_deg": 30.0}, {"azimuth_deg": 180.0, "elevation_deg": 30.0}]
    vertices = anchor_vertices(normals, anchors)
    np.testing.assert_allclose((normals[vertices] * eye_direction([0, 180], [30, 30])).sum(1), 1.0, atol=0.01)
    d = diameter_map(v, f, vertices, [15.0, 17.7])
    np.testing.assert_allclose(d[vertices], [15.0, 17.7])
    assert d.min() >= 15.0 and d.max() <= 17.7
    # Midway between the anchors, half way between their values.
    mid = np.argmax(normals @ eye_direction(0, 90))
    assert abs(d[mid] - 16.35) < 0.15
