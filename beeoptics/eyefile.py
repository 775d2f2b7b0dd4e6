"""Eye descriptions: ``eyes/<class>/eye.yaml`` and the hand-made mesh beside it.

An eye description holds one compound eye, the right one, in its own local
frame (millimetres, +z outward, so that the surface is a height field over
xy), how that frame sits on the head, the facet count, the facet diameters
measured at named anatomical anchors, and the published optics the eye is
meant to reproduce, each with its source. See ``beeoptics/schemas/eye.schema.yaml``.
"""

from pathlib import Path

import igl
import numpy as np

from beeoptics.errors import InputError
from beeoptics.headframe import eye_rotation
from beeoptics.meshfile import read_mesh
from beeoptics.validation import load_yaml, validate

#: Longest eye accepted, in mm: the largest bee eyes are a few millimetres long
#: (drone honey bees; Streinzer et al. 2013), so anything near a metre is in other units.
MAX_EYE_SIZE_MM = 20.0
#: Shortest eye accepted, in mm: even the smallest bees' eyes are a few tenths of a
#: millimetre long, so a bee eye of a few thousandths is a mesh in metres.
MIN_EYE_SIZE_MM = 0.1


def load_eye(path):
    """Read and check an eye description.

    Returns
    -------
    dict
        The description with defaults filled in, plus ``path`` (the file),
        ``mesh_path`` (resolved), and ``rotation`` (rows: the eye's local
        axes in the head frame) and ``origin`` (mm) of the right eye.
    """
    path = Path(path)
    eye = validate(load_yaml(path), "eye", path)
    eye["path"] = path
    eye["mesh_path"] = path.parent / eye["mesh"]
    p = eye["placement"]
    eye["rotation"] = eye_rotation(p["axis_azimuth_deg"], p["axis_elevation_deg"], p["roll_deg"])
    eye["origin"] = np.asarray(p["origin_mm"], float)
    return eye


def load_eye_mesh(eye):
    """The hand-made mesh of an eye, checked for size and orientation.

    Raises
    ------
    InputError
        If the mesh is missing (naming the eye file's ``mesh``), unusable
        (see :func:`~beeoptics.meshfile.read_mesh`), not one sheet (faces
        meeting at a single vertex), not in millimetres at bee size, or its
        faces do not face outward along the eye's local +z.
    """
    vertices, faces = read_mesh(eye["mesh_path"], source=eye["path"], field="mesh")
    pinched = ~np.asarray(igl.is_vertex_manifold(faces), bool).ravel()
    if pinched.any():
        raise InputError(
            eye["mesh_path"],
            "faces",
            f"the mesh is not manifold: faces meet at a single vertex ({int(pinched.sum())} such "
            f"vertices, the first at {vertices[np.argmax(pinched)].round(6).tolist()}); an eye is one sheet",
        )
    size = np.ptp(vertices, axis=0).max()
    if not MIN_EYE_SIZE_MM <= size <= MAX_EYE_SIZE_MM:
        raise InputError(
            eye["mesh_path"],
            "vertices",
            f"the eye is {size:g} units across; eye meshes are in millimetres, "
            f"and bee eyes are {MIN_EYE_SIZE_MM:g}–{MAX_EYE_SIZE_MM:g} mm long",
        )
    t = vertices[faces]
    normal_z = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])[:, 2]
    if (normal_z <= 0).any():
        raise InputError(
            eye["mesh_path"],
            "faces",
            f"{int((normal_z <= 0).sum())} faces do not face +z; the eye must be a height "
            "field over xy in its local frame, wound counter-clockwise seen from outside",
        )
    return vertices, faces
