"""The meadow generator: plants, ground, placement, the meadow as a scene; and flights."""

import numpy as np
import pytest
import yaml
from scipy.spatial import cKDTree

from beeoptics.io.errors import InputError
from beeoptics.world import placement, plants, terrain
from beeoptics.world.flight import (Flight, approach, azimuth_elevation_components, disc_angular_diameter, disc_hits,
                                    frame_times, optic_flow, pose, read_flight)
from beeoptics.world.meadow import (FLOWER_COLUMNS, check_meadow, expected_triangles, flower_table, generate, read_meadow,
                                   write_ply)
from beeoptics.world.species import PARTS, plant, species_table
from conftest import ROOT

TINY = ROOT / "tests" / "data" / "scenes" / "generated"


def areas(mesh):
    c = mesh.vertices[mesh.faces]
    return np.linalg.norm(np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), axis=1) / 2


def test_a_blade_is_as_long_as_asked_and_a_straight_one_stands_up():
    n = 5
    length = np.linspace(0.1, 0.3, n)
    mesh = plants.blades(length, np.full(n, 0.004), np.zeros(n), np.zeros(n), np.zeros(n), stations=6)
    tips = mesh.vertices.reshape(n, -1, 3)[:, -1]
    np.testing.assert_allclose(tips, np.column_stack([np.zeros(n), np.zeros(n), length]), atol=1e-12)
    # Bent through a right angle along an arc, the tip lies at (L·2/π, 0, L·2/π).
    bent = plants.arcs(np.array([0.2]), np.array([0.0]), np.array([np.pi / 2 / 0.2]), np.array([0.0]), 401)[0][0]
    np.testing.assert_allclose(bent[-1], [0.4 / np.pi, 0.0, 0.4 / np.pi], rtol=1e-5)
    assert areas(mesh).min() > 0


@pytest.mark.parametrize("name", sorted(species_table()))
def test_every_species_builds_non_degenerate_triangles_of_its_own_parts(name):
    spec = species_table()[name]
    mesh = plant(spec, np.random.default_rng(0))
    assert set(mesh.parts) == set(PARTS[spec["form"]])
    assert areas(mesh).min() > 0
    assert mesh.vertices[:, 2].max() <= spec["stem_height_m"][1] + spec.get("head_diameter_m", [0, 0.1])[1]


def test_the_thomas_process_has_the_asked_density_and_clumps():
    rng = np.random.default_rng(1)
    extent = [20.0, 20.0]
    clumped = placement.thomas(extent, 5.0, 10.0, 0.1, rng)
    random = placement.thomas(extent, 5.0, 1.0, 0.1, rng)
    for points in (clumped, random):
        assert len(points) / 400.0 == pytest.approx(5.0, rel=0.1)
        assert (np.abs(points) <= 10.0).all()

    def dispersion(points):  # variance over mean of counts in 1 m quadrats: 1 for Poisson
        counts = np.histogram2d(*points.T, bins=20, range=[[-10, 10], [-10, 10]])[0].ravel()
        return counts.var() / counts.mean()

    assert dispersion(random) == pytest.approx(1.0, abs=0.25)
    assert dispersion(clumped) > 5.0


def test_the_ground_has_the_asked_roughness_and_correlation_length():
    rng = np.random.default_rng(2)
    x, y, h = terrain.height_field([20.0, 20.0], 0.05, 0.02, 0.5, rng)
    inner = h[40:-40, 40:-40]  # inside the border that falls to zero
    assert inner.std() == pytest.approx(0.02, rel=0.15)
    # A Gaussian autocorrelation exp(−r²/ℓ²): at r = ℓ it has fallen to 1/e.
    lag = 10  # 0.5 m in grid steps
    r = np.mean(inner[:-lag] * inner[lag:]) / np.mean(inner * inner)
    assert r == pytest.approx(np.exp(-1.0), abs=0.08)
    assert np.abs(h[[0, -1]]).max() == 0.0 and np.abs(h[:, [0, -1]]).max() == 0.0


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    meadow = read_meadow(TINY / "meadow.yaml")
    mesh, colours, _ = generate(meadow)
    out = tmp_path_factory.mktemp("meadow") / "meadow.ply"
    write_ply(out, mesh, colours)
    return meadow, mesh, colours, out


def test_a_meadow_is_the_same_for_the_same_seed_and_a_new_species_leaves_the_rest(tiny, tmp_path):
    meadow, mesh, colours, out = tiny
    again = tmp_path / "again.ply"
    write_ply(again, *generate(read_meadow(TINY / "meadow.yaml"))[:2])
    assert again.read_bytes() == out.read_bytes()
    more = read_meadow(TINY / "meadow.yaml")
    more["plants"].append({"species": "echium_vulgare", "density_per_m2": 20.0, "per_clump": 1.0, "spread_m": 0.1,
                           "variants": 2})
    bigger, _, _ = generate(more)
    assert len(bigger.faces) > len(mesh.faces)
    np.testing.assert_array_equal(bigger.vertices[:len(mesh.vertices)], mesh.vertices)


def test_a_generated_meadow_is_an_ordinary_scene(tiny, tmp_path, wavelengths):
    from beeoptics.light.scene import load_scene

    _, mesh, _, out = tiny
    scene_yaml = yaml.safe_load((TINY / "scene.yaml").read_text())
    (tmp_path / "meadow.ply").write_bytes(out.read_bytes())
    (tmp_path / "scene.yaml").write_text(yaml.safe_dump(scene_yaml))
    scene = load_scene(tmp_path / "scene.yaml", wavelengths)
    meadow = next(o for o in scene.objects if o.name == "meadow")
    assert len(meadow.faces) == len(mesh.faces)
    # Every part has its own material: the daisy's rays are white, its disc yellow.
    names = [scene.material_names[i] for i in np.unique(meadow.face_material)]
    assert {"daisy_ray", "daisy_disc", "loam", "leaf"} <= set(names)


def test_specimens_stand_upright_on_level_ground_with_room_round_them(tiny):
    meadow, mesh, _, _ = tiny
    spec = meadow["specimens"][0]
    x, y = spec["position_m"]
    height = spec["sizes"]["stem_height_m"][0]
    disc = mesh.vertices[mesh.faces[mesh.parts == "leucanthemum_vulgare.disc"]].reshape(-1, 3)
    near = np.hypot(disc[:, 0] - x, disc[:, 1] - y) < 0.05
    # The specimen's disc centres on its place, at its stem's height, facing up.
    assert np.abs(disc[near][:, :2].mean(0) - [x, y]).max() < 1e-3
    assert disc[near][:, 2].min() == pytest.approx(height, abs=1e-6)
    others = mesh.vertices[mesh.faces[mesh.parts == "grass"]].reshape(-1, 3)
    assert np.hypot(others[:, 0] - x, others[:, 1] - y).min() > spec["clear_radius_m"] - 0.05


def test_an_unknown_species_is_one_line_naming_the_file():
    meadow = read_meadow(TINY / "meadow.yaml")
    meadow["plants"].append({"species": "bellis_perenis", "density_per_m2": 1.0, "per_clump": 1.0,
                             "spread_m": 0.1, "variants": 1})
    with pytest.raises(InputError, match="meadow.yaml: plants.2.species: unknown species 'bellis_perenis'"):
        check_meadow(meadow, "meadow.yaml")


def edited_meadow(tmp_path, edit):
    """The shipped meadow file, edited, in tmp_path."""
    meadow = yaml.safe_load((ROOT / "scenes" / "meadow" / "meadow.yaml").read_text())
    edit(meadow)
    path = tmp_path / "meadow.yaml"
    path.write_text(yaml.safe_dump(meadow))
    return path


@pytest.mark.parametrize("edit, field", [
    (lambda m: m["grass"].update(length_m=[0.30, 0.10]), "grass.length_m"),
    (lambda m: m["specimens"][0]["sizes"].update(stem_height_m=[0.3, 0.2]), "specimens.0.sizes.stem_height_m"),
    (lambda m: m.update(species={"mine": {"form": "composite", "stem_height_m": [0.5, 0.1], "colours": {}}}),
     "species.mine.stem_height_m"),
])
def test_a_range_that_runs_backwards_is_one_line_naming_the_file_and_field(tmp_path, edit, field):
    path = edited_meadow(tmp_path, edit)
    with pytest.raises(InputError, match="runs backwards") as e:
        read_meadow(path)
    assert e.value.field == field and str(path) in str(e.value) and "\n" not in str(e.value)


def test_a_meadow_larger_than_the_machine_holds_is_refused_before_any_of_it_is_made(tmp_path):
    """2000 × 3000 m of the shipped meadow is some 10¹¹ triangles: refused with the limit and what would fit,
    in a process whose address space is capped at 4 GiB (an attempt to generate it fails there, harmlessly)."""
    import resource
    import subprocess
    import sys

    path = edited_meadow(tmp_path, lambda m: m.update(extent_m=[2000.0, 3000.0]))
    cap = lambda: resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))  # noqa: E731
    result = subprocess.run([sys.executable, "-m", "beeoptics.cli", "meadow", str(path), "-o", str(tmp_path / "m.ply")],
                            capture_output=True, text=True, timeout=120, preexec_fn=cap)
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1, result.stderr
    assert f"{path}: grass.density_per_m2: a meadow of 2000 × 3000 m would have about" in result.stderr
    assert "GiB to generate" in result.stderr and "m² at these densities" in result.stderr
    assert not (tmp_path / "m.ply").exists()


def test_the_expected_triangles_match_a_generated_meadow():
    """The estimate the memory check rests on is within a tenth of the triangles 2 × 2 m of the shipped meadow has
    (a patch large enough for its densities to hold)."""
    meadow = read_meadow(ROOT / "scenes" / "meadow" / "meadow.yaml")
    meadow["extent_m"] = [2.0, 2.0]
    expected = sum(expected_triangles(meadow).values())
    assert expected == pytest.approx(len(generate(meadow)[0].faces), rel=0.1)


def test_optic_flow_of_pure_translation_and_rotation():
    d = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
    # Flying forward at 1 m/s past a wall 2 m to the side: the side sees 0.5 rad/s backwards,
    # the direction of flight sees nothing move (the focus of expansion).
    flow = optic_flow(d, np.array([5.0, 2.0, np.inf]), [1.0, 0, 0], [0, 0, 0])
    np.testing.assert_allclose(flow, [[0, 0, 0], [-0.5, 0, 0], [0, 0, 0]], atol=1e-12)
    # Turning left at 1 rad/s: every horizontal direction's image moves right at 1 rad/s, whatever its distance.
    flow = optic_flow(d, np.array([1.0, 9.0, 3.0]), [0, 0, 0], [0, 0, 1.0])
    np.testing.assert_allclose(azimuth_elevation_components(d[:2], flow[:2]), [[-1.0, 0], [-1.0, 0]], atol=1e-12)


def test_a_flights_pose_interpolates_and_has_the_segments_velocities():
    from beeoptics.headframe import head_rotation

    f = Flight(np.array([0.0, 2.0]), np.array([[0, 0, 1.0], [2.0, 0, 1.0]]),
               np.array([head_rotation(0, 0, 0), head_rotation(90, 0, 0)]))
    p = pose(f, 0.5)
    np.testing.assert_allclose(p.position, [0.5, 0, 1.0])
    np.testing.assert_allclose(p.velocity, [1.0, 0, 0])
    np.testing.assert_allclose(p.angular_velocity, [0, 0, np.pi / 4])
    assert p.eye()["heading_deg"] == pytest.approx(22.5)
    np.testing.assert_allclose(frame_times(f, 2.0), [0, 0.5, 1.0, 1.5, 2.0])


def test_the_approach_closes_at_a_constant_relative_rate(tmp_path):
    from beeoptics.io.table import write_table

    rows = approach([0.4, 0.0, 0.3], 0.3, 0.01, 30.0, 0.4, 0.1)
    write_table(tmp_path / "a.csv", rows)
    f = read_flight(tmp_path / "a.csv")
    d = np.linalg.norm(f.position - [0.4, 0.0, 0.3], axis=1)
    assert d[0] == pytest.approx(0.3) and d[-1] == pytest.approx(0.01)
    np.testing.assert_allclose(np.diff(np.log(d[:-1])) / np.diff(f.time[:-1]), -1 / 0.4, rtol=1e-6)
    # Looking along the line of approach, the target is straight ahead.
    ahead = f.rotation[:, :, 0]
    to_target = ([0.4, 0.0, 0.3] - f.position) / d[:, None]
    np.testing.assert_allclose((ahead * to_target).sum(1), 1.0, atol=1e-9)
    assert disc_hits(f.position, ahead, [0.4, 0.0, 0.3], [0, 0, 1.0], 0.02).all()


def test_a_disc_seen_face_on_subtends_twice_the_arctangent_of_its_radius_over_its_distance():
    assert disc_angular_diameter([0, 0, 0.1], [0, 0, 0], [0, 0, 1.0], 0.02) == pytest.approx(2 * np.arctan(0.2), 1e-4)
    # Edge-on from the side it is a segment of length 2r at distance d: 2 arctan(r/d) as well.
    assert disc_angular_diameter([0.1, 0, 0], [0, 0, 0], [1.0, 0, 0], 0.02) == pytest.approx(2 * np.arctan(0.2), 1e-4)
    rays = np.array([[0, 0, -1.0], [0.3, 0, -1.0], [0, 0, 1.0]])
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    np.testing.assert_array_equal(disc_hits(np.array([[0, 0, 0.1]] * 3), rays, [0, 0, 0], [0, 0, 1.0], 0.02),
                                  [True, False, False])


@pytest.mark.parametrize("text, field", [
    ("t_s,x_m,y_m,z_m,heading_deg,pitch_deg\n0,0,0,0,0,0\n1,0,0,0,0,0\n", "roll_deg"),
    ("t_s,x_m,y_m,z_m,heading_deg,pitch_deg,roll_deg\n0,0,0,0,0,0,0\n0,1,0,0,0,0,0\n", "t_s"),
    ("t_s,x_m,y_m,z_m,heading_deg,pitch_deg,roll_deg\n0,0,0,0,0,0,0\n", "t_s"),
    ("t_s,x_m,y_m,z_m,heading_deg,pitch_deg,roll_deg\n0,0,0,0,0,0,0\n1,nan,0,0,0,0,0\n", "x_m"),
])
def test_a_bad_flight_is_one_line_naming_the_field(tmp_path, text, field):
    (tmp_path / "f.csv").write_text(text)
    with pytest.raises(InputError, match=f"f.csv: {field}"):
        read_flight(tmp_path / "f.csv")


def test_the_default_meadow_has_a_million_triangles_and_every_species_flowers():
    meadow = read_meadow(ROOT / "scenes" / "meadow" / "meadow.yaml")
    mesh, colours, flowering = generate(meadow)
    assert len(mesh.faces) >= 1_000_000
    species = {p.split(".")[0] for p in mesh.parts}
    assert species >= {"grass", "soil", "leucanthemum_vulgare", "taraxacum_officinale", "achillea_millefolium",
                       "campanula_rotundifolia", "echium_vulgare"}
    # Every species' flowers are listed, each where its petals are: the sphere about it holds some of them.
    assert set(flowering) == species - {"grass", "soil"}
    table = flower_table(mesh, flowering)
    flower_parts = {p for parts in PARTS.values() for p in parts} - {"stem", "leaf"}
    petals = np.isin(mesh.parts, [p for p in np.unique(mesh.parts) if p.split(".")[-1] in flower_parts])
    corners = mesh.vertices[mesh.faces[petals]].mean(1)
    centres = np.column_stack([table["x_m"], table["y_m"], table["z_m"]])
    near = cKDTree(corners).query(centres)[0]
    assert (near <= table["radius_m"]).all()
    # The specimen daisy the approach flies to: its head, 4 cm across, facing up at (0.40, 0, 0.30) m.
    first = np.array([table[c][0] for c in FLOWER_COLUMNS[1:]])
    np.testing.assert_allclose(first, [0.40, 0.0, 0.30, 0.02, 0.0, 0.0, 1.0], atol=1e-9)
    # Four forms at least, every one of them in flower.
    forms = {species_table()[s]["form"] for s in species - {"grass", "soil"}}
    assert forms == {"composite", "corymb", "bell", "spike"}
    # Every colour of the mesh is in the meadow scene's palette.
    palette = yaml.safe_load((ROOT / "scenes" / "meadow" / "scene.yaml").read_text())["objects"][1]["palette"]
    used = {f"#{r:02x}{g:02x}{b:02x}" for r, g, b in np.unique(colours, axis=0)}
    assert used <= set(palette)


@pytest.mark.parametrize("size, value", [("stem_height_m", [-0.1, 0.3]), ("stem_height_m", [0.3, 300.0]),
                                         ("rays", [13, 3400]), ("leaf_height_fraction", [0.0, 2.0])])
def test_a_meadow_species_of_impossible_sizes_is_refused_naming_the_size(tmp_path, size, value):
    daisy = {**species_table()["leucanthemum_vulgare"], size: value}
    path = edited_meadow(tmp_path, lambda m: m.update(species={"mine": daisy}))
    with pytest.raises(InputError) as e:
        read_meadow(path)
    assert e.value.field.startswith(f"species.mine.{size}") and "\n" not in str(e.value)
