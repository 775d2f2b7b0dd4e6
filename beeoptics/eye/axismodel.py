"""Visual axes from a model of the measured field, for eyes whose axes are not their corneal normals.

Collins takes each receptor's axis from the interpolated surface normal.
In a real bee eye the ommatidia are skewed against the cornea, so that the
normals of a real-sized eye span a far narrower field than the eye sees
(Stürzl et al. 2010; micro-CT eyes show the same). The ``field`` axis model
instead sends each facet to a direction of the measured field
(:mod:`beeoptics.eye.fieldmodel`) by the Knothe–Rosenblatt map between the
two distributions (Rosenblatt 1952; Knothe 1957; Villani 2009, §1):

1. a facet's elevation is the one below which the model holds the same
   share of its ommatidia as the eye holds of its facets below that facet
   (heights measured along the head's dorsal direction in the eye's plane);
2. its azimuth, along the row at that elevation, is the one medial to which
   the model's row holds the same share of its ommatidia as the eye's row
   holds of its facets anterior to the facet.

Shares are counted with a Gaussian spread of one facet spacing (half one
along the row), so that they vary smoothly across the lattice rather than
in steps at each facet. The map keeps every facet's place among its
neighbours — the rows of facets become the rows of ommatidia — and so
reproduces the measured border, and the measured horizontal and vertical
Δφ where the eye's rows hold as many facets as the model's rows hold
ommatidia. Each receptor keeps its position on the cornea; only its axis
comes from the model.

References
----------
Rosenblatt M (1952) Remarks on a multivariate transformation. Ann Math
Stat 23:470–472.
Knothe H (1957) Contributions to the theory of convex bodies. Michigan
Math J 4:39–52.
Villani C (2009) Optimal transport, old and new. Springer.
Stürzl W, Boeddeker N, Dittmar L, Egelhaaf M (2010) Bioinspir Biomim
5:036002.
"""

import numpy as np
from scipy.special import ndtr

from beeoptics.eye import fieldmodel
from beeoptics.headframe import RIGHT, eye_direction, in_eye_plane

#: Rows of the pairwise tables at a time, bounding memory to a few tens of megabytes.
_CHUNK = 256
#: Beyond this many spacings above or below a position, a point counts as wholly below it or not at all,
#: and not in its row: Φ(12) is 1 and e^(−12²/2) 10⁻³¹ of a row's weight, to double precision.
_BAND = 12.0


def _shares(at, points, weights, spacing):
    """For each of ``at`` (m, 2: anterior, dorsal), the weighted shares of ``points`` below it
    and anterior to it in its row.

    Points and positions are taken in order of height, so that each block of
    positions meets only the points within :data:`_BAND` spacings of it; the
    weight of those further below is counted whole.
    """
    order = np.argsort(points[:, 1], kind="stable")
    y, x, w = points[order, 1], points[order, 0], np.asarray(weights, float)[order]
    lower = np.concatenate([[0.0], np.cumsum(w)])
    total = w.sum()
    below, anterior = np.empty(len(at)), np.empty(len(at))
    by_height = np.argsort(at[:, 1], kind="stable")
    for start in range(0, len(at), _CHUNK):
        rows = by_height[start:start + _CHUNK]
        block = at[rows]
        lo = np.searchsorted(y, block[:, 1].min() - _BAND * spacing, "left")
        hi = np.searchsorted(y, block[:, 1].max() + _BAND * spacing, "right")
        dv = (block[:, None, 1] - y[None, lo:hi]) / spacing
        below[rows] = (lower[lo] + ndtr(dv) @ w[lo:hi]) / total
        row = np.exp(-0.5 * dv**2) * w[lo:hi]
        ahead = ndtr((x[None, lo:hi] - block[:, None, 0]) / (0.5 * spacing))
        anterior[rows] = (row * ahead).sum(1) / row.sum(1)
    return below, anterior


def field_axes(rotation, points, weights, at, spacing):
    """Visual axes of the field model at positions on an eye, in its local frame.

    Parameters
    ----------
    rotation : ndarray (3, 3)
        The eye's rotation (:func:`beeoptics.headframe.eye_rotation`).
    points : ndarray (n, 3)
        Where the facets are (or vertices standing for them), local frame, mm.
    weights : ndarray (n,)
        How many facets each point stands for (ones for facets; areas for vertices).
    at : ndarray (m, 3)
        Positions whose axes are wanted, local frame, mm.
    spacing : float
        The facet spacing, mm.

    Returns
    -------
    ndarray (m, 3)
        Unit axes in the eye's local frame.
    """
    plane = in_eye_plane(rotation)
    below, anterior = _shares(np.asarray(at)[:, :2] @ plane.T, np.asarray(points)[:, :2] @ plane.T,
                              np.asarray(weights, float), spacing)
    azimuth, elevation = fieldmodel.direction_of_shares(below, anterior)
    return eye_direction(azimuth, elevation, RIGHT) @ np.asarray(rotation).T
