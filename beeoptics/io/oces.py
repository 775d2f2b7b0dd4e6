"""Receptor tables as Open Compound Eye Standard (OCES) glTF files.

OCES (Millward 2023, draft 0.4.0) is a glTF 2.0 extension, ``OCES_eyes``,
for compound eyes. The file-level ``extensions.OCES_eyes`` lists the eyes and
their *ommatidial properties*: per-ommatidium data, each an ``ACCESSOR`` (a
glTF accessor, one value per ommatidium), a ``COARSE`` value shared by every
ommatidium, or a ``TEXTURE``. Nodes carry ``{"head": true}`` or
``{"eye": index}``; an eye is placed by the node transforms between it and
its head. :func:`write_oces` writes a receptor table as such a file, ``.gltf``
(JSON with the data in a base64 ``data:`` URI) or ``.glb`` (binary glTF, a
JSON and a BIN chunk), by its suffix; :func:`read_oces` reads it, or an OCES
file another tool wrote, back as a :class:`~beeoptics.io.receptortable.ReceptorTable`.

The container is pygltflib's on writing: its glTF object model, GLB chunks
and data URIs. Reading walks the file's JSON itself, as a dict, because
what a malformed file gets is one line naming its field, and pygltflib's
reader names none: its GLB reader takes a chunk running past the file as
the bytes that remain and fails on a BIN chunk first with an AttributeError,
its JSON decoding fails on ``"nodes": 5`` with a TypeError and on
``"nodes": [5]`` with an AttributeError, naming no field, reads a count
of 3.5 as 3 and a file without ``asset`` as glTF 2.0, and its data URIs
skip characters that are not base64. Reading through it would mean these
checks in front of it and the same file parsed twice.

What is written
---------------
One scene: a head node (``{"head": true}``) whose children are one node per
eye present in the table, right then left, each a ``POINT_OMMATIDIAL`` eye
with its own accessors, all float32 (componentType 5126), the only
floating-point type glTF 2.0 has. Both eyes are written out; mirror planes
are not used. The ommatidial properties:

``POSITION`` (VEC3)
    The facet centre, in the eye node's coordinates (see Units).
``ORIENTATION`` (VEC3)
    The receptor axis, a unit vector.
``DIAMETER`` (SCALAR)
    The lens (facet) diameter, in the eye node's length units.
``FOCAL_OFFSET`` (SCALAR)
    The apex W of the ommatidium's sampling cone behind its lens, negative,
    in the eye node's length units, computed from the acceptance angle (see
    Acceptance angle).

and beeoptics' own, which the draft does not define but allows (§4.2.2: "any
other properties may be appended on a per-ommatidial basis"), declared as
the sub-extension ``BEEOPTICS_receptor_table`` in ``OCES_eyes.extensionsUsed``
(§4.3.1), so that a round trip keeps every column:

``BEEOPTICS_ID``
    The receptor's id. float32 holds whole numbers exactly up to 2²⁴; glTF's
    unsigned int type is for mesh indices only (glTF 2.0 §3.6.2.2).
``BEEOPTICS_DELTA_PHI_DEG``
    Δφ, degrees.
``BEEOPTICS_DORSAL_RIM``, ``BEEOPTICS_MICROVILLI_DEG``
    Written for tables with a dorsal rim area: 1 or 0, and degrees.
``BEEOPTICS_FOCAL_POINT_OFFSET``
    Written for tables that have one (from a CompoundRay ``.eye`` file):
    CompoundRay's focal point offset, in the eye node's length units.

glTF validators refuse NaN in accessors (glTF-Validator's
ACCESSOR_INVALID_FLOAT), so a Δφ or a microvillar orientation that is not
known (NaN) is written as :data:`MISSING` (−1: both are angles ≥ 0) and read
back as NaN. A receptor without a facet diameter cannot be written: OCES
requires DIAMETER (measure it with
:func:`beeoptics.eye.receptors.measure_spacing`).

Frame
-----
Eyes lie in the head's coordinate space (HCS), the local frame of the head
node. OCES names mirror-plane normals by HCS axis with anatomical aliases:
X is LEFT/RIGHT, Y is UP/DOWN/DORSOVENTRAL, Z is ANTERIOR/FORWARD
(``mirrorPlane.schema.json``, §7.2.1), glTF's own convention for an asset
(+Y up, +Z forward, +X its left; glTF 2.0 §3.4). So in these files the HCS
is +X the bee's left, +Y dorsal, +Z anterior, and beeoptics' head frame
(:mod:`beeoptics.headframe`: +x anterior, +y left, +z dorsal) is the HCS with
its axes renamed: (x, y, z) = (Z, X, Y), a rotation (:data:`HCS_FROM_HEAD`).
A head so written stands upright facing +Z in any glTF viewer, the default
mirror plane (normal [1, 0, 0]) is the bee's sagittal plane, and OCES's local
ommatidial coordinate space, built about the eye's Y axis (§4.2.1), keeps its
V axis towards the dorsal. (The plane names listed with the aliases,
FRONTAL, TRANSVERSE and SAGITTAL, do not fit these directions; every alias
is read by the axis the schema files it under.) The head node's own
transform, and those above it, place the head in a scene; of them only the
scale counts, as it sets the size of an HCS unit.

Units
-----
glTF lengths are metres (glTF 2.0 §3.4), and so are those of OCES (§4.3.2),
which allows an eye to be "specified in one metric and then wrapped in a
scaling node". Each eye node is such a node: scale 0.001, so that its data
(POSITION, DIAMETER, FOCAL_OFFSET) are in millimetres, like beeoptics' tables,
and a translation (metres, in the HCS) to the centre of the eye's bounding
box, so that positions are stored relative to it. float32 keeps a relative
precision of 6·10⁻⁸ in any unit, so the unit does not set the precision:
the size of the numbers stored does. Relative to the eye's centre they are
at most half the eye's extent, which keeps a position to 6·10⁻⁷ mm even for
the largest eyes (:data:`~beeoptics.headframe.EYE_SIZE_MM`), where
coordinates from the head's origin would err in proportion to their whole
distance from it; the translation is a JSON number, a double.

Acceptance angle
----------------
OCES describes an ommatidium's field by its lens diameter d and the apex of
its sampling cone, W behind the lens, and relates them to the acceptance
angle Δρ by W = −(d/2) / tan(Δρ/2) (§4.2.2); its glossary takes the
acceptance angle to be the full width at half maximum of a Gaussian
sampling function, as Δρ of a receptor table is. Writing computes W so
(:func:`focal_offset_from_acceptance`), and reading inverts it,
Δρ = 2 atan((d/2)/|W|) (:func:`acceptance_from_focal_offset`). Δρ is not
stored a second time: a copy could disagree with FOCAL_OFFSET once another
tool edits the file, the data inconsistency OCES warns of (§4.1.3).

Reading
-------
:func:`read_oces` reads every enabled point-ommatidial eye (the eye, its node
and its head all enabled) below one head node, applying the transforms of
the nodes between head and eye (translation, rotation, scale or matrix;
scales must be uniform, as DIAMETER and FOCAL_OFFSET are lengths). ACCESSOR
properties must be float32; COARSE values apply to every ommatidium. A
missing POSITION, ORIENTATION, DIAMETER or FOCAL_OFFSET takes OCES's
default ([0, 0, 0], [0, 0, 1], 1, −1) with an :class:`OcesWarning`, as
§11.2 asks of parsers. An eye that lists mirror planes (in its eye object,
or, as in the draft's examples, in its node's extension) is read once as
given and once mirrored across each plane (position and normal in the HCS;
normals by the schema's aliases). Which eye is which follows from the sign
of head-frame y of its positions' mean (negative: right), as
:func:`~beeoptics.io.interchange.read_compoundray_eye` does. Ids are the
file's ``BEEOPTICS_ID`` when every eye has them and none is a mirrored copy,
rows then in order of id; otherwise rows are numbered 0 … n−1, right eye
first. Surface and spherical eyes are refused: they describe how
ommatidia are distributed, not the ommatidia a receptor table needs.
Properties beeoptics does not use are not read, and the file is never
changed, as §11.2 requires of parsers.

Errors name the file and the field: OCES fields from the extension object
(``eyes.0.ommatidialProperties.POSITION``, ``mirrorPlanes.1.normal``), glTF
fields from the file's root (``nodes.2.rotation``, ``buffers.0.uri``).

References
----------
Millward B (2023) The Open Compound Eye Standard: a glTF extension definition
supporting compound eye structures, draft 0.4.0.
github.com/Blayzeing/open-compound-eye-standard (MIT licence).
Khronos Group (2021) glTF 2.0 Specification, version 2.0.1.
"""

import base64
import binascii
import functools
import json
import logging
import struct
import warnings
from datetime import datetime, timezone
from pathlib import Path
from urllib.parse import unquote

import numpy as np
import pygltflib as gltf
from scipy.spatial.transform import Rotation

from beeoptics import __version__
from beeoptics.headframe import SIDES
from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import ReceptorTable, checked

log = logging.getLogger("beeoptics")

#: The OCES draft written, and read.
OCES_VERSION = "0.4.0"
EXTENSION = "OCES_eyes"
#: beeoptics' properties, as an OCES sub-extension (§4.3.1).
SUB_EXTENSION = "BEEOPTICS_receptor_table"
#: Rows: the HCS's X, Y and Z axes in the head frame (see the module notes).
HCS_FROM_HEAD = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
#: The scale of eye nodes, metres per unit of their data: millimetres.
EYE_SCALE = 1e-3
#: A Δφ or microvillar orientation that is not known, in the file (glTF has no NaN).
MISSING = -1.0
#: The mandatory point-ommatidial properties and OCES's defaults for them (§7.4.1).
MANDATORY = {"POSITION": (0.0, 0.0, 0.0), "ORIENTATION": (0.0, 0.0, 1.0), "DIAMETER": (1.0,),
             "FOCAL_OFFSET": (-1.0,)}
#: beeoptics' properties and the receptor table field each holds.
OWN = {"BEEOPTICS_ID": "id", "BEEOPTICS_DELTA_PHI_DEG": "delta_phi_deg", "BEEOPTICS_DORSAL_RIM": "dorsal_rim",
       "BEEOPTICS_MICROVILLI_DEG": "microvilli_deg", "BEEOPTICS_FOCAL_POINT_OFFSET": "focal_offset_mm"}
#: Components per value of each property read: FOCAL_OFFSET is W, or [U, V, W].
WIDTHS = {"POSITION": (3,), "ORIENTATION": (3,), "DIAMETER": (1,), "FOCAL_OFFSET": (1, 3),
          **{key: (1,) for key in OWN}}
#: Mirror-plane normal aliases by HCS axis (mirrorPlane.schema.json). The draft's
#: table (§7.2.1) spells one ANTEROPOSTERIOR, the schema ANTEPOSTERIOR: both are read.
MIRROR_AXES = {alias: axis for axis, aliases in enumerate((
    ("X", "FRONTAL", "LEFT", "RIGHT"),
    ("Y", "TRANSVERSE", "DORSOVENTRAL", "UP", "DOWN"),
    ("Z", "SAGITTAL", "ANTERIOR", "POSTERIOR", "ANTEPOSTERIOR", "ANTEROPOSTERIOR", "FORWARD", "BACKWARD",
     "FRONT", "BACK"),
)) for alias in aliases}
ACCESSOR_TYPES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
#: The largest whole number float32 holds exactly, and so the largest id written.
FLOAT32_WHOLE = 2**24


class OcesWarning(UserWarning):
    """An OCES file that is read, but not as it says: a default or a dropped value."""


def focal_offset_from_acceptance(diameter, delta_rho_deg):
    """OCES's FOCAL_OFFSET W of a lens: W = −(d/2) / tan(Δρ/2) (OCES draft 0.4.0, §4.2.2).

    Parameters
    ----------
    diameter : array_like
        Lens diameter d, any length unit.
    delta_rho_deg : array_like
        Acceptance angle Δρ (full width at half maximum), degrees, in (0, 180).

    Returns
    -------
    ndarray
        W, negative, in the unit of ``diameter``.
    """
    half_angle = np.radians(np.asarray(delta_rho_deg, float)) / 2.0
    return -0.5 * np.asarray(diameter, float) / np.tan(half_angle)


def acceptance_from_focal_offset(diameter, focal_offset):
    """The acceptance angle Δρ = 2 atan((d/2) / |W|), degrees, of a lens of diameter d with FOCAL_OFFSET W.

    The inverse of :func:`focal_offset_from_acceptance`; ``diameter`` and
    ``focal_offset`` in one length unit.
    """
    return np.degrees(2.0 * np.arctan(0.5 * np.asarray(diameter, float) / np.abs(np.asarray(focal_offset, float))))


def write_oces(path, table, *, name="", generator_version=__version__):
    """Write a receptor table as an OCES glTF file, ``.gltf`` or ``.glb`` by its suffix, atomically.

    See the module notes for the layout, frame and units.

    Parameters
    ----------
    path : str or Path
        Ends in ``.gltf`` (JSON, data in a base64 URI) or ``.glb`` (binary).
    table : ReceptorTable
        mm, head frame, degrees, µm.
    name : str
        The head's name; its node is called so ("head" if empty), and its
        eyes "<name> right eye" and "<name> left eye".
    generator_version : str
        The version of beeoptics named as the file's generator.

    Raises
    ------
    ValueError
        If the suffix is neither, the table is empty, or a receptor has a
        side other than right and left, a position or axis that is not
        finite, an axis of zero length, an acceptance angle outside
        (0°, 180°), a facet diameter that is not positive and finite, an id
        that float32 does not hold exactly (beyond ±2²⁴), a negative Δφ or
        a microvillar orientation outside [0°, 180°), or a dorsal-rim flag
        other than 0 and 1.
    """
    path = Path(path)
    binary = _is_glb(path, ValueError)
    sides = _writable(table)
    columns, nodes, eyes = [], [], []
    for k, side in enumerate(s for s in SIDES if sides[s].size):
        rows = sides[side]
        position = table.position[rows]
        centre = (position.min(axis=0) + position.max(axis=0)) / 2.0
        axis = table.axis[rows] / np.linalg.norm(table.axis[rows], axis=1, keepdims=True)
        diameter_mm = np.asarray(table.facet_diameter_um, float)[rows] / 1000.0
        values = {
            "POSITION": (position - centre) @ HCS_FROM_HEAD.T,
            "ORIENTATION": axis @ HCS_FROM_HEAD.T,
            "DIAMETER": diameter_mm,
            "FOCAL_OFFSET": focal_offset_from_acceptance(diameter_mm, np.asarray(table.delta_rho_deg, float)[rows]),
            "BEEOPTICS_ID": np.asarray(table.id)[rows],
        }
        for key, field in OWN.items():
            column = getattr(table, field)
            if key not in values and column is not None:
                column = np.asarray(column, float)[rows]
                values[key] = np.where(np.isnan(column), MISSING, column)
        eye_name = " ".join(filter(None, (name, side, "eye")))
        first = len(columns)
        columns += [(f"{eye_name} {key}", v) for key, v in values.items()]
        eyes.append({"name": eye_name, "type": "POINT_OMMATIDIAL", "enabled": True,
                     "ommatidialProperties": {key: first + j for j, key in enumerate(values)}})
        nodes.append(gltf.Node(name=eye_name, translation=(EYE_SCALE * centre @ HCS_FROM_HEAD.T).tolist(),
                               scale=[EYE_SCALE] * 3, extensions={EXTENSION: {"eye": k}}))
    accessors, views, blob = _layout([v for _, v in columns])
    doc = gltf.GLTF2(
        asset=gltf.Asset(version="2.0", generator=f"beeoptics {generator_version}"),
        extensionsUsed=[EXTENSION],
        scene=0,
        scenes=[gltf.Scene(nodes=[0])],
        nodes=[gltf.Node(name=name or "head", children=list(range(1, len(nodes) + 1)),
                         extensions={EXTENSION: {"head": True}}), *nodes],
        accessors=accessors,
        bufferViews=views,
        buffers=[gltf.Buffer(byteLength=len(blob))],
        extensions={EXTENSION: {
            "version": OCES_VERSION,
            # The draft's text names the generator's "program", its schema "name": both are given.
            "generator": {"name": "beeoptics", "program": "beeoptics", "version": generator_version},
            "creationDatetime": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "extensionsUsed": [SUB_EXTENSION],
            "extensions": {SUB_EXTENSION: {
                "headCoordinateSpace": "+X left, +Y dorsal, +Z anterior (glTF's +X left, +Y up, +Z forward); "
                                       "beeoptics' head frame (x anterior, y left, z dorsal) is (Z, X, Y)",
                "eyeNodeUnits": "mm (eye nodes scale by 0.001 into the head's metres)",
                "missingValue": MISSING,
            }},
            "ommatidialProperties": [{"name": label, "type": "ACCESSOR", "value": j}
                                     for j, (label, _) in enumerate(columns)],
            "eyes": eyes,
        }},
    )
    doc.set_binary_blob(blob)
    with atomic_path(path) as tmp:
        if binary:
            tmp.write_bytes(b"".join(doc.save_to_bytes()))
        else:
            doc.convert_buffers(gltf.BufferFormat.DATAURI)
            tmp.write_text(doc.gltf_to_json(indent=1) + "\n", encoding="utf-8")


def read_oces(path):
    """Read the receptors of an OCES glTF file, ``.gltf`` or ``.glb``.

    See the module notes for what is read and how.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    ReceptorTable
        mm, head frame, unit axes, degrees, µm; checked
        (:func:`~beeoptics.io.receptortable.checked`). Δφ is NaN, and the
        dorsal rim and focal point offset None, unless the file has
        beeoptics' properties.

    Raises
    ------
    InputError
        If the file is missing or not glTF 2.0 JSON or binary glTF; has no
        ``OCES_eyes`` extension, no enabled eye, or eyes of more than one
        head; an eye is of a type other than point-ommatidial, lies outside
        every head or on the head's midline; a reference or number is
        malformed, an accessor is not float32, of the wrong type, or reaches
        past its buffer; a value is not finite, an orientation has zero
        length, a diameter is not positive or a FOCAL_OFFSET W not negative;
        a node's scale is not uniform; or the receptors are unusable
        (:func:`~beeoptics.io.receptortable.checked`).

    Warns
    -----
    OcesWarning
        If an eye lacks a mandatory property, read with OCES's default, or
        has a sheared FOCAL_OFFSET, whose U and V are dropped.
    """
    path = Path(path)
    doc, glb_bin = _load(path)
    version = _object(path, "asset", doc.get("asset")).get("version")
    if not (isinstance(version, str) and version.startswith("2.")):
        raise InputError(path, "asset.version", f"is {version!r}; OCES extends glTF 2.0")
    oces = _object(path, f"extensions.{EXTENSION}", _object(path, "extensions", doc.get("extensions")).get(EXTENSION))
    if not isinstance(oces.get("version"), str):
        raise InputError(path, f"extensions.{EXTENSION}.version", "missing: OCES files name the draft they follow")
    if not oces["version"].startswith(OCES_VERSION.rsplit(".", 1)[0] + "."):
        warnings.warn(f"{path}: follows OCES {oces['version']}; read as OCES {OCES_VERSION}", OcesWarning,
                      stacklevel=2)
    nodes = _list(path, "nodes", doc.get("nodes", []))
    parents = _parents(path, nodes)
    cache = {}
    instances, heads = [], set()
    for index, node in enumerate(nodes):
        ext = _node_extension(path, node, index)
        if "eye" not in ext:
            continue
        chain, above = _head(path, nodes, parents, index)
        head = above[0]
        head_ext = _node_extension(path, nodes[head], head)
        if not (_flag(path, f"nodes.{index}.extensions.{EXTENSION}.enabled", ext)
                and _flag(path, f"nodes.{head}.extensions.{EXTENSION}.enabled", head_ext)):
            continue
        found = _eye(path, doc, oces, ext, index, [_node_matrix(path, nodes, i) for i in chain], cache, glb_bin)
        if found is not None:
            heads.add(head)
            metres = np.prod([_scale(_node_matrix(path, nodes, i)) for i in above])
            instances += _mirrored(path, oces, found, metres)
    if not instances:
        raise InputError(path, "eyes", "no enabled point-ommatidial eye is attached to a node of the scene")
    if len(heads) > 1:
        raise InputError(path, "nodes", f"eyes belong to {len(heads)} heads (nodes {sorted(heads)}); "
                                        "a receptor table holds the eyes of one head")
    return checked(_table(path, instances), path)


# --- Writing ------------------------------------------------------------------------------


def _writable(table):
    """The rows of each side, once the table is found writable (see :func:`write_oces`)."""
    ids = np.asarray(table.id)
    if ids.size == 0:
        raise ValueError("the receptor table is empty")
    side = np.asarray(table.side).astype(str)
    length = np.linalg.norm(table.axis, axis=1)
    drho = np.asarray(table.delta_rho_deg, float)
    diameter = np.asarray(table.facet_diameter_um, float)
    dphi = np.asarray(table.delta_phi_deg, float)
    checks = [
        ("side", ~np.isin(side, SIDES), f"is not one of {', '.join(SIDES)}"),
        ("position", ~np.isfinite(table.position).all(1), "is not finite"),
        ("axis", ~np.isfinite(table.axis).all(1) | (length == 0.0), "is not finite or has zero length"),
        ("delta_rho_deg", ~((drho > 0.0) & (drho < 180.0)), "is not in (0, 180) degrees"),
        ("facet_diameter_um", ~(np.isfinite(diameter) & (diameter > 0.0)),
         "is not positive and finite, and OCES requires DIAMETER "
         "(beeoptics.eye.receptors.measure_spacing(..., facet_diameter_um=True) measures it)"),
        ("id", (ids.dtype.kind not in "iu") | (np.abs(ids.astype(float)) > FLOAT32_WHOLE),
         "is not a whole number within ±2^24, which float32 holds exactly"),
        ("delta_phi_deg", ~(np.isnan(dphi) | ((dphi >= 0.0) & np.isfinite(dphi))), "is negative or infinite"),
    ]
    if table.dorsal_rim is not None:
        micro = np.asarray(table.microvilli_deg, float)
        checks += [("dorsal_rim", ~np.isin(np.asarray(table.dorsal_rim, float), (0.0, 1.0)), "is not 0 or 1"),
                   ("microvilli_deg", ~(np.isnan(micro) | ((micro >= 0.0) & (micro < 180.0))),
                    "is not in [0, 180) degrees")]
    if table.focal_offset_mm is not None:
        checks.append(("focal_offset_mm", ~np.isfinite(np.asarray(table.focal_offset_mm, float)), "is not finite"))
    for column, bad, message in checks:
        bad = np.broadcast_to(bad, ids.shape)
        if bad.any():
            raise ValueError(f"{column} of receptor {ids[np.argmax(bad)]} {message}")
    return {s: np.flatnonzero(side == s) for s in SIDES}


def _layout(arrays):
    """Accessors, buffer views and the buffer's bytes for float32 columns, one view each."""
    accessors, views, blob = [], [], bytearray()
    for values in arrays:
        data = np.ascontiguousarray(values, "<f4")
        views.append(gltf.BufferView(buffer=0, byteOffset=len(blob), byteLength=data.nbytes))
        accessors.append(gltf.Accessor(bufferView=len(views) - 1, componentType=gltf.FLOAT, count=len(data),
                                       type=gltf.VEC3 if data.ndim == 2 else gltf.SCALAR))
        blob += data.tobytes()
    return accessors, views, bytes(blob)


def _is_glb(path, error):
    """True for a ``.glb``, False for a ``.gltf``; otherwise raise ``error``."""
    suffix = path.suffix.lower()
    if suffix not in (".gltf", ".glb"):
        message = "an OCES file ends in .gltf (JSON) or .glb (binary glTF)"
        raise error(path, "", message) if error is InputError else error(f"{path}: {message}")
    return suffix == ".glb"


# --- Reading: the container ---------------------------------------------------------------


def _load(path):
    """The glTF JSON of a file and, for a ``.glb``, its BIN chunk (else None)."""
    binary = _is_glb(path, InputError)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise InputError(path, "", "no such file") from None
    text, chunk = _glb_chunks(path, data) if binary else (data, None)
    try:
        doc = json.loads(text.decode("utf-8"), parse_constant=_no_constant)
    except UnicodeDecodeError:
        raise InputError(path, "", "its JSON is not UTF-8 text") from None
    except ValueError as e:
        raise InputError(path, "", f"not valid JSON ({e})") from None
    return _object(path, "", doc), chunk


def _no_constant(name):
    # Python's json reads NaN and Infinity, which JSON does not have.
    raise ValueError(f"{name} is not a JSON number")


def _glb_chunks(path, data):
    """The JSON chunk and the BIN chunk (or None) of binary glTF (glTF 2.0 §4)."""
    if len(data) < 12:
        raise InputError(path, "", "too short for a binary glTF header")
    magic, version, length = struct.unpack_from("<4sII", data)
    if magic != gltf.MAGIC:
        raise InputError(path, "", "not binary glTF: it does not start with 'glTF'")
    if version != gltf.GLTF_VERSION:
        raise InputError(path, "", f"binary glTF version {version}; glTF 2.0 files are version 2")
    if length != len(data):
        raise InputError(path, "", f"its header gives {length} bytes, but it has {len(data)}: cut off or padded")
    chunks, offset = [], 12
    while offset < length:
        if offset + 8 > length:
            raise InputError(path, "", f"the chunk header at byte {offset} is cut off")
        size, kind = struct.unpack_from("<I4s", data, offset)
        if offset + 8 + size > length:
            raise InputError(path, "", f"the chunk at byte {offset} runs past the end of the file")
        chunks.append((kind, data[offset + 8:offset + 8 + size]))
        offset += 8 + size
    if not chunks or chunks[0][0] != gltf.JSON.encode():
        raise InputError(path, "", "binary glTF's first chunk must be its JSON")
    return chunks[0][1], chunks[1][1] if len(chunks) > 1 and chunks[1][0] == gltf.BIN.encode() else None


def _buffer(path, doc, glb_bin, index, field, cache):
    """The bytes of buffer ``index`` (a data URI, a file beside this one, or the .glb's BIN chunk)."""
    if index in cache:
        return cache[index]
    where = f"buffers.{index}"
    buffer = _object(path, where, _item(path, field, index, _list(path, "buffers", doc.get("buffers")), "buffers"))
    length = _whole(path, f"{where}.byteLength", buffer.get("byteLength"), 1)
    uri = buffer.get("uri")
    if uri is None:
        if index != 0 or glb_bin is None:
            raise InputError(path, f"{where}.uri", "missing; only a .glb's first buffer, its BIN chunk, has none")
        data = glb_bin
    elif not isinstance(uri, str):
        raise InputError(path, f"{where}.uri", "must be a string")
    elif uri.startswith("data:"):
        header, comma, payload = uri.partition(",")
        if not (comma and header.endswith(";base64")):
            raise InputError(path, f"{where}.uri", "a data URI of a buffer must be base64 (data:…;base64,…)")
        try:
            data = base64.b64decode(payload, validate=True)
        except binascii.Error:
            raise InputError(path, f"{where}.uri", "is not valid base64") from None
    elif ":" in uri.split("/", 1)[0]:
        raise InputError(path, f"{where}.uri", f"{uri[:40]!r}: only data URIs and paths relative to the file are read")
    else:
        file = path.parent / unquote(uri)
        try:
            data = file.read_bytes()
        except OSError as e:
            raise InputError(path, f"{where}.uri", f"cannot read {file} ({e.strerror})") from None
    if len(data) < length:
        raise InputError(path, where, f"holds {len(data)} bytes, fewer than its byteLength {length}")
    cache[index] = data
    return data


def _accessor(path, doc, glb_bin, index, field, key, cache):
    """The values (count, components) of accessor ``index``, float64, for property ``key`` at ``field``."""
    acc = _object(path, field, _item(path, field, index, _list(path, "accessors", doc.get("accessors")), "accessors"))
    at = f"accessor {index}"
    if acc.get("componentType") != gltf.FLOAT:
        raise InputError(path, field, f"{at} has componentType {acc.get('componentType')!r}; "
                                      f"{key} is read as float32 ({gltf.FLOAT})")
    width = ACCESSOR_TYPES.get(acc.get("type"))
    if width not in WIDTHS[key]:
        wanted = " or ".join("SCALAR" if w == 1 else f"VEC{w}" for w in WIDTHS[key])
        raise InputError(path, field, f"{at} is {acc.get('type')!r}; {key} is {wanted}")
    if "sparse" in acc:
        raise InputError(path, field, f"{at} is sparse; sparse accessors are not read")
    count = _whole(path, field, acc.get("count"), 1, f"{at}: count")
    if "bufferView" not in acc:
        # glTF 2.0 (accessor.bufferView): an accessor without a buffer view is all zeros.
        return np.zeros((count, width))
    view_index = acc["bufferView"]
    view = _object(path, field, _item(path, field, view_index, _list(path, "bufferViews", doc.get("bufferViews")),
                                      "buffer views"))
    at += f" (bufferView {view_index})"
    view_offset = _whole(path, field, view.get("byteOffset", 0), 0, f"{at}: byteOffset")
    view_length = _whole(path, field, view.get("byteLength"), 1, f"{at}: byteLength")
    stride = _whole(path, field, view.get("byteStride", 4 * width), 4 * width, f"{at}: byteStride")
    data = _buffer(path, doc, glb_bin, view.get("buffer"), field, cache)
    if view_offset + view_length > len(data):
        raise InputError(path, field, f"{at} reaches byte {view_offset + view_length} of buffer "
                                      f"{view.get('buffer')}, which has {len(data)}")
    offset = _whole(path, field, acc.get("byteOffset", 0), 0, f"{at}: byteOffset")
    end = offset + stride * (count - 1) + 4 * width
    if end > view_length:
        raise InputError(path, field, f"{at} needs {end} bytes of its buffer view, which has {view_length}")
    return np.ndarray((count, width), "<f4", buffer=data, offset=view_offset + offset,
                      strides=(stride, 4)).astype(float)


# --- Reading: the scene graph -------------------------------------------------------------


def _parents(path, nodes):
    """Each node's parent (-1 for roots); glTF nodes form trees (glTF 2.0 §3.5.2)."""
    parents = np.full(len(nodes), -1)
    for index, node in enumerate(nodes):
        field = f"nodes.{index}.children"
        for child in _list(path, field, _object(path, f"nodes.{index}", node).get("children", [])):
            _item(path, field, child, nodes, "nodes")
            if parents[child] != -1:
                raise InputError(path, field, f"node {child} has two parents; glTF nodes form trees")
            parents[child] = index
    return parents


def _head(path, nodes, parents, index):
    """For eye node ``index``: the nodes below its head down to it, and the head and the nodes above it.

    The first list's transforms, in its order, take the eye's coordinates into
    the head's (HCS); the second's set the size of an HCS unit in the scene.
    """
    line = [index]
    while parents[line[-1]] != -1:
        line.append(parents[line[-1]])
        if len(line) > len(nodes):
            raise InputError(path, f"nodes.{index}", "is its own ancestor; glTF nodes form trees")
    for k, node in enumerate(line):
        if _node_extension(path, nodes[node], node).get("head") is True:
            return line[:k][::-1], line[k:]
    raise InputError(path, f"nodes.{index}", "is an eye outside every head; OCES eyes are descendants "
                                             "of a head node (§7.1), whose frame they are given in")


def _node_extension(path, node, index):
    ext = _object(path, f"nodes.{index}", node).get("extensions", {})
    found = _object(path, f"nodes.{index}.extensions", ext).get(EXTENSION, {})
    return _object(path, f"nodes.{index}.extensions.{EXTENSION}", found)


def _node_matrix(path, nodes, index):
    """A node's local transform (4, 4), once found a similarity (glTF 2.0 §3.5.3)."""
    node, field = nodes[index], f"nodes.{index}"
    if "matrix" in node:
        if any(key in node for key in ("translation", "rotation", "scale")):
            raise InputError(path, f"{field}.matrix", "is given with translation, rotation or scale; "
                                                      "glTF nodes have one or the other")
        field += ".matrix"
        matrix = _numbers(path, field, node["matrix"], 16).reshape(4, 4).T  # column-major
        if not np.array_equal(matrix[3], [0.0, 0.0, 0.0, 1.0]):
            raise InputError(path, field, "is not affine: its last row must be 0, 0, 0, 1")
    else:
        quaternion = _numbers(path, f"{field}.rotation", node.get("rotation", [0.0, 0.0, 0.0, 1.0]), 4)
        # Hand-written files round unit quaternions to a few digits.
        if abs(np.linalg.norm(quaternion) - 1.0) > 1e-3:
            raise InputError(path, f"{field}.rotation", "is not a unit quaternion (x, y, z, w)")
        matrix = np.eye(4)
        matrix[:3, :3] = Rotation.from_quat(quaternion).as_matrix() * _numbers(
            path, f"{field}.scale", node.get("scale", [1.0, 1.0, 1.0]), 3)
        matrix[:3, 3] = _numbers(path, f"{field}.translation", node.get("translation", [0.0, 0.0, 0.0]), 3)
        field += ".scale"
    linear = matrix[:3, :3]
    gram = linear.T @ linear
    square = np.trace(gram) / 3.0
    if not (square > 0.0 and np.allclose(gram, square * np.eye(3), rtol=0.0, atol=1e-6 * square)):
        raise InputError(path, field, "does not scale uniformly; DIAMETER and FOCAL_OFFSET are lengths, "
                                      "which only a uniform scale keeps")
    return matrix


def _scale(matrix):
    """The scale factor of a similarity transform (4, 4)."""
    return float(np.sqrt(np.trace(matrix[:3, :3].T @ matrix[:3, :3]) / 3.0))


# --- Reading: eyes ------------------------------------------------------------------------


def _eye(path, doc, oces, ext, node_index, matrices, cache, glb_bin):
    """An enabled point-ommatidial eye in its head's HCS, as a dict of arrays, or None if disabled.

    ``matrices`` are the transforms from the head down to the eye node.
    """
    eyes = _list(path, "eyes", oces.get("eyes"))
    index = ext["eye"]
    field = f"eyes.{index}"
    eye = _object(path, field, _item(path, f"nodes.{node_index}.extensions.{EXTENSION}.eye", index, eyes, "eyes"))
    kind = eye.get("type")
    if kind in ("SURFACE", "SPHERICAL"):
        raise InputError(path, f"{field}.type", f"is {kind}: such eyes describe how ommatidia are distributed, "
                                                "but a receptor table needs each ommatidium; convert the eye "
                                                "to POINT_OMMATIDIAL")
    if kind != "POINT_OMMATIDIAL":
        raise InputError(path, f"{field}.type", f"{kind!r} is not an OCES eye type")
    if not _flag(path, f"{field}.enabled", eye):
        return None
    listed = _object(path, f"{field}.ommatidialProperties", eye.get("ommatidialProperties", {}))
    values, count = {}, None
    for key in (*MANDATORY, *OWN):
        if key not in listed:
            continue
        found, each = _property(path, doc, oces, f"{field}.ommatidialProperties.{key}", listed[key], key, cache,
                                glb_bin)
        if each:
            if count is not None and len(found) != count:
                raise InputError(path, f"{field}.ommatidialProperties.{key}",
                                 f"has {len(found)} values, but the eye's other properties {count}")
            count = len(found)
        values[key] = found
    if count is None:
        raise InputError(path, f"{field}.ommatidialProperties",
                         "has no ACCESSOR property, so the eye has no number of ommatidia")
    unused = sorted(set(listed) - set(values))
    if unused:
        log.info("%s: %s: ommatidial properties %s are not read", path, field, ", ".join(unused))
    missing = [key for key in MANDATORY if key not in values]
    if missing:
        warnings.warn(f"{path}: {field}.ommatidialProperties: lacks mandatory {', '.join(missing)}; "
                      "read with OCES's defaults (POSITION [0, 0, 0], ORIENTATION [0, 0, 1], DIAMETER 1, "
                      "FOCAL_OFFSET -1)", OcesWarning, stacklevel=3)
    for key, default in MANDATORY.items():
        values.setdefault(key, np.array([default]))
    values = {key: np.broadcast_to(v, (count, v.shape[1])) for key, v in values.items()}
    # The schema lists an eye's mirror planes in its eye object, the draft's examples in its node's extension.
    planes = [(where, plane) for where, owner in ((f"{field}.mirrorPlanes", eye),
                                                  (f"nodes.{node_index}.extensions.{EXTENSION}.mirrorPlanes", ext))
              for plane in _list(path, where, owner.get("mirrorPlanes", []))]
    return dict(_placed(path, field, values, functools.reduce(np.matmul, matrices, np.eye(4))), planes=planes)


def _property(path, doc, oces, field, index, key, cache, glb_bin):
    """One ommatidial property: its values (m, k) and whether they are per ommatidium (else m = 1)."""
    props = _list(path, "ommatidialProperties", oces.get("ommatidialProperties"))
    prop = _object(path, field, _item(path, field, index, props, "ommatidial properties"))
    kind, value = prop.get("type"), prop.get("value")
    if kind == "ACCESSOR":
        if prop.get("dataStride", 1) != 1:
            raise InputError(path, field, f"ommatidial property {index} has dataStride {prop['dataStride']!r}; "
                                          f"{key} has one value per ommatidium")
        return _accessor(path, doc, glb_bin, value, field, key, cache), True
    if kind == "COARSE":
        numbers = [value] if _is_number(value) else value
        if not (isinstance(numbers, list) and len(numbers) in WIDTHS[key] and all(map(_is_number, numbers))):
            raise InputError(path, field, f"ommatidial property {index}: the COARSE value {value!r} is not "
                                          f"{' or '.join(map(str, WIDTHS[key]))} numbers")
        return np.array(numbers, float)[None, :], False
    if kind == "TEXTURE":
        raise InputError(path, field, f"ommatidial property {index} is a TEXTURE; point-ommatidial eyes take "
                                      "ACCESSOR or COARSE properties (§7.4.1)")
    raise InputError(path, field, f"ommatidial property {index}: type {kind!r} is not ACCESSOR, COARSE or TEXTURE")


def _placed(path, field, values, transform):
    """An eye's ommatidia in its head's HCS, once found usable: positions, unit axes, lengths in HCS units.

    ``values`` are the eye's properties (n, k); ``transform`` (4, 4) takes
    the eye node's coordinates into the HCS.
    """
    for key, v in values.items():
        bad = ~np.isfinite(v).all(1)
        _refuse(path, f"{field}.ommatidialProperties.{key}", bad, "is not finite")
    orientation, diameter = values["ORIENTATION"], values["DIAMETER"][:, 0]
    focal = values["FOCAL_OFFSET"]
    props = f"{field}.ommatidialProperties"
    _refuse(path, f"{props}.ORIENTATION", ~np.any(orientation != 0.0, axis=1),
            "has zero length; an ommatidium needs an axis")
    _refuse(path, f"{props}.DIAMETER", diameter <= 0.0, "is not positive")
    _refuse(path, f"{props}.FOCAL_OFFSET", focal[:, -1] >= 0.0,
            "has a W that is not negative; OCES puts the cone's apex behind the lens (W < 0, §7.4.1)")
    if focal.shape[1] == 3 and np.any(focal[:, :2] != 0.0):
        warnings.warn(f"{path}: {props}.FOCAL_OFFSET: the sampling cones' U, V shear is dropped; "
                      "a receptor's acceptance cone lies on its axis", OcesWarning, stacklevel=4)
    linear = transform[:3, :3]
    axis = orientation @ linear.T
    scale = _scale(transform)
    out = {
        "position": values["POSITION"] @ linear.T + transform[:3, 3],
        "axis": axis / np.linalg.norm(axis, axis=1, keepdims=True),
        "diameter": scale * diameter,
        "delta_rho_deg": acceptance_from_focal_offset(diameter, focal[:, -1]),
        "field": field,
    }
    for key, name in OWN.items():
        if key in values:
            column = values[key][:, 0]
            if name in ("delta_phi_deg", "microvilli_deg"):
                column = np.where(column == MISSING, np.nan, column)
            out[name] = scale * column if name == "focal_offset_mm" else column
    if "id" in out:
        _refuse(path, f"{props}.BEEOPTICS_ID", out["id"] != np.round(out["id"]), "is not a whole number")
    if "dorsal_rim" in out:
        _refuse(path, f"{props}.BEEOPTICS_DORSAL_RIM", ~np.isin(out["dorsal_rim"], (0.0, 1.0)), "is not 0 or 1")
    return out


def _mirrored(path, oces, eye, metres):
    """The eye and a copy of it mirrored across each of its mirror planes, in the head frame (mm, µm).

    ``metres`` is the size of an HCS unit.
    """
    copies = [dict(eye, mirrored=False)]
    for field, index in eye["planes"]:
        origin, normal = _mirror_plane(path, oces, field, index)
        reflect = np.eye(3) - 2.0 * np.outer(normal, normal)
        copies.append(dict(eye, mirrored=True, position=(eye["position"] - origin) @ reflect + origin,
                           axis=eye["axis"] @ reflect))
    mm = 1000.0 * metres
    return [dict(c, position=mm * c["position"] @ HCS_FROM_HEAD, axis=c["axis"] @ HCS_FROM_HEAD,
                 facet_diameter_um=1000.0 * mm * c["diameter"],
                 **({"focal_offset_mm": mm * c["focal_offset_mm"]} if "focal_offset_mm" in c else {}))
            for c in copies]


def _mirror_plane(path, oces, field, index):
    """A mirror plane's point and unit normal in the HCS (mirrorPlane.schema.json)."""
    plane = _object(path, field, _item(path, field, index, _list(path, "mirrorPlanes", oces.get("mirrorPlanes")),
                                       "mirror planes"))
    where = f"mirrorPlanes.{index}"
    origin = _numbers(path, f"{where}.position", plane.get("position", [0.0, 0.0, 0.0]), 3)
    normal = plane.get("normal", [1.0, 0.0, 0.0])
    if isinstance(normal, str):
        if normal not in MIRROR_AXES:
            raise InputError(path, f"{where}.normal", f"{normal!r} is not an axis alias "
                                                      f"({', '.join(MIRROR_AXES)})")
        return origin, np.eye(3)[MIRROR_AXES[normal]]
    normal = _numbers(path, f"{where}.normal", normal, 3)
    if not np.any(normal != 0.0):
        raise InputError(path, f"{where}.normal", "has zero length")
    return origin, normal / np.linalg.norm(normal)


def _table(path, instances):
    """The receptor table of the eyes read, each given its side."""
    for eye in instances:
        y = eye["position"][:, 1].mean()
        key = y if y != 0.0 else eye["axis"][:, 1].mean()
        if key == 0.0:
            raise InputError(path, eye["field"], "lies on the head's midline facing neither side, so it is "
                                                 "neither the right nor the left eye")
        eye["side"] = SIDES[0] if key < 0.0 else SIDES[1]
    file_ids = all("id" in e and not e["mirrored"] for e in instances)
    if not file_ids:
        # Right eyes first, as receptor tables have them; each keeps its file order.
        instances = sorted(instances, key=lambda e: SIDES.index(e["side"]))
    n = [len(e["position"]) for e in instances]

    def column(name, fill):
        return np.concatenate([e.get(name, np.full(k, fill)) for e, k in zip(instances, n)])

    rim = any("dorsal_rim" in e for e in instances)
    focal = any("focal_offset_mm" in e for e in instances)
    table = ReceptorTable(
        id=column("id", 0).astype(np.int64) if file_ids else np.arange(sum(n)),
        side=np.repeat([e["side"] for e in instances], n),
        position=np.concatenate([e["position"] for e in instances]),
        axis=np.concatenate([e["axis"] for e in instances]),
        facet_diameter_um=column("facet_diameter_um", np.nan),
        delta_phi_deg=column("delta_phi_deg", np.nan),
        delta_rho_deg=column("delta_rho_deg", np.nan),
        # An eye without beeoptics' columns has no dorsal rim area, and CompoundRay's offset 0.
        focal_offset_mm=column("focal_offset_mm", 0.0) if focal else None,
        dorsal_rim=column("dorsal_rim", 0.0).astype(int) if rim else None,
        microvilli_deg=column("microvilli_deg", np.nan) if rim else None,
    )
    if file_ids:
        order = np.argsort(table.id, kind="stable")
        table = ReceptorTable(*(None if v is None else v[order] for v in table))
    return table


# --- Reading: JSON values -----------------------------------------------------------------


def _refuse(path, field, bad, message):
    """Raise an InputError for the first ommatidium flagged in ``bad``."""
    if np.any(bad):
        raise InputError(path, field, f"ommatidium {np.argmax(bad)}: {message}")


def _object(path, field, value):
    if not isinstance(value, dict):
        raise InputError(path, field, "missing" if value is None else "must be a JSON object")
    return value


def _list(path, field, value):
    if not isinstance(value, list):
        raise InputError(path, field, "missing" if value is None else "must be a JSON array")
    return value


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _whole(path, field, value, minimum, what=""):
    """``value``, once found a whole number ≥ ``minimum``; ``what`` says which, within ``field``."""
    if not (isinstance(value, int) and not isinstance(value, bool) and value >= minimum):
        raise InputError(path, field, f"{what + ' ' if what else ''}{value!r} is not a whole number ≥ {minimum}")
    return value


def _item(path, field, index, items, what):
    """``items[index]``, once ``index`` is found to be one of its indices (a glTF id)."""
    if not (isinstance(index, int) and not isinstance(index, bool) and 0 <= index < len(items)):
        raise InputError(path, field, f"{index!r} is not the index of one of the file's {len(items)} {what}")
    return items[index]


def _numbers(path, field, value, length):
    """``value`` as an array, once found a list of ``length`` finite numbers."""
    if not (isinstance(value, list) and len(value) == length and all(map(_is_number, value))):
        raise InputError(path, field, f"must be {length} numbers")
    out = np.array(value, float)
    if not np.isfinite(out).all():
        raise InputError(path, field, "is not finite")
    return out


def _flag(path, field, obj):
    """The ``enabled`` flag of an OCES object (default true)."""
    value = obj.get("enabled", True)
    if not isinstance(value, bool):
        raise InputError(path, field, "must be true or false")
    return value
