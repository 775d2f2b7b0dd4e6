"""The workflow end to end, on a small eye and two small scenes, through Snakemake's CLI."""

import json
import re
import subprocess
import sys

import numpy as np
import pytest
import yaml

from beeoptics.io.imagefile import read_image
from beeoptics.pipeline.trace import gather_responses
from beeoptics.io.table import read_table
from conftest import ROOT, SNAKEMAKE, run
from test_readme import readme_script

def test_every_artifact_is_written(workdir):
    eye = workdir / "results" / "eyes" / "tiny"
    for name in ("remeshed.ply", "receptors.csv", "quality.json", "relaxation.npz",
                 "figures/relaxation.png", "figures/delta_phi.png", "figures/facet_diameter.png",
                 "figures/acceptance.png", "figures/field_of_view.png"):
        assert (eye / name).stat().st_size > 0
    for name in ("eyes/acuity.csv", "eyes/fields.png", "figures/sensitivities/apis_mellifera.png"):
        assert (workdir / "results" / name).stat().st_size > 0
    for scene in ("open", "flower"):
        for name in ("responses.csv", "irradiance.npz", "voronoi_map3.png", "voronoi_map2.png",
                     "density_map3.png", "density_map3_normalised.png", "channel_uv.png", "channel_b.png",
                     "channel_g.png", "catches.exr", "visual_field.png", "visual_field.exr", "triangle.png",
                     "hexagon.png"):
            assert (workdir / "results" / "tiny" / scene / name).stat().st_size > 0
        for name in ("human.png", "human.exr"):
            assert (workdir / "results" / "scenes" / scene / name).stat().st_size > 0
    assert (workdir / "scenes" / "generated" / "meadow.ply").stat().st_size > 0
    for name in ("responses.csv", "optic_flow.csv", "target.csv", "animation.gif", "optic_flow.png", "detection.csv",
                 "detection.json", "detection.png", "views.npz", "views.mp4"):
        assert (workdir / "results" / "flights" / "dive" / "tiny" / name).stat().st_size > 0
    assert (workdir / "scenes" / "generated" / "meadow_flowers.csv").stat().st_size > 0
    for name in ("tiny/detection.csv", "tiny/views.csv", "summary.csv", "detection.png"):
        assert (workdir / "results" / "detection" / "generated" / name).stat().st_size > 0
    for name in ("polarisation.csv", "field.png", "retina.png", "dorsal_rim.png", "compass.csv", "compass.json",
                 "compass.png"):
        assert (workdir / "results" / "tiny" / "flower" / "polarisation" / name).stat().st_size > 0
    for name in ("maps/0/0.npz", "ridf.csv", "tidf.csv", "places.csv", "catchment.csv", "catchment.png"):
        assert (workdir / "results" / "navigation" / "flower" / "small" / name).stat().st_size > 0


def test_a_flight_follows_its_flower_frame_by_frame(workdir):
    import OpenImageIO as oiio

    flight = workdir / "results" / "flights" / "dive" / "tiny"
    target = read_table(flight / "target.csv")
    frames = len(target["frame"])
    # The approach closes from 10 cm to 4 cm in 0.18 s: frames at 0, 0.1 s.
    assert frames == 2
    assert np.all(np.diff(target["distance_m"]) < 0) and np.all(np.diff(target["angular_diameter_deg"]) > 0)
    assert target["distance_m"][0] == pytest.approx(0.10)
    # Seen from 30° above its plane, 10 cm away, the head's widest extent is across the line of sight.
    assert target["angular_diameter_deg"][0] == pytest.approx(np.degrees(2 * np.arctan(0.02 / 0.10)), rel=0.02)
    flow = read_table(flight / "optic_flow.csv", text=["side"])
    responses = read_table(flight / "responses.csv", text=["side"])
    assert len(flow["id"]) == len(responses["id"]) == 600 * frames
    assert np.isfinite(flow["flow_deg_s"]).all() and (flow["flow_deg_s"] > 0).any()
    gif = oiio.ImageInput.open(str(flight / "animation.gif"))
    count = 0
    while gif.seek_subimage(count, 0):
        count += 1
    assert count == frames


def test_receptor_table_describes_both_eyes_in_the_head_frame(workdir):
    t = read_table(workdir / "results" / "eyes" / "tiny" / "receptors.csv")
    assert list(t) == ["id", "side", "x", "y", "z", "ax", "ay", "az",
                       "facet_diameter_um", "delta_phi_deg", "delta_rho_deg", "dorsal_rim", "microvilli_deg"]
    assert t["dorsal_rim"].sum() == 24 and np.isnan(t["microvilli_deg"][t["dorsal_rim"] == 0]).all()
    assert len(t["id"]) == 600 and set(t["side"]) == {"right", "left"}
    right = t["side"] == "right"
    assert np.all(t["y"][right] < 0) and np.all(t["y"][~right] > 0)
    axes = np.column_stack([t["ax"], t["ay"], t["az"]])
    np.testing.assert_allclose(np.linalg.norm(axes, axis=1), 1.0, atol=1e-6)
    quality = json.loads((workdir / "results" / "eyes" / "tiny" / "quality.json").read_text())
    assert quality["facets_per_eye"] == 300


def test_catches_and_exr_agree(workdir):
    r = read_table(workdir / "results" / "tiny" / "flower" / "responses.csv")
    assert {"UV", "B", "G"} <= set(r) and np.all(r["G"] > 0)
    pixels, names = read_image(workdir / "results" / "tiny" / "flower" / "catches.exr")
    assert sorted(names) == ["B", "G", "UV"]
    shown = pixels[..., names.index("G")]
    assert shown.max() == pytest.approx(r["G"].max(), rel=1e-6)


def test_nothing_reruns_when_nothing_changed(workdir):
    dry = run(workdir, "--dry-run")
    assert dry.returncode == 0
    assert "Nothing to be done" in dry.stdout + dry.stderr


def test_editing_one_scene_reruns_only_that_scene(workdir):
    scene = workdir / "scenes" / "open" / "scene.yaml"
    scene.write_text(scene.read_text().replace("luminance_cd_m2: 5000", "luminance_cd_m2: 6000"))
    dry = run(workdir, "--dry-run")
    assert dry.returncode == 0
    outputs = [line for line in dry.stdout.splitlines() if line.strip().startswith("output:")]
    assert any("results/tiny/open/responses.csv" in line for line in outputs)
    assert any("results/tiny/open/voronoi_map3.png" in line for line in outputs)
    assert not any("/flower/" in line or "/eyes/" in line for line in outputs)


def test_a_misspelt_config_key_stops_the_run_naming_it(workdir, tmp_path):
    bad = yaml.safe_load((workdir / "config.yaml").read_text())
    bad["trace"]["sampels_per_receptor"] = 4
    (tmp_path / "config.yaml").write_text(yaml.safe_dump(bad))
    result = subprocess.run([SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
                             "--configfile", str(tmp_path / "config.yaml"), "--cores", "1", "--dry-run"],
                            capture_output=True, text=True)
    assert result.returncode != 0
    assert "sampels_per_receptor" in result.stderr + result.stdout


def test_slurm_profile_dry_run(workdir):
    """The SLURM profile parses, and plans every job for sbatch, without a cluster."""
    result = run(workdir, "--workflow-profile", str(ROOT / "workflow" / "profiles" / "slurm"),
                 "--dry-run", "--forceall")
    assert result.returncode == 0, result.stderr[-3000:]
    assert "rule trace" in result.stdout + result.stderr


def test_a_trace_split_into_parts_is_bit_identical(workdir):
    """Scatter/gather: three shares give the same bytes as one job (the eye is rebuilt, too)."""
    one = (workdir / "results" / "tiny" / "flower" / "irradiance.npz").read_bytes()
    responses = (workdir / "results" / "tiny" / "flower" / "responses.csv").read_bytes()
    split = workdir / "split"
    split.mkdir()
    config = yaml.safe_load((workdir / "config.yaml").read_text())
    config["trace"]["parts"] = 3
    config["scenes"] = ["flower"]
    (split / "config.yaml").write_text(yaml.safe_dump(config))
    result = run(split, "results/tiny/flower/irradiance.npz", "results/tiny/flower/responses.csv")
    assert result.returncode == 0, result.stderr[-3000:]
    assert len(list((split / "results" / "tiny" / "flower" / "parts").glob("radiance_*_of_3.npz"))) == 3
    assert (split / "results" / "tiny" / "flower" / "irradiance.npz").read_bytes() == one
    assert (split / "results" / "tiny" / "flower" / "responses.csv").read_bytes() == responses


def test_the_visual_field_exr_holds_the_catches_of_the_receptors_that_see(workdir):
    pixels, names = read_image(workdir / "results" / "tiny" / "flower" / "visual_field.exr")
    # EXR stores channels sorted by name; they are read back by name.
    assert sorted(names) == sorted(["UV", "B", "G", "eyes"])
    pixels = pixels[..., [names.index(k) for k in ("UV", "B", "G", "eyes")]]
    resp = read_table(workdir / "results" / "tiny" / "flower" / "responses.csv", numeric=["UV", "B", "G"], text=["side"])
    seen = pixels[..., 3] > 0
    assert seen.any() and set(np.unique(pixels[..., 3])) <= {0.0, 1.0, 2.0, 3.0}
    catches = np.column_stack([resp[k] for k in ("UV", "B", "G")]).astype(np.float32)
    # Every seen pixel carries one receptor's catches, exactly.
    got = {tuple(p) for p in pixels[seen][:, :3]}
    assert got <= {tuple(c) for c in catches}
    assert (pixels[~seen][:, :3] == 0).all()


@pytest.fixture(scope="module")
def report(workdir):
    """The run's HTML report, written where the README writes it: in the run's folder."""
    # As the README gives it: no --cores, which only running jobs needs.
    result = subprocess.run(
        [SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(workdir),
         "--configfile", str(workdir / "config.yaml"), "--report", str(workdir / "report.html")],
        capture_output=True, text=True, cwd=workdir)
    assert result.returncode == 0, result.stderr[-3000:]
    return workdir / "report.html"


def test_the_report_builds_with_every_figure_captioned(report):
    html = report.read_text()
    for caption in ("binocular overlap", "Govardovskii", "Snyder", "colour hexagon", "Collins' Fig. 7",
                    "Normalised density", "Rayleigh limit"):
        assert caption in html, caption


def test_the_report_links_every_viewer_and_embeds_none(workdir, report):
    """Each viewer carries plotly.js (4.8 MB): embedded, nine of them made the report 143 MB. The report
    links them from its captions instead, by their paths from the report's folder."""
    html = report.read_text()
    made = {p.relative_to(workdir).as_posix() for p in (workdir / "results").rglob("viewer.html")}
    linked = set(re.findall(r'href=\\"(results/[^"\\]*viewer\.html)\\"', html))
    assert made and linked == made
    # No page embedded (Snakemake embeds every figure as a data URI).
    assert "data:text/html" not in html
    print(f"report: {report.stat().st_size / 1e6:.2f} MB, {len(linked)} viewers linked")


def test_a_sweep_traces_every_combination_and_tables_them(workdir):
    sweep = workdir / "results" / "sweeps" / "demo"
    rows = read_table(sweep / "summary.csv", numeric=["delta_rho_deg", "sun_elevation_deg", "brightness_mean"],
                      text=["variant", "eye", "scene"])
    assert list(rows["variant"]) == ["drho-1.5_sun-20", "drho-1.5_sun-70", "drho-4_sun-20", "drho-4_sun-70"]
    assert list(rows["eye"]) == ["tiny"] * 4 and list(rows["scene"]) == ["flower"] * 4
    np.testing.assert_array_equal(rows["delta_rho_deg"], [1.5, 1.5, 4.0, 4.0])
    # A higher sun lights the flower and the ground more: every receptor class catches more.
    b = rows["brightness_mean"]
    assert b[1] > b[0] and b[3] > b[2]
    for variant, drho in (("drho-1.5_sun-20", 1.5), ("drho-4_sun-70", 4.0)):
        table = read_table(sweep / variant / "eyes" / "tiny" / "receptors.csv", numeric=["delta_rho_deg"])
        assert (table["delta_rho_deg"] == drho).all()
        assert (sweep / variant / "tiny" / "flower" / "responses.csv").stat().st_size > 0


def test_receptor_curves_from_a_csv_replace_the_default(workdir, tmp_path):
    from beeoptics.spectra import grid, write_pavo_csv
    from beeoptics.vision.receptorset import TEMPLATE, load_receptor_set
    from beeoptics.vision.sensitivity import receptor_sensitivities

    apis = load_receptor_set("apis_mellifera")
    flower = workdir / "results" / "tiny" / "flower"
    args = (workdir / "results" / "eyes" / "tiny" / "receptors.csv", workdir / "scenes" / "flower" / "scene.yaml",
            [flower / "parts" / "radiance_0_of_1.npz"])
    spectral = {"start_nm": 300, "end_nm": 700, "step_nm": 10}
    wl = grid(300, 700, 1)
    curves = receptor_sensitivities(wl, apis.lambda_max_nm)
    write_pavo_csv(tmp_path / "same.csv", wl, dict(zip(("UV", "B", "G"), curves.T)))
    for name, curves_setting in (("same", str(tmp_path / "same.csv")), ("template", TEMPLATE),
                                 ("peitsch", str(apis.curves_file))):
        gather_responses(*args, {"responses": tmp_path / f"{name}.out", "irradiance": tmp_path / f"{name}.npz"},
                         spectral=spectral, receptor_set=apis, receptor_curves=curves_setting)
    default = read_table(flower / "responses.csv", numeric=["UV", "B", "G"], text=["side"])
    same, ours, peitsch = (read_table(tmp_path / f"{name}.out", numeric=["UV", "B", "G"], text=["side"])
                           for name in ("same", "template", "peitsch"))
    for k in ("UV", "B", "G"):
        # The template written as a CSV is the template; the workflow's default is Peitsch's file.
        np.testing.assert_allclose(same[k], ours[k], rtol=1e-6)
        np.testing.assert_allclose(default[k], peitsch[k], rtol=1e-12)
    # A green receptor peaking 30 nm further red catches less of this scene's light relative to blue.
    shifted = receptor_sensitivities(wl, (344.0, 436.0, 574.0))
    write_pavo_csv(tmp_path / "red.csv", wl, dict(zip(("UV", "B", "G"), shifted.T)))
    gather_responses(*args, {"responses": tmp_path / "red.out", "irradiance": tmp_path / "red.npz"},
                     spectral=spectral, receptor_set=apis, receptor_curves=str(tmp_path / "red.csv"))
    red = read_table(tmp_path / "red.out", numeric=["UV", "B", "G"], text=["side"])
    np.testing.assert_allclose(red["B"], ours["B"], rtol=1e-6)
    assert not np.allclose(red["G"], ours["G"], rtol=1e-3)


def test_the_comparison_target_builds_and_compares_its_eyes(workdir):
    # Not part of the default run: asked for by name, it builds the fly too and compares both.
    assert not (workdir / "results" / "eyes" / "drosophila_melanogaster").exists()
    result = run(workdir, "comparison")
    assert result.returncode == 0, result.stderr[-3000:]
    out = workdir / "results" / "comparison"
    assert read_table(out / "acuity.csv")["eye"].tolist() == ["tiny", "drosophila_melanogaster"]
    assert (out / "fields.png").stat().st_size > 0 and (out / "allometry.png").stat().st_size > 0


def test_the_readmes_passages_are_written_from_a_runs_files(workdir):
    """docs/readme.py writes the eye table from the run's comparison (the test run compares the tiny eye and the
    fly) and leaves a passage whose files the run lacks as it is, saying so."""
    # After the comparison's own test, which checks that the default run did not build the fly.
    if not (workdir / "results" / "comparison" / "acuity.csv").exists():
        assert run(workdir, "comparison").returncode == 0
    script, said = readme_script(), []
    text = ("<!-- from the run: eyes -->\nold\n<!-- end eyes -->\n"
            "<!-- from the run: compass -->\nold\n<!-- end compass -->")
    new = script.rewrite(text, workdir / "results", workdir / "eyes", log=said.append)
    rows = [line for line in new.splitlines() if line.startswith("| ")]
    assert [row.split(" | ")[0] for row in rows[1:]] == ["| tiny", "| drosophila_melanogaster"]
    assert "699 (800)" in rows[-1]
    assert new.endswith("<!-- from the run: compass -->\nold\n<!-- end compass -->")
    assert len(said) == 1 and said[0].startswith("compass: left as it is")


def test_the_survey_approaches_each_species_and_the_flight_detects_its_flower(workdir):
    survey = workdir / "results" / "detection" / "generated"
    approaches = read_table(survey / "tiny" / "detection.csv", text=["species"])
    # One flower of each of the meadow's two species, from two directions.
    assert sorted(approaches["species"]) == ["campanula_rotundifolia"] * 2 + ["leucanthemum_vulgare"] * 2
    views = read_table(survey / "tiny" / "views.csv", text=["species"])
    assert len(views["distance_m"]) == 4 * 4 and (views["receptors_touched"] >= 0).all()
    summary = read_table(survey / "summary.csv", text=["species", "eye"])
    assert list(summary["eye"]) == ["tiny", "tiny"]
    detection = read_table(workdir / "results" / "flights" / "dive" / "tiny" / "detection.csv")
    target = read_table(workdir / "results" / "flights" / "dive" / "tiny" / "target.csv")
    np.testing.assert_allclose(detection["distance_m"], target["distance_m"])
    np.testing.assert_allclose(detection["angular_diameter_deg"], target["angular_diameter_deg"])
    # 10 cm from a 4 cm head the flower fills some receptors' acceptance.
    assert (detection["receptors_touched"] > 0).all() and (detection["cover_max"] > 0).all()
    first = json.loads((workdir / "results" / "flights" / "dive" / "tiny" / "detection.json").read_text())
    assert set(first) == {"achromatic_detectable", "chromatic_detectable", "receptors_green_above_threshold",
                          "receptors_colour_above_threshold"}


def test_jobs_that_draw_figures_or_tables_load_neither_open3d_nor_numba(workdir):
    logs = workdir / "results" / "logs"
    light = [logs / "acuity.log", *logs.glob("eye_figures/*.log"), *logs.glob("images/*/*.log"),
             *logs.glob("sensitivities/*.log"), *logs.glob("gather/*/*.log"), *logs.glob("detection/*/summary.log"),
             *logs.glob("flights/*/*/detection.log"), *logs.glob("flights/*/*/gather.log"),
             *logs.glob("sweeps/*/summary.log")]
    assert len(light) >= 10
    for log in light:
        assert "loaded: none of open3d, numba" in log.read_text(), log
    # The heavy ones do load them: the tracer's.
    assert "loaded: open3d, numba" in next(logs.glob("trace/*/*/*.log")).read_text()


def test_a_flights_views_hold_every_receptors_catches_at_every_frame_and_play_as_a_video(workdir):
    flight = workdir / "results" / "flights" / "dive" / "tiny"
    views = np.load(flight / "views.npz")
    target = read_table(flight / "target.csv")
    assert views["catches"].shape == (len(target["frame"]), 600, 3) and list(views["classes"]) == ["UV", "B", "G"]
    np.testing.assert_allclose(views["t_s"], target["t_s"])
    assert np.isfinite(views["catches"]).all() and (views["catches"] > 0).any()
    # An MP4 (ISO base media: an ftyp box first) of as many frames as the flight has.
    data = (flight / "views.mp4").read_bytes()
    assert data[4:8] == b"ftyp"
    import imageio_ffmpeg

    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(flight / "views.mp4"))
    assert frames == len(target["frame"])


def test_editing_a_flight_or_a_readme_reruns_no_trace_of_its_scene(workdir):
    """A scene's flights and READMEs are not what its traces read; the flights' own rules read them."""
    folder = workdir / "scenes" / "generated"
    flight, readme = folder / "flights" / "approach.csv", folder / "flights" / "README.md"
    text = flight.read_bytes()
    readme.write_text("notes\n")
    try:
        # The same flight written otherwise (its first time 0.0 for 0): new content, which Snakemake sees
        # (a new time alone it does not, when the content it recorded is unchanged).
        flight.write_bytes(text.replace(b"\n0,", b"\n0.0,", 1))
        dry = run(workdir, "--dry-run")
        assert dry.returncode == 0, dry.stderr[-2000:]
        outputs = [line for line in dry.stdout.splitlines() if line.strip().startswith("output:")]
        assert any("results/flights/dive/" in line for line in outputs)
        # Nothing of the scene's own: no trace in it, no survey of its flowers.
        assert not any("results/tiny/generated/" in line or "results/detection/" in line for line in outputs)
    finally:
        readme.unlink()
        flight.write_bytes(text)


def test_a_run_of_one_eye_in_one_scene_runs_nothing_else(tmp_path):
    """The extras (flights, polarisation, the detection survey) follow the run's eyes and scenes, and a
    flight set to null is off: the default config asked for the drone in the meadow plans no job of
    another eye or scene."""
    def planned(*settings):
        dry = subprocess.run([SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
                              "--configfile", str(ROOT / "config" / "config.yaml"), "--dry-run", "--config",
                              f"eyes_dir={ROOT / 'eyes'}", f"scenes_dir={ROOT / 'scenes'}", *settings],
                             capture_output=True, text=True)
        assert dry.returncode == 0, dry.stderr[-2000:]
        return [line.split(":", 1)[1] for line in dry.stdout.splitlines() if line.strip().startswith("output:")]

    outputs = planned("eyes=[drone]", "scenes=[meadow]")
    assert any("results/drone/meadow/responses.csv" in line for line in outputs)
    assert any("results/detection/meadow/drone/detection.csv" in line for line in outputs)
    others = ("worker", "queen", "bombus", "/sky/", "/patches/", "flights/", "polarisation/")
    assert not [line for line in outputs if any(other in line for other in others)]
    assert not any("flights/" in line for line in planned("flights={approach: null}"))


def test_render_with_the_runs_settings_writes_the_workflows_files(workdir, tmp_path):
    """The CLI's render is the workflow's stages (README, "Command-line tool"): with the run's settings its
    responses, retinal images and colour-space figures are the workflow's, byte for byte, titles included;
    its visual field differs only in having no human view beside it."""
    out = tmp_path / "render"
    result = subprocess.run(
        [sys.executable, "-m", "beeoptics.cli", "render",
         str(workdir / "results/eyes/tiny/receptors.csv"), str(workdir / "scenes/flower/scene.yaml"),
         "--eye", str(workdir / "eyes/tiny/eye.yaml"), "-o", str(out), "--samples", "16", "--precision", "auto",
         "--depth", "2",
         "--seed", "3", "--step-nm", "10", "--width-px", "64", "--field-width-px", "180", "--figures", "--quiet"],
        capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]
    ran = workdir / "results/tiny/flower"
    for name in ("responses.csv", "voronoi_map3.png", "density_map3.png", "channel_uv.png", "catches.exr",
                 "hexagon.png", "triangle.png"):
        assert (out / name).read_bytes() == (ran / name).read_bytes(), name


def test_a_run_asking_the_animal_s_precision_traces_views_so_and_the_sections_their_samples(workdir):
    """Asked the animal's precision (``trace.precision.target: auto``, as the test run is), each receptor's
    samples in ``responses.csv`` are its own, after a pilot of 64; a flight, the detection survey and the
    compass trace the samples their sections name unless they ask a precision too (README, "Speed"): here
    the flight's 4."""
    samples = read_table(workdir / "results/tiny/flower/responses.csv")["samples"]
    assert np.ptp(samples) > 0 and samples.min() >= 64
    logs = workdir / "results/logs"
    frames = "".join(log.read_text() for log in (logs / "flights/dive/tiny").glob("*.log"))
    assert ": 4 samples each" in frames and "adaptive sampling" not in frames
    assert "adaptive sampling" in (logs / "trace/tiny/flower/0_of_1.log").read_text()
