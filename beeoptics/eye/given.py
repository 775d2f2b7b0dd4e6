"""Eyes whose receptors are given: a measured table of ommatidia used as it is.

Some eyes are measured ommatidium by ommatidium: Buchner's (1971) map of
*Drosophila* gives each one's direction (placed on a sphere of the fly's
eye's size by ``beeoptics convert --directions``). An eye description
with an ``ommatidia`` table is built from it directly, with no lattice to
relax: each of the right eye's rows is a receptor, the left eye its
mirror. A micro-CT cornea's points (:mod:`beeoptics.eye.cornea`) can be
built so too, "as given" (``beeoptics build-eye --as-given``): then each
25-µm sample of the cornea is a receptor with the file's acceptance angle,
as CompoundRay renders it, which compares our rendering with CompoundRay's
rather than with the bee.

Neighbours are those of a spherical Delaunay triangulation of the axes
(:func:`beeoptics.eye.lattice.sphere_triangles`); Δφ is the mean angle to
them, the facet diameter the mean distance (only meaningful where the
positions are the facets'). The eye's surface, for its area and figures,
is the same triangulation with the receptors' positions as its vertices.

References
----------
Buchner E (1971) Dunkelanregung des stationären Flugs der Fruchtfliege
Drosophila. Diplomarbeit, Universität Tübingen; as digitised by Straw AD
(strawlab/drosophila_eye_map).
Millward BF, Maddock S, Mangan M (2022) CompoundRay, an open-source tool for
high-speed and high-fidelity rendering of compound eyes. eLife 11:e73893.
"""

import numpy as np
from scipy.spatial import ConvexHull

from beeoptics.eye.build import BuiltEye
from beeoptics.eye.lattice import sphere_triangles, triangle_edges
from beeoptics.eye.optics import acceptance_angles
from beeoptics.eye.quality import fields, optics_quality, published_checks, size
from beeoptics.eye.receptors import delta_phi, joined, measure_spacing, receptor_table
from beeoptics.headframe import RIGHT
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import read_receptors, rows_of


def given_right_eye(path, source, field):
    """The right eye's rows of a given table (head frame, mm), with Δφ and the facet diameter measured.

    Raises
    ------
    InputError
        Naming ``source`` and ``field`` if the file is missing, or naming the
        table if it has too few right-eye rows to triangulate.
    """
    if not path.is_file():
        raise InputError(source, field, f"no such file {path}")
    table = read_receptors(path)
    right = rows_of(table, np.asarray(table.side).astype(str) == RIGHT)
    if len(right.id) < 4:
        raise InputError(path, "side", "an eye needs the right eye's receptors (side right), four at least")
    return measure_spacing(right, path, facet_diameter_um=True)


def surface(eye, table):
    """The given receptors' own triangulation in the eye's local frame: vertices, faces, vertex normals."""
    faces = sphere_triangles(table.axis)
    local = (table.position - eye.origin) @ eye.rotation.T
    # Wound so that each face looks out along its corners' axes.
    corners = local[faces]
    outward = np.einsum("ij,ij->i", np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]),
                        (table.axis @ eye.rotation.T)[faces].sum(axis=1))
    faces = np.where((outward < 0)[:, None], faces[:, ::-1], faces)
    return local, faces, table.axis @ eye.rotation.T


def build_given(eye, table, acceptance, keep_delta_rho=False):
    """Build an eye from its given receptors (the right eye's rows of ``table``, measured by :func:`given_right_eye`).

    Parameters
    ----------
    eye : EyeDescription
    table : ReceptorTable
    acceptance : AcceptanceModel
        How Δρ is set, as for a built eye; unless ``keep_delta_rho``, which
        keeps the table's (CompoundRay's, for a cornea built as given).

    Returns
    -------
    BuiltEye
        Its relaxation holds the given positions alone (iteration 0), so that
        the eye's figures draw them as they draw a relaxed lattice.
    """
    axes, points_head = table.axis, table.position
    edges = joined(axes, triangle_edges(sphere_triangles(axes)))
    dphi, facet_um = delta_phi(axes, edges), table.facet_diameter_um
    drho = table.delta_rho_deg if keep_delta_rho else acceptance_angles(
        facet_um, acceptance, eye.rhabdom_acceptance_deg, axes, eye.delta_rho_anchors, eye.delta_rho, dphi)
    vertices, faces, _ = surface(eye, table)
    local_axes = axes @ eye.rotation.T
    count = len(axes)
    sizes = size(vertices, faces, eye.rotation, count, facet_um)
    eye_optics = optics_quality(axes, dphi, facet_um, points_head)
    seen = fields(axes, axes, drho, dphi, dphi)
    quality = {
        "eye": eye.name,
        "facets_per_eye": count,
        "facets_published": eye.facet_count,
        "facets_published_sd": eye.facet_count_sd,
        "given": {"receptors": count, "delta_rho": "the table's" if keep_delta_rho else "the eye's optics"},
        "optics": eye_optics,
        "size": sizes,
        "fields": seen,
        "published": dict(eye.published),
        "checks": published_checks(eye, count, None, eye_optics, None, None, sizes, seen),
    }
    relaxation = {
        "iterations": np.array([0]),
        "snapshots": vertices[None],
        "snapshot_diameter_um": facet_um[None],
        "delta_phi_deg": dphi,
        "facet_diameter_um": facet_um,
        # The outline the receptors fill, seen along the eye's local z (their triangulation's rim has gaps).
        "boundary_xy": vertices[ConvexHull(vertices[:, :2]).vertices, :2],
    }
    return BuiltEye(receptor_table(eye, vertices, local_axes, facet_um, dphi, drho), quality, relaxation, 0.0)
