"""OCES glTF files of receptor tables (beeoptics.io.oces)."""

import base64
import json
import re
import struct
from datetime import datetime

import numpy as np
import pytest
from jsonschema import Draft202012Validator
from referencing import Registry, Resource
from referencing.jsonschema import DRAFT202012

from beeoptics.headframe import mirror
from beeoptics.io.errors import InputError
from beeoptics.io.oces import (
    HCS_FROM_HEAD,
    OcesWarning,
    acceptance_from_focal_offset,
    focal_offset_from_acceptance,
    read_oces,
    write_oces,
)
from beeoptics.io.receptortable import ReceptorTable

MANDATORY = ("POSITION", "ORIENTATION", "DIAMETER", "FOCAL_OFFSET")


def receptor_table(n=400, focal=False):
    """Both eyes of a synthetic bee: axes on a lateral hemisphere, a dorsal rim area, some Δφ unknown."""
    k = np.arange(n)
    # A Fibonacci lattice on the hemisphere around local +z, turned to face -y, the right eye's lateral.
    z = 1.0 - (k + 0.5) / n
    turn = np.pi * (3.0 - np.sqrt(5.0)) * k
    local = np.column_stack([np.sqrt(1.0 - z**2) * np.cos(turn), np.sqrt(1.0 - z**2) * np.sin(turn), z])
    axes = local @ np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]).T
    points = 1.2 * axes + np.array([0.3, -1.1, 0.4])
    rng = np.random.default_rng(3)
    rim = (axes[:, 2] > 0.6).astype(int)
    dphi = np.where(k % 11 == 0, np.nan, rng.uniform(1.0, 3.0, n))
    return ReceptorTable(
        # Ids that are not 0 … n−1, to show that they are the file's.
        id=7 + 3 * np.arange(2 * n), side=np.repeat(np.array(["right", "left"]), n),
        position=np.vstack([points, mirror(points)]), axis=np.vstack([axes, mirror(axes)]),
        facet_diameter_um=np.tile(rng.uniform(15.0, 25.0, n), 2), delta_phi_deg=np.tile(dphi, 2),
        delta_rho_deg=np.tile(rng.uniform(1.5, 3.0, n), 2),
        focal_offset_mm=np.tile(rng.uniform(0.0, 0.05, n), 2) if focal else None,
        dorsal_rim=np.tile(rim, 2), microvilli_deg=np.tile(np.where(rim == 1, rng.uniform(0.0, 180.0, n), np.nan), 2),
    )


@pytest.fixture(scope="module")
def table():
    return receptor_table()


def select(table, keep):
    return ReceptorTable(*(None if v is None else np.asarray(v)[keep] for v in table))


def assert_same_table(got, want):
    # float32 keeps 7 significant digits: positions to 1e-6 mm, axes to 1e-6, the rest relatively.
    np.testing.assert_allclose(got.position, want.position, rtol=0, atol=1e-6)
    np.testing.assert_allclose(got.axis, want.axis, rtol=0, atol=1e-6)
    np.testing.assert_array_equal(got.id, want.id)
    np.testing.assert_array_equal(got.side, want.side)
    for name in ("facet_diameter_um", "delta_phi_deg", "delta_rho_deg", "microvilli_deg", "focal_offset_mm"):
        if getattr(want, name) is None:
            assert getattr(got, name) is None, name
        else:
            # NaN where the table has NaN (assert_allclose takes NaN as equal to NaN, and only to NaN).
            np.testing.assert_allclose(getattr(got, name), getattr(want, name), rtol=1e-6, atol=1e-9, err_msg=name)
    np.testing.assert_array_equal(got.dorsal_rim, want.dorsal_rim)


def load(path):
    return json.loads(path.read_text())


def save(path, doc):
    path.write_text(json.dumps(doc))
    return path


def written(tmp_path, table, name="bee.gltf"):
    """A .gltf of ``table`` and its JSON."""
    path = tmp_path / name
    write_oces(path, table)
    return path, load(path)


def extension(doc):
    return doc["extensions"]["OCES_eyes"]


def accessor_of(doc, eye, key):
    oces = extension(doc)
    return oces["ommatidialProperties"][oces["eyes"][eye]["ommatidialProperties"][key]]["value"]


def raw(doc, eye, key):
    """The float32 values of an eye's ACCESSOR property in a .gltf's data URI buffer."""
    acc = doc["accessors"][accessor_of(doc, eye, key)]
    view = doc["bufferViews"][acc["bufferView"]]
    blob = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1])
    width = 3 if acc["type"] == "VEC3" else 1
    return np.frombuffer(blob, "<f4", acc["count"] * width, view["byteOffset"]).reshape(acc["count"], width)


def patch(doc, eye, key, row, values):
    """Set one ommatidium's values of an eye's ACCESSOR property in a .gltf's data URI buffer."""
    acc = doc["accessors"][accessor_of(doc, eye, key)]
    width = 3 if acc["type"] == "VEC3" else 1
    header, data = doc["buffers"][0]["uri"].split(",", 1)
    blob = bytearray(base64.b64decode(data))
    start = doc["bufferViews"][acc["bufferView"]]["byteOffset"] + 4 * width * row
    blob[start:start + 4 * width] = np.asarray(values, "<f4").tobytes()
    doc["buffers"][0]["uri"] = f"{header},{base64.b64encode(bytes(blob)).decode()}"


def coarse(doc, eye, key, value):
    """Make an eye's property a COARSE value, as other tools may write it."""
    oces = extension(doc)
    oces["ommatidialProperties"].append({"type": "COARSE", "value": value})
    oces["eyes"][eye]["ommatidialProperties"][key] = len(oces["ommatidialProperties"]) - 1


# --- Round trip and layout ---------------------------------------------------------------


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
@pytest.mark.parametrize("focal", [False, True])
def test_round_trip_keeps_every_column(tmp_path, suffix, focal):
    want = receptor_table(focal=focal)
    path = tmp_path / f"bee{suffix}"
    write_oces(path, want, name="bee")
    assert_same_table(read_oces(path), want)


def test_rows_come_back_in_order_of_id(tmp_path, table):
    # Eyes are written one after the other; a table whose rows alternate between them reads back as it was.
    n = len(table.id) // 2
    alternating = select(table, np.column_stack([np.arange(n), n + np.arange(n)]).ravel())._replace(id=np.arange(2 * n))
    path = tmp_path / "bee.gltf"
    write_oces(path, alternating)
    assert_same_table(read_oces(path), alternating)


def test_gltf_layout_frame_and_units(tmp_path, table):
    path, doc = written(tmp_path, table)
    head, right, left = doc["nodes"]
    assert head["extensions"]["OCES_eyes"] == {"head": True} and head["children"] == [1, 2]
    assert doc["scenes"][doc["scene"]]["nodes"] == [0] and "OCES_eyes" in doc["extensionsUsed"]
    assert doc["buffers"][0]["uri"].startswith("data:application/octet-stream;base64,")
    datetime.fromisoformat(extension(doc)["creationDatetime"])
    mine = table.side == "right"
    for node, eye, rows in ((right, 0, mine), (left, 1, ~mine)):
        assert node["extensions"]["OCES_eyes"] == {"eye": eye} and node["scale"] == [0.001] * 3
        assert extension(doc)["eyes"][eye]["type"] == "POINT_OMMATIDIAL"
        assert [doc["accessors"][accessor_of(doc, eye, k)]["componentType"] for k in MANDATORY] == [5126] * 4
        # Positions in mm about the eye's centre; the node takes them into the head's metres,
        # whose axes are +X left, +Y dorsal, +Z anterior.
        position = 0.001 * raw(doc, eye, "POSITION") + node["translation"]
        np.testing.assert_allclose(position, 0.001 * table.position[rows][:, [1, 2, 0]], atol=1e-9)
        np.testing.assert_allclose(np.ptp(raw(doc, eye, "POSITION"), axis=0) / 2,
                                   np.abs(raw(doc, eye, "POSITION")).max(axis=0), rtol=1e-6)
        np.testing.assert_allclose(raw(doc, eye, "ORIENTATION"), table.axis[rows][:, [1, 2, 0]], atol=1e-7)
        np.testing.assert_allclose(raw(doc, eye, "DIAMETER")[:, 0], table.facet_diameter_um[rows] / 1000, rtol=1e-7)
    np.testing.assert_array_equal(HCS_FROM_HEAD @ [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])


def test_glb_is_a_binary_gltf_container(tmp_path, table):
    path = tmp_path / "bee.glb"
    write_oces(path, table)
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON" and json_length % 4 == 0
    doc = json.loads(data[20:20 + json_length])
    bin_length, bin_type = struct.unpack_from("<I4s", data, 20 + json_length)
    assert bin_type == b"BIN\0" and 28 + json_length + bin_length == len(data)
    assert "uri" not in doc["buffers"][0] and doc["buffers"][0]["byteLength"] <= bin_length


def test_a_table_that_cannot_be_written_leaves_no_file(tmp_path, table):
    bad = table._replace(facet_diameter_um=np.where(table.id == 10, np.nan, table.facet_diameter_um))
    with pytest.raises(ValueError, match="facet_diameter_um of receptor 10 .*measure_spacing"):
        write_oces(tmp_path / "bee.gltf", bad)
    with pytest.raises(ValueError, match=r"\.gltf"):
        write_oces(tmp_path / "bee.json", table)
    assert list(tmp_path.iterdir()) == []


# --- The draft's JSON schemas ------------------------------------------------------------

# The draft's schemas, as shipped, are not valid JSON, and $ref glTF's base schemas without
# shipping them. Repaired here, minimally:
#  - "$comment": "…" written as bare key-value pairs inside arrays (eye.schema.json,
#    eye.shared.schema.json, ommatidialProperty.schema.json, node.OCES_eyes.schema.json) are
#    dropped. By JSON's grammar only an array element can follow "[" or precede "]" after a
#    comma, or be followed by ", {": the regex removes only those.
#  - node.OCES_eyes.schema.json puts "oneOf": [ "head": {…}, "eye": {…} ] inside "properties";
#    its members become properties and the exclusive choice the oneOf meant a top-level
#    oneOf of {"required": ["head"]} and {"required": ["eye"]}.
#  - glTFid, glTFProperty and glTFChildOfRootProperty get minimal stand-ins, registered, like
#    every schema, under its file name, which is how the $refs name them (their $ids differ).
# Nothing else is changed; defects our documents never reach (the texture schema's "type"
# holding a schema) are left as shipped.
STRAY_COMMENT = re.compile(r'(?<=\[)\s*"\$comment"\s*:\s*"[^"]*"\s*,'
                           r'|"\$comment"\s*:\s*"[^"]*"\s*,(?=\s*[\[{])'
                           r'|,\s*"\$comment"\s*:\s*"[^"]*"(?=\s*\])')
MISPLACED_ONE_OF = re.compile(r'"oneOf":\s*\[(.*?)\]\s*,(?=\s*"extensions")', re.S)
GLTF_STAND_INS = {
    "glTFid.schema.json": {"type": "integer", "minimum": 0},
    "glTFProperty.schema.json": {"type": "object", "properties": {"extensions": {"type": "object"}, "extras": {}}},
    "glTFChildOfRootProperty.schema.json": {"allOf": [{"$ref": "glTFProperty.schema.json"}],
                                            "properties": {"name": {"type": "string"}}},
}


def repaired_schemas(folder):
    schemas = {}
    for file in sorted(folder.glob("*.json")):
        text = STRAY_COMMENT.sub("", file.read_text())
        if file.name == "node.OCES_eyes.schema.json":
            text = MISPLACED_ONE_OF.sub(r'"oneOf": {\1},', text)
        schemas[file.name] = json.loads(text)
    node = schemas["node.OCES_eyes.schema.json"]
    choice = node["properties"].pop("oneOf")
    node["properties"].update(choice)
    node["oneOf"] = [{"required": [key]} for key in choice]
    return schemas


@pytest.fixture(scope="module")
def validator(shared_data):
    """A validator for one of the draft's schemas, by file name."""
    schemas = repaired_schemas(shared_data / "oces" / "schema")
    registry = Registry().with_resources(
        (name, Resource.from_contents(schema, default_specification=DRAFT202012))
        for name, schema in {**schemas, **GLTF_STAND_INS}.items())
    return lambda name: Draft202012Validator(schemas[name], registry=registry)


def schema_errors(validator, doc):
    """Messages of every part of a document's OCES data that fails its schema."""
    oces = extension(doc)
    parts = [("glTF.OCES_eyes.schema.json", oces)]
    parts += [("eye.schema.json", eye) for eye in oces["eyes"]]
    parts += [("ommatidialProperty.schema.json", p) for p in oces["ommatidialProperties"]]
    parts += [("node.OCES_eyes.schema.json", n["extensions"]["OCES_eyes"]) for n in doc["nodes"]]
    return [f"{name}: {e.message}" for name, part in parts for e in validator(name).iter_errors(part)]


def test_written_files_follow_the_drafts_schemas(tmp_path, table, validator):
    _, doc = written(tmp_path, table)
    assert schema_errors(validator, doc) == []
    binary = tmp_path / "bee.glb"
    write_oces(binary, table)
    data = binary.read_bytes()
    assert schema_errors(validator, json.loads(data[20:20 + struct.unpack_from("<I", data, 12)[0]])) == []


@pytest.mark.parametrize("break_it, complaint", [
    (lambda oces, nodes: oces["eyes"][0].pop("type"), "'type' is a required property"),
    (lambda oces, nodes: oces["eyes"][1]["ommatidialProperties"].pop("DIAMETER"), "not valid under any"),
    (lambda oces, nodes: oces["ommatidialProperties"][2].pop("value"), "'value' is a required property"),
    (lambda oces, nodes: nodes[1]["extensions"]["OCES_eyes"].update(head=True), "valid under each of"),
    (lambda oces, nodes: oces.update(version=4), "is not of type 'string'"),
])
def test_the_schema_check_catches_broken_documents(tmp_path, table, validator, break_it, complaint):
    _, doc = written(tmp_path, table)
    break_it(extension(doc), doc["nodes"])
    errors = schema_errors(validator, doc)
    assert errors and any(complaint in e for e in errors), errors


# --- Reading what other tools write ------------------------------------------------------


@pytest.mark.parametrize("normal", ["LEFT", "X", "FRONTAL", [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]])
@pytest.mark.parametrize("where", ["eye", "node"])
def test_a_mirror_plane_gives_the_other_eye(tmp_path, table, normal, where):
    right = select(table, table.side == "right")
    path, doc = written(tmp_path, right)
    extension(doc)["mirrorPlanes"] = [{"normal": "Z"}, {"normal": normal}]
    # The schema lists an eye's mirror planes in its eye object, the draft's examples in its node.
    owner = extension(doc)["eyes"][0] if where == "eye" else doc["nodes"][1]["extensions"]["OCES_eyes"]
    owner["mirrorPlanes"] = [1]
    got = read_oces(save(path, doc))
    n = len(right.id)
    np.testing.assert_array_equal(got.side, ["right"] * n + ["left"] * n)
    # A mirrored copy cannot keep the file's ids, which would be repeated.
    np.testing.assert_array_equal(got.id, np.arange(2 * n))
    np.testing.assert_allclose(got.position[n:], mirror(right.position), atol=1e-6)
    np.testing.assert_allclose(got.axis[n:], mirror(right.axis), atol=1e-6)
    np.testing.assert_allclose(got.delta_rho_deg[n:], right.delta_rho_deg, rtol=1e-6)


def test_a_mirror_plane_off_the_origin(tmp_path, table):
    right = select(table, table.side == "right")
    path, doc = written(tmp_path, right)
    # The plane y = 0.5 mm of the head frame: the HCS's X is the head's y, in metres.
    extension(doc)["mirrorPlanes"] = [{"position": [0.0005, 0.0, 0.0], "normal": "RIGHT"}]
    extension(doc)["eyes"][0]["mirrorPlanes"] = [0]
    got = read_oces(save(path, doc))
    want = right.position * [1.0, -1.0, 1.0] + [0.0, 1.0, 0.0]
    np.testing.assert_allclose(got.position[got.side == "left"], want, atol=1e-6)


@pytest.mark.parametrize("missing", MANDATORY)
def test_a_missing_mandatory_property_warns_and_takes_the_default(tmp_path, table, missing):
    right = select(table, table.side == "right")
    path, doc = written(tmp_path, right)
    del extension(doc)["eyes"][0]["ommatidialProperties"][missing]
    centre = np.array(doc["nodes"][1]["translation"])[[2, 0, 1]] * 1000
    if missing == "DIAMETER":
        # OCES's default facet, 1 mm, is no insect's (5–100 µm), and its Δρ, 53° at a 1 mm focal offset, no
        # ommatidium's: the table is refused once the default is taken.
        with pytest.warns(OcesWarning, match=f"lacks mandatory {missing}"), \
                pytest.raises(InputError, match="delta_rho_deg: receptor [0-9]+: an acceptance angle above 30°"):
            read_oces(save(path, doc))
        return
    diameter_mm = raw(doc, 0, "DIAMETER")[:, 0].astype(float)
    w_mm = raw(doc, 0, "FOCAL_OFFSET")[:, 0].astype(float) if missing != "FOCAL_OFFSET" else -1.0
    with pytest.warns(OcesWarning, match=f"lacks mandatory {missing}"):
        got = read_oces(save(path, doc))
    # Defaults are in the eye node's units, mm here: POSITION [0, 0, 0] is the node's origin,
    # ORIENTATION [0, 0, 1] the HCS's +Z, the head's anterior; FOCAL_OFFSET -1 mm.
    expected = {
        "POSITION": (got.position, np.broadcast_to(centre, right.position.shape)),
        "ORIENTATION": (got.axis, np.broadcast_to([1.0, 0.0, 0.0], right.axis.shape)),
        "FOCAL_OFFSET": (got.delta_rho_deg, np.degrees(2 * np.arctan(diameter_mm / 2 / 1.0))),
    }
    np.testing.assert_allclose(*expected[missing], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(got.delta_rho_deg, np.degrees(2 * np.arctan(diameter_mm / 2 / -w_mm)), rtol=1e-6)


def test_files_of_other_tools_coarse_properties_and_no_beeoptics_columns(tmp_path, table):
    path, doc = written(tmp_path, table)
    for eye in extension(doc)["eyes"]:
        eye["ommatidialProperties"] = {k: v for k, v in eye["ommatidialProperties"].items() if k in MANDATORY}
    # DIAMETER 0.02 mm and W = -0.5 mm for every ommatidium of the left eye.
    coarse(doc, 1, "DIAMETER", 0.02)
    coarse(doc, 1, "FOCAL_OFFSET", [0.0, 0.0, -0.5])
    # The left eye first in the file: a table still has the right eye's rows first.
    doc["nodes"][1:] = doc["nodes"][:0:-1]
    got = read_oces(save(path, doc))
    np.testing.assert_array_equal(got.id, np.arange(len(table.id)))
    np.testing.assert_array_equal(got.side, table.side)
    np.testing.assert_allclose(got.position, table.position, atol=1e-6)
    assert np.isnan(got.delta_phi_deg).all() and got.dorsal_rim is None and got.focal_offset_mm is None
    left = got.side == "left"
    np.testing.assert_allclose(got.facet_diameter_um[left], 20.0, rtol=1e-12)
    # Δρ = 2 atan(0.01 / 0.5) = 2 × 1.1457628°, worked by hand.
    np.testing.assert_allclose(got.delta_rho_deg[left], 2.2915257, rtol=1e-7)
    np.testing.assert_allclose(got.delta_rho_deg[~left], table.delta_rho_deg[~left], rtol=1e-6)


def test_the_shear_of_a_vec3_focal_offset_is_dropped_with_a_warning(tmp_path, table):
    path, doc = written(tmp_path, table)
    coarse(doc, 0, "FOCAL_OFFSET", [0.001, 0.0, -0.5])
    with pytest.warns(OcesWarning, match="shear"):
        got = read_oces(save(path, doc))
    np.testing.assert_allclose(got.delta_rho_deg[got.side == "right"],
                               np.degrees(2 * np.arctan(raw(doc, 0, "DIAMETER")[:, 0] / 2 / 0.5)), rtol=1e-6)


def rotation_about_dorsal(degrees):
    """A rotation about the HCS's Y (dorsal) axis: its quaternion (x, y, z, w) and matrix, by hand."""
    a = np.radians(degrees)
    c, s = np.cos(a), np.sin(a)
    return [0.0, np.sin(a / 2), 0.0, np.cos(a / 2)], np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@pytest.mark.parametrize("form", ["trs", "matrix"])
def test_node_transforms_between_head_and_eye_are_applied(tmp_path, table, form):
    path, doc = written(tmp_path, table)
    quaternion, rotation = rotation_about_dorsal(20.0)
    scale, shift = 2.0, np.array([0.0, 0.0, 0.0002])
    wrapper = {"children": [1, 2]}
    if form == "trs":
        wrapper.update(rotation=quaternion, scale=[scale] * 3, translation=shift.tolist())
    else:
        matrix = np.eye(4)
        matrix[:3, :3], matrix[:3, 3] = scale * rotation, shift
        wrapper["matrix"] = matrix.T.ravel().tolist()  # column-major
    doc["nodes"].append(wrapper)
    doc["nodes"][0]["children"] = [3]
    # The head's own placement in the scene changes nothing.
    doc["nodes"][0].update(translation=[5.0, 5.0, 5.0], rotation=rotation_about_dorsal(90.0)[0])
    got = read_oces(save(path, doc))
    hcs = 0.001 * table.position @ HCS_FROM_HEAD.T
    want = 1000 * (scale * hcs @ rotation.T + shift) @ HCS_FROM_HEAD
    np.testing.assert_allclose(got.position, want, atol=1e-6)
    np.testing.assert_allclose(got.axis, table.axis @ HCS_FROM_HEAD.T @ rotation.T @ HCS_FROM_HEAD, atol=1e-6)
    np.testing.assert_allclose(got.facet_diameter_um, scale * table.facet_diameter_um, rtol=1e-6)
    np.testing.assert_allclose(got.delta_rho_deg, table.delta_rho_deg, rtol=1e-6)


def test_the_heads_scale_sets_the_size_of_the_eyes(tmp_path, table):
    path, doc = written(tmp_path, table)
    doc["nodes"][0]["scale"] = [0.5] * 3
    got = read_oces(save(path, doc))
    np.testing.assert_allclose(got.position, 0.5 * table.position, atol=1e-6)
    np.testing.assert_allclose(got.facet_diameter_um, 0.5 * table.facet_diameter_um, rtol=1e-6)


@pytest.mark.parametrize("where", ["eye", "eye node"])
def test_disabled_eyes_are_skipped(tmp_path, table, where):
    path, doc = written(tmp_path, table)
    owner = extension(doc)["eyes"][1] if where == "eye" else doc["nodes"][2]["extensions"]["OCES_eyes"]
    owner["enabled"] = False
    got = read_oces(save(path, doc))
    assert (got.side == "right").all() and len(got.id) == (table.side == "right").sum()


# --- Acceptance angle and FOCAL_OFFSET ---------------------------------------------------


def test_focal_offset_follows_the_drafts_formula(tmp_path):
    # W = -(d/2) / tan(Δρ/2): d = 20 µm = 0.02 mm, Δρ = 2°: -0.01 / tan(1°) = -0.01 / 0.0174550649 mm.
    assert focal_offset_from_acceptance(0.02, 2.0) == pytest.approx(-0.5728996, rel=1e-7)
    assert acceptance_from_focal_offset(0.02, -0.5728996) == pytest.approx(2.0, rel=1e-6)
    one = ReceptorTable(id=np.array([0, 1]), side=np.array(["right", "right"]),
                        position=np.array([[0.0, -1.0, 0.0], [0.0, -1.5, 0.0]]), axis=np.array([[0.0, -1.0, 0.0]] * 2),
                        facet_diameter_um=np.array([20.0, 20.0]), delta_phi_deg=np.array([np.nan, np.nan]),
                        delta_rho_deg=np.array([2.0, 2.0]))
    _, doc = written(tmp_path, one)
    np.testing.assert_allclose(raw(doc, 0, "FOCAL_OFFSET")[:, 0], -0.5728996, rtol=1e-7)
    np.testing.assert_allclose(raw(doc, 0, "DIAMETER")[:, 0], 0.02, rtol=1e-7)


# --- Bad input ---------------------------------------------------------------------------

POSITION, ORIENTATION, FOCAL_OFFSET = (f"eyes.0.ommatidialProperties.{k}" for k in ("POSITION", "ORIENTATION",
                                                                                     "FOCAL_OFFSET"))


def set_accessor(key, **changes):
    return lambda doc: doc["accessors"][accessor_of(doc, 0, key)].update(changes)


def shorten_view(key):
    return lambda doc: doc["bufferViews"][doc["accessors"][accessor_of(doc, 0, key)]["bufferView"]].update(
        byteLength=8)


@pytest.mark.parametrize("edit, field, message", [
    (set_accessor("POSITION", componentType=5123), POSITION, "componentType 5123"),
    (set_accessor("ORIENTATION", type="SCALAR"), ORIENTATION, "'SCALAR'; ORIENTATION is VEC3"),
    (lambda doc: extension(doc)["ommatidialProperties"][0].update(value=99), POSITION, "99 is not the index"),
    (shorten_view("ORIENTATION"), ORIENTATION, "bytes of its buffer view, which has 8"),
    (lambda doc: doc["buffers"][0].update(byteLength=10**6), "buffers.0", "fewer than its byteLength"),
    (lambda doc: patch(doc, 0, "POSITION", 5, [0.1, np.nan, 0.0]), POSITION, "ommatidium 5: is not finite"),
    (lambda doc: patch(doc, 0, "ORIENTATION", 3, [0.0, 0.0, 0.0]), ORIENTATION, "ommatidium 3: has zero length"),
    (lambda doc: coarse(doc, 0, "FOCAL_OFFSET", 0.0), FOCAL_OFFSET, "not negative"),
    (lambda doc: coarse(doc, 0, "FOCAL_OFFSET", 0.4), FOCAL_OFFSET, "not negative"),
    (lambda doc: extension(doc)["eyes"][0].update(type="SURFACE"), "eyes.0.type", "POINT_OMMATIDIAL"),
    (lambda doc: extension(doc)["eyes"][0].update(type="SPHERICAL"), "eyes.0.type", "POINT_OMMATIDIAL"),
    (lambda doc: extension(doc)["ommatidialProperties"][0].update(type="TEXTURE"), POSITION, "TEXTURE"),
    (lambda doc: doc["nodes"][1].update(scale=[0.001, 0.002, 0.001]), "nodes.1.scale", "uniformly"),
    (lambda doc: doc["nodes"][0]["extensions"].pop("OCES_eyes"), "nodes.1", "outside every head"),
    (lambda doc: doc["extensions"].pop("OCES_eyes"), "extensions.OCES_eyes", "missing"),
    (lambda doc: doc["nodes"][0]["extensions"]["OCES_eyes"].update(enabled=False), "eyes", "no enabled"),
    # The glTF container's own fields are named too: pygltflib's decoding names none, failing with a TypeError
    # or an AttributeError, or reads a count of 3.5 as 3 and a missing asset as glTF 2.0 (beeoptics.io.oces).
    (lambda doc: doc.update(nodes=5), "nodes", "must be a JSON array"),
    (lambda doc: doc["nodes"].__setitem__(1, "eye"), "nodes.1", "must be a JSON object"),
    (lambda doc: doc.pop("asset"), "asset", "missing"),
    (set_accessor("POSITION", bufferView="x"), POSITION, "'x' is not the index of one of the file's"),
    (set_accessor("POSITION", count=3.5), POSITION, "count 3.5 is not a whole number"),
    (lambda doc: doc["buffers"][0].update(uri=5), "buffers.0.uri", "must be a string"),
    (lambda doc: doc["buffers"][0].update(uri=doc["buffers"][0]["uri"][:99] + "!" + doc["buffers"][0]["uri"][99:]),
     "buffers.0.uri", "is not valid base64"),
])
def test_malformed_files_name_the_file_and_field(tmp_path, table, edit, field, message):
    path, doc = written(tmp_path, table)
    edit(doc)
    with pytest.raises(InputError) as e:
        read_oces(save(path, doc))
    assert e.value.path == str(path) and e.value.field == field, str(e.value)
    assert message in str(e.value) and str(e.value).startswith(f"{path}: {field}: ")


@pytest.mark.parametrize("name, content, message", [
    ("bad.gltf", b'{"asset": {"version": "2.0"}', "not valid JSON"),
    ("bad.gltf", b'{"asset": {"version": "2.0"}, "nodes": [], "x": NaN}', "NaN is not a JSON number"),
    ("bad.gltf", b'{"asset": {"version": "1.0"}}', "OCES extends glTF 2.0"),
    ("bad.glb", b"glTF\x02\x00\x00\x00\x40\x00\x00\x00", "its header gives 64 bytes"),
    ("bad.glb", b"not a binary glTF file", "does not start with 'glTF'"),
])
def test_files_that_are_not_gltf(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(InputError, match=re.escape(message)) as e:
        read_oces(path)
    assert e.value.path == str(path)


def glb(path, *chunks):
    """Write a binary glTF of ``chunks``, (type, bytes), each padded to 4 bytes (glTF 2.0 §4)."""
    body = b"".join(struct.pack("<I4s", len(c) + -len(c) % 4, t) + c + b" " * (-len(c) % 4) for t, c in chunks)
    path.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
    return path


def chunks_of(doc):
    """The JSON and BIN chunks of a .glb holding what a .gltf's JSON ``doc`` holds in its data URI."""
    blob = base64.b64decode(doc["buffers"][0].pop("uri").split(",", 1)[1])
    return (b"JSON", json.dumps(doc).encode()), (b"BIN\0", blob)


@pytest.mark.parametrize("order, message", [
    (lambda json_chunk, bin_chunk: (bin_chunk, json_chunk), "first chunk must be its JSON"),
    (lambda json_chunk, bin_chunk: ((b"JSON", json_chunk[1].replace(b'"head": true', b'"head": NaN')), bin_chunk),
     "NaN is not a JSON number"),
])
def test_a_malformed_glb_is_named(tmp_path, table, order, message):
    _, doc = written(tmp_path, table)
    path = glb(tmp_path / "bee.glb", *order(*chunks_of(doc)))
    with pytest.raises(InputError, match=re.escape(message)) as e:
        read_oces(path)
    assert e.value.path == str(path) and e.value.field == ""


def test_what_gltf_allows_is_read(tmp_path, table):
    """A buffer's data URI of type application/gltf-buffer, and a GLB chunk of a type the reader does not know.

    glTF 2.0 allows both: a data URI of a buffer is application/octet-stream
    or application/gltf-buffer (§3.6.1.1), and readers skip chunks of unknown
    types, which extensions may add after the first two (§4.4.3.1).
    """
    path, doc = written(tmp_path, table)
    want = read_oces(path)
    doc["buffers"][0]["uri"] = doc["buffers"][0]["uri"].replace("octet-stream", "gltf-buffer", 1)
    assert_same_table(read_oces(save(path, doc)), want)
    assert_same_table(read_oces(glb(tmp_path / "bee.glb", *chunks_of(doc), (b"XTRA", b"1234"))), want)


def test_a_cut_off_glb(tmp_path, table):
    path = tmp_path / "bee.glb"
    write_oces(path, table)
    path.write_bytes(path.read_bytes()[:-100])
    with pytest.raises(InputError, match="cut off") as e:
        read_oces(path)
    assert e.value.path == str(path) and e.value.field == ""


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_oces(tmp_path / "none.gltf")


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_convert_chooses_oces_by_extension_and_round_trips_a_built_eye(tmp_path, suffix, validator, capsys):
    from beeoptics.cli import main
    from beeoptics.io.receptortable import read_receptors
    from conftest import ROOT

    eye = ROOT / "eyes" / "drosophila_melanogaster" / "ommatidia.csv"
    out, back = tmp_path / f"fly{suffix}", tmp_path / "back.csv"
    assert main(["convert", str(eye), str(out)]) == 0
    assert main(["convert", str(out), str(back)]) == 0
    data = out.read_bytes()
    doc = json.loads(data if suffix == ".gltf" else data[20:20 + struct.unpack_from("<I", data, 12)[0]])
    assert schema_errors(validator, doc) == []
    first, again = read_receptors(eye), read_receptors(back)
    np.testing.assert_allclose(again.position, first.position, atol=1e-6)
    np.testing.assert_allclose(again.axis, first.axis, atol=1e-6)
    np.testing.assert_allclose(again.delta_rho_deg, first.delta_rho_deg, atol=1e-6)
