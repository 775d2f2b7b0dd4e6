"""Building an eye: its facet lattice, the receptors on it, and how good both are.

Collins §4.1: the hexagonal grid is projected onto the remeshed eye with the
count rule, relaxed over the surface to follow the facet-diameter map, and
each facet becomes a receptor whose axis is the interpolated surface normal
(axis model ``normals``) or, for eyes of real size, the direction the
field model gives its place in the lattice (``field``,
:mod:`beeoptics.eye.axismodel`).

The relaxation is a long chain of steps, each depending on the last, so a
difference in the last bit of one sum grows into another lattice. OpenBLAS
splits long dot products (the norms of FIRE's forces and velocities) across
its threads, which changes their rounding with the number of threads; the
eye is therefore built with BLAS on one thread, so that the workflow, the
command-line tool and any machine build the same eye to the last bit.
"""

import time
from typing import NamedTuple

import igl
import numpy as np
from scipy.spatial import cKDTree
from threadpoolctl import threadpool_limits

from beeoptics.eye.axismodel import field_axes
from beeoptics.eye.dorsalrim import dorsal_rim, rim_summary
from beeoptics.eye.facetmap import FILL, anchor_vertices, diameter_map, fill_diameter
from beeoptics.eye.lattice import conformal_map, project_grid
from beeoptics.eye.meshquery import MeshQuery
from beeoptics.eye.optics import acceptance_angles
from beeoptics.eye.quality import (anisotropy, field_match, fields, lattice_quality, optics_quality, published_checks,
                                   size, zone_contrast)
from beeoptics.eye.receptors import delta_phi, receptor_table, to_head
from beeoptics.eye.relax import relax
from beeoptics.io.errors import InputError


class BuiltEye(NamedTuple):
    """An eye's receptors (:class:`~beeoptics.io.receptortable.ReceptorTable`),
    its quality figures (a JSON-ready dict), its relaxation's snapshots
    (arrays, see :func:`build_eye`) and the relaxation's wall time, s (kept
    out of the quality figures, so that identical runs write identical files)."""

    receptors: object
    quality: dict
    relaxation: dict
    seconds: float


def build_eye(eye, vertices, faces, normals, tolerance_um, acceptance, progress=None):
    """Place, relax and describe the facets of an eye on its remeshed surface.

    Parameters
    ----------
    eye : EyeDescription
    vertices, faces, normals : ndarray
        The remeshed eye in its local frame, mm.
    tolerance_um : float
        The lattice is relaxed until no facet would move further than this, µm.
    acceptance : AcceptanceModel
        How the receptors' acceptance angles are set.
    progress : callable, optional
        Called with (iteration, largest move in mm) during relaxation.

    Returns
    -------
    BuiltEye
        ``relaxation`` holds ``iterations`` and ``snapshots`` (s, n, 3), the
        facets at the stored stages, ``snapshot_diameter_um`` (s, n),
        ``delta_phi_deg`` and ``facet_diameter_um`` (n,) at rest, and
        ``boundary_xy``, the eye's rim in its local xy-plane.
    """
    with threadpool_limits(limits=1, user_api="blas"):
        return _build_eye(eye, vertices, faces, normals, tolerance_um, acceptance, progress)


def _build_eye(eye, vertices, faces, normals, tolerance_um, acceptance, progress):
    query = MeshQuery(vertices, faces)
    points, point_faces, pitch = project_grid(query, eye.facet_count, eye.lattice_lines)
    if eye.axis_model == "field":
        # Before relaxation the projected grid stands for the facets, evenly spread and as many:
        # each anchor goes to the mesh vertex nearest the grid point that looks its way.
        grid_axes = field_axes(eye.rotation, points, np.ones(len(points)), points, pitch)
        sources = cKDTree(vertices).query(points[anchor_vertices(grid_axes @ eye.rotation, eye.anchors)])[1]
    else:
        sources = anchor_vertices(normals @ eye.rotation, eye.anchors)
    values = [None if a["diameter_um"] == FILL else a["diameter_um"] * 1e-3 for a in eye.anchors]
    filled = None
    if None in values:
        filled = fill_diameter(vertices, faces, sources, values, eye.facet_count, eye.diameter_power)
        if filled is None:
            raise InputError(eye.path, "facet_diameter.anchors", f"no diameter of the {FILL} anchor lets "
                             f"{eye.facet_count} facets tile this cornea with the other anchors' diameters")
        values = [filled if v is None else v for v in values]
    diameters = diameter_map(vertices, faces, sources, values, eye.diameter_power)
    start = time.perf_counter()
    result = relax(query, conformal_map(vertices, faces), diameters, points, point_faces, tolerance_um * 1e-3,
                   progress=progress)
    seconds = time.perf_counter() - start

    points, edges = result.points, result.edges
    corneal = query.interpolate(normals, points, result.faces)
    corneal /= np.linalg.norm(corneal, axis=1, keepdims=True)
    if eye.axis_model == "field":
        spacing = np.median(np.linalg.norm(points[edges[:, 1]] - points[edges[:, 0]], axis=1))
        axes = field_axes(eye.rotation, points, np.ones(len(points)), points, spacing)
    else:
        axes = corneal
    facet_um = query.interpolate(diameters, points, result.faces) * 1e3
    dphi = delta_phi(axes, edges)
    points_head, axes_head = to_head(eye, points, axes)
    drho = acceptance_angles(facet_um, acceptance, eye.rhabdom_acceptance_deg, axes_head, eye.delta_rho_anchors,
                             eye.delta_rho, dphi)
    chord = np.linalg.norm(points[edges[:, 1]] - points[edges[:, 0]], axis=1)
    lattice = lattice_quality(edges, result.boundary, result.geodesic, chord, facet_um)
    eye_optics = optics_quality(axes_head, dphi, facet_um, points_head)
    zone = None
    if "acute_zone" in eye.published:
        spec = eye.published["acute_zone"]
        anchor = next(a for a in eye.anchors if a["name"] == spec["anchor"])
        zone = zone_contrast(axes_head, dphi, facet_um, anchor, spec["radius_deg"])
    rim = None
    if eye.dorsal_rim is not None:
        rim = dorsal_rim(points, axes_head, vertices[igl.boundary_loop(faces)], eye.rotation, eye.dorsal_rim["count"])
    count = len(points)
    sizes = size(vertices, faces, eye.rotation, count, facet_um)
    field = None
    if eye.axis_model == "field" or "field_model" in eye.published:
        field = {"coverage": field_match(axes_head, drho, dphi)}
    if "field_model" in eye.published:
        field["anisotropy"] = anisotropy(points, axes_head, edges, eye.rotation, eye.lattice_lines)
    normals_head = corneal @ eye.rotation
    seen = fields(axes_head, normals_head, drho, dphi, delta_phi(corneal, edges))
    quality = {
        "eye": eye.name,
        "facets_per_eye": count,
        "facets_published": eye.facet_count,
        "facets_published_sd": eye.facet_count_sd,
        "grid_pitch_um": pitch * 1e3,
        "facet_diameter_fill_um": None if filled is None else filled * 1e3,
        "relaxation": {
            "iterations": result.iterations,
            "tolerance_um": tolerance_um,
            "fill_factor": result.fill_factor,
        },
        "lattice": lattice,
        "optics": eye_optics,
        "acute_zone": zone,
        "size": sizes,
        "fields": seen,
        "field": field,
        "dorsal_rim": None if rim is None else rim_summary(axes_head, *rim),
        "published": dict(eye.published),
        "checks": published_checks(eye, count, lattice, eye_optics, zone, field, sizes, seen),
    }
    snapshots = [p for _, p in result.snapshots]
    relaxation = {
        "iterations": np.array([it for it, _ in result.snapshots]),
        "snapshots": np.stack(snapshots),
        "snapshot_diameter_um": np.stack([query.interpolate(diameters, *query.project(p)) * 1e3 for p in snapshots]),
        "delta_phi_deg": dphi,
        "facet_diameter_um": facet_um,
        "boundary_xy": vertices[igl.boundary_loop(faces), :2],
    }
    return BuiltEye(receptor_table(eye, points, axes, facet_um, dphi, drho, rim), quality, relaxation, seconds)
