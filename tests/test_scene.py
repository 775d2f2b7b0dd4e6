"""Scene meshes in every format the README names, and their patterns per face and per texel."""

import base64
import hashlib
import json
import shutil
import struct
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import pytest
import yaml

from beeoptics.io.errors import InputError
from beeoptics.io.meshfile import read_mesh
from beeoptics.io.validation import load_yaml, validate
from beeoptics.light.sensors import cone_samples
from beeoptics.light.scene import load_scene
from beeoptics.light.integrator import trace_paths
from conftest import ROOT, write_scene

FLOWER = Path(__file__).parent / "data" / "scenes" / "flower"
SKY = {"gaussian": {"base": 0.01, "peak": 0.05, "centre_nm": 400, "width_nm": 50}}


def write_gltf(path, vertices, faces, face_colours=None, uv=None):
    """A glTF 2.0 file (``.gltf`` with an embedded buffer, or ``.glb``).

    Faces of one colour form one primitive whose material has that
    ``baseColorFactor``, as exporters write them. ``uv`` holds per-vertex
    texture coordinates with v up (OBJ's convention); glTF's v points down.
    """
    vertices = np.asarray(vertices, np.float32)
    colours = np.zeros((len(faces), 3)) if face_colours is None else np.asarray(face_colours)
    groups = np.unique(colours, axis=0)
    blob, views, accessors = b"", [], []

    def add(array, kind, component, target):
        nonlocal blob
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": array.nbytes, "target": target})
        accessors.append({"bufferView": len(views) - 1, "componentType": component,
                          "count": len(array), "type": kind})
        blob += array.tobytes() + b"\0" * (-array.nbytes % 4)
        return len(accessors) - 1

    attributes = {"POSITION": add(vertices, "VEC3", 5126, 34962)}
    accessors[0].update(min=vertices.min(0).tolist(), max=vertices.max(0).tolist())
    if uv is not None:
        st = np.column_stack([uv[:, 0], 1.0 - uv[:, 1]]).astype(np.float32)
        attributes["TEXCOORD_0"] = add(st, "VEC2", 5126, 34962)
    primitives, materials = [], []
    for colour in groups:
        these = np.asarray(faces)[(colours == colour).all(1)].astype(np.uint32).ravel()
        primitives.append({"attributes": attributes, "indices": add(these, "SCALAR", 5125, 34963),
                           "material": len(materials)})
        materials.append({"pbrMetallicRoughness": {"baseColorFactor": [*map(float, colour), 1.0]}})
    gltf = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0, "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": primitives}], "materials": materials,
            "bufferViews": views, "accessors": accessors, "buffers": [{"byteLength": len(blob)}]}
    path = Path(path)
    if path.suffix == ".gltf":
        gltf["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
        path.write_text(json.dumps(gltf))
        return path
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(blob), b"BIN\0") + blob
    path.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)
    return path


def faces_and_materials(scene, name):
    """Each face of the named object as (centroid x, y, z, material), sorted: independent of face order."""
    o = next(o for o in scene.objects if o.name == name)
    rows = np.column_stack([o.vertices[o.faces].mean(1), o.face_material])
    return rows[np.lexsort(rows.T[::-1])]


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_a_gltf_flower_reads_as_its_obj_with_a_material_per_face(tmp_path, wavelengths, suffix):
    v, f, colours, _ = read_mesh(FLOWER / "daisy.obj", patterns=True)
    write_gltf(tmp_path / f"daisy{suffix}", v, f, colours)
    scene = yaml.safe_load((FLOWER / "scene.yaml").read_text())
    scene["objects"][1]["mesh"] = f"daisy{suffix}"
    spec = write_scene(tmp_path / "scene.yaml", scene)
    want = faces_and_materials(load_scene(FLOWER / "scene.yaml", wavelengths), "flower")
    got = faces_and_materials(load_scene(spec, wavelengths), "flower")
    assert len(np.unique(want[:, 3])) == 2  # the centre and the tips: the pattern is there to compare
    np.testing.assert_allclose(got, want, atol=1e-6)


def test_a_gltf_whose_face_corners_differ_in_colour_cannot_take_a_palette(tmp_path, wavelengths):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    path = tmp_path / "tri.gltf"
    write_gltf(path, v, [[0, 1, 2]])
    gltf = json.loads(path.read_text())
    # Per-vertex colours that differ round the one face: no colour for the face as a whole.
    colours = np.array([[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]], np.float32).tobytes()
    buffer = base64.b64decode(gltf["buffers"][0]["uri"].split(",")[1])
    gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(colours)})
    gltf["accessors"].append({"bufferView": len(gltf["bufferViews"]) - 1, "componentType": 5126,
                              "count": 3, "type": "VEC4"})
    buffer += colours
    gltf["buffers"] = [{"byteLength": len(buffer),
                        "uri": "data:application/octet-stream;base64," + base64.b64encode(buffer).decode()}]
    gltf["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = len(gltf["accessors"]) - 1
    del gltf["meshes"][0]["primitives"][0]["material"]
    path.write_text(json.dumps(gltf))
    spec = write_scene(tmp_path / "scene.yaml", {
        "name": "corners", "light": {"sky": "uniform", "radiance": 1.0, "sun": False},
        "eye": {"position_m": [0, 0, 1]}, "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"mesh": "tri.gltf", "palette": {"#ff0000": "grey"}}]})
    with pytest.raises(InputError, match="tri.gltf.*one colour per face"):
        load_scene(spec, wavelengths)


def write_meshlab_ply(path, vertices, faces, face_colours=None, vertex_colours=None, binary=True):
    """A PLY file as MeshLab (pymeshlab) writes it: colours per face (``save_face_color``) or per vertex."""
    import pymeshlab

    def rgba(c):
        return None if c is None else np.column_stack([np.asarray(c, float), np.ones(len(c))])

    kwargs = {k: v for k, v in (("f_color_matrix", rgba(face_colours)), ("v_color_matrix", rgba(vertex_colours)))
              if v is not None}
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.asarray(vertices, float), np.asarray(faces), **kwargs))
    ms.save_current_mesh(str(path), binary=binary, save_face_color=face_colours is not None,
                         save_vertex_color=vertex_colours is not None)
    return path


@pytest.mark.parametrize("binary", [True, False], ids=["binary", "ascii"])
def test_a_ply_with_face_colours_as_meshlab_writes_it_gets_its_materials_through_the_palette(tmp_path, wavelengths,
                                                                                            binary):
    v, f, colours, _ = read_mesh(FLOWER / "daisy.obj", patterns=True)
    write_meshlab_ply(tmp_path / "daisy.ply", v, f, face_colours=colours, binary=binary)
    assert b"element face" in (tmp_path / "daisy.ply").read_bytes()[:400]
    scene = yaml.safe_load((FLOWER / "scene.yaml").read_text())
    scene["objects"][1]["mesh"] = "daisy.ply"
    spec = write_scene(tmp_path / "scene.yaml", scene)
    want = faces_and_materials(load_scene(FLOWER / "scene.yaml", wavelengths), "flower")
    got = faces_and_materials(load_scene(spec, wavelengths), "flower")
    assert len(np.unique(want[:, 3])) == 2
    np.testing.assert_allclose(got, want, atol=1e-6)


def test_a_ply_with_vertex_colours_gives_a_face_the_colour_its_corners_share(tmp_path):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 0, 0]], float)
    corners = [[1, 0, 0], [1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0]]
    write_meshlab_ply(tmp_path / "two.ply", v, [[0, 1, 2], [1, 3, 2]], vertex_colours=corners)
    _, _, colours, _ = read_mesh(tmp_path / "two.ply", patterns=True)
    assert colours is None  # the second face's corners differ: no colour for it
    write_meshlab_ply(tmp_path / "one.ply", v, [[0, 1, 2], [1, 4, 3]], vertex_colours=corners)
    _, _, colours, _ = read_mesh(tmp_path / "one.ply", patterns=True)
    assert colours is None
    write_meshlab_ply(tmp_path / "ok.ply", v, [[0, 1, 2], [3, 4, 1]][:1], vertex_colours=corners)
    _, _, colours, _ = read_mesh(tmp_path / "ok.ply", patterns=True)
    np.testing.assert_array_equal(colours, [[1, 0, 0]])


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_a_textured_gltf_gives_each_texel_its_material(tmp_path, wavelengths, suffix):
    # A 1 m square, u along x and v along y, under a 2 × 2 checkerboard texture:
    # the image's top-left texel covers the square's corner at low x and high y.
    v = np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]], float)
    write_gltf(tmp_path / f"board{suffix}", v, [[0, 1, 2], [0, 2, 3]], uv=v[:, :2] + 0.5)
    image = np.array([[[1, 0, 0], [0, 0, 1]], [[0, 0, 1], [1, 0, 0]]], np.float32)
    out = oiio.ImageBuf(oiio.ImageSpec(2, 2, 3, oiio.UINT8))
    out.set_pixels(oiio.ROI(0, 2, 0, 2, 0, 1, 0, 3), image)
    assert out.write(str(tmp_path / "board.png"))
    spec = write_scene(tmp_path / "scene.yaml", {
        "name": "board", "light": {"sky": "uniform", "radiance": SKY, "sun": False},
        "eye": {"position_m": [0, 0, 1.0]},
        "materials": {"dark": {"reflectance": 0.1}, "pale": {"reflectance": 0.7}},
        "objects": [{"mesh": f"board{suffix}",
                     "texture": {"image": "board.png", "palette": {"#ff0000": "dark", "#0000ff": "pale"}}}]})
    scene = load_scene(spec, wavelengths)
    # One narrow receptor on each quadrant's centre, from straight above.
    targets = np.array([[-0.25, 0.25], [0.25, 0.25], [-0.25, -0.25], [0.25, -0.25]])
    axes = np.column_stack([targets, -np.ones(4)])
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    dirs, w = cone_samples(axes, 1.0, 16, 1)
    # Escaping only (the sky not sampled from the surface): the estimate is then exact.
    seen = trace_paths(scene, np.tile(scene.eye_position, (4, 1)), dirs, w, depth=2, seed=1, sky_sampling="escape")
    # A Lambertian square under a uniform sky, seen from above, is ρ times the sky: the bounce sees only sky.
    rho = np.array([0.1, 0.7, 0.7, 0.1])
    np.testing.assert_allclose(seen, rho[:, None] * scene.sky.basis[0], rtol=1e-9)


def test_measured_ground_is_feister_and_grewes_albedo(wavelengths):
    from beeoptics.light.materials import spectrum

    at = np.searchsorted(wavelengths, [300.0, 400.0, 500.0, 700.0])
    grass = spectrum({"ground": "grass"}, wavelengths, ".", "scene.yaml", "materials.soil.reflectance")[at]
    loam = spectrum({"ground": "loam"}, wavelengths, ".", "scene.yaml", "materials.soil.reflectance")[at]
    # Feister & Grewe (1995), as libRadtran tabulates them: grass 0.016 at 300 nm, loam 0.041.
    assert grass[0] == pytest.approx(0.016) and loam[0] == pytest.approx(0.041)
    # Green grass reflects far more in the red edge than in the UV; bare loam rises steadily.
    assert grass[-1] > 5 * grass[0] and np.all(np.diff(loam) > 0)
    with pytest.raises(InputError) as e:
        spectrum({"ground": "lawns"}, wavelengths, ".", "scene.yaml", "materials.soil.reflectance")
    assert "scene.yaml: materials.soil.reflectance.ground:" in str(e.value) and "did you mean 'lawn'?" in str(e.value)


def test_a_fred_median_is_the_median_of_the_spectra_it_names(wavelengths):
    from beeoptics.light import fred
    from beeoptics.light.materials import spectrum

    leaf = spectrum({"fred": {"part": "leaf upper side", "median": True}}, wavelengths, ".", "scene.yaml", "leaf")
    at = dict(zip(wavelengths, leaf))
    # A typical green leaf: a peak in the green, chlorophyll's trough in the red, little UV.
    assert at[550.0] > at[450.0] and at[550.0] > at[675.0] and at[350.0] < at[550.0]
    ids = fred.matching(genus="Senecio")
    assert 1 < len(ids) < 30
    want = np.median([fred.reflectance(i, wavelengths) for i in ids], axis=0)
    got = spectrum({"fred": {"genus": "Senecio", "median": True}}, wavelengths, ".", "scene.yaml", "petal")
    np.testing.assert_array_equal(got, want)
    with pytest.raises(InputError, match="no FReD spectrum"):
        spectrum({"fred": {"genus": "Nonexistentia", "median": True}}, wavelengths, ".", "scene.yaml", "petal")


@pytest.mark.parametrize("median", [None, False])
def test_a_fred_record_by_name_is_the_one_record_the_fields_match(tmp_path, wavelengths, median):
    """The scene schema's form {fred: {genus, species, part}}, through the schema (which fills in median)."""
    from beeoptics.light import fred

    name = {"genus": "Acanthus", "species": "Syriacus", "part": "leaf lower side"}
    scene = yaml.safe_load((ROOT / "tests" / "data" / "scenes" / "open" / "scene.yaml").read_text())
    scene["materials"]["leaf"]["reflectance"] = {"fred": {**name, **({} if median is None else {"median": median})}}
    loaded = load_scene(write_scene(tmp_path / "scene.yaml", scene), wavelengths)
    want = fred.reflectance(fred.find(**name), wavelengths)
    np.testing.assert_array_equal(loaded.reflectance[loaded.material_names.index("leaf")], want)


def test_a_scene_read_without_its_geometry_has_the_same_light_and_materials(wavelengths):
    """geometry=False (what gathering the responses needs) keeps the sky, sun and materials, and no object."""
    path = ROOT / "tests" / "data" / "scenes" / "flower" / "scene.yaml"
    whole, light = load_scene(path, wavelengths), load_scene(path, wavelengths, geometry=False)
    assert light.objects == [] and whole.objects
    assert light.material_names == whole.material_names
    np.testing.assert_array_equal(light.reflectance, whole.reflectance)
    np.testing.assert_array_equal(light.sky.basis, whole.sky.basis)
    np.testing.assert_array_equal(light.sun.radiance, whole.sun.radiance)


def test_a_loaded_scene_is_cached_and_mapped_back_while_its_files_are_unchanged(tmp_path, wavelengths, monkeypatch,
                                                                                  caplog):
    from beeoptics.light import scenecache

    monkeypatch.setenv("BEEOPTICS_CACHE", str(tmp_path / "cache"))
    folder = tmp_path / "scene"
    shutil.copytree(ROOT / "tests" / "data" / "scenes" / "flower", folder)
    first = load_scene(folder / "scene.yaml", wavelengths)
    again = load_scene(folder / "scene.yaml", wavelengths)
    assert isinstance(again.objects[1].vertices, np.memmap)
    for a, b in zip(first.objects, again.objects):
        np.testing.assert_array_equal(a.vertices, b.vertices)
        np.testing.assert_array_equal(a.faces, b.faces)
        np.testing.assert_array_equal(a.face_material, b.face_material)
    np.testing.assert_array_equal(first.reflectance, again.reflectance)
    # An edited mesh is another key: read from the file again.
    mesh = folder / "daisy.obj"
    mesh.write_text(mesh.read_text().replace("v ", "v  ", 1))
    edited = load_scene(folder / "scene.yaml", wavelengths)
    assert not isinstance(edited.objects[1].vertices, np.memmap)
    # A broken entry is refused, named, and written again.
    key = scenecache.scene_key(validate(load_yaml(folder / "scene.yaml"), "scene", folder / "scene.yaml"), folder,
                               wavelengths)
    entry = tmp_path / "cache" / key
    (entry / "object1_vertices.npy").write_bytes(b"broken")
    with caplog.at_level("WARNING", logger="beeoptics"):
        fixed = load_scene(folder / "scene.yaml", wavelengths)
    assert any("unreadable" in r.getMessage() and str(entry) in r.getMessage() for r in caplog.records)
    np.testing.assert_array_equal(fixed.objects[1].vertices, edited.objects[1].vertices)
    assert isinstance(load_scene(folder / "scene.yaml", wavelengths).objects[1].vertices, np.memmap)


def loaded(path, wavelengths, cache=True):
    """The SHA-256 of a scene's objects' arrays and its reflectances, or the one line of the error loading it
    gave."""
    try:
        scene = load_scene(path, wavelengths, cache=cache)
    except InputError as e:
        return str(e)
    h = hashlib.sha256(scene.reflectance.tobytes())
    for a in (a for o in scene.objects for a in (o.vertices, o.faces, o.face_material) if a is not None):
        h.update(np.asarray(a).tobytes())
    return h.hexdigest()


def swap_colours(folder):
    mtl = folder / "daisy.mtl"
    mtl.write_text(mtl.read_text().replace("Kd 0.6 0.4 0.0", "Kd swapped").replace("Kd 1.0 1.0 0.4", "Kd 0.6 0.4 0.0")
                   .replace("Kd swapped", "Kd 1.0 1.0 0.4"))


def use_a_csv_spectrum(folder):
    """The flower's leaf from a table of spectra, in pavo's layout."""
    data = yaml.safe_load((folder / "scene.yaml").read_text())
    data["materials"]["leaf"] = {"reflectance": {"csv": {"file": "spectra.csv", "column": "leaf"}}}
    write_scene(folder / "scene.yaml", data)
    (folder / "spectra.csv").write_text("wl,leaf\n300,0.05\n800,0.45\n")


@pytest.mark.parametrize("edit", [
    swap_colours,
    lambda folder: (folder / "daisy.mtl").write_text(""),
    lambda folder: (folder / "daisy.mtl").unlink(),
    lambda folder: (folder / "spectra.csv").write_text("wl,leaf\n300,0.30\n800,0.10\n"),
], ids=["mtl colours swapped", "mtl emptied", "mtl deleted", "spectrum csv changed"])
def test_a_cached_flower_is_read_again_when_a_file_that_made_it_changes(tmp_path, wavelengths, monkeypatch, edit):
    # The palette maps the colours of the OBJ's material library (daisy.mtl), which scene.yaml does not name.
    monkeypatch.setenv("BEEOPTICS_CACHE", str(tmp_path / "cache"))
    folder = tmp_path / "flower"
    shutil.copytree(FLOWER, folder)
    use_a_csv_spectrum(folder)
    before = loaded(folder / "scene.yaml", wavelengths)
    assert loaded(folder / "scene.yaml", wavelengths) == before  # from the cache
    edit(folder)
    fresh = loaded(folder / "scene.yaml", wavelengths, cache=False)
    assert fresh != before
    assert loaded(folder / "scene.yaml", wavelengths) == fresh


def test_a_deleted_material_library_is_named_in_one_line(tmp_path, wavelengths, monkeypatch):
    monkeypatch.setenv("BEEOPTICS_CACHE", str(tmp_path / "cache"))
    folder = tmp_path / "flower"
    shutil.copytree(FLOWER, folder)
    load_scene(folder / "scene.yaml", wavelengths)
    (folder / "daisy.mtl").unlink()
    with pytest.raises(InputError) as e:
        load_scene(folder / "scene.yaml", wavelengths)
    assert str(e.value) == f"{folder / 'daisy.obj'}: line 2: its material library daisy.mtl does not exist"


@pytest.mark.parametrize("change", ["buffer", "image", "buffer deleted"])
def test_a_cached_gltf_is_read_again_when_its_buffer_or_image_changes(tmp_path, wavelengths, monkeypatch, change):
    monkeypatch.setenv("BEEOPTICS_CACHE", str(tmp_path / "cache"))
    v = np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]], float)
    gltf = write_gltf(tmp_path / "board.gltf", v, [[0, 1, 2], [0, 2, 3]], uv=v[:, :2] + 0.5)
    # Its buffer beside it, and a base colour image (which pymeshlab reads), as exporters write them.
    doc = json.loads(gltf.read_text())
    (tmp_path / "board.bin").write_bytes(base64.b64decode(doc["buffers"][0]["uri"].split(",", 1)[1]))
    doc["buffers"][0]["uri"] = "board.bin"
    doc["images"], doc["textures"] = [{"uri": "skin.png"}], [{"source": 0}]
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    gltf.write_text(json.dumps(doc))

    def skin(value):
        image = oiio.ImageBuf(oiio.ImageSpec(2, 2, 3, oiio.UINT8))
        oiio.ImageBufAlgo.fill(image, [value] * 3)
        assert image.write(str(tmp_path / "skin.png"))

    skin(0.2)
    spec = write_scene(tmp_path / "scene.yaml", {
        "name": "board", "light": {"sky": "uniform", "radiance": SKY, "sun": False},
        "eye": {"position_m": [0, 0, 1.0]}, "materials": {"pale": {"reflectance": 0.7}},
        "objects": [{"mesh": "board.gltf", "material": "pale"}]})
    before = loaded(spec, wavelengths)
    assert isinstance(load_scene(spec, wavelengths).objects[0].vertices, np.memmap)  # from the cache
    if change == "buffer":
        buffer = tmp_path / "board.bin"
        blob = bytearray(buffer.read_bytes())
        blob[:48] = (2 * v.astype(np.float32)).tobytes()  # the vertices, twice as far apart
        buffer.write_bytes(bytes(blob))
        assert loaded(spec, wavelengths) == loaded(spec, wavelengths, cache=False) != before
    elif change == "buffer deleted":
        (tmp_path / "board.bin").unlink()
        assert loaded(spec, wavelengths) == f"{gltf}: buffers: its buffer board.bin does not exist"
    else:
        # The image changes no colour a palette could map (a face's is its material's baseColorFactor),
        # but pymeshlab reads it: the scene is read again all the same.
        skin(0.8)
        assert not isinstance(load_scene(spec, wavelengths).objects[0].vertices, np.memmap)


def test_a_cached_light_is_made_again_when_a_table_it_read_changes(tmp_path, wavelengths, monkeypatch):
    # The package's own table of albedos, which no scene names, read for a sky's radiance.
    from beeoptics.light import materials

    monkeypatch.setenv("BEEOPTICS_CACHE", str(tmp_path / "cache"))
    table = tmp_path / "albedos.csv"
    shutil.copyfile(materials.GROUND_ALBEDO_FILE, table)
    monkeypatch.setattr(materials, "GROUND_ALBEDO_FILE", table)
    spec = write_scene(tmp_path / "scene" / "scene.yaml", {
        "name": "loam", "light": {"sky": "uniform", "radiance": {"ground": "loam"}, "sun": False},
        "eye": {"position_m": [0, 0, 1.0]}, "materials": {"grey": {"reflectance": 0.5}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0}}, "material": "grey"}]})
    before = load_scene(spec, wavelengths, geometry=False).sky.basis
    rows = table.read_text().splitlines()
    table.write_text("\n".join([rows[0], *(r.replace(",0.", ",0.0", 1) for r in rows[1:])]) + "\n")  # loam / 10
    fresh = load_scene(spec, wavelengths, geometry=False, cache=False).sky.basis
    assert not np.array_equal(fresh, before)
    np.testing.assert_array_equal(load_scene(spec, wavelengths, geometry=False).sky.basis, fresh)


def test_the_cache_keys_on_the_code_and_data_that_make_a_scene(tmp_path):
    from beeoptics.light import scenecache

    package = Path(scenecache.__file__).parents[1]
    copy = tmp_path / "beeoptics"
    for name in scenecache.CODE:
        (shutil.copytree if (package / name).is_dir() else shutil.copyfile)(package / name, copy / name)
    # The same files give the same key wherever the package lies; compiled caches do not count.
    (copy / "light" / "__pycache__").mkdir(exist_ok=True)
    (copy / "light" / "__pycache__" / "scene.nbi").write_bytes(b"numba's index")
    assert scenecache.code_digest(copy) == scenecache.code_digest()
    for changed in ("light/data/ground_albedo_feister_grewe1995.csv", "io/schemas/scene.schema.yaml",
                    "light/materials.py", "spectra.py"):
        before = scenecache.code_digest.__wrapped__(copy)
        (copy / changed).write_text((copy / changed).read_text() + "\n")
        assert scenecache.code_digest.__wrapped__(copy) != before, changed


def test_a_cache_that_cannot_be_written_is_not_used(tmp_path, wavelengths, monkeypatch):
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    monkeypatch.setenv("BEEOPTICS_CACHE", str(blocked / "cache"))
    scene = load_scene(ROOT / "tests" / "data" / "scenes" / "flower" / "scene.yaml", wavelengths)
    assert len(scene.objects) == 2 and not isinstance(scene.objects[1].vertices, np.memmap)


def test_a_scenes_light_is_cached_apart_and_comes_back_as_it_was_made(tmp_path, wavelengths, monkeypatch, caplog):
    from beeoptics.light import scene as scene_module
    from beeoptics.light import scenecache

    monkeypatch.setenv("BEEOPTICS_CACHE", str(tmp_path / "cache"))
    made = []
    make = scene_module._made_light
    monkeypatch.setattr(scene_module, "_made_light", lambda *a: made.append(a[0]) or make(*a))
    for name in ("flower", "open"):  # a clear sky with the sun; a uniform sky without it
        path = ROOT / "tests" / "data" / "scenes" / name / "scene.yaml"
        first, again = load_scene(path, wavelengths), load_scene(path, wavelengths)
        for a, b in ((first.sky, again.sky), (first.sun, again.sun)):
            assert type(a) is type(b)
            for x, y in zip(a or (), b or ()):
                assert type(x) is type(y) or isinstance(x, np.ndarray) and x.dtype == y.dtype, (name, x, y)
                np.testing.assert_array_equal(x, y)
    assert len(made) == 2, "a light was made again though its section and files were unchanged"
    # Another light (a sweep's, a flight's, the compass's) is made, then cached as well.
    flower = ROOT / "tests" / "data" / "scenes" / "flower" / "scene.yaml"
    hazy = load_scene(flower, wavelengths, light={"turbidity": 6.0})
    assert len(made) == 3 and not np.array_equal(hazy.sky.basis, load_scene(flower, wavelengths).sky.basis)
    # Only the materials, for the stages that need no geometry: from the cache, no spectrum read again.
    monkeypatch.setattr(scene_module, "material", lambda *a: pytest.fail("a material was read again"))
    light_only = load_scene(flower, wavelengths, geometry=False)
    assert light_only.objects == [] and len(made) == 3
    # A broken entry is refused, named, and made again.
    data = validate(load_yaml(flower), "scene", flower)
    entry = tmp_path / "cache" / "lights" / f"{scenecache.scene_key(data, flower.parent, wavelengths, ('light',))}.npz"
    entry.write_bytes(b"broken")
    with caplog.at_level("WARNING", logger="beeoptics"):
        load_scene(flower, wavelengths, geometry=False)
    assert any("unreadable" in r.getMessage() and str(entry) in r.getMessage() for r in caplog.records)
    assert len(made) == 4
