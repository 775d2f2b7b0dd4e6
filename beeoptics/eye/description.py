"""Eye descriptions: ``eyes/<class>/eye.yaml`` and the hand-made mesh beside it.

An eye description holds one compound eye, the right one, in its own local
frame (millimetres, +z outward, so that the surface is a height field over
xy), how that frame sits on the head, the facet count, the facet diameters
measured at named anatomical anchors, and the published optics the eye is
meant to reproduce, each with its source. See ``beeoptics/io/schemas/eye.schema.yaml``.
"""

import json
from pathlib import Path
from typing import NamedTuple

import numpy as np

from beeoptics.eye.facetmap import FILL
from beeoptics.eye.given import given_right_eye, surface
from beeoptics.eye.optics import RHABDOM_ACCEPTANCE_DEG
from beeoptics.headframe import EYE_SIZE_MM, RIGHT, eye_rotation
from beeoptics.io.errors import InputError
from beeoptics.io.meshfile import read_mesh
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.validation import load_yaml, validate



class EyeDescription(NamedTuple):
    """One eye class, as its ``eye.yaml`` describes it.

    ``rotation`` has the right eye's local axes as rows, in the head frame,
    and ``origin`` is its local origin in the head frame, mm: the
    placement's, or a measured cornea's own (:mod:`beeoptics.eye.cornea`),
    when the eye has a ``cornea`` (``cornea_path``) instead of a hand-made
    mesh (``mesh_path``), or its measured ommatidia (``ommatidia_path``,
    :mod:`beeoptics.eye.given`; ``facet_count`` is then the published count
    if given, else the table's, and there are no anchors). ``anchors``
    are the facet-diameter anchors (``name``, ``azimuth_deg``,
    ``elevation_deg``, ``diameter_um``), spread with Shepard's exponent
    ``diameter_power``. ``axis_model`` names where the receptors' axes come
    from, ``"normals"`` or ``"field"`` (:mod:`beeoptics.eye.axismodel`); ``lattice_lines`` how the
    lenses line up, ``"rows"`` or ``"columns"`` (:func:`beeoptics.eye.lattice.hex_grid`); ``dorsal_rim``, if
    given, how many facets form the dorsal rim area. ``published`` holds the published optics the eye is
    checked against, ``document`` the whole checked file, defaults filled in.
    ``delta_rho`` is how its acceptance angles are set (its ``optics.delta_rho``,
    or None). ``receptors`` names its receptor set (a shipped set's name, or a path
    relative to the eye's folder; :mod:`beeoptics.vision.receptorset`).
    """

    name: str
    path: Path
    mesh_path: Path | None
    cornea_path: Path | None
    ommatidia_path: Path | None
    rotation: np.ndarray
    origin: np.ndarray
    facet_count: int
    facet_count_sd: float
    anchors: list
    diameter_power: float
    rhabdom_acceptance_deg: float
    axis_model: str
    lattice_lines: str
    dorsal_rim: dict
    delta_rho_anchors: list
    delta_rho: dict | None
    published: dict
    receptors: str
    document: dict


def load_eye(path):
    """Read and check an eye description.

    Returns
    -------
    EyeDescription
    """
    path = Path(path)
    doc = validate(load_yaml(path), "eye", path)
    optics = doc.get("optics", {})
    own = optics.get("delta_rho", {})
    if own.get("model") == "measured" and not optics.get("delta_rho_anchors"):
        raise InputError(path, "optics.delta_rho", "the measured model needs optics.delta_rho_anchors, the "
                         "acceptance angles measured in named regions")
    anchors = doc.get("facet_diameter", {}).get("anchors", [])
    if sum(a["diameter_um"] == FILL for a in anchors) > 1:
        raise InputError(path, "facet_diameter.anchors", f"one anchor at most may be left to {FILL}")
    if own.get("model") == "delta_phi" and "ratio" not in own:
        raise InputError(path, "optics.delta_rho.ratio", "the delta_phi model needs the ratio of Δρ to Δφ")
    cornea_path = ommatidia_path = None
    facets = doc.get("facets", {})
    if "cornea" in doc or "ommatidia" in doc:
        # A measured eye's frame is its own: the cornea's points, or the ommatidia's.
        if "cornea" in doc:
            cornea_path = path.parent / doc["cornea"]["file"]
            positions, normals = _cornea(cornea_path, path)
        else:
            ommatidia_path = path.parent / doc["ommatidia"]["file"]
            given = given_right_eye(ommatidia_path, path, "ommatidia.file")
            positions, normals = given.position, given.axis
            facets = {"count": len(given.id), **facets}
        # Imported where used, as are libigl and the mesh readers: most stages read an eye's description
        # for its frame and its anchors, and need not pay for the surface reconstruction's libraries.
        from beeoptics.eye.cornea import cornea_frame

        rotation, origin = cornea_frame(positions, normals)
    else:
        p = doc["placement"]
        rotation = eye_rotation(p["axis_azimuth_deg"], p["axis_elevation_deg"], p["roll_deg"])
        origin = np.asarray(p["origin_mm"], float)
    return EyeDescription(
        name=doc["name"], path=path, mesh_path=path.parent / doc["mesh"] if "mesh" in doc else None,
        cornea_path=cornea_path, ommatidia_path=ommatidia_path, rotation=rotation, origin=origin,
        facet_count=facets["count"], facet_count_sd=facets.get("sd"),
        anchors=anchors, diameter_power=doc.get("facet_diameter", {}).get("power", 2.0),
        rhabdom_acceptance_deg=doc.get("optics", {}).get("rhabdom_acceptance_deg", RHABDOM_ACCEPTANCE_DEG),
        axis_model=doc["axes"]["model"], lattice_lines=doc["lattice"]["lines"], dorsal_rim=doc.get("dorsal_rim"),
        delta_rho_anchors=doc.get("optics", {}).get("delta_rho_anchors", []),
        delta_rho=doc.get("optics", {}).get("delta_rho"),
        published=doc.get("published", {}), receptors=doc["receptors"], document=doc,
    )


#: How far a receptor table's count per eye may stray from its eye's, as a share, before the table is taken for
#: another eye's: the built eyes hold their count exactly, a measured eye its table's (its published count beside
#: it within 15 %: the fly's 699 charted of about 800), while the eyes this package ships differ by more (the fly's
#: 699, the queen's 3,500, the worker's 5,432, the drone's 9,973).
COUNT_SHARE = 0.25


def check_receptors_of(eye, receptors_csv, table):
    """Refuse a receptor table that is not this eye's: the eye its quality.json names (build-eye writes one beside
    every table), or without one a count per eye more than :data:`COUNT_SHARE` from the eye's.

    Parameters
    ----------
    eye : EyeDescription
    receptors_csv : path
        The table's file, beside which its ``quality.json`` is looked for.
    table : ReceptorTable
        Its receptors.

    Raises
    ------
    InputError
        Naming ``receptors_csv``, the eye the table was built for and the eye it is not.
    """
    quality = Path(receptors_csv).parent / "quality.json"
    try:
        built_for = json.loads(quality.read_text()).get("eye") if quality.is_file() else None
    except (OSError, ValueError, AttributeError):
        built_for = None
    if built_for is not None and built_for != eye.name:
        raise InputError(receptors_csv, "", f"built for the eye {built_for!r} (its {quality.name}), not for "
                         f"{eye.name!r} ({eye.path}): give the eye it was built for")
    count = int(np.sum(np.asarray(table.side).astype(str) == RIGHT))
    if built_for is None and abs(count - eye.facet_count) > COUNT_SHARE * eye.facet_count:
        raise InputError(receptors_csv, "", f"{count} receptors an eye, where the eye {eye.name!r} ({eye.path}) "
                         f"has {eye.facet_count}: the table is another eye's")


def _cornea(path, source):
    """The right eye's points and normals of a measured cornea's table (head frame, mm)."""
    if not path.is_file():
        raise InputError(source, "cornea.file", f"no such file {path}")
    table = read_receptors(path)
    right = np.asarray(table.side).astype(str) == RIGHT
    if right.sum() < 4:
        raise InputError(path, "side", "a cornea needs the right eye's points (side right)")
    return table.position[right], table.axis[right]


def cornea_points(eye):
    """A measured cornea's points and normals in the eye's local frame (mm)."""
    positions, normals = _cornea(eye.cornea_path, eye.path)
    return (positions - eye.origin) @ eye.rotation.T, normals @ eye.rotation.T


def load_eye_mesh(eye):
    """The hand-made mesh of an eye, or its measured cornea's surface, checked for size and orientation.

    Raises
    ------
    InputError
        If the mesh is missing (naming the eye file's ``mesh``), unusable
        (see :func:`~beeoptics.io.meshfile.read_mesh`), not one sheet (faces
        meeting at a single vertex), not in millimetres at bee size, or its
        faces do not face outward along the eye's local +z; or if the eye's
        facet count could not tile it (:func:`check_facet_count`).
    """
    import igl

    from beeoptics.eye.cornea import reconstruct

    if eye.ommatidia_path is not None:
        return surface(eye, given_right_eye(eye.ommatidia_path, eye.path, "ommatidia.file"))[:2]
    if eye.cornea_path is not None:
        vertices, faces = reconstruct(*cornea_points(eye), eye.cornea_path)
    else:
        vertices, faces = read_mesh(eye.mesh_path, source=eye.path, field="mesh")
    pinched = ~np.asarray(igl.is_vertex_manifold(faces), bool).ravel()
    if pinched.any():
        raise InputError(
            eye.mesh_path,
            "faces",
            f"the mesh is not manifold: faces meet at a single vertex ({int(pinched.sum())} such "
            f"vertices, the first at {vertices[np.argmax(pinched)].round(6).tolist()}); an eye is one sheet",
        )
    size = np.ptp(vertices, axis=0).max()
    if not EYE_SIZE_MM[0] <= size <= EYE_SIZE_MM[1]:
        raise InputError(
            eye.mesh_path,
            "vertices",
            f"the eye is {size:g} units across; eye meshes are in millimetres, "
            f"and bee eyes are {EYE_SIZE_MM[0]:g}–{EYE_SIZE_MM[1]:g} mm long",
        )
    t = vertices[faces]
    normal_z = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])[:, 2]
    if (normal_z <= 0).any():
        raise InputError(
            eye.mesh_path,
            "faces",
            f"{int((normal_z <= 0).sum())} faces do not face +z; the eye must be a height "
            "field over xy in its local frame, wound counter-clockwise seen from outside",
        )
    check_facet_count(eye, 0.5 * igl.doublearea(vertices, faces).sum())
    return vertices, faces


def facet_count_range(area_mm2, diameters_um):
    """How many hexagonal facets of the given diameters tile a cornea of ``area_mm2``: (fewest, most).

    A hexagon of diameter d (between opposite sides) has area (√3/2)·d²;
    the cornea holds fewest facets if all were as large as the largest
    diameter, most if all were as small as the smallest.
    """
    hexagon = np.sqrt(3.0) / 2.0 * (np.asarray(diameters_um, float) * 1e-3) ** 2
    return area_mm2 / hexagon.max(), area_mm2 / hexagon.min()


def check_facet_count(eye, area_mm2):
    """Refuse, at once, a facet count the cornea's area and the eye's facet diameters cannot hold.

    Relaxation fills the cornea with facets at the diameters of the map
    (:mod:`beeoptics.eye.relax`): far fewer facets than fit cannot fill it
    (three cannot even be triangulated), far more would take hours to
    squeeze in, each ending far smaller than measured.
    """
    if any(a["diameter_um"] == FILL for a in eye.anchors):
        return  # the count sets the missing diameter (beeoptics.eye.facetmap.fill_diameter)
    fewest, most = facet_count_range(area_mm2, [a["diameter_um"] for a in eye.anchors])
    if not np.floor(fewest) <= eye.facet_count <= np.ceil(most):
        sizes = sorted({a["diameter_um"] for a in eye.anchors})
        raise InputError(eye.path, "facets.count",
                         f"{eye.facet_count} facets cannot tile this cornea of {area_mm2:.3g} mm² at "
                         f"{'–'.join(f'{d:g}' for d in (sizes[0], sizes[-1]))} µm (facet_diameter.anchors): "
                         f"facets of those diameters number {int(np.floor(fewest))}–{int(np.ceil(most))}")
