"""Other species' measured eyes: micro-CT bumblebees and honey bees, Buchner's fruit fly, and their comparison."""

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from beeoptics.cli import main
from beeoptics.eye.description import load_eye, load_eye_mesh
from beeoptics.io.receptortable import read_receptors
from beeoptics.vision.receptorset import lacking, load_receptor_set, ommatidium_types, receptor_set_of
from conftest import ROOT, build_eye_files

EYES = ROOT / "eyes"
CT = {f"bombus_terrestris_{s}": f"BT_{s}" for s in ("77966", "77967", "77970", "77971", "77973", "77974")}
CT |= {f"apis_mellifera_{s}": f"AM_{s}" for s in ("60185", "60186")}
FLY = "drosophila_melanogaster"
#: How strawlab's model of Buchner's map sets the fly's Δρ (eyes/drosophila_melanogaster/eye.yaml).
FLY_DELTA_RHO_PER_DELTA_PHI = 1.1


@pytest.fixture(scope="module")
def smallest_bumblebee(tmp_path_factory):
    out = build_eye_files(EYES / "bombus_terrestris_77973" / "eye.yaml", tmp_path_factory.mktemp("bt"))
    return {k: Path(v) for k, v in out.items()}


@pytest.fixture(scope="module")
def fly(tmp_path_factory):
    out = build_eye_files(EYES / FLY / "eye.yaml", tmp_path_factory.mktemp("fly"))
    return {k: Path(v) for k, v in out.items()}


@pytest.mark.parametrize("name", [*CT, FLY])
def test_every_measured_eye_names_its_source_licence_and_frame(name):
    doc = yaml.safe_load((EYES / name / "eye.yaml").read_text())
    measured = doc.get("cornea") or doc["ommatidia"]
    assert measured["source"] and measured["licence"] and "frame" in measured["converted_from"]
    assert (EYES / name / "ATTRIBUTION.md").is_file()
    eye = load_eye(EYES / name / "eye.yaml")
    assert receptor_set_of(eye.path).species == doc["species"]
    # The frame the cornea's points give: local z leaves the eye laterally, on its own (right) side.
    assert eye.rotation[2, 1] < -0.3


@pytest.mark.parametrize("name", sorted(CT))
def test_a_ct_cornea_is_the_shared_file_written_by_the_converter(name, shared_data, tmp_path):
    source = shared_data / "eyes_ct" / f"{CT[name]}-real.eye"
    out = tmp_path / "cornea.csv"
    assert main(["convert", str(source), str(out), "--frame", "x=left,y=ventral,z=posterior", "--only", "right"]) == 0
    assert out.read_bytes() == (EYES / name / "cornea.csv").read_bytes()


def test_the_fly_map_is_buchners_file_written_by_the_converter(shared_data, tmp_path):
    out = tmp_path / "ommatidia.csv"
    assert main(["convert", str(shared_data / "drosophila" / "receptor_directions_buchner71.csv"), str(out),
                 "--directions", "--frame", "head", "--halves", "left,right", "--sphere-mm", "0.185",
                 "--centre-mm", "0,-0.255,0", "--delta-rho-per-delta-phi", "1.1", "--only", "right"]) == 0
    assert out.read_bytes() == (EYES / FLY / "ommatidia.csv").read_bytes()


@pytest.mark.parametrize("name, published", [("bombus_terrestris_77970", 2.2), ("bombus_terrestris_77971", 2.4),
                                             ("apis_mellifera_60185", 2.4), ("apis_mellifera_60186", 2.4)])
def test_the_reconstructed_cornea_has_the_published_area(name, published):
    # Taylor et al. (2019): 2.2 and 2.4 mm² for the medium bumblebees, 2.4 mm² for both honey bees.
    import igl

    vertices, faces = load_eye_mesh(load_eye(EYES / name / "eye.yaml"))
    area = igl.doublearea(vertices, faces).sum() / 2
    assert area == pytest.approx(published, rel=0.1)


def test_a_bumblebee_is_built_the_papers_way_on_its_measured_cornea(smallest_bumblebee):
    quality = json.loads(smallest_bumblebee["quality"].read_text())
    eye = load_eye(EYES / "bombus_terrestris_77973" / "eye.yaml")
    assert quality["facets_per_eye"] == eye.facet_count
    assert all(quality["checks"].values()), quality["checks"]
    table = read_receptors(smallest_bumblebee["receptors"])
    # Taylor et al.'s assumption: Δρ = Δφ, receptor by receptor; the CT file's 2.6° placeholder is gone.
    np.testing.assert_allclose(table.delta_rho_deg, table.delta_phi_deg)
    assert not np.isclose(table.delta_rho_deg, 2.6).all()
    # The facets are not the file's 25-µm samples: fewer than the samples would be, larger than the grid.
    cornea = read_receptors(EYES / "bombus_terrestris_77973" / "cornea.csv")
    assert quality["facets_per_eye"] != len(cornea.id)
    # The largest facet is the published (or allometric) maximum, the fill anchor smaller.
    assert quality["facet_diameter_fill_um"] < quality["size"]["facet_diameter_max_um"] == pytest.approx(21.2, 1e-3)


def test_as_given_each_ct_point_is_a_receptor_with_the_files_acceptance(tmp_path, smallest_bumblebee, capsys):
    out = tmp_path / "as_given"
    assert main(["build-eye", str(EYES / "bombus_terrestris_77973" / "eye.yaml"), "-o", str(out), "--as-given",
                 "--quiet"]) == 0
    given, cornea = read_receptors(out / "receptors.csv"), read_receptors(EYES / "bombus_terrestris_77973" /
                                                                            "cornea.csv")
    right = given.side == "right"
    np.testing.assert_allclose(given.position[right], cornea.position, atol=1e-9)
    np.testing.assert_allclose(given.axis[right], cornea.axis, atol=1e-9)
    np.testing.assert_allclose(given.delta_rho_deg, 2.6)
    # Both come from the same cornea, so the normals' field is nearly the same, relaxed or as given.
    relaxed = json.loads(smallest_bumblebee["quality"].read_text())["fields"]["normals"]["right_sr"]
    as_given = json.loads((out / "quality.json").read_text())["fields"]["normals"]["right_sr"]
    assert as_given == pytest.approx(relaxed, rel=0.05)


def test_only_a_measured_cornea_can_be_built_as_given(tmp_path, capsys):
    assert main(["build-eye", str(EYES / "worker" / "eye.yaml"), "-o", str(tmp_path / "x"), "--as-given"]) == 2
    assert "cornea" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_the_fly_eye_is_buchners_axes_on_a_sphere_of_the_flys_size(fly):
    eye = load_eye(EYES / FLY / "eye.yaml")
    sphere = eye.document["ommatidia"]["sphere"]
    table = read_receptors(fly["receptors"])
    right = table.side == "right"
    assert right.sum() == 699
    distance = np.linalg.norm(table.position[right] - np.array(sphere["centre_mm"]), axis=1)
    np.testing.assert_allclose(distance, sphere["radius_mm"], rtol=1e-8)
    np.testing.assert_allclose(table.delta_rho_deg, FLY_DELTA_RHO_PER_DELTA_PHI * table.delta_phi_deg)
    quality = json.loads(fly["quality"].read_text())
    # Buchner's map spans nearly a hemisphere an eye, with a frontal and dorsal overlap.
    assert 5.0 < quality["fields"]["axes"]["right_sr"] < 7.0
    assert quality["fields"]["axes"]["binocular_sr"] > 0.3
    # Neighbours ~5° apart (strawlab's figure contours 4-16°, most near 5-6°).
    assert 4.5 < quality["optics"]["delta_phi_deg"]["p50"] < 7.0


def test_a_fly_sees_through_its_pale_and_yellow_ommatidia():
    flyset = load_receptor_set("drosophila_melanogaster")
    types = ommatidium_types(flyset, 20000)
    # The published shares (33 % pale), to within four binomial standard deviations.
    pale = np.mean(types == 0)
    assert abs(pale - 0.33) < 4 * np.sqrt(0.33 * 0.67 / 20000)
    # Always the same mosaic: receptor k keeps its type.
    np.testing.assert_array_equal(types[:500], ommatidium_types(flyset, 500))
    absent = lacking(flyset, types[:4])
    for k in range(4):
        pale_one = types[k] == 0
        assert list(np.array(flyset.classes)[absent[k]]) == (["R7y", "R8y"] if pale_one else ["R7p", "R8p"])
    assert ommatidium_types(load_receptor_set("apis_mellifera"), 5) is None


def test_map3_shows_the_class_each_ommatidium_has():
    from beeoptics.images.display import map3

    flyset = load_receptor_set("drosophila_melanogaster")
    nan = np.nan
    # R1_6, R7p, R7y, R8p, R8y relative to white: a pale ommatidium, then a yellow one.
    relative = np.array([[1.0, 0.5, nan, 0.25, nan], [1.0, nan, 0.7, nan, 0.9]])
    np.testing.assert_allclose(map3(relative, flyset.display), [[0.5, 0.0, 0.25], [0.7, 0.9, 0.0]])
    bee = load_receptor_set("apis_mellifera")
    np.testing.assert_allclose(map3(np.array([[0.2, 0.3, 0.4]]), bee.display), [[0.2, 0.4, 0.3]])
    # Where no receptor sees, all stays NaN (transparent).
    assert np.isnan(map3(np.full((1, 3), nan), bee.display)).all()


def test_mosaic_shares_must_sum_to_one(tmp_path):
    from beeoptics.io.errors import InputError

    doc = yaml.safe_load((ROOT / "beeoptics/vision/data/receptor_sets/drosophila_melanogaster.yaml").read_text())
    doc["mosaic"]["types"][0]["share"] = 0.5
    curves = ROOT / "beeoptics/vision/data" / doc["curves"]["file"]
    (tmp_path / curves.name).write_bytes(curves.read_bytes())
    path = tmp_path / "fly.yaml"
    path.write_text(yaml.safe_dump(doc, allow_unicode=True))
    with pytest.raises(InputError, match="mosaic.types.*sum to 1.17"):
        load_receptor_set(str(path))


def test_the_comparison_tabulates_and_draws_every_eye(tmp_path, fly, smallest_bumblebee):
    from beeoptics.pipeline.eyes import acuity_table

    eyes = {FLY: (EYES / FLY / "eye.yaml", fly["receptors"], fly["quality"]),
            "bombus_terrestris_77973": (EYES / "bombus_terrestris_77973" / "eye.yaml",
                                        smallest_bumblebee["receptors"], smallest_bumblebee["quality"])}
    outputs = {"acuity": tmp_path / "acuity.csv", "fields": tmp_path / "fields.png",
               "allometry": tmp_path / "allometry.png"}
    acuity_table(eyes, outputs)
    from beeoptics.io.table import read_table

    table = read_table(outputs["acuity"])
    assert list(table["eye"]) == list(eyes)
    assert list(table["species"]) == ["Drosophila melanogaster", "Bombus terrestris"]
    np.testing.assert_array_equal(table["facets_per_eye"], [699, 4513])
    assert np.isnan(table["intertegular_width_mm"][0]) and table["intertegular_width_mm"][1] == 1.97
    # Each species' own classes: a bee's column is empty in the fly's row, and the other way round.
    assert np.isnan(table["rayleigh_deg_UV_median_facet"][0]) and np.isnan(table["rayleigh_deg_R8y_median_facet"][1])
    assert outputs["fields"].stat().st_size > 0 and outputs["allometry"].stat().st_size > 0


@pytest.mark.parametrize("which", ["fly", "smallest_bumblebee"])
def test_a_measured_eye_renders_in_a_scene_with_its_own_receptors(which, request, tmp_path):
    from beeoptics.io.table import read_table

    built = request.getfixturevalue(which)
    name = FLY if which == "fly" else "bombus_terrestris_77973"
    out = tmp_path / "render"
    scene = ROOT / "tests" / "data" / "scenes" / "flower" / "scene.yaml"
    assert main(["render", str(built["receptors"]), str(scene), "--eye", str(EYES / name / "eye.yaml"), "-o",
                 str(out), "--samples", "4", "--depth", "1", "--width-px", "48", "--figures", "--quiet"]) == 0
    responses = read_table(out / "responses.csv")
    classes = receptor_set_of(EYES / name / "eye.yaml").classes
    assert all(c in responses for c in classes)
    for c in classes:
        assert (out / f"channel_{c.lower()}.png").is_file()
    if which == "fly":
        # Each ommatidium catches with its own type's R7 and R8 only.
        pale = responses["ommatidium"] == "pale"
        assert np.isnan(responses["R7y"][pale]).all() and np.isfinite(responses["R7p"][pale]).all()
        assert np.isnan(responses["R8p"][~pale]).all() and np.isfinite(responses["R8y"][~pale]).all()
        assert not (out / "hexagon.png").exists()
    else:
        assert (out / "hexagon.png").is_file() and "hex_x" in responses and "rnl_dS" not in responses
