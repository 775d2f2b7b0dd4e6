"""The receptors of an eye pair, from its relaxed lattice or from imported axes.

A built eye's receptors are the relaxed facets of the right eye, placed on
the head, and their mirror images for the left eye (the table's columns are
described in :mod:`beeoptics.io.receptortable`). Δφ of a receptor is the
mean angle between its axis and its neighbours' axes: the lattice's
neighbours for a built eye; for receptors imported without a lattice (a
CompoundRay eye), the neighbours of a spherical Delaunay triangulation of
each eye's axes (:func:`beeoptics.eye.lattice.sphere_triangles`).
"""

import numpy as np
from scipy.spatial import QhullError, cKDTree

from beeoptics.eye.lattice import edge_angles, mean_over_edges, sphere_triangles, triangle_edges
from beeoptics.headframe import LEFT, RIGHT, SIDES, mirror
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import ReceptorTable


def delta_phi(axes, edges):
    """Mean angle, in degrees, between each receptor's axis and its neighbours' axes; NaN without any.

    Parameters
    ----------
    axes : ndarray, shape (n, 3)
        Unit axes.
    edges : ndarray, shape (m, 2)
        Neighbour pairs.
    """
    return mean_over_edges(edges, np.degrees(edge_angles(axes, edges)), len(axes))


def to_head(eye, points, axes):
    """Right-eye local points and axes, in the head frame."""
    return points @ eye.rotation + eye.origin, axes @ eye.rotation


def receptor_table(eye, points, axes, facet_diameter_um, dphi, drho, rim=None):
    """The :class:`ReceptorTable` of both eyes, from the right eye's local lattice.

    ``rim``, if given, is the right eye's dorsal rim area (membership,
    microvillar angle; :func:`beeoptics.eye.dorsalrim.dorsal_rim`); the
    angle, measured towards the anterior, is the same on the mirrored eye.
    """
    right_p, right_a = to_head(eye, points, axes)
    n = len(points)
    member, angle = (None, None) if rim is None else (np.tile(rim[0], 2), np.tile(rim[1], 2))
    return ReceptorTable(
        id=np.arange(2 * n), side=np.repeat(np.array([RIGHT, LEFT]), n),
        position=np.vstack([right_p, mirror(right_p)]), axis=np.vstack([right_a, mirror(right_a)]),
        facet_diameter_um=np.tile(facet_diameter_um, 2), delta_phi_deg=np.tile(dphi, 2),
        delta_rho_deg=np.tile(drho, 2), dorsal_rim=member, microvilli_deg=angle,
    )


#: The nearest axes a receptor left out of every triangle takes as its neighbours.
LONE_NEIGHBOURS = 2


def joined(axes, edges):
    """``edges`` and, for a receptor in none (a lone point the triangulation drops at the rim), edges to its
    :data:`LONE_NEIGHBOURS` nearest axes, so that every receptor has a Δφ."""
    lone = np.setdiff1d(np.arange(len(axes)), edges.ravel())
    if not lone.size:
        return edges
    nearest = cKDTree(axes).query(axes[lone], k=LONE_NEIGHBOURS + 1)[1][:, 1:]
    return np.vstack([edges, np.column_stack([np.repeat(lone, LONE_NEIGHBOURS), nearest.ravel()])])


def measure_spacing(table, source, delta_phi_deg=True, facet_diameter_um=False):
    """A receptor table with Δφ, the facet diameter, or both measured from each eye's neighbours.

    The facet diameter is taken as the mean distance to the neighbours,
    which is only meaningful when the positions are the real facets' (many
    eye files place ommatidia on a sphere of arbitrary size).

    Raises
    ------
    InputError
        Naming ``source``, if an eye's axes cannot be triangulated (fewer
        than four, or all in one plane).
    """
    dphi, facet = table.delta_phi_deg.copy(), table.facet_diameter_um.copy()
    for side in SIDES:
        rows = np.flatnonzero(np.asarray(table.side) == side)
        if rows.size == 0:
            continue
        try:
            if rows.size < 4:
                raise QhullError("fewer than four points")
            edges = joined(table.axis[rows], triangle_edges(sphere_triangles(table.axis[rows])))
        except QhullError:
            raise InputError(source, "direction",
                             "the axes cannot be triangulated to find neighbours (fewer than four, or all in one "
                             "plane); give delta_phi to set Δφ instead") from None
        if delta_phi_deg:
            dphi[rows] = delta_phi(table.axis[rows], edges)
        if facet_diameter_um:
            position = table.position[rows]
            length = np.linalg.norm(position[edges[:, 1]] - position[edges[:, 0]], axis=1)
            facet[rows] = 1e3 * mean_over_edges(edges, length, rows.size)
    return table._replace(delta_phi_deg=dphi, facet_diameter_um=facet)
