"""The dorsal rim area: the skyward-looking facets at the eye's dorsal margin, and their microvilli.

In most of the honey bee's retina the rhabdoms twist through 180° along
their length, so a receptor has no single microvillar orientation and
little polarisation sensitivity (Collins §1.2). At the dorsal margin of the
eye a strip of at least 60 ommatidia, looking skyward, has straight
rhabdoms whose microvilli keep their orientations (Schinz 1975): the dorsal
rim area, which sees the polarisation pattern of the sky. This module marks
its facets, those nearest the dorsal margin, and gives each the
orientation of its UV receptors' microvilli. Across the dorsal rim areas of
insects these orientations turn gradually along the rim, a fan (Labhart &
Meyer 1999); here the microvilli of one set lie along the rim at each
facet, those of its partner set at right angles (not stored).

The orientation is an angle in the plane normal to the receptor's axis,
in degrees in [0, 180), from the projection of the head's dorsal direction
(+z), positive towards the projection of the head's anterior direction
(+x) — the frame in which an angle of polarisation is compared with it.

References
----------
Schinz RH (1975) Structural specialization in the dorsal retina of the
bee, Apis mellifera. Cell Tissue Res 162:23–34.
Labhart T, Meyer EP (1999) Detectors for polarized skylight in insects: a
survey of ommatidial specializations in the dorsal rim area of the
compound eye. Microsc Res Tech 47:368–379.
"""

import numpy as np
from scipy.spatial import cKDTree

from beeoptics.headframe import RIGHT, eye_azimuth_elevation, in_eye_plane, microvillar_angle

#: The share of the eye's height, from the top, whose rim counts as its dorsal margin.
DORSAL_MARGIN = 0.1


def dorsal_rim(points, axes_head, rim, rotation, count):
    """The dorsal rim area's facets and their microvillar orientation.

    Parameters
    ----------
    points : ndarray (n, 3)
        Facets, the eye's local frame, mm.
    axes_head : ndarray (n, 3)
        Their axes, head frame.
    rim : ndarray (b, 3)
        The eye's margin, in order around it, local frame, mm.
    rotation : ndarray (3, 3)
        The eye's rotation.
    count : int
        How many facets the area holds.

    Returns
    -------
    member : ndarray of bool (n,)
    microvilli_deg : ndarray (n,)
        NaN outside the area.
    """
    plane = in_eye_plane(rotation)
    height = rim[:, :2] @ plane[1]
    top = np.flatnonzero(height >= height.max() - DORSAL_MARGIN * np.ptp(height))
    distance, nearest = cKDTree(rim[top, :2]).query(points[:, :2])
    chosen = np.argsort(distance, kind="stable")[:count]
    member = np.zeros(len(points), bool)
    member[chosen] = True
    # The rim's direction at each facet's nearest rim point, from its neighbours along the margin.
    k = top[nearest]
    tangent = rim[(k + 1) % len(rim)] - rim[(k - 1) % len(rim)]
    tangent_head = tangent @ np.asarray(rotation)
    angle = np.full(len(points), np.nan)
    angle[member] = microvillar_angle(axes_head[member], tangent_head[member])
    return member, angle


def rim_summary(axes_head, member, microvilli_deg):
    """Where the dorsal rim area looks and how its microvilli turn: a JSON-ready dict."""
    azimuth, elevation = eye_azimuth_elevation(axes_head[member], RIGHT)
    return {
        "facets": int(member.sum()),
        "elevation_deg": [float(elevation.min()), float(np.median(elevation)), float(elevation.max())],
        "azimuth_deg": [float(azimuth.min()), float(np.median(azimuth)), float(azimuth.max())],
        "microvilli_deg": [float(np.nanmin(microvilli_deg)), float(np.nanmax(microvilli_deg))],
    }
