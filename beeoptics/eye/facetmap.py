"""The facet-diameter map: diameters measured at anatomical anchors, spread over the eye.

Facet (lens) diameters are published for a few named regions of the eye
(dorsal, lower frontal, the drone's dorsal acute zone, …). Each anchor is
placed on the mesh at the vertex whose normal points closest to the
anchor's viewing direction, and the diameter anywhere else is Shepard's
inverse-distance weighting of the anchor values, with geodesic distances
over the eye surface (libigl heat method) so that the map follows the
cornea rather than cutting through the head.

References
----------
Shepard D (1968) A two-dimensional interpolation function for
irregularly-spaced data. Proc 23rd ACM National Conference, 517–524.
"""

import numpy as np

from beeoptics.eye.geodesic import heat_distances
from beeoptics.headframe import eye_direction


def anchor_vertices(normals, anchors):
    """The points (mesh vertices, say) whose directions point closest to each anchor's direction.

    Parameters
    ----------
    normals : ndarray, shape (n, 3)
        Vertex normals, or the points' visual axes, in the head frame, for the right eye.
    anchors : sequence of dict
        Each with ``azimuth_deg`` and ``elevation_deg``.
    """
    dirs = eye_direction([a["azimuth_deg"] for a in anchors], [a["elevation_deg"] for a in anchors])
    return np.argmax(normals @ dirs.T, axis=0)


def diameter_map(vertices, faces, sources, values, power=2.0):
    """Inverse-geodesic-distance interpolation of anchor values over a mesh.

    Parameters
    ----------
    vertices, faces : ndarray
    sources : ndarray of int
        The anchor vertices.
    values : ndarray
        The diameter at each anchor.
    power : float
        Shepard's exponent.

    Returns
    -------
    ndarray, shape (n_vertices,)
    """
    values = np.asarray(values, float)
    dist = heat_distances(vertices, faces, sources)
    dist[np.arange(len(sources)), sources] = 0.0
    with np.errstate(divide="ignore"):
        weight = np.abs(dist) ** -power
    exact = np.isinf(weight)
    weight[:, exact.any(0)] = exact[:, exact.any(0)]
    return (weight * values[:, None]).sum(0) / weight.sum(0)
