"""The eye stages: remesh an eye, build its receptors, draw its figures, tabulate the acuity of every eye.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically. The Snakemake rules in
``workflow/rules/eyes.smk`` and the command-line tool call nothing else.
"""

import json
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from beeoptics.eye.acuity import acuity
from beeoptics.eye.build import build_eye
from beeoptics.eye import fieldmodel
from beeoptics.eye.cornea import measured_normals
from beeoptics.eye.description import cornea_points, load_eye, load_eye_mesh
from beeoptics.eye.given import build_given, given_right_eye, surface
from beeoptics.eye.fieldofview import MAP_WIDTH_PX, visual_field
from beeoptics.eye.lattice import kernel_mean
from beeoptics.eye.remesh import remesh, target_edge_mm
from beeoptics.io.atomic import atomic_path, write_json
from beeoptics.io.errors import InputError
from beeoptics.io.meshfile import read_mesh_normals, write_mesh
from beeoptics.io.receptortable import read_receptors, write_receptors
from beeoptics.headframe import RIGHT
from beeoptics.io.table import write_table
from beeoptics.io.validation import config_default
from beeoptics.pipeline.logs import log
from beeoptics.vision.receptorset import peaks_nm, receptor_set_of
#: The Δφ map's kernel, in facet spacings: wide enough to average a facet's six-edge noise over
#: some thirty facets, narrow against the eye's hundred-facet gradients.
DELTA_PHI_KERNEL = 3.0


def remesh_eye(eye_file, outputs, *, edge_fraction=config_default("eye.edge_fraction"), subdivisions=2):
    """Remesh an eye's hand-made mesh isotropically: ``outputs["remeshed"]``, a PLY with normals.

    The target edge is ``edge_fraction`` of the mean facet diameter of the
    eye's anchors (:func:`beeoptics.eye.remesh.target_edge_mm`).
    """
    eye = load_eye(eye_file)
    if eye.ommatidia_path is not None:
        # Given ommatidia are not relaxed on a surface: theirs is their own triangulation, kept as it is.
        write_mesh(outputs["remeshed"], *surface(eye, given_right_eye(eye.ommatidia_path, eye.path, "ommatidia.file")))
        return
    vertices, faces = load_eye_mesh(eye)
    if eye.cornea_path is None:
        write_mesh(outputs["remeshed"], *remesh(vertices, faces, target_edge_mm(eye, edge_fraction),
                                                subdivisions=subdivisions))
        return
    # A measured cornea's reconstruction is smooth and fine already: it is not subdivided, and its
    # normals are the measured ones (beeoptics.eye.cornea.measured_normals).
    vertices, faces, _ = remesh(vertices, faces, target_edge_mm(eye, edge_fraction), subdivisions=0)
    points, normals = cornea_points(eye)
    write_mesh(outputs["remeshed"], vertices, faces, measured_normals(points, normals, vertices))


def build_facets(eye_file, remeshed_ply, outputs, *, tolerance_um, acceptance, progress=None, as_given=False):
    """Place and relax the facets on the remeshed eye and describe every receptor.

    Writes ``receptors`` (the receptor table of both eyes), ``quality``
    (JSON) and ``relaxation`` (the lattice's snapshots, npz); see
    :func:`beeoptics.eye.build.build_eye`. An eye of given ommatidia is
    built from them instead (:func:`beeoptics.eye.given.build_given`), and
    so, with ``as_given``, is a measured cornea's eye, each of its points a
    receptor with the file's Δρ. Logs, and returns, the relaxation's wall
    time in seconds.

    Parameters
    ----------
    tolerance_um : float
        Relax until no facet would move further than this, µm.
    acceptance : AcceptanceModel
        How the receptors' Δρ is set.
    """
    eye = load_eye(eye_file)
    if as_given and eye.cornea_path is None:
        raise InputError(eye_file, "cornea", "only a measured cornea's points can be built as given")
    if eye.ommatidia_path is not None:
        built = build_given(eye, given_right_eye(eye.ommatidia_path, eye.path, "ommatidia.file"), acceptance)
    elif as_given:
        built = build_given(eye, given_right_eye(eye.cornea_path, eye.path, "cornea.file"), acceptance,
                            keep_delta_rho=True)
    else:
        built = build_eye(eye, *read_mesh_normals(remeshed_ply), tolerance_um, acceptance, progress=progress)
    write_receptors(outputs["receptors"], built.receptors)
    write_json(outputs["quality"], built.quality)
    with atomic_path(outputs["relaxation"]) as tmp:
        np.savez_compressed(tmp, **built.relaxation)
    log.info("%s: %d facets an eye relaxed in %.1f s", eye.name, built.quality["facets_per_eye"], built.seconds)
    return built.seconds


def eye_figures(eye_file, relaxation_npz, receptors_csv, quality_json, outputs):
    """Collins' Fig. 7 for one eye, maps of its Δφ and facet diameters, its acceptance functions, its field.

    ``outputs`` maps ``relaxation``, ``delta_phi``, ``facet_diameter``,
    ``acceptance`` and ``field_of_view`` to PNG paths; the field is drawn
    against the measured border for an eye compared with it (``published:
    field_model``), with the shares ``quality_json`` reports.
    """
    from beeoptics.images import figures  # imported where drawn: matplotlib is half a second of each eye job

    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    figures.angular_sensitivities(table.delta_rho_deg, table.delta_phi_deg, outputs["acceptance"], eye.name)
    data = np.load(relaxation_npz)
    rest, rim = data["snapshots"][-1], data["boundary_xy"]
    figures.relaxation(data["snapshots"], data["iterations"], data["snapshot_diameter_um"], rim,
                       outputs["relaxation"], eye.name)
    # Each facet's Δφ is the mean over its few lattice edges, so neighbours scatter by lattice
    # noise; the map shows the trend, averaged over a stated kernel.
    spacing = np.median(cKDTree(rest).query(rest, k=2)[0][:, 1])
    smooth = kernel_mean(rest, data["delta_phi_deg"], DELTA_PHI_KERNEL * spacing)
    figures.eye_map(rest, smooth, rim, outputs["delta_phi"], "Δφ, degrees",
                    f"{eye.name}: interommatidial angle Δφ, Gaussian kernel mean (σ = {DELTA_PHI_KERNEL:g} "
                    "facet spacings); per-facet values in receptors.csv")
    figures.eye_map(rest, data["facet_diameter_um"], rim, outputs["facet_diameter"],
                    "facet diameter, µm", f"{eye.name}: facet diameter")
    right = table.side == RIGHT
    field = visual_field(table.axis[right], table.side[right], table.delta_rho_deg[right],
                         table.delta_phi_deg[right], MAP_WIDTH_PX)
    # The map's azimuth runs towards the bee's left; the right eye's own, towards its right, from -90°.
    order = np.argsort((-field.azimuth_deg + 90.0) % 360.0)
    azimuth = (-field.azimuth_deg[order] + 90.0) % 360.0 - 90.0
    seen = field.eyes[:, order] > 0
    title = f"{eye.name}: the right eye's field of view (grey, within Δρ/2 of an axis or inside the lattice)"
    border = None
    if "field_model" in eye.published:
        # The border, and beyond its closed rings the caps, to the poles.
        e = np.linspace(-90.0, 90.0, 361)
        border = (e, *fieldmodel.ring(e))
        quality = json.loads(Path(quality_json).read_text())["field"]["coverage"]
        title += (f"; covers {100 * quality['covered']:.0f} % of the measured field with its polar caps "
                  f"({100 * quality['covered_without_caps']:.0f} % without), "
                  f"{100 * quality['outside']:.1f} % of ours lies beyond it")
    figures.field_of_view(azimuth, field.elevation_deg, seen, outputs["field_of_view"], title, border)


def acuity_table(eyes, outputs, *, width_px=MAP_WIDTH_PX):
    """Compare eye classes: ``outputs["acuity"]``, one row each, and ``outputs["fields"]``, a figure of their fields.

    A row holds the eye's species and specimen (its intertegular width,
    where the eye.yaml gives it), facets an eye, the eye's length and
    corneal area and the single-eye field published for it (quality.json),
    and its acuity (:func:`beeoptics.eye.acuity.acuity`), with the Rayleigh
    limit at each receptor class's peak; a column of a class another
    species lacks is empty in its row. ``outputs["allometry"]``, if asked
    for, plots the bumblebees' fields, Δφ and facets against body size
    beside the trends Taylor et al. (2019) publish
    (:func:`beeoptics.images.figures.allometry`).

    Parameters
    ----------
    eyes : dict of str to (path, path, path)
        Eye class to its eye.yaml, its receptor table and its quality.json.
    """
    from beeoptics.images import figures  # as in eye_figures

    rows, fields_seen = [], {}
    for name, (eye_file, csv, quality_json) in eyes.items():
        eye, table = load_eye(eye_file), read_receptors(csv)
        quality = json.loads(Path(quality_json).read_text())
        receptor_set = receptor_set_of(eye_file)
        row = {"eye": name, "species": eye.document.get("species", ""),
               "intertegular_width_mm": eye.document.get("specimen", {}).get("intertegular_width_mm", np.nan),
               "facets_per_eye": quality["facets_per_eye"], "facets_published": quality["facets_published"],
               "eye_length_mm": quality["size"]["eye_length_mm"],
               "corneal_area_mm2": quality["size"]["corneal_area_mm2"],
               "field_fraction_published": eye.published.get("field_fraction", {}).get("value", np.nan)}
        fields_seen[name] = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, width_px)
        row.update(acuity(table, dict(zip(receptor_set.classes, peaks_nm(receptor_set))), fields_seen[name]))
        rows.append(row)
    keys = list(dict.fromkeys(k for r in rows for k in r))
    text = ("eye", "species")
    write_table(outputs["acuity"], {k: [r[k] for r in rows] if k in text else
                                    np.array([r.get(k, np.nan) for r in rows]) for k in keys})
    figures.eye_fields(fields_seen, outputs["fields"])
    if "allometry" in outputs:
        figures.allometry(rows, outputs["allometry"])
