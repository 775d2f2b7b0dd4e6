"""The visual field of both eyes on the sphere of directions, as an equirectangular map.

Each pixel of the map is a direction in the head frame: azimuth from +x
(anterior), positive towards the bee's left (+y), running from +180° at the
map's left edge through 0° (straight ahead) to −180° at its right edge, so
that the left eye's field lies on the left; elevation from the xy-plane,
positive dorsal, +90° at the top. The map is equirectangular (plate carrée):
equal steps of azimuth and elevation, the projection of Stürzl et al.'s
(2010) and Seidl's (1982) maps of the bee's field.

A pixel shows the receptor whose optical axis is nearest to it, a Voronoi
diagram on the sphere, found with a KD-tree on unit vectors (the chord
between two unit vectors ranks pairs as their angle does). An eye sees a
direction that lies within its lattice of axes, or beyond the outermost
axes by no more than Δρ/2, where a receptor still has half its peak
sensitivity (Snyder's Gaussian). The lattice is the spherical Delaunay
triangulation of the eye's axes, less the triangles that span gaps rather
than join neighbours (:func:`beeoptics.eye.lattice.sphere_triangles`), and a
direction is inside it when a ray from the centre in that direction hits one
of its triangles (Open3D). Directions both eyes see are the binocular overlap.

References
----------
Seidl R (1982) Die Sehfelder und Ommatidien-Divergenzwinkel von Arbeiterin,
Königin und Drohn der Honigbiene (Apis mellifica). Dissertation, TH Darmstadt.
Stürzl W, Böddeker N, Dittmar L, Egelhaaf M (2010) Mimicking honeybee eyes
with a 280° field of view catadioptric imaging system. Bioinspir Biomim 5:036002.
"""

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from beeoptics.eye.lattice import sphere_triangles
from beeoptics.headframe import LEFT, RIGHT, direction_from_x_towards_y
from beeoptics.io.validation import config_default

#: Width of a visual-field map, pixels (half a degree each): the config schema's ``images.visual_field_width_px``.
MAP_WIDTH_PX = config_default("images.visual_field_width_px")

#: Bits of :attr:`VisualField.eyes`: which eyes see a direction.
EYE_BITS = {RIGHT: 1, LEFT: 2}


class VisualField(NamedTuple):
    """An equirectangular map of both eyes' fields.

    ``azimuth_deg`` (w,) and ``elevation_deg`` (h,) are the pixel centres;
    ``receptor`` (h, w) the index of the receptor each pixel shows, −1 where
    none sees it; ``eyes`` (h, w) the bits (:data:`EYE_BITS`) of the eyes
    that see it: 1 right, 2 left, 3 both (the binocular overlap).
    """

    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    receptor: np.ndarray
    eyes: np.ndarray


def directions(width_px):
    """Pixel centres of an equirectangular map ``width_px`` wide and half as high.

    Returns
    -------
    azimuth_deg : ndarray (w,)
    elevation_deg : ndarray (h,)
    unit : ndarray (h, w, 3)
        Head-frame unit vectors.
    """
    height = width_px // 2
    az = 180.0 - (np.arange(width_px) + 0.5) * 360.0 / width_px
    el = 90.0 - (np.arange(height) + 0.5) * 180.0 / height
    return az, el, direction_from_x_towards_y(*np.meshgrid(az, el))


def within_lattice(axes, delta_phi_deg, unit):
    """Whether each direction falls in a triangle of neighbouring axes of one eye.

    Parameters
    ----------
    axes : ndarray (n, 3)
        One eye's unit axes.
    delta_phi_deg : ndarray (n,)
        Each receptor's interommatidial angle.
    unit : ndarray (m, 3)
        Directions.
    """
    tri = sphere_triangles(axes, delta_phi_deg)
    unit = np.asarray(unit, float)
    inside = np.zeros(len(unit), bool)
    if len(tri) == 0:
        return inside
    a, b, c = (np.asarray(axes, float)[tri[:, k]] for k in range(3))
    centre = a + b + c
    centre /= np.linalg.norm(centre, axis=1, keepdims=True)
    # A direction in a spherical triangle lies within the triangle's farthest corner of its centre.
    reach = np.max([np.linalg.norm(v - centre, axis=1) for v in (a, b, c)])
    # The planes through the origin and each edge, turned so that the triangle lies on their positive side.
    turn = np.sign(np.einsum("ij,ij->i", a, np.cross(b, c)))[:, None]
    planes = np.stack([np.cross(a, b), np.cross(b, c), np.cross(c, a)], axis=1) * turn[:, :, None]
    tree = cKDTree(centre)
    # Only directions near some axis can lie in a triangle: within the longest edge of its nearest corner.
    longest = max(np.linalg.norm(a - b, axis=1).max(), np.linalg.norm(b - c, axis=1).max(),
                  np.linalg.norm(c - a, axis=1).max())
    todo = np.flatnonzero(cKDTree(axes).query(unit, distance_upper_bound=longest)[0] <= longest)
    k = min(4, len(tri))
    while todo.size:
        distance, near = tree.query(unit[todo], k=k)
        distance, near = distance.reshape(len(todo), -1), near.reshape(len(todo), -1)
        side = np.einsum("mkpj,mj->mkp", planes[near], unit[todo])
        inside[todo] = ((side >= 0.0).all(axis=2) & (distance <= reach)).any(axis=1)
        # Where the k-th nearest centre is still within reach, a farther triangle might hold it: look further.
        todo = todo[~inside[todo] & (distance[:, -1] <= reach)] if k < len(tri) else todo[:0]
        k = min(4 * k, len(tri))
    return inside


def visual_field(axes, sides, delta_rho_deg, delta_phi_deg, width_px=MAP_WIDTH_PX):
    """Which receptor, of which eye, sees each direction of the sphere.

    Parameters
    ----------
    axes : ndarray (n, 3)
        Receptor optical axes, head frame, unit vectors.
    sides : array_like of str (n,)
        ``"left"`` or ``"right"``.
    delta_rho_deg : ndarray (n,)
        Acceptance angle of each receptor, degrees.
    delta_phi_deg : ndarray (n,)
        Interommatidial angle of each receptor, degrees.
    width_px : int
        Map width; the height is half of it.

    Returns
    -------
    VisualField
    """
    az, el, unit = directions(width_px)
    flat = unit.reshape(-1, 3)
    sides = np.asarray(sides)
    half_width = np.radians(np.asarray(delta_rho_deg, float)) / 2.0
    delta_phi_deg = np.asarray(delta_phi_deg, float)
    receptor = np.full(len(flat), -1)
    best = np.full(len(flat), np.inf)
    eyes = np.zeros(len(flat), np.uint8)
    for side, bit in EYE_BITS.items():
        mine = np.flatnonzero(sides == side)
        if mine.size == 0:
            continue
        tree = cKDTree(axes[mine])
        # Most of the sphere lies beyond every axis's half width: the tree looks no further than that,
        # then finds the nearest axis of the directions the lattice's test adds.
        chord, k = tree.query(flat, distance_upper_bound=2.0 * np.sin(half_width[mine].max() / 2.0) * (1 + 1e-9))
        near = np.isfinite(chord)
        angle = np.full(len(flat), np.inf)
        angle[near] = 2.0 * np.arcsin(np.clip(chord[near] / 2.0, 0.0, 1.0))
        seen = near.copy()
        seen[near] = angle[near] <= half_width[mine[k[near]]]
        rest = np.flatnonzero(~seen)
        seen[rest] = within_lattice(axes[mine], delta_phi_deg[mine], flat[rest])
        added = rest[seen[rest]]
        chord[added], k[added] = tree.query(flat[added])
        angle[added] = 2.0 * np.arcsin(np.clip(chord[added] / 2.0, 0.0, 1.0))
        eyes[seen] |= bit
        nearer = seen & (angle < best)
        receptor[nearer], best[nearer] = mine[k[nearer]], angle[nearer]
    shape = unit.shape[:2]
    return VisualField(az, el, receptor.reshape(shape), eyes.reshape(shape))


def extent(field):
    """Solid angle of each eye's field and of the overlap, steradians and fraction of the sphere.

    Returns
    -------
    dict
        ``right_sr``, ``left_sr``, ``binocular_sr``, ``total_sr`` and the
        same over 4π as ``*_fraction``.
    """
    # A pixel's solid angle is cos(elevation) dφ dθ on an equirectangular map.
    h, w = field.eyes.shape
    pixel = np.cos(np.radians(field.elevation_deg))[:, None] * (np.pi / h) * (2.0 * np.pi / w)
    pixel = np.broadcast_to(pixel, (h, w))
    sr = {
        "right_sr": pixel[(field.eyes & EYE_BITS[RIGHT]) > 0].sum(),
        "left_sr": pixel[(field.eyes & EYE_BITS[LEFT]) > 0].sum(),
        "binocular_sr": pixel[field.eyes == EYE_BITS[RIGHT] | EYE_BITS[LEFT]].sum(),
        "total_sr": pixel[field.eyes > 0].sum(),
    }
    return {**{k: float(v) for k, v in sr.items()},
            **{k.replace("_sr", "_fraction"): float(v / (4.0 * np.pi)) for k, v in sr.items()}}
