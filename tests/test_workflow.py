"""The workflow end to end, on a small eye and two small scenes, through Snakemake's CLI."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from beeoptics.imagefile import read_image
from beeoptics.table import read_table
from conftest import ROOT

DATA = ROOT / "tests" / "data"
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))


def run(workdir, *args):
    return subprocess.run(
        [SNAKEMAKE, "--snakefile", str(ROOT / "Snakefile"), "--directory", str(workdir),
         "--configfile", str(workdir / "config.yaml"), "--cores", "2", *args],
        capture_output=True, text=True, cwd=workdir)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    work = tmp_path_factory.mktemp("workflow")
    shutil.copytree(DATA / "eyes", work / "eyes")
    shutil.copytree(DATA / "scenes", work / "scenes")
    config = {
        "eyes": ["tiny"], "scenes": ["open", "flower"],
        "eyes_dir": str(work / "eyes"), "scenes_dir": str(work / "scenes"),
        "spectral": {"start_nm": 300, "end_nm": 700, "step_nm": 10},
        "trace": {"samples_per_receptor": 16, "depth": 2, "seed": 3},
        "images": {"width_px": 64},
    }
    (work / "config.yaml").write_text(yaml.safe_dump(config))
    # The workflow's own files (config schema, report captions) are found beside its Snakefile.
    result = run(work)
    assert result.returncode == 0, result.stderr[-3000:]
    return work


def test_every_artifact_is_written(workdir):
    eye = workdir / "results" / "eyes" / "tiny"
    for name in ("remeshed.ply", "receptors.csv", "quality.json", "relaxation.npz",
                 "figures/relaxation.png", "figures/delta_phi.png", "figures/facet_diameter.png"):
        assert (eye / name).stat().st_size > 0
    for scene in ("open", "flower"):
        for name in ("responses.csv", "irradiance.npz", "voronoi_map3.png", "voronoi_map2.png",
                     "density_map3.png", "channel_uv.png", "channel_b.png", "channel_g.png", "catches.exr"):
            assert (workdir / "results" / "tiny" / scene / name).stat().st_size > 0
        for name in ("human.png", "human.exr"):
            assert (workdir / "results" / "scenes" / scene / name).stat().st_size > 0


def test_receptor_table_describes_both_eyes_in_the_head_frame(workdir):
    t = read_table(workdir / "results" / "eyes" / "tiny" / "receptors.csv")
    assert list(t) == ["id", "side", "x", "y", "z", "ax", "ay", "az",
                       "facet_diameter_um", "delta_phi_deg", "delta_rho_deg"]
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
