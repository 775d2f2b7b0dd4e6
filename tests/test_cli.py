"""The command-line tool: every subcommand on the tiny eye and test scenes, its help, and bad input."""

import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

from beeoptics import cli
from beeoptics.io.atomic import Terminated, sigterm_as_interrupt
from beeoptics.io.errors import InputError
from beeoptics.io.interchange import read_receptor_ply
from beeoptics.io.receptortable import COLUMNS, read_receptors
from beeoptics.io.table import read_table
from beeoptics.pipeline.outputs import IMAGES
from conftest import ROOT

DATA = ROOT / "tests" / "data"
EYE = DATA / "eyes" / "tiny" / "eye.yaml"
FLOWER = DATA / "scenes" / "flower" / "scene.yaml"
TOOL = Path(sys.executable).with_name("beeoptics")
# Few rays on a coarse spectrum: these tests check the tool, not the picture.
FAST = ["--samples", "4", "--depth", "1", "--step-nm", "20", "--width-px", "32", "--quiet"]


def call(capsys, *args):
    """Run the tool in this process: exit status, stdout, stderr."""
    code = cli.main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def render_args(receptors, scene, out, *extra):
    return ["render", receptors, scene, "--eye", EYE, "-o", out, *FAST, *extra]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "tiny"
    assert cli.main(["build-eye", str(EYE), "-o", str(out), "--ply", "--quiet"]) == 0
    return out


@pytest.fixture(scope="module")
def rendered(built, tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "flower"
    assert cli.main([str(a) for a in render_args(built / "receptors.csv", FLOWER, out)]) == 0
    return out


def test_help_of_every_subcommand_explains_every_option(capsys):
    top = cli.parser()
    code, out, _ = call(capsys, "--help")
    assert code == 0
    subcommands = top._subparsers._group_actions[0].choices
    assert set(subcommands) == {"build-eye", "render", "daylight", "meadow", "convert", "info", "compile-kernels"}
    schema = yaml.safe_load(cli.CONFIG_SCHEMA.read_text())
    for name, sub in subcommands.items():
        assert name in out
        code, out_sub, _ = call(capsys, name, "--help")
        assert code == 0
        text = " ".join(out_sub.split())
        for action in sub._actions:
            assert action.help, (name, action.dest)
            for word in action.option_strings or [action.metavar]:
                assert word in text, (name, word)
        # Defaults are the workflow schema's, not numbers of the tool's own.
        for option, key, _, _ in cli.SETTINGS.get(name, []):
            node = schema
            for part in key.split("."):
                node = node["properties"][part]
            assert f"{option} " in text and f"(default: {node['default']})" in text, option


def test_the_help_names_every_format_convert_and_info_read(capsys):
    """In the list of subcommands and in info's own help, .gltf and .glb among them."""
    _, top, _ = call(capsys, "--help")
    _, info, _ = call(capsys, "info", "--help")
    for name in ("convert", "info"):
        # Its entry, continuation lines (indented further) included.
        line = " ".join(re.search(rf"^    {name} (.*?)\n {{0,4}}\S", top, re.S | re.M).group(1).split())
        assert all(suffix in line for suffix in cli.FORMATS), (name, line)
    assert all(" ".join(info.split()).count(suffix) >= 2 for suffix in cli.FORMATS), info


def test_build_eye_writes_the_receptor_table(built):
    for name in ("remeshed.ply", "receptors.csv", "quality.json", "relaxation.npz", "receptors.ply"):
        assert (built / name).stat().st_size > 0
    table = read_table(built / "receptors.csv")
    assert tuple(table) == COLUMNS
    assert len(table["id"]) == 600 and sorted(set(table["side"])) == ["left", "right"]
    ply = read_receptor_ply(built / "receptors.ply")
    np.testing.assert_array_equal(ply.position, read_receptors(built / "receptors.csv").position)
    assert not list(built.glob(".partial-*"))


def test_building_the_eye_again_writes_the_same_bytes(built, tmp_path):
    """Identical runs give identical files: no timing is written into them (the relaxation's time is logged)."""
    again = tmp_path / "again"
    assert cli.main(["build-eye", str(EYE), "-o", str(again), "--quiet"]) == 0
    for name in ("quality.json", "receptors.csv", "remeshed.ply"):
        assert (again / name).read_bytes() == (built / name).read_bytes(), name


def test_render_writes_responses_and_images(rendered):
    responses = read_table(rendered / "responses.csv")
    assert len(responses["id"]) == 600 and np.all(responses["G"] > 0)
    for name in ["irradiance.npz", *IMAGES.values()]:
        assert (rendered / name).stat().st_size > 0, name
    assert not list(rendered.glob(".partial-*"))


def test_the_installed_script_renders_the_same_bytes_again(built, rendered, tmp_path):
    again = tmp_path / "again"
    result = subprocess.run([str(a) for a in [TOOL, *render_args(built / "receptors.csv", FLOWER, again)]],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in again.iterdir()) == sorted(p.name for p in rendered.iterdir())
    for path in rendered.iterdir():
        assert (again / path.name).read_bytes() == path.read_bytes(), path.name


def test_daylight_writes_clear_sky_irradiance_in_pavos_layout(tmp_path, capsys):
    from beeoptics.light.materials import ground_albedo
    from beeoptics.sky.daylight import clear_sky

    out = tmp_path / "daylight.csv"
    code, text, _ = call(capsys, "daylight", "--sun-elevation-deg", 30, "--turbidity", 2, "--ground", "snow",
                         "--step-nm", 10, "-o", out)
    assert code == 0 and "daylight.csv" in text
    table = read_table(out, numeric=["wl", "global", "direct", "diffuse"])
    assert list(table) == ["wl", "global", "direct", "diffuse"]
    wl = np.arange(300.0, 701.0, 10.0)
    np.testing.assert_array_equal(table["wl"], wl)
    want = clear_sky(wl, 30.0, 2.0, ground_albedo("snow", wl, "", ""))
    np.testing.assert_allclose(table["diffuse"], want.diffuse, rtol=1e-6)
    np.testing.assert_allclose(table["direct"], want.direct_normal * 0.5, rtol=1e-6)
    np.testing.assert_allclose(table["global"], table["direct"] + table["diffuse"], rtol=1e-6)


def test_daylight_writes_a_scenes_light_as_it_lights_the_ground(tmp_path, capsys):
    from beeoptics.light.scene import load_scene
    from beeoptics.sky.dome import horizontal_irradiance

    out = tmp_path / "light.csv"
    assert call(capsys, "daylight", "--scene", FLOWER, "-o", out)[0] == 0
    table = read_table(out, numeric=["wl", "global", "direct", "diffuse"])
    scene = load_scene(FLOWER, table["wl"])
    np.testing.assert_allclose(table["global"], horizontal_irradiance(scene.sky, scene.sun, len(table["wl"])),
                               rtol=1e-6)


def test_meadow_writes_the_generated_mesh_and_its_palette(tmp_path, capsys):
    from beeoptics.io.meshfile import read_mesh

    meadow = ROOT / "tests" / "data" / "scenes" / "generated" / "meadow.yaml"
    code, text, _ = call(capsys, "meadow", meadow, "-o", tmp_path / "a.ply")
    assert code == 0 and "palette: leucanthemum_vulgare: stem #3f7d2c" in text
    _, faces, colours, _ = read_mesh(tmp_path / "a.ply", patterns=True)
    assert f"{len(faces)} triangles" in text and len(np.unique(colours, axis=0)) == 8  # soil, grass, three parts of each species
    assert call(capsys, "meadow", meadow, "-o", tmp_path / "b.ply")[0] == 0
    assert (tmp_path / "a.ply").read_bytes() == (tmp_path / "b.ply").read_bytes()


def test_convert_round_trips_through_compoundray_and_ply(built, tmp_path, capsys):
    csv = built / "receptors.csv"
    original = read_receptors(csv)
    for conventions in ([], ["--units", "mm", "--frame", "head", "--acceptance", "variance"]):
        assert call(capsys, "convert", csv, tmp_path / "eye.eye", *conventions)[0] == 0
        code, _, err = call(capsys, "convert", tmp_path / "eye.eye", tmp_path / "back.csv", "--side", "auto",
                            *conventions)
        assert code == 0, err
        back = read_receptors(tmp_path / "back.csv")
        np.testing.assert_array_equal(back.side, original.side)
        np.testing.assert_allclose(back.position, original.position, atol=1e-8)
        np.testing.assert_allclose(back.axis, original.axis, atol=1e-8)
        np.testing.assert_allclose(back.delta_rho_deg, original.delta_rho_deg, rtol=1e-7)
    assert call(capsys, "convert", csv, tmp_path / "r.ply")[0] == 0
    assert call(capsys, "convert", tmp_path / "r.ply", tmp_path / "r.csv")[0] == 0
    assert (tmp_path / "r.csv").read_bytes() == csv.read_bytes()
    code, out, _ = call(capsys, "convert", csv, tmp_path / "left.eye", "--only", "left")
    assert code == 0 and "300 receptors" in out
    assert len((tmp_path / "left.eye").read_text().splitlines()) == 300


def test_an_eye_goes_to_compoundray_and_back_with_the_default_options(built, tmp_path, capsys):
    original = read_receptors(built / "receptors.csv")
    assert call(capsys, "convert", built / "receptors.csv", tmp_path / "q.eye")[0] == 0
    code, _, err = call(capsys, "convert", tmp_path / "q.eye", tmp_path / "back.csv")
    assert code == 0, err
    back = read_receptors(tmp_path / "back.csv")
    np.testing.assert_array_equal(back.side, original.side)
    np.testing.assert_allclose(back.position, original.position, atol=1e-8)
    # Δφ measured again on the sphere of axes, as the lattice measured it; a few corner facets
    # of this coarse eye keep no neighbour there (NaN).
    assert np.isnan(back.delta_phi_deg).mean() < 0.05
    assert np.nanmedian(back.delta_phi_deg) == pytest.approx(np.median(original.delta_phi_deg), rel=0.02)


def test_info_describes_eyes_scenes_and_receptors(built, tmp_path, capsys):
    code, out, _ = call(capsys, "info", EYE)
    assert code == 0 and "facets per eye, published: 300" in out and "anchor dorsal" in out
    for path in (built / "receptors.csv", built / "receptors.ply"):
        code, out, _ = call(capsys, "info", path)
        assert code == 0 and "receptors: 600 (right 300, left 300)" in out and "Δφ, degrees: min" in out
    call(capsys, "convert", built / "receptors.csv", tmp_path / "eye.eye")
    code, out, _ = call(capsys, "info", tmp_path / "eye.eye", "--side", "auto")
    assert code == 0 and "right 300, left 300" in out and "facet diameter, µm: not given" in out
    code, out, _ = call(capsys, "info", FLOWER)
    assert code == 0 and "materials: centre, tip, leaf" in out and "object flower" in out
    # Readable text, not Python's reprs of lists and mappings.
    for path in (EYE, ROOT / "eyes" / "drone" / "eye.yaml", FLOWER):
        code, out, _ = call(capsys, "info", path)
        assert code == 0 and not set("[]{}'") & set(out), out


def test_info_describes_measured_eyes(capsys):
    code, out, _ = call(capsys, "info", ROOT / "eyes" / "bombus_terrestris_77970" / "eye.yaml")
    assert code == 0 and "cornea: " in out and "placement: from the cornea" in out and "anchor dorsal: fill" in out
    code, out, _ = call(capsys, "info", ROOT / "eyes" / "drosophila_melanogaster" / "eye.yaml")
    assert code == 0 and "ommatidia: " in out and "699 vertices" in out and "model delta_phi, ratio 1.1" in out


def test_output_piped_to_a_reader_that_stops_early_ends_quietly():
    # As `beeoptics info eye.yaml | head -2`: no "Broken pipe" error once head has its lines.
    result = subprocess.run(f"{TOOL} info {EYE} | head -1", shell=True, capture_output=True, text=True)
    assert result.stdout.startswith("eye: ") and result.stderr == ""


def missing_mesh(tmp_path, built):
    eye = yaml.safe_load(EYE.read_text())
    eye["mesh"] = "nowhere.obj"
    (tmp_path / "eye.yaml").write_text(yaml.safe_dump(eye))
    return ["build-eye", tmp_path / "eye.yaml", "-o", tmp_path / "out"], "eye.yaml", "mesh"


def unknown_material(tmp_path, built):
    shutil.copytree(FLOWER.parent, tmp_path / "flower")
    scene = tmp_path / "flower" / "scene.yaml"
    scene.write_text(FLOWER.read_text().replace("material: leaf", "material: grass"))
    return render_args(built / "receptors.csv", scene, tmp_path / "out"), "scene.yaml", "objects.0.material"


def edited_receptors(tmp_path, built, edits, row=5):
    """A copy of the built receptor table with cells of one row (receptor ``row - 1``) replaced."""
    table = read_table(built / "receptors.csv")
    lines = (built / "receptors.csv").read_text().splitlines()
    cells = lines[row].split(",")
    for column, value in edits.items():
        cells[list(table).index(column)] = value
    lines[row] = ",".join(cells)
    (tmp_path / "receptors.csv").write_text("\n".join(lines) + "\n")
    return tmp_path / "receptors.csv"


def nonpositive_delta_rho(tmp_path, built):
    table = edited_receptors(tmp_path, built, {"delta_rho_deg": "0"})
    return render_args(table, FLOWER, tmp_path / "out"), "receptors.csv", "delta_rho_deg"


def zero_axis(tmp_path, built):
    table = edited_receptors(tmp_path, built, {"ax": "0", "ay": "0", "az": "0"})
    return render_args(table, FLOWER, tmp_path / "out"), "receptors.csv", "ax, ay, az"


def nan_axis(tmp_path, built):
    table = edited_receptors(tmp_path, built, {"ay": "nan"})
    return ["convert", table, tmp_path / "out" / "eye.eye"], "receptors.csv", "ax, ay, az"


def infinite_position(tmp_path, built):
    table = edited_receptors(tmp_path, built, {"x": "inf"})
    return ["info", table], "receptors.csv", "x, y, z"


def zero_samples(tmp_path, built):
    return render_args(built / "receptors.csv", FLOWER, tmp_path / "out", "--samples", "0"), "command line", "--samples"


def unknown_background(tmp_path, built):
    args = render_args(built / "receptors.csv", FLOWER, tmp_path / "out", "--background", "grass")
    return args, "scene.yaml", "materials"


def turbid_daylight(tmp_path, built):
    return ["daylight", "--turbidity", "20", "-o", tmp_path / "out" / "d.csv"], "command line", "--turbidity"


def unknown_ground(tmp_path, built):
    return ["daylight", "--ground", "gras", "-o", tmp_path / "out" / "d.csv"], "command line", "--ground"


def meadow_of_unknown_species(tmp_path, built):
    (tmp_path / "meadow.yaml").write_text("plants: [{species: bellis_perenis, density_per_m2: 1}]\n")
    return ["meadow", tmp_path / "meadow.yaml", "-o", tmp_path / "out" / "meadow.ply"], "meadow.yaml", "plants"


def directions_without_a_sphere(tmp_path, built):
    path = tmp_path / "directions.csv"
    path.write_text("1,0,0\n0,1,0\n0,0,1\n")
    return ["convert", path, tmp_path / "out" / "eye.csv", "--directions"], "directions.csv", ""


def unknown_format(tmp_path, built):
    return ["convert", built / "receptors.csv", tmp_path / "out" / "eye.txt"], "eye.txt", ""


@pytest.mark.parametrize("case", [missing_mesh, unknown_material, nonpositive_delta_rho, zero_axis, nan_axis,
                                  infinite_position, zero_samples, unknown_background, turbid_daylight, unknown_ground,
                                  meadow_of_unknown_species, directions_without_a_sphere, unknown_format])
def test_bad_input_is_one_line_naming_file_and_field_and_writes_nothing(case, tmp_path, built, capsys):
    args, file, field = case(tmp_path, built)
    code, out, err = call(capsys, *args)
    assert code == 2
    assert len(err.splitlines()) == 1 and err.startswith("beeoptics: error: "), err
    assert f"{file}: {field}" in err, err
    if file == "receptors.csv":
        assert f"{field}: receptor 4: " in err, err
    assert not (tmp_path / "out").exists()


def test_the_installed_script_reports_bad_input_without_a_traceback(tmp_path, built):
    args, _, _ = nonpositive_delta_rho(tmp_path, built)
    args.remove("--quiet")
    result = subprocess.run([str(a) for a in [TOOL, *args]], capture_output=True, text=True)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        f"beeoptics: error: {tmp_path / 'receptors.csv'}: delta_rho_deg: receptor 4: acceptance angles must be positive and finite"]
    assert not (tmp_path / "out").exists()


def test_a_run_failing_late_leaves_the_output_folder_as_it_was(tmp_path, built, capsys, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    (out / "responses.csv").write_text("older\n")

    def fail(*args, **kwargs):
        raise InputError("eye.yaml", "placement", "refused after the trace")

    monkeypatch.setattr("beeoptics.pipeline.images.retinal_images", fail)
    code, _, err = call(capsys, *render_args(built / "receptors.csv", FLOWER, out))
    assert code == 2 and "refused after the trace" in err
    assert [p.name for p in out.iterdir()] == ["responses.csv"]
    assert (out / "responses.csv").read_text() == "older\n"


def test_an_eye_from_compoundray_renders_here(tmp_path, capsys):
    # An eye as a micro-CT study would export it for CompoundRay: one line per ommatidium,
    # position (mm) and direction in CompoundRay's camera frame (right, up, forward), the
    # acceptance angle (rad) and a focal offset; a hemispherical eye of 0.5 mm radius.
    k = np.arange(400) + 0.5
    z = 1.0 - k / 400
    phi = np.pi * (1.0 + 5**0.5) * k
    r = np.sqrt(1.0 - z * z)
    axes = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    lines = [" ".join(f"{v:.9g}" for v in (*(0.5 * a), *a, np.radians(2.6), 0.0)) for a in axes]
    (tmp_path / "scanned.eye").write_text("\n".join(lines) + "\n")
    code, _, err = call(capsys, "convert", tmp_path / "scanned.eye", tmp_path / "scanned.csv")
    assert code == 0, err
    code, out, err = call(capsys, "render", tmp_path / "scanned.csv", FLOWER, "-o", tmp_path / "out", *FAST)
    assert code == 0, err
    resp = read_table(tmp_path / "out" / "responses.csv", numeric=["UV", "B", "G"], text=["side"])
    assert len(resp["UV"]) == 400
    assert all(np.isfinite(resp[c]).all() and (resp[c] > 0).all() for c in ("UV", "B", "G"))
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["irradiance.npz", "responses.csv"]


def render_under_way(built, out):
    """A long render started in a subprocess, returned once its scratch folder exists and it is tracing."""
    args = [str(a) for a in [TOOL, "render", built / "receptors.csv", FLOWER, "--eye", EYE, "-o", out,
                             "--samples", "4096", "--depth", "2", "--step-nm", "20", "--width-px", "32", "--quiet"]]
    run = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(out.glob(".partial-*")) and run.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(0.5)
    assert run.poll() is None, "the render ended before it could be stopped"
    return run


def test_a_killed_render_leaves_nothing_once_the_next_command_runs(built, rendered, tmp_path):
    out = tmp_path / "out"
    run = render_under_way(built, out)
    run.send_signal(signal.SIGKILL)
    run.wait(30)
    assert [p.name.startswith(".partial-") for p in out.iterdir()] == [True]
    code = subprocess.run([str(a) for a in [TOOL, *render_args(built / "receptors.csv", FLOWER, out)]],
                          capture_output=True, text=True).returncode
    assert code == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in rendered.iterdir())
    for path in rendered.iterdir():
        assert (out / path.name).read_bytes() == path.read_bytes(), path.name


def test_a_render_sent_sigterm_cleans_up_as_after_ctrl_c(built, tmp_path):
    # SIGTERM is what a cluster's scheduler sends at a job's time limit (Slurm, then SIGKILL after its KillWait).
    out = tmp_path / "out"
    run = render_under_way(built, out)
    run.send_signal(signal.SIGTERM)
    _, err = run.communicate(timeout=60)
    # The folder the render made for its outputs goes too, as nothing was written into it.
    assert not out.exists() or [p.name for p in out.iterdir()] == []
    assert (run.returncode, err) == (128 + signal.SIGTERM, "beeoptics: terminated\n")


class Finalised:
    def __del__(self):
        os.kill(os.getpid(), signal.SIGTERM)


def in_a_finaliser():
    Finalised()  # dropped at once: its finaliser runs here, and Python prints what it raises and goes on


def in_a_library_that_catches_everything():
    try:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(1)
    except BaseException:
        pass


@pytest.mark.parametrize("swallowed", [in_a_finaliser, in_a_library_that_catches_everything])
def test_a_sigterm_swallowed_where_it_landed_still_stops_the_render(built, tmp_path, capsys, monkeypatch, swallowed):
    # Python raises a stop at whatever step it lands; not every step lets it through. Of 150 renders sent
    # SIGTERM in their first seconds, two went on and committed their outputs with exit status 0, as one in CI did.
    from beeoptics.pipeline import trace

    gather = trace.gather_responses

    def gather_after_a_stop(*args, **kwargs):
        swallowed()
        return gather(*args, **kwargs)

    monkeypatch.setattr(trace, "gather_responses", gather_after_a_stop)
    out = tmp_path / "out"
    assert call(capsys, *render_args(built / "receptors.csv", FLOWER, out)) == (128 + signal.SIGTERM, "",
                                                                              "beeoptics: terminated\n")
    assert not out.exists()


def test_a_run_started_with_ctrl_c_ignored_keeps_it_ignored():
    # A shell's background job (`make test &`, nohup) inherits SIGINT ignored: a Ctrl-C at the terminal is
    # not for it, and the stops kept for a commit (a handler of their own) must not make it so.
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with sigterm_as_interrupt():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.1)
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_stop_during_a_compiled_modules_import_is_reported_as_the_stop(monkeypatch, capsys):
    # SIGTERM (or Ctrl-C) while Open3D's module initialises reaches the caller as pybind11's
    # ImportError("initialization failed"), caused by the stop: seen with a render stopped 2 s in.
    def stopped(args):
        try:
            raise Terminated
        except Terminated as e:
            raise ImportError("initialization failed") from e

    monkeypatch.setattr(cli, "info", stopped)
    assert call(capsys, "info", EYE) == (128 + signal.SIGTERM, "", "beeoptics: terminated\n")
    monkeypatch.setattr(cli, "info", lambda args: __import__("a_module_that_is_not_there"))
    with pytest.raises(ImportError):
        cli.main(["info", str(EYE)])


def test_help_and_version_load_none_of_the_heavy_libraries():
    """--help must answer at once: the stages' libraries are imported by the commands that use them."""
    code = ("import sys; from beeoptics import cli; cli.parser().format_help(); "
            "print(' '.join(m for m in ('open3d', 'pymeshlab', 'igl', 'colour', 'matplotlib', 'OpenImageIO') "
            "if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == ""
    version = subprocess.run([str(TOOL), "--version"], capture_output=True, text=True)
    assert version.returncode == 0 and version.stdout.strip() == "beeoptics 0.1.0"


def test_render_can_write_the_visual_field_and_colour_space_figures(built, tmp_path, capsys):
    out = tmp_path / "out"
    code, _, err = call(capsys, *render_args(built / "receptors.csv", FLOWER, out, "--figures",
                                             "--field-width-px", "90"))
    assert code == 0, err
    for name in ("visual_field.png", "visual_field.exr", "triangle.png", "hexagon.png", "viewer.html"):
        assert (out / name).stat().st_size > 0, name


def test_relaxation_progress_runs_from_the_first_move_to_the_tolerance():
    assert cli.settled(1.0, 1.0, 0.01) == 0
    assert cli.settled(1.0, 0.1, 0.01) == 50
    assert cli.settled(1.0, 0.0101, 0.01) == 99
    assert cli.settled(1.0, 0.005, 0.01) == 100


def test_a_generated_meadow_not_yet_generated_is_made_on_demand_as_the_meadow_command_makes_it(tmp_path, capsys):
    """As in a fresh clone, whose scenes/meadow has its meadow.yaml but not the mesh the workflow generates."""
    scene = tmp_path / "generated"
    shutil.copytree(DATA / "scenes" / "generated", scene)
    code, out, err = call(capsys, "info", scene / "scene.yaml")
    assert code == 0 and "object meadow:" in out and "generating" in err, err
    code, _, _ = call(capsys, "meadow", scene / "meadow.yaml", "-o", tmp_path / "meadow.ply", "--flowers",
                      tmp_path / "flowers.csv")
    assert code == 0
    assert (scene / "meadow.ply").read_bytes() == (tmp_path / "meadow.ply").read_bytes()
    assert (scene / "meadow_flowers.csv").read_bytes() == (tmp_path / "flowers.csv").read_bytes()


def test_render_reads_a_compoundray_eye_as_convert_does(built, tmp_path, capsys):
    eye = tmp_path / "tiny.eye"
    assert call(capsys, "convert", built / "receptors.csv", eye)[0] == 0
    out = tmp_path / "out"
    code, _, err = call(capsys, "render", eye, FLOWER, "-o", out, *FAST)
    assert code == 0, err
    # The table the responses' ids refer to, beside them: the .eye's receptors.
    table, responses = read_receptors(out / "receptors.csv"), read_table(out / "responses.csv", text=["side"])
    np.testing.assert_allclose(table.position, read_receptors(built / "receptors.csv").position, atol=1e-8)
    np.testing.assert_array_equal(responses["id"], table.id)


def test_the_relaxations_progress_never_goes_back(monkeypatch, tmp_path, capsys):
    """The largest move rises again where the springs turn geodesic: the bar holds its furthest point."""
    import beeoptics.pipeline.eyes as stages

    shown = []

    class Bar(cli.tqdm):
        def update(self, n=1):
            assert n >= 0, "the bar went back"
            super().update(n)
            shown.append(self.n)

    def build_facets(*args, progress, **kwargs):
        for iteration, largest_mm in enumerate((6e-3, 1e-3, 2e-4, 3e-3, 5e-4, 4e-5)):
            progress(iteration, largest_mm)
        raise InputError("eye.yaml", "facets", "stopped here by the test")

    monkeypatch.setattr(cli, "tqdm", Bar)
    monkeypatch.setattr(stages, "remesh_eye", lambda *args, **kwargs: None)
    monkeypatch.setattr(stages, "build_facets", build_facets)
    code, _, _ = call(capsys, "build-eye", EYE, "-o", tmp_path / "out")
    assert code == 2 and shown == sorted(shown) and shown[-1] == 100, shown


def test_an_output_folder_that_cannot_be_written_is_named(built, tmp_path, capsys):
    blocker = tmp_path / "a file"
    blocker.write_text("not a folder\n")
    code, _, err = call(capsys, *render_args(built / "receptors.csv", FLOWER, blocker / "out"))
    assert code == 2 and err.strip() == f"beeoptics: error: {blocker / 'out'}: cannot write there (Not a directory)"
    code, _, err = call(capsys, "convert", built / "receptors.csv", blocker / "eye.eye")
    # The cause in words, without Python's "[Errno 17]".
    assert code == 1 and err.strip() == f"beeoptics: error: {blocker}: cannot write there (a file, not a folder)"
