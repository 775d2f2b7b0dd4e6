"""The receptors of an eye pair, from its relaxed lattice or from imported axes.

A built eye's receptors are the relaxed facets of the right eye, placed on
the head, and their mirror images for the left eye (the table's columns are
described in :mod:`beeoptics.io.receptortable`). Δφ of a receptor is the
mean angle between its axis and its neighbours' axes: the lattice's
neighbours for a built eye; for receptors imported without a lattice (a
CompoundRay eye), the neighbours of a spherical Delaunay triangulation of
each eye's axes (:func:`beeoptics.eye.lattice.sphere_triangles`).
"""

from pathlib import Path

import numpy as np
from scipy.spatial import QhullError, cKDTree

from beeoptics.eye.lattice import edge_angles, mean_over_edges, sphere_triangles, triangle_edges
from beeoptics.headframe import LEFT, RIGHT, SIDES, mirror
from beeoptics.io import interchange
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import ReceptorTable, checked, read_receptors

#: The formats receptors are read from and written to, by extension.
FORMATS = {".csv": "receptor table", ".eye": "CompoundRay eye", ".ply": "receptor point cloud",
           ".gltf": "OCES glTF", ".glb": "OCES binary glTF"}


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


def receptor_format(path):
    """The format of a receptor file, its extension (a key of :data:`FORMATS`); an unknown one is refused."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise InputError(path, "", f"unknown format {suffix!r}; use "
                         + ", ".join(f"{s} ({name})" for s, name in FORMATS.items()))
    return suffix


def read_receptor_file(path, *, units="mm", frame=None, acceptance="fwhm", side=None, delta_phi_deg=None,
                       facet_diameter_um=None, directions=False, halves=None, sphere_mm=None, centre_mm=None,
                       delta_rho_per_delta_phi=None):
    """A receptor table from a ``.csv``, ``.eye``, ``.ply``, ``.gltf`` or ``.glb`` file, in the conventions given.

    A ``.eye`` file holds no Δφ or facet diameter: unless given, Δφ is
    measured from neighbouring axes, and the facet diameter from neighbouring
    positions where ``facet_diameter_um="spacing"`` asks for it. With
    ``directions`` the file is a table of bare directions
    (:func:`beeoptics.io.interchange.read_directions`), placed on the sphere
    given, its Δφ measured and its Δρ that many Δφ. The keywords are
    ``beeoptics convert``'s options (see its ``--help``).

    Parameters
    ----------
    units : {"mm", "m"} or float
        Lengths in a ``.eye`` file: mm, m, or file units per mm.
    frame : str, optional
        A ``.eye`` file's or a directions table's axes: ``"camera"``, ``"head"`` or ``"x=…,y=…,z=…"``.
    acceptance : {"fwhm", "variance"}
        A ``.eye`` file's acceptance angle is Δρ or √2·Δρ.
    side : {"left", "right", "auto"}, optional
        The eye a ``.eye`` file holds; by default each receptor's by the sign of its head-frame y.
    delta_phi_deg : float, optional
        Δφ of every receptor of a ``.eye`` file, degrees; measured from neighbouring axes by default.
    facet_diameter_um : float or "spacing", optional
        The facet diameter of every receptor of a ``.eye`` file, µm, or the mean distance to its neighbours.
    directions : bool
        The file is a table of bare unit directions (x,y,z a line, no header).
    halves : (str, str), optional
        A directions table's first and second halves' eyes.
    sphere_mm, centre_mm, delta_rho_per_delta_phi : float, (3,) and float
        A directions table's sphere radius (mm), its right eye's centre (head frame, mm), and each
        receptor's Δρ as a multiple of its Δφ.

    Raises
    ------
    InputError
        Naming the file and the field of bad input.
    """
    if directions:
        if sphere_mm is None or centre_mm is None or delta_rho_per_delta_phi is None:
            raise InputError(path, "", "a table of directions needs --sphere-mm, --centre-mm and "
                             "--delta-rho-per-delta-phi to place its receptors and set their Δρ")
        table = interchange.read_directions(path, halves=halves, frame=frame or "camera", radius_mm=sphere_mm,
                                            centre_mm=centre_mm)
        table = measure_spacing(table, path, facet_diameter_um=True)
        return checked(table._replace(delta_rho_deg=delta_rho_per_delta_phi * table.delta_phi_deg), path)
    kind = receptor_format(path)
    if kind == ".csv":
        return read_receptors(path)
    if kind == ".ply":
        return interchange.read_receptor_ply(path)
    if kind in (".gltf", ".glb"):
        # Imported here: its glTF library (pygltflib, with dataclasses-json and marshmallow) adds 30–40 ms to
        # the start of every job and command that reads receptors, nearly all of which read a CSV.
        from beeoptics.io import oces

        return oces.read_oces(path)
    spacing = facet_diameter_um == "spacing"
    table = interchange.read_compoundray_eye(path, side=side or "auto", units=units, frame=frame,
                                             angle_convention=acceptance, delta_phi_deg=delta_phi_deg,
                                             facet_diameter_um=None if spacing else facet_diameter_um)
    if delta_phi_deg is None or spacing:
        table = measure_spacing(table, path, delta_phi_deg=delta_phi_deg is None, facet_diameter_um=spacing)
    return table
