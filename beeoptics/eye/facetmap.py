"""The facet-diameter map: diameters measured at anatomical anchors, spread over the eye.

Facet (lens) diameters are published for a few named regions of the eye
(dorsal, lower frontal, the drone's dorsal acute zone, …). Each anchor is
placed on the mesh at the vertex whose normal points closest to the
anchor's viewing direction, and the diameter anywhere else is Shepard's
inverse-distance weighting of the anchor values, with geodesic distances
over the eye surface (libigl heat method) so that the map follows the
cornea rather than cutting through the head. Where a region's diameter is
not published but the eye's facet count and its measured cornea are, one
anchor may be left to ``fill``: its diameter is then the one at which the
map's hexagons, as many as the count, tile the cornea
(:func:`fill_diameter`).

References
----------
Shepard D (1968) A two-dimensional interpolation function for
irregularly-spaced data. Proc 23rd ACM National Conference, 517–524.
"""

import igl
import numpy as np

from beeoptics.eye.geodesic import heat_distances
from beeoptics.headframe import eye_direction

#: An anchor whose diameter the count and the cornea set (facet_diameter.anchors[].diameter_um).
FILL = "fill"


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


def _weights(vertices, faces, sources, power):
    """Shepard's normalised weights of each anchor at each vertex (anchors, vertices)."""
    dist = heat_distances(vertices, faces, sources)
    dist[np.arange(len(sources)), sources] = 0.0
    with np.errstate(divide="ignore"):
        weight = np.abs(dist) ** -power
    exact = np.isinf(weight)
    weight[:, exact.any(0)] = exact[:, exact.any(0)]
    return weight / weight.sum(0)


def fill_diameter(vertices, faces, sources, values, count, power=2.0):
    """The diameter of the anchor whose value is None at which ``count`` hexagons of the map tile the mesh.

    Each vertex's share of the surface (its Voronoi area) holds area / ((√3/2)·d²)
    facets of the map's diameter d there; the unknown anchor's diameter is
    found (Brent's method) where they sum to ``count``.

    Returns
    -------
    float, or None if no diameter between a tenth and ten times the known ones tiles it so.
    """
    weight = _weights(vertices, faces, sources, power)
    unknown = [k for k, v in enumerate(values) if v is None]
    known = np.array([0.0 if v is None else v for v in values])
    base, slope = (weight * known[:, None]).sum(0), weight[unknown[0]]
    area = igl.massmatrix(vertices, faces, igl.MASSMATRIX_TYPE_VORONOI).diagonal()

    def surplus(d):
        return float((area / (np.sqrt(3.0) / 2.0 * (base + slope * d) ** 2)).sum()) - count

    from scipy.optimize import brentq  # imported where used: most stages importing this module solve nothing (0.3 s)

    lo, hi = 0.1 * known.max(), 10.0 * known.max()
    if surplus(lo) * surplus(hi) > 0.0:
        return None
    return brentq(surplus, lo, hi, xtol=1e-12)


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
    return (_weights(vertices, faces, sources, power) * np.asarray(values, float)[:, None]).sum(0)
