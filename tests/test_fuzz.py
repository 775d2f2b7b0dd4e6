"""Fuzzing: malformed input files of every kind get a result or one line naming the file, nothing else.

Each case mutates a valid file (a config, an eye or scene description, a
spectrum CSV, a mesh, a CompoundRay eye, a receptor table) and runs the
loader or the command-line tool on it. It must either succeed or raise an
:class:`InputError` whose message is one line naming the file; the tool
must exit 0 with its output written, or 2 with one line and no output.
Never a traceback, a signal or a partial artifact. The examples are drawn
from a fixed seed, so a run is reproducible; a longer search:

    BEEOPTICS_FUZZ_EXAMPLES=2000 .venv/bin/pytest tests/test_fuzz.py
"""

import contextlib
import io
import os
import shutil
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from beeoptics import cli
from beeoptics.eye.description import load_eye, load_eye_mesh
from beeoptics.eye.receptors import measure_spacing
from beeoptics.io.errors import InputError
from beeoptics.io.interchange import read_compoundray_eye
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.validation import CONFIG_SCHEMA, validate_config
from beeoptics.light.scene import load_scene
from beeoptics.spectra import grid, read_pavo_csv
from conftest import ROOT

DATA = ROOT / "tests" / "data"
WL = grid(300.0, 700.0, 20.0)
FUZZ = settings(max_examples=int(os.environ.get("BEEOPTICS_FUZZ_EXAMPLES", 500)), deadline=None, derandomize=True,
                database=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
#: What a mutation puts into a file: numbers out of range and not numbers, separators, nothing.
NOISE = ["nan", "-1", "0", "1e309", "-0", "9999999999", "", "abc", ",", " ", "\n", ":", "[", "{", "#", "'", "\t",
         "-", ".", "1.5.2", "f 1 2 99999", "v 1 2", "/"]


@st.composite
def mutated(draw, text):
    """``text`` with a few spans replaced by noise, or cut short."""
    for _ in range(draw(st.integers(1, 3))):
        if not text:
            break
        start = draw(st.integers(0, len(text) - 1))
        end = draw(st.integers(start, min(len(text), start + 12)))
        text = text[:start] + draw(st.sampled_from(NOISE)) + text[end:]
    if draw(st.booleans()) and draw(st.booleans()):
        text = text[:draw(st.integers(0, len(text)))]
    return text


def one_line_naming(error, path):
    message = str(error)
    assert "\n" not in message and Path(path).name in message, message


def outcome(load, path):
    """Run a loader: it succeeds, or refuses in one line naming ``path``."""
    try:
        load(path)
    except InputError as e:
        one_line_naming(e, path)


def tool(*args):
    """Run the command-line tool in this process: exit status and what it printed to stderr."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = cli.main([str(a) for a in args])
    return code, err.getvalue()


def copy_of(tmp_path, folder):
    target = tmp_path / f"case{len(list(tmp_path.iterdir()))}"
    shutil.copytree(folder, target)
    return target


@FUZZ
@given(data=st.data())
def test_a_mutated_eye_description_or_mesh(tmp_path, data):
    eye = copy_of(tmp_path, DATA / "eyes" / "tiny")
    name = data.draw(st.sampled_from(["eye.yaml", "mesh.obj"]))
    (eye / name).write_text(data.draw(mutated((eye / name).read_text())))
    try:
        load_eye_mesh(load_eye(eye / "eye.yaml"))
    except InputError as e:
        assert "\n" not in str(e) and any(n in str(e) for n in ("eye.yaml", "mesh.obj")), str(e)


@FUZZ
@given(data=st.data())
def test_a_mutated_scene_or_its_mesh(tmp_path, data):
    scene = copy_of(tmp_path, DATA / "scenes" / "flower")
    name = data.draw(st.sampled_from(["scene.yaml", "daisy.obj", "daisy.mtl"]))
    (scene / name).write_text(data.draw(mutated((scene / name).read_text())))
    try:
        load_scene(scene / "scene.yaml", WL)
    except InputError as e:
        assert "\n" not in str(e) and any(n in str(e) for n in ("scene.yaml", "daisy.obj", "daisy.mtl")), str(e)


@pytest.fixture(scope="module")
def ply_flower(tmp_path_factory):
    """The flower scene with its daisy as a binary PLY with face colours, as MeshLab (pymeshlab) writes it."""
    from beeoptics.io.meshfile import read_mesh
    from test_scene import write_meshlab_ply

    folder = tmp_path_factory.mktemp("ply_flower")
    shutil.copytree(DATA / "scenes" / "flower", folder / "flower")
    v, f, colours, _ = read_mesh(folder / "flower" / "daisy.obj", patterns=True)
    write_meshlab_ply(folder / "flower" / "daisy.ply", v, f, face_colours=colours)
    scene = yaml.safe_load((folder / "flower" / "scene.yaml").read_text())
    scene["objects"][1]["mesh"] = "daisy.ply"
    (folder / "flower" / "scene.yaml").write_text(yaml.safe_dump(scene))
    return folder / "flower"


@FUZZ
@given(data=st.data())
def test_a_mutated_binary_ply_with_face_colours(tmp_path, ply_flower, data):
    scene = copy_of(tmp_path, ply_flower)
    # Bytes as latin-1 text, so that the mutations reach the header and the binary records alike.
    text = (scene / "daisy.ply").read_bytes().decode("latin-1")
    (scene / "daisy.ply").write_bytes(data.draw(mutated(text)).encode("latin-1", errors="replace"))
    try:
        load_scene(scene / "scene.yaml", WL)
    except InputError as e:
        assert "\n" not in str(e) and any(n in str(e) for n in ("scene.yaml", "daisy.ply")), str(e)


@FUZZ
@given(data=st.data())
def test_a_mutated_spectrum_csv(tmp_path, data):
    lines = ["wl,petal,leaf"] + [f"{w:g},{0.2 + w / 2000:.3f},{0.05 + w / 5000:.3f}" for w in range(300, 701, 10)]
    path = tmp_path / f"spectra{len(list(tmp_path.iterdir()))}.csv"
    path.write_text(data.draw(mutated("\n".join(lines) + "\n")))
    outcome(lambda p: read_pavo_csv(p, WL), path)


@FUZZ
@given(data=st.data())
def test_a_mutated_config(tmp_path, data):
    text = (ROOT / "config" / "config.yaml").read_text()
    mutation = data.draw(mutated(text))
    try:
        config = yaml.safe_load(mutation)
    except yaml.YAMLError:
        return  # Snakemake parses the config file itself
    config = config if isinstance(config, dict) else {"eyes": config}
    config.update(eyes_dir=str(ROOT / "eyes"), scenes_dir=str(ROOT / "scenes"))
    outcome(lambda p: validate_config(config, CONFIG_SCHEMA, p), tmp_path / "config.yaml")


@pytest.fixture(scope="module")
def receptors(tmp_path_factory):
    """The tiny eye's receptor table, and the same as a CompoundRay eye."""
    out = tmp_path_factory.mktemp("fuzz")
    assert cli.main(["build-eye", str(DATA / "eyes" / "tiny" / "eye.yaml"), "-o", str(out), "--quiet"]) == 0
    assert cli.main(["convert", str(out / "receptors.csv"), str(out / "tiny.eye")]) == 0
    return out


@FUZZ
@given(data=st.data())
def test_a_mutated_receptor_table_or_compoundray_eye_through_the_tool(tmp_path, receptors, data):
    name = data.draw(st.sampled_from(["receptors.csv", "tiny.eye"]))
    case = tmp_path / f"case{len(list(tmp_path.iterdir()))}"
    case.mkdir()
    source = case / name
    source.write_text(data.draw(mutated((receptors / name).read_text())))
    target = case / "out" / ("back.csv" if name.endswith(".eye") else "back.eye")
    code, err = tool("convert", source, target)
    if code == 0:
        assert target.stat().st_size > 0
        read_receptors(target) if target.suffix == ".csv" else measure_spacing(read_compoundray_eye(target), target)
    else:
        assert code == 2 and len(err.splitlines()) == 1 and err.startswith("beeoptics: error: "), err
        assert not target.exists()
    # Nothing half-written beside the output.
    assert not [p for p in target.parent.glob(".*")] if target.parent.exists() else True
