"""Bad input gets one clear error naming the file and the field, a nonzero exit, and no partial artifact.

One test (or parametrised case) per kind of bad input. Every error is a
:class:`beeoptics.io.errors.InputError` (or, for the workflow's config,
Snakemake's validation error) whose one-line message names the file and
the field at fault.
"""

import base64
import copy
import json
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import yaml
from snakemake.exceptions import WorkflowError
from snakemake.utils import validate as snakemake_validate

from beeoptics.eye import description as eyefile
from beeoptics.eye.optics import AcceptanceModel, acceptance_angles
from beeoptics.light.sensors import cone_samples
from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.meshfile import read_mesh
from beeoptics.io.receptortable import read_receptors
from beeoptics.light.scene import load_scene
from beeoptics.vision.sensitivity import measured_sensitivities
from beeoptics.spectra import read_pavo_csv
from beeoptics.io.table import read_table, write_table
from beeoptics.io.validation import CONFIG_SCHEMA, validate_config
from conftest import ROOT, cap_mesh, write_scene

DATA = ROOT / "tests" / "data"
WL = np.arange(300, 701, 10)


# --- helpers ---------------------------------------------------------------------------------


def assert_names(excinfo, file, field):
    """The error is an InputError on one line naming ``file`` (its name) and ``field``."""
    err = excinfo.value
    assert isinstance(err, InputError)
    message = str(err)
    assert "\n" not in message, message
    assert Path(file).name in message, message
    assert Path(err.path).name == Path(file).name, message
    assert err.field == field, message
    assert field in message, message
    return message


def write_obj(path, vertices, faces):
    """A Wavefront OBJ of vertices (n, 3) and faces (lists of 0-based indices, any length)."""
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in np.asarray(vertices, float)]
    lines += ["f " + " ".join(str(int(i) + 1) for i in face) for face in faces]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def eye_dir(tmp_path, edit=None, mesh=None):
    """The tiny test eye copied to tmp_path/tiny, its eye.yaml edited in place by ``edit``."""
    folder = tmp_path / "tiny"
    shutil.copytree(DATA / "eyes" / "tiny", folder)
    eye = yaml.safe_load((folder / "eye.yaml").read_text())
    if mesh is not None:
        eye["mesh"] = mesh
    if edit is not None:
        edit(eye)
    (folder / "eye.yaml").write_text(yaml.safe_dump(eye, sort_keys=False))
    return folder / "eye.yaml"


def open_scene():
    return yaml.safe_load((DATA / "scenes" / "open" / "scene.yaml").read_text())


def pavo(path, columns, wl=WL):
    """A CSV in pavo's layout: ``wl`` then one column per entry of ``columns`` (name -> f(wl) or list)."""
    rows = ["wl," + ",".join(columns)]
    cells = {k: (v(wl) if callable(v) else v) for k, v in columns.items()}
    for i, w in enumerate(wl):
        rows.append(f"{w}," + ",".join(str(cells[k][i]) for k in columns))
    Path(path).write_text("\n".join(rows) + "\n")
    return Path(path)


def flat(value):
    return lambda wl: [value] * len(wl)


def with_one(value, at=500, base=0.5):
    return lambda wl: [value if w == at else base for w in wl]


def bee_curves(wl):
    """Three single-peaked curves at 350, 440 and 540 nm, in the order UV, B, G."""
    wl = np.asarray(wl, float)
    return {k: list(np.exp(-0.5 * ((wl - p) / 40.0) ** 2)) for k, p in (("UV", 350), ("B", 440), ("G", 540))}


def default_config():
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    cfg.update(eyes=["tiny"], scenes=["open", "generated"], eyes_dir=str(DATA / "eyes"),
               scenes_dir=str(DATA / "scenes"),
               flights={"dive": {"scene": "generated", "path": "flights/approach.csv", "eyes": ["tiny"]}},
               polarisation={"eyes": [], "scenes": []}, comparison={"eyes": []}, detection={"eyes": [], "scenes": []})
    return cfg


@pytest.fixture(scope="module")
def grid():
    from beeoptics.spectra import grid

    return grid(300.0, 700.0, 10.0)


# --- meshes: missing, empty, non-manifold, not triangles ---------------------------------------

SQUARE = np.array([[0, 0, 0], [0.5, 0, 0], [0.5, 0.5, 0], [0, 0.5, 0]], float)
# Three triangles on one edge, (0, 1): a fin, which no surface has.
FIN = (np.array([[0, 0, 0], [0.5, 0, 0], [0, 0.5, 0], [0, -0.5, 0], [0.2, 0, 0.3]], float),
       [[0, 1, 2], [1, 0, 3], [0, 1, 4]])

BAD_MESHES = {
    # name: (file text or (vertices, faces), expected words in the message)
    "empty": ("", "empty"),
    "no_faces": ("v 0 0 0\nv 0.5 0 0\nv 0 0.5 0\n", "no faces"),
    "quads": ((SQUARE, [[0, 1, 2, 3]]), "triangles"),
    "non_manifold": (FIN, "not manifold"),
}


def make_mesh(folder, name):
    spec, _ = BAD_MESHES[name]
    path = Path(folder) / f"{name}.obj"
    if isinstance(spec, str):
        path.write_text(spec)
    else:
        write_obj(path, *spec)
    return path


@pytest.mark.parametrize("name", sorted(BAD_MESHES))
def test_a_bad_mesh_file_is_refused_naming_it_and_its_faces(tmp_path, name):
    path = make_mesh(tmp_path, name)
    with pytest.raises(InputError) as e:
        read_mesh(path)
    assert BAD_MESHES[name][1] in assert_names(e, path, "faces")


@pytest.mark.parametrize("name", sorted(BAD_MESHES))
def test_a_bad_eye_mesh_is_refused_naming_it_and_its_faces(tmp_path, name):
    eye_file = eye_dir(tmp_path, mesh=f"{name}.obj")
    path = make_mesh(eye_file.parent, name)
    with pytest.raises(InputError) as e:
        eyefile.load_eye_mesh(eyefile.load_eye(eye_file))
    assert BAD_MESHES[name][1] in assert_names(e, path, "faces")


@pytest.mark.parametrize("name", sorted(BAD_MESHES))
def test_a_bad_scene_mesh_is_refused_naming_it_and_its_faces(tmp_path, grid, name):
    scene = open_scene()
    scene["objects"].append({"name": "bad", "mesh": f"{name}.obj", "material": "leaf"})
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    path = make_mesh(tmp_path, name)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert BAD_MESHES[name][1] in assert_names(e, path, "faces")


def test_a_missing_mesh_file_is_named(tmp_path):
    with pytest.raises(InputError) as e:
        read_mesh(tmp_path / "nowhere.obj")
    assert "no such mesh file" in assert_names(e, tmp_path / "nowhere.obj", "")


def test_a_missing_eye_mesh_names_the_eye_file_and_its_mesh_key(tmp_path):
    eye_file = eye_dir(tmp_path, mesh="nowhere.obj")
    with pytest.raises(InputError) as e:
        eyefile.load_eye_mesh(eyefile.load_eye(eye_file))
    assert "nowhere.obj" in assert_names(e, eye_file, "mesh")


def test_a_missing_scene_mesh_names_the_scene_file_and_the_object(tmp_path, grid):
    scene = open_scene()
    scene["objects"].append({"name": "flower", "mesh": "nowhere.obj", "material": "leaf"})
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert "nowhere.obj" in assert_names(e, scene_file, "objects.1.mesh")


def test_an_unreadable_mesh_file_gets_one_line_naming_it(tmp_path):
    path = tmp_path / "notes.obj"
    path.write_text("this is not a mesh\n")
    with pytest.raises(InputError) as e:
        read_mesh(path)
    # The file as a whole is at fault: there is no field to name.
    assert "cannot read mesh" in assert_names(e, path, "")


def test_an_eye_mesh_pinched_at_a_vertex_is_refused(tmp_path):
    # Two triangles meeting only at a corner: each edge is fine, the surface is not one sheet.
    v = np.array([[0, 0, 0], [0.5, 0, 0], [0.5, 0.5, 0], [-0.5, 0, 0], [-0.5, -0.5, 0]], float)
    eye_file = eye_dir(tmp_path, mesh="bowtie.obj")
    path = write_obj(eye_file.parent / "bowtie.obj", v, [[0, 1, 2], [0, 3, 4]])
    with pytest.raises(InputError) as e:
        eyefile.load_eye_mesh(eyefile.load_eye(eye_file))
    assert "single vertex" in assert_names(e, path, "faces")


# --- meshes in the wrong units -------------------------------------------------------------------


@pytest.fixture(scope="module")
def cap():
    # A cap 2.6 mm across, the length of a worker's eye.
    v, f = cap_mesh(radius=1.3 / np.sin(np.radians(60.0)), half_angle_deg=60.0)
    return v, f


@pytest.mark.parametrize("scale, units", [(1000.0, "micrometres"), (1e-3, "metres")])
def test_an_eye_mesh_in_the_wrong_units_is_refused(tmp_path, cap, scale, units):
    v, f = cap
    eye_file = eye_dir(tmp_path, mesh="eye.obj")
    path = write_obj(eye_file.parent / "eye.obj", v * scale, f)
    with pytest.raises(InputError) as e:
        eyefile.load_eye_mesh(eyefile.load_eye(eye_file))
    assert "millimetres" in assert_names(e, path, "vertices")


def test_the_same_eye_mesh_in_millimetres_is_accepted(tmp_path, cap):
    v, f = cap
    # As many facets as the cap's 6.8 mm² holds at the tiny eye's 40–46 µm.
    eye_file = eye_dir(tmp_path, edit=lambda e: e["facets"].update(count=4000), mesh="eye.obj")
    write_obj(eye_file.parent / "eye.obj", v, f)
    vertices, _ = eyefile.load_eye_mesh(eyefile.load_eye(eye_file))
    assert np.ptp(vertices, axis=0).max() == pytest.approx(2.6, rel=0.01)


# --- the facet-diameter map -------------------------------------------------------------------

ANCHOR = "facet_diameter.anchors.0.diameter_um"


def _anchor(**kw):
    return lambda e: e["facet_diameter"]["anchors"][0].update(kw)


@pytest.mark.parametrize(
    "edit, field",
    [
        (_anchor(diameter_um=-40.0), ANCHOR),
        (_anchor(diameter_um=0.0), ANCHOR),
        (_anchor(diameter_um=None), ANCHOR),
        (_anchor(diameter_um=float("nan")), ANCHOR),
        (lambda e: e["facet_diameter"]["anchors"][0].pop("diameter_um"), ANCHOR),
        (lambda e: e["facet_diameter"].update(anchors=[]), "facet_diameter.anchors"),
        (lambda e: e["facet_diameter"].pop("anchors"), "facet_diameter.anchors"),
        (lambda e: e.pop("facet_diameter"), "facet_diameter"),
    ],
    ids=["negative", "zero", "null", "nan", "missing_key", "no_anchors", "anchors_key_missing", "no_map"],
)
def test_a_facet_map_with_negative_or_missing_values_is_refused(tmp_path, edit, field):
    eye_file = eye_dir(tmp_path, edit)
    with pytest.raises(InputError) as e:
        eyefile.load_eye(eye_file)
    assert_names(e, eye_file, field)


def test_an_empty_yaml_value_is_a_missing_value(tmp_path):
    eye_file = eye_dir(tmp_path)
    eye_file.write_text(eye_file.read_text().replace("diameter_um: 40.0", "diameter_um:"))
    with pytest.raises(InputError) as e:
        eyefile.load_eye(eye_file)
    assert_names(e, eye_file, ANCHOR)


# --- spectra: coverage of 300–700 nm, NaN, negative values -------------------------------------


@pytest.mark.parametrize(
    "columns, wl, field, words",
    [
        ({"petal": flat(0.5)}, np.arange(400, 701, 10), "petal", "must cover 300–700"),
        ({"petal": flat(0.5)}, np.arange(300, 601, 10), "petal", "must cover 300–700"),
        ({"petal": with_one("nan")}, WL, "petal", "NaN"),
        ({"petal": with_one("inf")}, WL, "petal", "infinity"),
        ({"petal": with_one("")}, WL, "petal", "not a number"),
        ({"petal": with_one("NA")}, WL, "petal", "not a number"),
        ({"leaf": flat(0.1), "petal": with_one(-0.01)}, WL, "petal", "negative"),
        ({"petal": flat(0.5)}, [300, "nan", 700], "wl", "wavelengths"),
        ({"petal": flat(0.5)}, [300, 700, 500], "wl", "increasing"),
        ({"petal": flat(0.5)}, [500], "wl", "at least two"),
        ({"petal": flat(0.5)}, [], "wl", "at least two"),
    ],
    ids=["starts_at_400", "ends_at_600", "nan", "inf", "blank", "NA", "negative", "nan_wavelength",
         "unsorted_wavelengths", "one_row", "header_only"],
)
def test_a_bad_pavo_csv_is_refused_naming_the_column(tmp_path, grid, columns, wl, field, words):
    path = pavo(tmp_path / "spectra.csv", columns, wl)
    with pytest.raises(InputError) as e:
        read_pavo_csv(path, grid)
    assert words in assert_names(e, path, field)


def test_a_scene_material_from_a_bad_csv_names_the_csv_and_its_column(tmp_path, grid):
    path = pavo(tmp_path / "petals.csv", {"white": flat(0.8), "blue": with_one(-0.2)})
    scene = open_scene()
    scene["materials"]["petal"] = {"reflectance": {"csv": {"file": "petals.csv", "column": "blue"}}}
    scene["objects"].append({"primitive": {"sphere": {"radius_m": 0.01, "subdivisions": 1}}, "material": "petal"})
    with pytest.raises(InputError) as e:
        load_scene(write_scene(tmp_path / "scene.yaml", scene), grid)
    assert "negative" in assert_names(e, path, "blue")


def test_a_scene_material_from_a_short_csv_names_the_csv_and_its_column(tmp_path, grid):
    path = pavo(tmp_path / "petals.csv", {"blue": flat(0.3)}, np.arange(400, 701, 10))
    scene = open_scene()
    scene["materials"]["petal"] = {"reflectance": {"csv": {"file": "petals.csv", "column": "blue"}}}
    with pytest.raises(InputError) as e:
        load_scene(write_scene(tmp_path / "scene.yaml", scene), grid)
    assert "300–700" in assert_names(e, path, "blue")


def test_a_scene_material_from_a_missing_csv_column_is_named(tmp_path, grid):
    path = pavo(tmp_path / "petals.csv", {"white": flat(0.8)})
    scene = open_scene()
    scene["materials"]["petal"] = {"reflectance": {"csv": {"file": "petals.csv", "column": "blue"}}}
    with pytest.raises(InputError) as e:
        load_scene(write_scene(tmp_path / "scene.yaml", scene), grid)
    assert "no such column" in assert_names(e, path, "blue")


@pytest.mark.parametrize("value", [-0.2, float("nan")], ids=["negative", "nan"])
def test_a_scene_material_with_a_bad_constant_reflectance_is_refused(tmp_path, grid, value):
    scene = open_scene()
    scene["materials"]["leaf"]["reflectance"] = value
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert_names(e, scene_file, "materials.leaf.reflectance")


@pytest.mark.parametrize("spec, field, words", [
    ("my.csv", "materials.leaf.reflectance", "is not a spectrum: a number, or a mapping of one of constant, csv"),
    ({"csv": {"file": "petals.csv"}}, "materials.leaf.reflectance.csv.column", "required"),
    ({"cvs": {"file": "petals.csv", "column": "blue"}}, "materials.leaf.reflectance.cvs", "did you mean 'csv'"),
    ({"ground": "lome"}, "materials.leaf.reflectance.ground", "is not one of"),
    ({"fred": {"data_id": 1189}, "constant": 0.5}, "materials.leaf.reflectance", "is not a spectrum"),
], ids=["a_file_name", "no_column", "misspelt_form", "unknown_ground", "two_forms"])
def test_a_spectrum_not_of_the_schemas_forms_is_named_with_the_forms(tmp_path, grid, spec, field, words):
    """The scene schema documents every spectrum form and checks a material's against them."""
    scene = open_scene()
    scene["materials"]["leaf"]["reflectance"] = spec
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert words in assert_names(e, scene_file, field)


def test_a_material_with_a_coating_and_a_gloss_or_an_unknown_property_is_named(tmp_path, grid):
    for extra, field in [({"coating": {"roughness": 0.1}, "gloss": {"specular": 0.1}}, "materials.leaf"),
                         ({"shine": 1}, "materials.leaf.shine")]:
        scene = open_scene()
        scene["materials"]["leaf"].update(extra)
        scene_file = write_scene(tmp_path / "scene.yaml", scene)
        with pytest.raises(InputError) as e:
            load_scene(scene_file, grid)
        assert_names(e, scene_file, field)


def _curves(**edits):
    def make(wl):
        c = bee_curves(wl)
        for k, f in edits.items():
            c[k] = f(wl) if callable(f) else f
        return c
    return make


@pytest.mark.parametrize(
    "curves, wl, field, words",
    [
        (_curves(), np.arange(350, 651, 10), "UV", "must cover 300–700"),
        (_curves(B=lambda wl: [float("nan")] + [0.5] * (len(wl) - 1)), WL, "B", "NaN"),
        (_curves(G=lambda wl: [-0.1] + [0.5] * (len(wl) - 1)), WL, "G", "negative"),
        (_curves(B=flat(0.0)), WL, "B", "zero everywhere"),
        (lambda wl: dict(reversed(list(bee_curves(wl).items()))), WL, "B", "UV, B, G"),
        (lambda wl: {k: v for k, v in bee_curves(wl).items() if k != "G"}, WL, "UV, B", "expected 3"),
    ],
    ids=["short", "nan", "negative", "zero_column", "wrong_order", "two_columns"],
)
def test_bad_measured_sensitivities_are_refused_naming_the_column(tmp_path, grid, curves, wl, field, words):
    path = pavo(tmp_path / "sensitivity.csv", curves(np.asarray(wl)), wl)
    with pytest.raises(InputError) as e:
        measured_sensitivities(path, grid, ("UV", "B", "G"), (344.0, 436.0, 544.0))
    assert words in assert_names(e, path, field)


def test_good_measured_sensitivities_are_accepted(tmp_path, grid):
    path = pavo(tmp_path / "sensitivity.csv", bee_curves(WL))
    # Each of area 1 nm on the grid (beeoptics.vision.sensitivity.unit_area).
    assert measured_sensitivities(path, grid, ("UV", "B", "G"), (344.0, 436.0, 544.0)).sum(0) * (grid[1] - grid[0]) == \
        pytest.approx([1.0, 1.0, 1.0])


# --- unknown material, unknown eye class ---------------------------------------------------------


def test_an_unknown_material_is_named_with_the_object_that_uses_it(tmp_path, grid):
    scene = open_scene()
    scene["objects"][0]["material"] = "leef"
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    message = assert_names(e, scene_file, "objects.0.material")
    assert "'leef'" in message and f"object {scene['objects'][0]['name']!r}" in message
    assert "did you mean 'leaf'?" in message


def test_an_unknown_eye_class_in_the_config_is_named(tmp_path):
    cfg = default_config()
    cfg["eyes"] = ["tiny", "nonexistent"]
    source = tmp_path / "config.yaml"
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, source)
    message = assert_names(e, source, "eyes.1")
    # It says what is there instead.
    assert "'nonexistent'" in message and "tiny" in message


def test_an_unknown_scene_in_the_config_is_named(tmp_path):
    cfg = default_config()
    cfg["scenes"] = ["opne"]
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert "flower, generated, meadow_tiny, open" in assert_names(e, tmp_path / "config.yaml", "scenes.0")


@pytest.mark.parametrize("change, field", [
    (lambda f: f.update(path="flights/nowhere.csv"), "flights.dive.path"),
    (lambda f: f.update(eyes=["tiny", "tinny"]), "flights.dive.eyes.1"),
    (lambda f: f.update(scene="meadw"), "flights.dive.scene"),
])
def test_a_flight_with_a_missing_file_eye_or_scene_is_named(tmp_path, change, field):
    cfg = default_config()
    change(cfg["flights"]["dive"])
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert_names(e, tmp_path / "config.yaml", field)


@pytest.mark.parametrize("change, field, says", [
    (lambda p: p.update(eyes=["tiny"], scenes=["open"]), "polarisation.eyes.0", "no dorsal rim area"),
    (lambda p: p.update(scenes=["flwer"]), "polarisation.scenes.0", "no scene 'flwer'"),
])
def test_polarisation_of_an_eye_without_a_dorsal_rim_or_of_a_missing_scene_is_named(tmp_path, change, field, says):
    cfg = default_config()
    change(cfg.setdefault("polarisation", {}))
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert says in assert_names(e, tmp_path / "config.yaml", field)


@pytest.mark.parametrize("change, field, says", [
    (lambda d: d.update(scenes=["open"]), "detection.scenes.0", "has no meadow.yaml"),
    (lambda d: d.update(eyes=["tinny"]), "detection.eyes.0", "no eye 'tinny'"),
    (lambda d: d.update(directions=0), "detection.directions", "minimum"),
])
def test_a_detection_survey_of_a_scene_without_a_meadow_or_of_a_missing_eye_is_named(tmp_path, change, field, says):
    cfg = default_config()
    cfg["detection"] = {"eyes": ["tiny"], "scenes": ["generated"]}
    change(cfg["detection"])
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert says in assert_names(e, tmp_path / "config.yaml", field)


def test_known_eyes_and_scenes_pass_the_config_check(tmp_path):
    cfg = default_config()
    cfg["scenes"] = ["open", "flower"]
    assert validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml") is cfg


def test_a_config_key_the_command_line_set_is_blamed_on_the_command_line(tmp_path):
    cfg = default_config()
    cfg["eyes"] = ["wroker"]
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml", overrides={"eyes": ["wroker"]})
    assert e.value.path == "command line (--config)" and e.value.field == "eyes.0"
    cfg = default_config()
    cfg["trace"]["depth"] = 0
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml", overrides={"trace": {"parts": 2}})
    assert_names(e, tmp_path / "config.yaml", "trace.depth")


def test_numbers_given_as_text_on_the_command_line_are_read_as_numbers(tmp_path):
    # Snakemake 9 reads --config trace='{parts: 16}' as {"trace": {"parts": "16"}}.
    cfg = default_config()
    cfg["trace"]["parts"] = "16"
    cfg["spectral"]["step_nm"] = "2.5"
    validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml", overrides={"trace": {"parts": "16"}})
    assert cfg["trace"]["parts"] == 16 and cfg["spectral"]["step_nm"] == 2.5
    cfg["trace"]["parts"] = "sixteen"
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert_names(e, tmp_path / "config.yaml", "trace.parts")


def test_numbers_in_a_list_given_as_text_on_the_command_line_are_read_as_numbers(tmp_path):
    # --config sweeps='{s: {eyes: [tiny], scenes: [open], delta_rho_deg: [1.5, 4]}}', as Snakemake 9 reads it.
    cfg = default_config()
    cfg["sweeps"] = {"s": {"eyes": ["tiny"], "scenes": ["open"], "delta_rho_deg": ["1.5", "4"]}}
    validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml", overrides={"sweeps": cfg["sweeps"]})
    assert cfg["sweeps"]["s"]["delta_rho_deg"] == [1.5, 4]


def dry_run_refuses(tmp_path, cfg):
    """What a dry run of the workflow with this config prints; it must fail."""
    (tmp_path / "config.yaml").write_text(yaml.safe_dump(cfg))
    result = subprocess.run(
        [str(Path(sys.executable).with_name("snakemake")), "-n", "--directory", str(tmp_path),
         "--snakefile", str(ROOT / "Snakefile"), "--configfile", str(tmp_path / "config.yaml")],
        capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert result.returncode != 0
    return result.stdout + result.stderr


def test_a_syntax_error_in_the_workflow_config_names_its_line_and_column(tmp_path):
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "config.yaml").write_text("eyes: [worker\nscenes: [meadow]\n")
    result = subprocess.run(
        [str(Path(sys.executable).with_name("snakemake")), "-n", "--directory", str(tmp_path),
         "--snakefile", str(ROOT / "Snakefile")], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert result.returncode != 0
    assert "config/config.yaml: line 2, column 7: not valid YAML" in result.stderr + result.stdout


def test_a_dry_run_with_an_unknown_eye_class_stops_naming_the_config_key(tmp_path):
    cfg = default_config()
    cfg["eyes"] = ["nonexistent"]
    printed = dry_run_refuses(tmp_path, cfg)
    assert "config.yaml: eyes.0:" in printed and "nonexistent" in printed


def test_a_dry_run_adapting_to_a_material_some_scene_lacks_stops_naming_the_config_key(tmp_path):
    cfg = default_config()
    cfg["colour"] = {"background": "tip"}  # a petal of the flower scene; the open scene has only leaf
    cfg["scenes"] = ["flower", "open"]
    printed = dry_run_refuses(tmp_path, cfg)
    assert "config.yaml: colour.background:" in printed and "open/scene.yaml" in printed


# --- a scene with no light ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "light, field",
    [
        ({"sky": "none", "sun": False}, "light"),
        ({"sky": "none", "sun": True, "sun_elevation_deg": -10}, "light"),
        ({"sky": "uniform", "radiance": 0.0, "sun": False}, "light"),
        ({"sky": "uniform", "radiance": -1.0, "sun": False}, "light.radiance"),
        ({"sky": "preetham", "sun": False, "sun_elevation_deg": -5}, "light.sun_elevation_deg"),
        ({"sky": "preetham", "sun": True, "sun_elevation_deg": 0}, "light.sun_elevation_deg"),
    ],
    ids=["no_sky_no_sun", "sun_below_horizon", "black_sky", "negative_sky", "preetham_at_night",
         "preetham_sun_on_horizon"],
)
def test_a_scene_with_no_light_is_refused(tmp_path, grid, light, field):
    scene = open_scene()
    scene["light"] = light
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert_names(e, scene_file, field)


def test_an_emitting_material_that_no_object_uses_is_no_light(tmp_path, grid):
    scene = open_scene()
    scene["light"] = {"sky": "none", "sun": False}
    scene["materials"]["lamp"] = {"reflectance": 0.5, "emission": 1.0}
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert "no light" in assert_names(e, scene_file, "light")
    # Made into an object, the lamp lights the scene.
    scene["objects"].append({"primitive": {"sphere": {"radius_m": 0.1, "subdivisions": 1}}, "material": "lamp"})
    load_scene(write_scene(tmp_path / "scene.yaml", scene), grid)


# --- Δρ ≤ 0 and zero samples -------------------------------------------------------------------


@pytest.mark.parametrize(
    "edit, field",
    [
        (lambda c: c["eye"]["delta_rho"].update(fixed_deg=0), "eye.delta_rho.fixed_deg"),
        (lambda c: c["eye"]["delta_rho"].update(fixed_deg=-2.6), "eye.delta_rho.fixed_deg"),
        (lambda c: c["eye"]["delta_rho"].update(wavelength_nm=0), "eye.delta_rho.wavelength_nm"),
        (lambda c: c["trace"].update(samples_per_receptor=0), "trace.samples_per_receptor"),
        (lambda c: c["trace"].update(samples_per_receptor=2.5), "trace.samples_per_receptor"),
    ],
    ids=["zero_delta_rho", "negative_delta_rho", "zero_wavelength", "zero_samples", "fractional_samples"],
)
def test_a_nonpositive_acceptance_angle_or_sample_count_in_the_config_is_refused(tmp_path, edit, field):
    cfg = default_config()
    edit(cfg)
    # The schema's exclusiveMinimum / minimum, as the Snakefile checks it now ...
    with pytest.raises(WorkflowError, match=field.rsplit(".", 1)[-1]):
        snakemake_validate(copy.deepcopy(cfg), str(CONFIG_SCHEMA), set_default=True)
    # ... and as validate_config does, in one line naming the file and the dotted key.
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert_names(e, tmp_path / "config.yaml", field)


def test_a_nan_acceptance_angle_in_the_config_is_refused(tmp_path):
    # NaN slips through every JSON Schema bound (each comparison with it is false), so
    # Snakemake's validate accepts it; validate_config does not.
    config_file = tmp_path / "config.yaml"
    config_file.write_text("eye:\n  delta_rho:\n    fixed_deg: .nan\n")
    cfg = {**default_config(), **yaml.safe_load(config_file.read_text())}
    assert np.isnan(cfg["eye"]["delta_rho"]["fixed_deg"])
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, config_file)
    assert "finite" in assert_names(e, config_file, "eye.delta_rho.fixed_deg")


@pytest.mark.parametrize("value", [0, -1.7], ids=["zero", "negative"])
def test_a_nonpositive_rhabdom_acceptance_in_the_eye_file_is_refused(tmp_path, value):
    eye_file = eye_dir(tmp_path, lambda e: e.update(optics={"rhabdom_acceptance_deg": value}))
    with pytest.raises(InputError) as e:
        eyefile.load_eye(eye_file)
    assert_names(e, eye_file, "optics.rhabdom_acceptance_deg")


def test_a_receptor_table_with_a_nonpositive_acceptance_angle_is_refused(tmp_path):
    path = tmp_path / "receptors.csv"
    write_table(path, {"id": [0, 1], "side": ["right", "left"], "x": [0.0, 0.0], "y": [1.0, -1.0],
                       "z": [0.0, 0.0], "ax": [0.0, 0.0], "ay": [1.0, -1.0], "az": [0.0, 0.0],
                       "facet_diameter_um": [20.0, 20.0], "delta_phi_deg": [2.0, 2.0],
                       "delta_rho_deg": [2.6, 0.0]})
    assert list(read_table(path))[-1] == "delta_rho_deg"
    with pytest.raises(InputError) as e:
        read_receptors(path)
    assert_names(e, path, "delta_rho_deg")


@pytest.mark.parametrize("rim, angle, column", [([1, 2], [30.0, ""], "dorsal_rim"),
                                                ([1, 0], ["", ""], "microvilli_deg"),
                                                ([1, 0], [180.0, ""], "microvilli_deg")],
                         ids=["not-0-or-1", "rim-without-angle", "angle-out-of-range"])
def test_a_receptor_tables_dorsal_rim_columns_are_checked(tmp_path, rim, angle, column):
    path = tmp_path / "receptors.csv"
    write_table(path, {"id": [0, 1], "side": ["right", "left"], "x": [0.0, 0.0], "y": [1.0, -1.0],
                       "z": [0.0, 0.0], "ax": [0.0, 0.0], "ay": [1.0, -1.0], "az": [0.0, 0.0],
                       "facet_diameter_um": [20.0, 20.0], "delta_phi_deg": [2.0, 2.0],
                       "delta_rho_deg": [2.6, 2.6], "dorsal_rim": rim, "microvilli_deg": angle})
    with pytest.raises(InputError) as e:
        read_receptors(path)
    assert_names(e, path, column)


def test_the_optics_refuse_a_nonpositive_acceptance_angle_or_sample_count():
    axes = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match="fixed_deg"):
        acceptance_angles(np.array([20.0]), AcceptanceModel("fixed", fixed_deg=0.0))
    with pytest.raises(ValueError, match="samples"):
        cone_samples(axes, 2.6, 0, seed=1)


# --- a misspelt key ------------------------------------------------------------------------------


def test_a_misspelt_config_key_stops_the_snakefiles_validation_naming_it():
    # The same call as the Snakefile's: snakemake.utils.validate against the workflow's schema.
    cfg = default_config()
    cfg["trace"]["sampels_per_receptor"] = cfg["trace"].pop("samples_per_receptor")
    with pytest.raises(WorkflowError, match="sampels_per_receptor"):
        snakemake_validate(cfg, str(CONFIG_SCHEMA))


@pytest.mark.parametrize(
    "edit, field, hint",
    [
        (lambda c: c["trace"].update(sampels_per_receptor=c["trace"].pop("samples_per_receptor")),
         "trace.sampels_per_receptor", "did you mean 'samples_per_receptor'?"),
        (lambda c: c.update(scense=c.pop("scenes")), "scense", "did you mean 'scenes'?"),
        (lambda c: c["eye"]["delta_rho"].update(fixed=2.6), "eye.delta_rho.fixed", "did you mean 'fixed_deg'?"),
    ],
    ids=["trace", "top_level", "nested"],
)
def test_a_misspelt_config_key_is_named_with_its_file_and_section(tmp_path, edit, field, hint):
    cfg = default_config()
    edit(cfg)
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert hint in assert_names(e, tmp_path / "config.yaml", field)


def test_a_misspelt_key_in_an_eye_file_is_named(tmp_path):
    eye_file = eye_dir(tmp_path, lambda e: e["facets"].update(cuont=e["facets"].pop("count")))
    with pytest.raises(InputError) as e:
        eyefile.load_eye(eye_file)
    # The misspelling is reported, with the key it stands for, rather than the key it leaves missing.
    assert "did you mean 'count'?" in assert_names(e, eye_file, "facets.cuont")
    eye_file = eye_dir(tmp_path / "2", lambda e: e["facets"].update(sd_=3))
    with pytest.raises(InputError) as e:
        eyefile.load_eye(eye_file)
    assert "did you mean 'sd'?" in assert_names(e, eye_file, "facets.sd_")


def test_a_misspelt_key_in_a_scene_file_is_named(tmp_path, grid):
    scene = open_scene()
    scene["light"]["sun_elevation"] = 30
    scene_file = write_scene(tmp_path / "scene.yaml", scene)
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert "did you mean 'sun_elevation_deg'?" in assert_names(e, scene_file, "light.sun_elevation")


def test_config_defaults_are_not_shared_between_configs(tmp_path):
    a, b = {"eyes": ["tiny"]}, {"eyes": ["tiny"]}
    for cfg in (a, b):
        cfg.update(eyes_dir=str(DATA / "eyes"), scenes=["open"], scenes_dir=str(DATA / "scenes"))
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    a["trace"]["samples_per_receptor"] = 4
    assert b["trace"]["samples_per_receptor"] == 256


# --- a nonzero exit and no partial artifact ------------------------------------------------------


def run_stage(code, cwd):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          cwd=cwd, timeout=120)


def leftovers(folder, stem):
    """The temporary files atomic writes of ``stem`` would leave behind."""
    return sorted(p.name for p in Path(folder).glob(f".{stem}.*"))


def test_remeshing_an_eye_in_the_wrong_units_exits_nonzero_and_writes_nothing(tmp_path, cap):
    v, f = cap
    eye_file = eye_dir(tmp_path, mesh="eye.obj")
    write_obj(eye_file.parent / "eye.obj", v * 1000.0, f)
    out = tmp_path / "results" / "remeshed.ply"
    result = run_stage(f"""
        from beeoptics.pipeline.eyes import remesh_eye
        remesh_eye({str(eye_file)!r}, {{"remeshed": {str(out)!r}}})
        """, tmp_path)
    assert result.returncode != 0
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith("beeoptics.io.errors.InputError: ")
    assert "eye.obj: vertices:" in last and "millimetres" in last
    assert not out.exists()
    assert not out.parent.exists() or leftovers(out.parent, "remeshed") == []


def test_tracing_a_scene_with_no_light_exits_nonzero_and_writes_nothing(tmp_path):
    scene = open_scene()
    scene["light"] = {"sky": "none", "sun": False}
    scene_file = write_scene(tmp_path / "dark" / "scene.yaml", scene)
    out = tmp_path / "results"
    out.mkdir()
    result = run_stage(f"""
        from beeoptics.pipeline.trace import trace_part
        from beeoptics.vision.receptorset import load_receptor_set
        trace_part("receptors.csv", {str(scene_file)!r}, {{"radiance": {str(out / "radiance_0_of_1.npz")!r}}},
                   spectral={{"start_nm": 300, "end_nm": 700, "step_nm": 10}},
                   trace={{"samples_per_receptor": 4, "depth": 1, "seed": 1, "batch_rays": 1024}}, threads=1,
                   receptor_set=load_receptor_set())
        """, tmp_path)
    assert result.returncode != 0
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith("beeoptics.io.errors.InputError: ")
    assert "scene.yaml: light:" in last and "no light" in last
    assert sorted(p.name for p in out.iterdir()) == []


def test_a_failed_write_leaves_neither_the_artifact_nor_a_temporary_file(tmp_path):
    out = tmp_path / "quality.json"
    with pytest.raises(RuntimeError):
        with atomic_path(out) as tmp:
            tmp.write_text('{"half": ')
            raise RuntimeError("killed")
    assert not out.exists()
    assert leftovers(tmp_path, "quality") == []


# --- meshes a native library would crash on, checked in Python first -------------------------

TRIANGLES = [[0, 1, 2], [0, 2, 3]]


def ply_bytes(vertices, faces):
    """A binary little-endian PLY of float vertices and int triangles."""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\nproperty float x\n"
              f"property float y\nproperty float z\nelement face {len(faces)}\n"
              "property list uchar int vertex_indices\nend_header\n").encode()
    body = np.asarray(vertices, "<f4").tobytes()
    body += b"".join(np.uint8(3).tobytes() + np.asarray(f, "<i4").tobytes() for f in faces)
    return header + body


def gltf_text(vertices, faces):
    """A glTF of one primitive, its buffer inline."""
    v = np.asarray(vertices, "<f4").tobytes()
    i = np.asarray(faces, "<u4").tobytes()
    return json.dumps({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(v) + len(i),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(v + i).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(v)},
                        {"buffer": 0, "byteOffset": len(v), "byteLength": len(i)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(vertices), "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5125, "count": 3 * len(faces), "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    })


@pytest.mark.parametrize("name, write, field, words", [
    ("past.obj", lambda p: write_obj(p, SQUARE, [[0, 1, 2], [0, 2, 9]]), "face 2", "refers to vertex 10"),
    ("negative.obj", lambda p: p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -1 -2 -3\n"), "face 2",
     "relative"),
    ("repeat.obj", lambda p: write_obj(p, SQUARE, [[0, 1, 2], [0, 2, 2]]), "face 2", "names one vertex twice"),
    ("flat.obj", lambda p: write_obj(p, [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], [[0, 1, 3], [0, 1, 2]]),
     "face 2", "zero area"),
    ("nan.obj", lambda p: p.write_text("v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n"), "vertex 3", "not a finite"),
    ("texture_only.obj", lambda p: p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf /1 /1 /1\n"), "line 5",
     "has no vertex index"),
    ("past.ply", lambda p: p.write_bytes(ply_bytes(SQUARE, [[0, 1, 2], [0, 2, 7]])), "face 2", "refers to vertex 8"),
    ("truncated.ply", lambda p: p.write_bytes(ply_bytes(SQUARE, TRIANGLES)[:-7]), "", "cannot read mesh"),
    ("past.gltf", lambda p: p.write_text(gltf_text(SQUARE, [[0, 1, 2], [0, 2, 4]])), "face 2", "refers to vertex 5"),
], ids=lambda x: x if isinstance(x, str) and "." in x else "")
def test_a_mesh_that_would_crash_a_native_library_is_refused_naming_the_element(tmp_path, name, write, field, words):
    path = tmp_path / name
    write(path)
    with pytest.raises(InputError) as e:
        read_mesh(path)
    assert words in assert_names(e, path, field)


def test_a_scene_mesh_with_an_index_past_its_vertices_stops_the_trace_in_one_line(tmp_path):
    shutil.copytree(DATA / "scenes" / "flower", tmp_path / "flower")
    obj = tmp_path / "flower" / "daisy.obj"
    obj.write_text(obj.read_text().replace("f 1 2 3\n", "f 1 2 300\n", 1))
    result = run_stage(f"""
        from beeoptics.light.scene import load_scene
        from beeoptics.spectra import grid
        load_scene({str(tmp_path / "flower" / "scene.yaml")!r}, grid(300, 700, 10))
        """, tmp_path)
    assert result.returncode == 1  # an exception, not a signal
    assert result.stderr.strip().splitlines()[-1].endswith("daisy.obj: face 1: refers to vertex 300, but the mesh "
                                                           "has 104 vertices")


# --- an eye whose facet count its cornea cannot hold, an eye inside the scene's surfaces ---------


@pytest.mark.parametrize("count", [3, 20_000])
def test_a_facet_count_the_cornea_cannot_hold_gets_one_line_at_once(tmp_path, count):
    # The tiny eye's 0.46 mm² cornea holds 251–334 facets of its 40–46 µm.
    eye_file = eye_dir(tmp_path, edit=lambda e: e["facets"].update(count=count))
    result = subprocess.run([sys.executable, "-m", "beeoptics.cli", "build-eye", str(eye_file), "-o",
                             str(tmp_path / "out"), "--quiet"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert "eye.yaml: facets.count:" in result.stderr and "251–334" in result.stderr, result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("height_m, warned", [(0.1, False), (-0.1, True)])
def test_an_eye_below_the_ground_still_renders_but_is_warned_of(tmp_path, caplog, height_m, warned):
    from beeoptics.light.batching import TraceSettings
    from beeoptics.tracing import trace_receptors
    from beeoptics.spectra import grid as spectral_grid
    from conftest import build_eye_files

    table = read_receptors(build_eye_files(DATA / "eyes" / "tiny" / "eye.yaml", tmp_path / "eye")["receptors"])
    scene = open_scene()
    scene["eye"]["position_m"] = [0.0, 0.0, height_m]
    wl = spectral_grid(300.0, 700.0, 20.0)
    loaded = load_scene(write_scene(tmp_path / "scene" / "scene.yaml", scene), wl)
    with caplog.at_level("WARNING", logger="beeoptics"):
        radiance, _ = trace_receptors(loaded, table, 0, len(table.id), TraceSettings(4, 1, 1, 4096), len(wl))
    assert np.isfinite(radiance).all()
    said = [r.getMessage() for r in caplog.records if "back face" in r.getMessage()]
    assert bool(said) == warned, said
    if warned:
        # Below a plane, every receptor that meets it meets its underside.
        assert said[0].startswith("100% of the receptors whose axis meets a surface meet its back face")


def test_an_extra_naming_another_folders_scene_is_not_run_but_a_misspelt_one_stops_the_run(tmp_path):
    """The default flight's meadow in a run of other scenes is another folder's: not an error, not run. A
    name close to a scene that is there is a misspelling, named with what it is close to."""
    cfg = default_config()
    cfg["flights"]["dive"]["scene"] = "forest"
    assert validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")["flights"] == {}
    cfg = default_config()
    cfg["flights"]["dive"]["scene"] = "generatd"
    with pytest.raises(InputError) as e:
        validate_config(cfg, CONFIG_SCHEMA, tmp_path / "config.yaml")
    assert "did you mean 'generated'" in assert_names(e, tmp_path / "config.yaml", "flights.dive.scene")


# --- inputs checked against what they can mean -----------------------------------------------------


def receptor_table(path, per_eye=2, **columns):
    """A receptor table of ``per_eye`` receptors an eye, on a 1 mm arc either side of the head, its columns
    replaced by ``columns``."""
    a = np.linspace(-0.5, 0.5, per_eye)
    x, y = np.concatenate([a, a]), np.concatenate([np.full(per_eye, 1.0), np.full(per_eye, -1.0)])
    n = 2 * per_eye
    write_table(path, {"id": np.arange(n), "side": ["right"] * per_eye + ["left"] * per_eye, "x": x, "y": y,
                       "z": np.zeros(n), "ax": np.zeros(n), "ay": np.sign(y), "az": np.zeros(n),
                       "facet_diameter_um": np.full(n, 20.0), "delta_phi_deg": np.full(n, 2.0),
                       "delta_rho_deg": np.full(n, 2.6), **columns})
    return path


@pytest.mark.parametrize("column, value", [("delta_rho_deg", 120.0), ("facet_diameter_um", 0.04),
                                           ("facet_diameter_um", 4000.0), ("delta_phi_deg", 120.0)])
def test_a_receptor_table_with_values_no_compound_eye_has_is_refused(tmp_path, column, value):
    usual = {"delta_rho_deg": 2.6, "facet_diameter_um": 20.0, "delta_phi_deg": 2.0}[column]
    path = receptor_table(tmp_path / "receptors.csv", **{column: [value, usual, usual, usual]})
    with pytest.raises(InputError) as e:
        read_receptors(path)
    assert "receptor 0" in assert_names(e, path, column)


@pytest.mark.parametrize("column, value, warned", [("delta_rho_deg", 2.6, False), ("delta_rho_deg", 25.0, True),
                                                   ("delta_rho_deg", 0.2, True), ("facet_diameter_um", 113.0, True),
                                                   ("facet_diameter_um", 3.0, True)])
def test_an_unusual_receptor_in_a_receptor_table_is_warned_of_in_one_line(tmp_path, caplog, column, value, warned):
    usual = {"delta_rho_deg": 2.6, "facet_diameter_um": 20.0}[column]
    path = receptor_table(tmp_path / "receptors.csv", **{column: [value, usual, usual, usual]})
    with caplog.at_level("WARNING", logger="beeoptics"):
        read_receptors(path)
    said = [r.getMessage() for r in caplog.records]
    assert bool(said) == warned, said
    if warned:
        assert said[0].startswith(f"{path}: {column}: 1 receptors") and "\n" not in said[0], said


def receptor_set_file(tmp_path, lambdas):
    from beeoptics.vision.receptorset import SETS_DIR

    doc = yaml.safe_load((SETS_DIR / "apis_mellifera.yaml").read_text())
    for c, lam in zip(doc["classes"], lambdas):
        c["lambda_max_nm"] = lam
    doc["curves"] = {"source": "the A1 template"}
    path = tmp_path / "set.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


@pytest.mark.parametrize("lambdas, field", [([250, 436, 544], "classes.0.lambda_max_nm"),
                                            ([344, 436, 760], "classes.2.lambda_max_nm"),
                                            ([344, 436, 436], "classes.2.lambda_max_nm")],
                         ids=["250-nm", "760-nm", "two-at-436-nm"])
def test_a_receptor_set_with_a_peak_no_insect_has_or_two_classes_at_one_peak_is_refused(tmp_path, lambdas, field):
    from beeoptics.vision.receptorset import load_receptor_set

    path = receptor_set_file(tmp_path, lambdas)
    load_receptor_set(str(receptor_set_file(tmp_path / "..", [344, 436, 544])))
    with pytest.raises(InputError) as e:
        load_receptor_set(str(path))
    assert_names(e, path, field)


@pytest.mark.parametrize("diameter", [0.04, 400.0])
def test_an_eye_anchors_facet_diameter_no_insect_has_is_refused(tmp_path, diameter):
    eye_file = eye_dir(tmp_path, lambda e: e["facet_diameter"]["anchors"][0].update(diameter_um=diameter))
    with pytest.raises(InputError) as e:
        eyefile.load_eye(eye_file)
    assert "5–100 µm" in assert_names(e, eye_file, "facet_diameter.anchors.0.diameter_um")


def test_one_eyes_receptors_rendered_with_another_eye_are_refused_in_one_line(tmp_path):
    """The worker's table (its quality.json names it) with the tiny eye's --eye: refused before any work."""
    receptors = receptor_table(tmp_path / "worker" / "receptors.csv")
    (tmp_path / "worker" / "quality.json").write_text(json.dumps({"eye": "worker", "facets_per_eye": 2}))
    result = subprocess.run([sys.executable, "-m", "beeoptics.cli", "render", str(receptors),
                             str(DATA / "scenes" / "open" / "scene.yaml"), "--eye", str(DATA / "eyes" / "tiny" /
                                                                                        "eye.yaml"),
                             "-o", str(tmp_path / "out"), "--quiet"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1, result.stderr
    assert f"{receptors}: built for the eye 'worker' (its quality.json), not for 'tiny'" in result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("per_eye, refused", [(30, True), (300, False)])
def test_a_receptor_table_without_its_quality_is_matched_to_the_eye_by_its_count(tmp_path, per_eye, refused):
    eye = eyefile.load_eye(DATA / "eyes" / "tiny" / "eye.yaml")  # 300 facets an eye
    path = receptor_table(tmp_path / "receptors.csv", per_eye=per_eye)
    table = read_receptors(path)
    if not refused:
        eyefile.check_receptors_of(eye, path, table)
        return
    with pytest.raises(InputError) as e:
        eyefile.check_receptors_of(eye, path, table)
    assert "30 receptors an eye, where the eye 'tiny'" in assert_names(e, path, "")


@pytest.mark.parametrize("scale, warned", [(1.0, False), (1000.0, True)], ids=["metres", "millimetres"])
def test_a_scene_modelled_in_millimetres_is_warned_of_in_one_line(tmp_path, caplog, scale, warned):
    """Every length of the ymaze 1000 times too large, as a scene modelled in millimetres is read: its eye, 0.15 m
    up, is then 150 m up."""
    from beeoptics.spectra import grid as spectral_grid

    scene = yaml.safe_load((DATA / "scenes" / "ymaze" / "scene.yaml").read_text())
    for o in scene["objects"]:
        o["scale"] = o.get("scale", 1.0) * scale
        o["translate_m"] = [scale * v for v in o.get("translate_m", [0, 0, 0])]
        if "primitive" in o and "plane" in o["primitive"]:
            o["primitive"]["plane"]["size_m"] *= scale
    scene["eye"]["position_m"] = [0.0, 0.0, 0.15 * scale]
    shutil.copytree(DATA / "scenes" / "ymaze", tmp_path / "ymaze")
    path = write_scene(tmp_path / "ymaze" / "scene.yaml", scene)
    with caplog.at_level("WARNING", logger="beeoptics"):
        load_scene(path, spectral_grid(300.0, 700.0, 20.0), cache=False)
    said = [r.getMessage() for r in caplog.records if "millimetres" in r.getMessage()]
    assert bool(said) == warned, said
    if warned:
        assert said[0].startswith(f"{path}: eye.position_m: 150 m from the origin: is the scene modelled in "
                                  "millimetres?") and "\n" not in said[0], said


def _numeric_fields(node, path=""):
    """(dotted path, schema) of every number or integer a schema takes."""
    if isinstance(node, dict):
        kinds = node.get("type") if isinstance(node.get("type"), list) else [node.get("type")]
        if {"number", "integer"} & set(kinds):
            yield path, node
        for key, value in node.items():
            yield from _numeric_fields(value, f"{path}.{key}" if key not in ("properties", "items") else path)
    elif isinstance(node, list):
        for item in node:
            yield from _numeric_fields(item, path)


@pytest.mark.parametrize("schema", sorted(p.name for p in (ROOT / "beeoptics" / "io" / "schemas").glob("*.yaml")))
def test_every_number_of_every_input_schema_has_a_range(schema):
    """Both bounds for every number an input takes (what it cannot be below, and beyond what it means
    nothing or costs more than any run can give), bounds that are numbers (YAML 1.1 reads 1e9 as text), and a
    default within them."""
    doc = yaml.safe_load((ROOT / "beeoptics" / "io" / "schemas" / schema).read_text())
    for field, node in _numeric_fields(doc):
        assert "minimum" in node or "exclusiveMinimum" in node, f"{schema}: {field} has no lower bound"
        assert "maximum" in node or "exclusiveMaximum" in node, f"{schema}: {field} has no upper bound"
        if isinstance(node.get("default"), (int, float)) and not isinstance(node["default"], bool):
            d = node["default"]
            within = (node["minimum"] <= d if "minimum" in node else node["exclusiveMinimum"] < d) and \
                (d <= node["maximum"] if "maximum" in node else d < node["exclusiveMaximum"])
            assert within, f"{schema}: {field}'s default is out of range"
        for bound in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"):
            assert isinstance(node.get(bound, 0), (int, float)), f"{schema}: {field}.{bound} is not a number"


@pytest.mark.parametrize("scale, field", [(1000.0, "t_s"), (1e5, "x_m, y_m, z_m")], ids=["millimetres", "too-far"])
def test_a_flight_in_millimetres_or_beyond_a_bees_reach_is_refused(tmp_path, scale, field):
    """The approach flight's positions 1000 times too large fly at some 600 m/s; 10⁵ times, 14 km out."""
    from beeoptics.world.flight import read_flight

    flight = read_table(ROOT / "scenes" / "meadow" / "flights" / "approach.csv")
    read_flight(ROOT / "scenes" / "meadow" / "flights" / "approach.csv")
    path = tmp_path / "flight.csv"
    write_table(path, {**flight, **{c: scale * np.asarray(flight[c]) for c in ("x_m", "y_m", "z_m")}})
    with pytest.raises(InputError) as e:
        read_flight(path)
    assert "millimetres" in assert_names(e, path, field)


# --- errors in their true form: the cause, not what it led to -----------------------------------


def test_a_bad_line_in_a_flight_stops_the_workflow_at_its_start_in_one_line(tmp_path):
    """Not in the traceback of the flight rules' input function, which reads the CSV to share its frames."""
    shutil.copytree(DATA / "scenes", tmp_path / "scenes")
    flight = tmp_path / "scenes" / "generated" / "flights" / "approach.csv"
    lines = flight.read_text().splitlines()
    fields = lines[2].split(",")
    fields[1] += "x"  # x_m of the second flight row, the file's third line
    flight.write_text("\n".join([*lines[:2], ",".join(fields), *lines[3:]]) + "\n")
    cfg = default_config()
    cfg["scenes_dir"] = str(tmp_path / "scenes")
    printed = dry_run_refuses(tmp_path, cfg)
    assert "Traceback" not in printed and "InputFunctionException" not in printed, printed
    said = [line for line in printed.splitlines() if "error" in line.lower()]
    assert said == [f"beeoptics: error: {flight}: x_m: row 3: {fields[1]!r} is not a number"], printed


def gltf_scene(vertices, faces):
    """:func:`gltf_text`'s document with a scene that places its mesh, as pymeshlab needs to read it."""
    doc = json.loads(gltf_text(vertices, faces))
    doc.update(scenes=[{"nodes": [0]}], scene=0, nodes=[{"mesh": 0}])
    doc["accessors"][0].update(min=np.min(vertices, 0).tolist(), max=np.max(vertices, 0).tolist())
    return doc


def textured_square(folder, png):
    """A scene of one textured square (a glTF) whose texture is the PNG bytes ``png``."""
    v = np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]], "<f4")
    uv = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], "<f4")
    doc = gltf_scene(v, TRIANGLES)
    blob = base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1]) + uv.tobytes()
    doc["buffers"][0].update(byteLength=len(blob), uri="data:application/octet-stream;base64,"
                             + base64.b64encode(blob).decode())
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob) - uv.nbytes, "byteLength": uv.nbytes})
    doc["accessors"].append({"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"})
    doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
    (folder / "square.gltf").write_text(json.dumps(doc))
    (folder / "square.png").write_bytes(png)
    scene = open_scene()
    scene["objects"] = [{"name": "square", "mesh": "square.gltf",
                         "texture": {"image": "square.png", "palette": {"#ff0000": "leaf"}}}]
    return write_scene(folder / "scene.yaml", scene)


def noisy_png(path):
    """A 64 × 64 PNG of random colours (which compresses badly: its pixels fill most of the file)."""
    import OpenImageIO as oiio

    pixels = np.random.default_rng(0).random((64, 64, 3)).astype(np.float32)
    image = oiio.ImageBuf(oiio.ImageSpec(64, 64, 3, oiio.UINT8))
    image.set_pixels(oiio.ROI(0, 64, 0, 64, 0, 1, 0, 3), pixels)
    assert image.write(str(path))
    return Path(path).read_bytes()


def test_a_truncated_texture_is_said_to_be_unreadable_without_libpngs_noise(tmp_path, grid, capfd):
    whole = noisy_png(tmp_path / "whole.png")
    scene_file = textured_square(tmp_path, whole[:len(whole) // 2])
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    assert "truncated" in assert_names(e, tmp_path / "square.png", "")
    # libpng writes to the process's stderr, below Python: capfd sees it.
    assert capfd.readouterr().err == ""


def test_colours_missing_from_a_palette_are_printed_as_plain_text(tmp_path, grid):
    scene_file = textured_square(tmp_path, noisy_png(tmp_path / "noise.png"))
    with pytest.raises(InputError) as e:
        load_scene(scene_file, grid)
    message = assert_names(e, scene_file, "objects.0.texture.palette")
    assert "np.str_" not in message and re.search(r"colours (#[0-9a-f]{6}, ){4}#[0-9a-f]{6} and \d+ more", message)


def test_a_gltf_primitive_naming_a_material_the_file_lacks_is_named(tmp_path, grid):
    doc = gltf_scene(SQUARE, TRIANGLES)
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}]
    doc["meshes"][0]["primitives"][0]["material"] = 3
    (tmp_path / "square.gltf").write_text(json.dumps(doc))
    scene = open_scene()
    scene["objects"] = [{"name": "square", "mesh": "square.gltf", "palette": {"#ff0000": "leaf"}}]
    with pytest.raises(InputError) as e:
        load_scene(write_scene(tmp_path / "scene.yaml", scene), grid)
    message = assert_names(e, tmp_path / "square.gltf", "meshes.0.primitives.0.material")
    assert "material 3 does not exist (the file has 1 materials)" in message


def test_a_receptor_table_with_a_byte_order_mark_is_read(tmp_path):
    """As a spreadsheet's "CSV UTF-8" writes it."""
    path = tmp_path / "receptors.csv"
    write_table(path, {"id": [0, 1], "side": ["right", "left"], "x": [0.0, 0.0], "y": [-1.0, 1.0],
                       "z": [0.0, 0.0], "ax": [0.0, 0.0], "ay": [-1.0, 1.0], "az": [0.0, 0.0],
                       "facet_diameter_um": [20.0, 20.0], "delta_phi_deg": [2.0, 2.0], "delta_rho_deg": [2.6, 2.6]})
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    assert list(read_receptors(path).id) == [0, 1]


def test_a_sample_count_beyond_reason_is_refused_before_any_work(tmp_path, capsys):
    from beeoptics import cli

    with pytest.raises(InputError) as e:
        validate_config({"trace": {"samples_per_receptor": 10 ** 9}}, CONFIG_SCHEMA, tmp_path / "config.yaml",
                        folders=False)
    assert "maximum of 65536" in assert_names(e, tmp_path / "config.yaml", "trace.samples_per_receptor")
    code = cli.main(["render", str(tmp_path / "receptors.csv"), str(DATA / "scenes" / "open" / "scene.yaml"),
                     "-o", str(tmp_path / "out"), "--samples", "1000000000", "--quiet"])
    assert (code, capsys.readouterr().err) == (2, "beeoptics: error: command line: --samples: 1000000000 is greater "
                                                  "than the maximum of 65536\n")
    assert not (tmp_path / "out").exists()
