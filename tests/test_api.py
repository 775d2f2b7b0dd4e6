"""The Python API: an eye, a scene and a look give what the command line writes, and refuse bad input."""

import numpy as np
import pytest

import beeoptics
import beeoptics.tracing
from beeoptics import api, cli
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import write_table
from beeoptics.light.scene import load_scene
from beeoptics.pipeline import eyes
from beeoptics.replicates import standard_error
from beeoptics.vision.receptorset import curves
from conftest import ROOT

DATA = ROOT / "tests" / "data"
EYE = DATA / "eyes" / "tiny" / "eye.yaml"
FLOWER = DATA / "scenes" / "flower" / "scene.yaml"
#: As tests/test_cli.py renders: few rays on a coarse spectrum.
FAST = {"samples": 4, "depth": 1}
STEP_NM = 20


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("api") / "tiny"
    assert cli.main(["build-eye", str(EYE), "-o", str(out), "--quiet"]) == 0
    return out


@pytest.fixture(scope="module")
def eye():
    return beeoptics.load_eye(EYE)


@pytest.fixture(scope="module")
def scene():
    return beeoptics.load_scene(FLOWER, step_nm=STEP_NM)


@pytest.fixture(scope="module")
def view(eye, scene):
    return beeoptics.look(eye, scene, **FAST, seed=3)


def test_an_eye_yaml_is_built_as_build_eye_builds_it_then_read_from_the_cache(eye, built, monkeypatch):
    by_tool = read_receptors(built / "receptors.csv")
    for field in ("id", "side", "position", "axis", "facet_diameter_um", "delta_phi_deg", "delta_rho_deg"):
        np.testing.assert_array_equal(getattr(eye.table, field), getattr(by_tool, field), err_msg=field)
    assert list(eye.receptor_set.classes) == ["UV", "B", "G"]
    assert list(eye.receptors.columns[:2]) == ["id", "side"] and len(eye.receptors) == len(by_tool.id)

    fly = beeoptics.load_eye(built / "receptors.csv", receptor_set="drosophila_melanogaster")
    assert set(fly.receptors.ommatidium) == {name for name, *_ in fly.receptor_set.mosaic}
    assert "ommatidium" not in eye.receptors

    def refused(*args, **kwargs):
        raise AssertionError("built again")
    monkeypatch.setattr(eyes, "build_facets", refused)
    np.testing.assert_array_equal(beeoptics.load_eye(EYE).table.axis, eye.table.axis)


def test_a_look_gives_the_bytes_render_writes(built, eye, view, tmp_path):
    out = tmp_path / "rendered"
    assert cli.main([str(a) for a in ["render", built / "receptors.csv", FLOWER, "--eye", EYE, "-o", out,
                                      "--samples", 4, "--depth", 1, "--seed", 3, "--step-nm", STEP_NM,
                                      "--width-px", 32, "--quiet"]]) == 0
    write_table(tmp_path / "responses.csv", view.table())
    assert (tmp_path / "responses.csv").read_bytes() == (out / "responses.csv").read_bytes()
    rendered = np.load(out / "irradiance.npz")
    np.testing.assert_array_equal(view.radiance.astype(np.float32), rendered["radiance"])
    np.testing.assert_array_equal(view.wavelengths_nm, rendered["wavelength_nm"])
    classes = list(eye.receptor_set.classes)
    assert list(view.catches.columns) == ["id", "side", "azimuth_deg", "elevation_deg",
                                          *[c for k in classes for c in (k, f"se_{k}")]]
    # Made without the colour, the catches are the table's to the last bit.
    catches = view.catches
    for column in [c for k in classes for c in (k, f"se_{k}")]:
        np.testing.assert_array_equal(catches[column], view.table()[column])
    assert {"hex_x", "se_hex_x", "coc_A", "rnl_dS", "se_rnl_dS"} <= set(view.colour.columns)


def test_the_same_look_on_other_threads_is_the_same_view(eye, scene, view):
    again = beeoptics.look(eye, scene, **FAST, seed=3, threads=1)
    assert again.table().equals(view.table())


def test_a_look_and_cones_make_their_errors_when_first_asked_for_them_as_the_trace_made_them(eye, scene, view,
                                                                                              monkeypatch):
    made = []
    monkeypatch.setattr(beeoptics.tracing, "standard_error", lambda *a, **k: made.append(1) or standard_error(*a, **k))
    lazy = beeoptics.look(eye, scene, **FAST, seed=3, threads=1)
    t, r = eye.table, scene.scene.eye_rotation
    cones = beeoptics.look_cones(scene, t.position * 1e-3 @ r.T + scene.scene.eye_position, t.axis @ r.T,
                                 t.delta_rho_deg, streams=t.id, receptor_set=eye.receptor_set, **FAST, seed=3)
    np.testing.assert_array_equal(lazy.radiance, view.radiance)
    np.testing.assert_array_equal(cones.radiance, view.radiance)
    assert not made  # a flight's frames and a compass, which keep the radiance alone, never make them
    # Made at once, as a trace asked for them makes them.
    errors, wl = {}, scene.wavelengths_nm
    settings = api._settings(api._config(scene, FAST["samples"], FAST["depth"], 3, None, None, None, None, "look"),
                             1, eye.receptor_set)
    beeoptics.tracing.trace_receptors(scene.scene, t, 0, len(t.id), settings, len(wl), rs=scene.raycasting,
                                      errors=errors, sensitivities=(wl, curves(eye.receptor_set, wl, "species")))
    assert made
    for traced in (lazy, cones):
        np.testing.assert_array_equal(traced.radiance_se, errors["radiance_se"])
        np.testing.assert_array_equal(traced.replicate_catches, errors["catches"])


def test_turning_the_head_turns_every_axis_about_the_vertical(eye, scene, view):
    # The flower scene's head: heading 0, pitch -10; a heading of 90 keeps its pitch and turns it about z.
    turned = beeoptics.look(eye, scene, **FAST, seed=3, heading_deg=90.0)
    np.testing.assert_allclose(((turned.catches.azimuth_deg - view.catches.azimuth_deg) % 360.0), 90.0, atol=1e-9)
    np.testing.assert_allclose(turned.catches.elevation_deg, view.catches.elevation_deg, atol=1e-9)
    same = beeoptics.look(eye, scene, **FAST, seed=3, position_m=[0.0, 0.0, 0.1], pitch_deg=-10.0)
    assert same.table().equals(view.table())


def test_a_scene_relit_is_the_scene_loaded_under_that_light(scene):
    light = {"sun_elevation_deg": 25.0, "turbidity": 4.0}
    relit = scene.with_light(**light)
    loaded = load_scene(FLOWER, scene.wavelengths_nm, light)
    np.testing.assert_array_equal(relit.scene.sun.radiance, loaded.sun.radiance)
    np.testing.assert_array_equal(relit.scene.sky.basis, loaded.sky.basis)
    assert not np.array_equal(relit.scene.sun.radiance, scene.scene.sun.radiance)
    assert relit.raycasting is scene.raycasting  # the geometry is not loaded again


def test_a_scene_shows_its_objects_materials_and_the_light_it_is_lit_by(scene):
    # tests/data/scenes/flower/scene.yaml: a ground of leaf, a flower whose palette names centre and tip.
    assert scene.objects[["name", "materials"]].values.tolist() == [["ground", "leaf"], ["flower", "centre tip"]]
    lit = scene.lighting
    assert (lit["sun_elevation_deg"], lit["turbidity"], lit["sky"]) == (50.0, 3.0, "hosek_wilkie")
    assert lit["day_of_year"] == 172  # the schema's default, which the file does not give
    relit = scene.with_light(sun_elevation_deg=25.0).with_light(turbidity=4.0).lighting
    assert (relit["sun_elevation_deg"], relit["turbidity"], relit["sun_azimuth_deg"]) == (25.0, 4.0, 150.0)


def test_a_scene_shows_how_each_material_s_surface_scatters_and_emits(tmp_path):
    import shutil

    import yaml

    doc = yaml.safe_load(FLOWER.read_text())
    doc["materials"].update({"sheen": {"reflectance": 0.2, "gloss": {"specular": 0.04, "exponent": 50}},
                             "wet": {"reflectance": 0.0, "coating": {"roughness": 0.001, "refractive_index": 1.3334}},
                             "lamp": {"reflectance": 0.5, "emission": 2.0}})
    shutil.copy(FLOWER.parent / "daisy.obj", tmp_path)
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(doc))
    surfaces = beeoptics.load_scene(tmp_path / "scene.yaml", step_nm=STEP_NM, geometry=False).surfaces
    assert surfaces.kind.to_dict() == {"centre": "lambertian", "tip": "lambertian", "leaf": "lambertian",
                                       "sheen": "gloss", "wet": "coating", "lamp": "lambertian"}
    assert surfaces.loc["sheen", ["specular", "exponent"]].tolist() == [0.04, 50.0]
    assert surfaces.loc["wet", ["roughness", "refractive_index"]].tolist() == [0.001, 1.3334]
    assert surfaces.loc["lamp", "emission_peak"] == 2.0 and surfaces.loc["leaf", "emission_peak"] == 0.0
    # What a kind does not have is not shown as a number: a Lambertian surface has no lobe and no η.
    assert surfaces.loc["leaf", ["specular", "exponent", "roughness", "refractive_index"]].isna().all()


def test_an_eye_names_each_receptor_s_classes_and_a_view_labels_its_radiance(eye, view):
    assert set(eye.receptors["classes"]) == {"UV B G"}
    fly = beeoptics.load_eye(ROOT / "eyes" / "drosophila_melanogaster" / "ommatidia.csv",
                             receptor_set="drosophila_melanogaster").receptors
    # Wernet et al. (2006): a pale ommatidium's R7 and R8 hold Rh3 and Rh5, a yellow one's Rh4 and Rh6.
    pale = fly.ommatidium == "pale"
    assert set(fly.classes[pale]) == {"R1_6 R7p R8p"} and set(fly.classes[~pale]) == {"R1_6 R7y R8y"}
    radiance, se = view.spectral_radiance, view.spectral_radiance_se
    assert radiance.index.name == "id" and radiance.columns.name == "wavelength_nm"
    np.testing.assert_array_equal(radiance.index, eye.table.id)
    np.testing.assert_array_equal(radiance.columns, view.wavelengths_nm)
    np.testing.assert_array_equal(radiance.to_numpy(), view.radiance)
    np.testing.assert_array_equal(se.to_numpy(), view.radiance_se)


@pytest.mark.parametrize("suffix", [".glb", ".eye"])
def test_an_eye_read_from_oces_or_compoundray_is_the_eye_written(eye, tmp_path, suffix):
    from beeoptics.io.interchange import write_compoundray_eye
    from beeoptics.io.oces import write_oces

    path = tmp_path / f"tiny{suffix}"
    (write_oces if suffix == ".glb" else write_compoundray_eye)(path, eye.table)
    read = beeoptics.load_eye(path)
    assert read.receptor_set.name == eye.receptor_set.name and repr(read).startswith(f"Eye({str(path)!r}: ")
    np.testing.assert_allclose(read.table.axis, eye.table.axis, atol=1e-6)
    np.testing.assert_allclose(read.table.delta_rho_deg, eye.table.delta_rho_deg, rtol=1e-5)


def test_looks_trace_frame_after_frame_the_first_the_look_from_its_pose(eye, scene, view):
    here = {"position_m": scene.scene.eye_position, "rotation": scene.scene.eye_rotation}
    turned = {"position_m": [0.0, 0.0, 0.1], "heading_deg": 90.0, "pitch_deg": -10.0}
    counts = {}
    first, second = beeoptics.looks(eye, scene, [here, turned], **FAST, seed=3, counts=counts)
    assert first.table().equals(view.table())
    np.testing.assert_allclose(first.relative, view.relative, rtol=1e-12)
    # The second frame is at its own pose, drawing random numbers of its own (not the look's from there).
    np.testing.assert_allclose(second.directions, beeoptics.look(eye, scene, **FAST, **turned).directions)
    assert counts["cast"] == first.counts["cast"] > 0


def test_a_view_gives_its_images_as_arrays_and_its_figures(eye, view):
    images = view.images(width_px=32, field_width_px=72)
    assert images["field_map3"].shape == (36, 72, 3) and images["field_eyes"].shape == (36, 72)
    retinal = ["voronoi_map3", "voronoi_map2", "density_map3", "density_map3_normalised", "channel_uv",
               "channel_b", "channel_g"]
    assert set(images) == {"field_map3", "field_map2", "field_eyes", *retinal}
    for name in retinal:
        assert images[name].shape[:2] == images["voronoi_map3"].shape[:2]
        shown = images[name][np.isfinite(images[name])]
        assert shown.size and shown.min() >= 0.0 and shown.max() <= 1.0, name
    # What no receptor sees is NaN on the map, and the eyes' bits say which those directions are.
    np.testing.assert_array_equal(np.isnan(images["field_map3"]).all(-1), images["field_eyes"] == 0)
    with pytest.raises(InputError) as refused:
        view.plot("mosaic")
    assert view.plot("channel_uv", width_px=32).axes
    assert refused.value.field == "kind"


def test_any_cones_traced_as_a_looks_receptors_are_its_view_bit_for_bit(eye, scene, view):
    """Cones at the receptors' places, drawing their ids' random numbers, are the look's receptors: their
    radiance, replicates, Stokes vectors and catches (over the acceptance: the view's table's) the look's."""
    t, r = eye.table, scene.scene.eye_rotation
    cones = (scene, t.position * 1e-3 @ r.T + scene.scene.eye_position, t.axis @ r.T, t.delta_rho_deg)
    traced = beeoptics.look_cones(*cones, streams=t.id, receptor_set=eye.receptor_set, **FAST, seed=3)
    np.testing.assert_array_equal(traced.radiance, view.radiance)
    np.testing.assert_array_equal(traced.replicate_catches, view.replicate_catches)
    classes = list(eye.receptor_set.classes)
    np.testing.assert_array_equal(beeoptics.catches(traced.radiance, scene.wavelengths_nm, eye.receptor_set,
                                                    delta_rho_deg=t.delta_rho_deg), view.catches[classes])
    polarised = beeoptics.look_cones(*cones, streams=t.id, dorsal=r[:, 2], **FAST, seed=3)
    np.testing.assert_array_equal(polarised.radiance, beeoptics.look(eye, scene, **FAST, seed=3, polarised=True).stokes)
    # The same light with nothing in it: the ground's receptors see the sky below the horizon too.
    empty = scene.without_objects()
    assert not empty.scene.objects and empty.scene.sky is scene.scene.sky and len(scene.scene.objects)


@pytest.mark.parametrize("call, field", [
    (lambda e, s: beeoptics.look(e, s, samples=0), "trace.samples_per_receptor"),
    (lambda e, s: beeoptics.look(e, s, **FAST, background="granite"), "background"),
    (lambda e, s: beeoptics.load_eye(EYE.with_name("none.yaml")), ""),
    (lambda e, s: beeoptics.load_eye(DATA / "none.eye", unit="mm"), "unit"),
    (lambda e, s: next(beeoptics.looks(e, s, [{"position_m": [0.0, 0.1]}], **FAST)), "position_m"),
    (lambda e, s: next(beeoptics.looks(e, s, [{"position_m": [0.0, 0.0, 0.1], "rotation": np.eye(2)}])), "rotation"),
    (lambda e, s: beeoptics.look(e, s, **FAST, part=2, parts=2), "part"),
    (lambda e, s: beeoptics.look_cones(s, np.zeros((2, 3)), [[0.0, 0.0, 1.0]], 2.0), "axes"),
    (lambda e, s: beeoptics.look_cones(s, np.zeros((1, 3)), [[0.0, 0.0, 1.0]], -2.0), "delta_rho_deg"),
    (lambda e, s: beeoptics.catches(s.wavelengths_nm[None], s.wavelengths_nm, e.receptor_set, classes=["R"]), "classes"),
])
def test_bad_input_is_refused_naming_the_field(eye, scene, call, field):
    with pytest.raises(InputError) as refused:
        call(eye, scene)
    assert refused.value.field == field


def test_a_look_traces_its_samples_or_to_the_precision_asked(eye, scene):
    """By default each receptor takes the configuration's samples; asked a precision (the animal's, ``auto``,
    or a relative standard error), each takes its own, after a pilot of 64, whatever the samples given."""
    np.testing.assert_array_equal(beeoptics.look(eye, scene, samples=16, depth=1, seed=3).samples, 16)
    np.testing.assert_array_equal(beeoptics.look(eye, scene, depth=1, seed=3).samples, 256)
    animal = beeoptics.look(eye, scene, precision="auto", depth=1, seed=3).samples
    asked = beeoptics.look(eye, scene, samples=16, precision=0.05, depth=1, seed=3).samples
    for samples in (animal, asked):
        assert np.ptp(samples) > 0 and samples.min() >= 64
    assert not np.array_equal(animal, asked)
