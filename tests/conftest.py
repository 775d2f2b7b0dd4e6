"""Shared fixtures: the spectral grid, meshes, the reference data, scene files."""

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
import yaml

from beeoptics.spectra import grid

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
SHARED = ROOT.parent / "shared" / "data"
# The tests' scene cache is their own (beeoptics.light.scenecache), not the user's; the workflows they
# run inherit it.
os.environ["BEEOPTICS_CACHE"] = tempfile.mkdtemp(prefix="beeoptics-test-cache-")


@pytest.fixture(scope="session")
def wavelengths():
    return grid(300.0, 700.0, 5.0)


@pytest.fixture(scope="session")
def shared_data():
    """The measured reference data beside the repository, or a skip saying why."""
    if not SHARED.is_dir():
        pytest.skip(f"reference data not found at {SHARED} (it is not part of the repository)")
    return SHARED


def cap_mesh(radius=1.0, half_angle_deg=60.0, rings=24):
    """A spherical cap around +z, a height field over xy: (vertices, faces)."""
    import igl

    v, f = igl.icosahedron()
    for _ in range(5):
        v, f = igl.loop(v, f)
        v = v / np.linalg.norm(v, axis=1, keepdims=True)
    keep_f = (v[f][:, :, 2] >= np.cos(np.radians(half_angle_deg))).all(1)
    f = f[keep_f]
    used, inv = np.unique(f, return_inverse=True)
    return v[used] * radius, inv.reshape(-1, 3)


def disc_mesh(radius=1.0, edge=0.05):
    """A flat disc in the xy-plane, remeshed isotropically with pymeshlab."""
    import pymeshlab

    n = 64
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    v = np.vstack([[0, 0, 0], np.column_stack([radius * np.cos(t), radius * np.sin(t), np.zeros(n)])])
    f = np.array([[0, 1 + i, 1 + (i + 1) % n] for i in range(n)])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(v, f))
    ms.meshing_isotropic_explicit_remeshing(iterations=10, targetlen=pymeshlab.PureValue(edge))
    m = ms.current_mesh()
    return m.vertex_matrix(), m.face_matrix().astype(np.int64)


def build_eye_files(eye_yaml, outdir):
    """Remesh and build an eye with the default settings, as the workflow does: its output paths."""
    from beeoptics.eye.optics import AcceptanceModel
    from beeoptics.io.validation import config_defaults
    from beeoptics.pipeline.eyes import build_facets, remesh_eye
    from beeoptics.pipeline.outputs import FACET_OUTPUTS

    eye = config_defaults()["eye"]
    outdir = Path(outdir)
    outputs = {"remeshed": outdir / "remeshed.ply", **{k: outdir / name for k, name in FACET_OUTPUTS.items()}}
    remesh_eye(eye_yaml, outputs, edge_fraction=eye["edge_fraction"])
    build_facets(eye_yaml, outputs["remeshed"], outputs, tolerance_um=eye["tolerance_um"],
                 acceptance=AcceptanceModel.from_config(eye["delta_rho"]))
    return outputs


def _build_on_two_blas_threads(eye_yaml, outdir):
    from threadpoolctl import threadpool_limits

    # BLAS on two threads, as on this two-core machine by default.
    with threadpool_limits(limits=2, user_api="blas"):
        return build_eye_files(eye_yaml, outdir)


def build_eyes(eyes):
    """Build eyes as :func:`build_eye_files` does, two at a time in fresh processes (each build is
    mostly single-threaded): ``eyes`` maps a name to ``(eye_yaml, outdir)``; their output paths by name."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        built = {name: pool.submit(_build_on_two_blas_threads, *args) for name, args in eyes.items()}
        return {name: job.result() for name, job in built.items()}


@pytest.fixture(scope="session")
def built_eyes(tmp_path_factory):
    """The repository's eyes built once a session: ``built_eyes(*names)`` builds those not built yet
    (:func:`build_eyes`) and returns each one's output paths by name. The worker's build, the eye tests'
    and the detection tests', was twice half a minute."""
    done = {}

    def build(*names):
        todo = [name for name in names if name not in done]
        if todo:
            done.update(build_eyes({name: (ROOT / "eyes" / name / "eye.yaml", tmp_path_factory.mktemp(name))
                                    for name in todo}))
        return {name: done[name] for name in names}

    return build


def write_scene(path, scene):
    """Write a scene description to ``path`` (a scene.yaml), creating its folder."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(scene, sort_keys=False))
    return path


SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))


def run(workdir, *args):
    return subprocess.run(
        [SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(workdir),
         "--configfile", str(workdir / "config.yaml"), "--cores", "2", *args],
        capture_output=True, text=True, cwd=workdir)


@pytest.fixture(scope="session")
def workdir(tmp_path_factory):
    """The workflow run once on a small eye and small scenes, every stage and product; for the workflow's
    and the viewers' tests."""
    work = tmp_path_factory.mktemp("workflow")
    shutil.copytree(DATA / "eyes", work / "eyes")
    shutil.copytree(DATA / "scenes", work / "scenes")
    # The fly, a measured eye built fast (its ommatidia are given), for the comparison target.
    shutil.copytree(ROOT / "eyes" / "drosophila_melanogaster", work / "eyes" / "drosophila_melanogaster")
    # A dorsal rim area, for the polarisation stages: the 12 facets nearest the dorsal margin (a test value).
    with open(work / "eyes" / "tiny" / "eye.yaml", "a") as f:
        f.write("dorsal_rim: {count: 12}\n")
    config = {
        # The generated meadow for the flight and the survey, which run only in the run's scenes.
        "eyes": ["tiny"], "scenes": ["open", "flower", "generated"],
        "eyes_dir": str(work / "eyes"), "scenes_dir": str(work / "scenes"),
        "spectral": {"start_nm": 300, "end_nm": 700, "step_nm": 10},
        # The animal's precision, so that the stages are run adaptive; the sections' own samples, fixed.
        "trace": {"samples_per_receptor": 16, "depth": 2, "seed": 3, "precision": {"target": "auto"}},
        "images": {"width_px": 64, "visual_field_width_px": 180},
        "sweeps": {"demo": {"eyes": ["tiny"], "scenes": ["flower"], "delta_rho_deg": [1.5, 4.0],
                            "sun_elevation_deg": [20, 70]}},
        "flights": {"dive": {"scene": "generated", "path": "flights/approach.csv", "eyes": ["tiny"], "fps": 10,
                             "samples_per_receptor": 4, "target": {"position_m": [0.1, 0.0, 0.12], "radius_m": 0.02},
                             "human_view": {"width_px": 40, "height_px": 30, "samples_per_pixel": 1}}},
        "comparison": {"eyes": ["tiny", "drosophila_melanogaster"]},
        "detection": {"eyes": ["tiny"], "scenes": ["generated"], "flowers_per_species": 1, "directions": 2,
                      "distances": {"steps": 4}, "samples_per_receptor": 4, "depth": 1},
        "polarisation": {"eyes": ["tiny"], "scenes": ["flower"], "samples_per_receptor": 8,
                         "compass": {"headings": 8, "samples_per_receptor": 8, "turbidities": [5],
                                     "heights_m": [0.02]}},
        # Views for navigation: one place (its map, every 10° heading, a catchment of one), the stages' outputs.
        "navigation": {"eyes": ["tiny"], "scenes": ["flower"], "heading_step_deg": 10,
                       "grids": {"small": {"extent_m": 0.0, "spacing_m": 0.1}}},
    }
    (work / "config.yaml").write_text(yaml.safe_dump(config))
    # The workflow's own files (report captions) are found beside its Snakefile.
    result = run(work)
    assert result.returncode == 0, result.stderr[-3000:]
    return work
