"""The eye stages: remesh an eye, build its receptors, draw its figures, tabulate the acuity of every eye.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically. The Snakemake rules in
``workflow/rules/eyes.smk`` and the command-line tool call nothing else.
"""

import numpy as np

from beeoptics.eye.acuity import acuity
from beeoptics.eye.build import build_eye
from beeoptics.eye.description import load_eye, load_eye_mesh
from beeoptics.eye.remesh import remesh, target_edge_mm
from beeoptics.images import figures
from beeoptics.io.atomic import atomic_path, write_json
from beeoptics.io.meshfile import read_mesh_normals, write_mesh
from beeoptics.io.receptortable import read_receptors, write_receptors
from beeoptics.io.table import write_table
from beeoptics.vision.sensitivity import LAMBDA_MAX_APIS, RECEPTORS

#: Wavelengths at which the Rayleigh limit is given, one per receptor class: its λmax (Peitsch et al. 1992).
RAYLEIGH_NM = dict(zip(RECEPTORS, LAMBDA_MAX_APIS))


def remesh_eye(eye_file, outputs, *, edge_fraction=1 / 3, subdivisions=2):
    """Remesh an eye's hand-made mesh isotropically: ``outputs["remeshed"]``, a PLY with normals.

    The target edge is ``edge_fraction`` of the mean facet diameter of the
    eye's anchors (:func:`beeoptics.eye.remesh.target_edge_mm`).
    """
    eye = load_eye(eye_file)
    vertices, faces = load_eye_mesh(eye)
    write_mesh(outputs["remeshed"], *remesh(vertices, faces, target_edge_mm(eye, edge_fraction),
                                            subdivisions=subdivisions))


def build_facets(eye_file, remeshed_ply, outputs, *, tolerance_um, acceptance, progress=None):
    """Place and relax the facets on the remeshed eye and describe every receptor.

    Writes ``receptors`` (the receptor table of both eyes), ``quality``
    (JSON) and ``relaxation`` (the lattice's snapshots, npz); see
    :func:`beeoptics.eye.build.build_eye`.

    Parameters
    ----------
    tolerance_um : float
        Relax until no facet would move further than this, µm.
    acceptance : AcceptanceModel
        How the receptors' Δρ is set.
    """
    eye = load_eye(eye_file)
    built = build_eye(eye, *read_mesh_normals(remeshed_ply), tolerance_um, acceptance, progress=progress)
    write_receptors(outputs["receptors"], built.receptors)
    write_json(outputs["quality"], built.quality)
    with atomic_path(outputs["relaxation"]) as tmp:
        np.savez_compressed(tmp, **built.relaxation)


def eye_figures(eye_file, relaxation_npz, receptors_csv, outputs):
    """Collins' Fig. 7 for one eye, maps of its Δφ and facet diameters, its acceptance functions.

    ``outputs`` maps ``relaxation``, ``delta_phi``, ``facet_diameter`` and
    ``acceptance`` to PNG paths.
    """
    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    figures.angular_sensitivities(table.delta_rho_deg, table.delta_phi_deg, outputs["acceptance"], eye.name)
    data = np.load(relaxation_npz)
    rest, rim = data["snapshots"][-1], data["boundary_xy"]
    figures.relaxation(data["snapshots"], data["iterations"], data["snapshot_diameter_um"], rim,
                       outputs["relaxation"], eye.name)
    figures.eye_map(rest, data["delta_phi_deg"], rim, outputs["delta_phi"],
                    "Δφ, degrees", f"{eye.name}: interommatidial angle Δφ")
    figures.eye_map(rest, data["facet_diameter_um"], rim, outputs["facet_diameter"],
                    "facet diameter, µm", f"{eye.name}: facet diameter")


def acuity_table(receptors_csvs, outputs, *, width_px=720):
    """``outputs["acuity"]``: the acuity of each eye class, one row each (:func:`beeoptics.eye.acuity.acuity`).

    The Rayleigh limit is given at each receptor class's λmax.

    Parameters
    ----------
    receptors_csvs : dict of str to path
        Eye class to its receptor table.
    """
    rows = [{"eye": name, **acuity(read_receptors(csv), RAYLEIGH_NM, width_px)}
            for name, csv in receptors_csvs.items()]
    write_table(outputs["acuity"], {k: [r[k] for r in rows] if k == "eye" else np.array([r[k] for r in rows])
                                    for k in rows[0]})
