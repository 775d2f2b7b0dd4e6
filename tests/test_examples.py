"""The examples run as a user runs them, small (``BEEOPTICS_EXAMPLES_SMALL=1``: the small test eye, a toy
scene, few rays), and write their tables and figures where they are told."""

import runpy

import matplotlib
import numpy as np
import pandas as pd
import pytest

from conftest import ROOT

EXAMPLES = ROOT / "examples"


@pytest.fixture
def run(tmp_path, monkeypatch):
    """Run an example from the repository's folder, as its notes say, its outputs in ``tmp_path``: its globals."""
    matplotlib.use("Agg")
    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("BEEOPTICS_EXAMPLES_SMALL", "1")
    monkeypatch.setenv("BEEOPTICS_EXAMPLES_OUT", str(tmp_path))

    def example(name, **env):
        for key, value in env.items():
            monkeypatch.setenv(key, value)
        found = runpy.run_path(str(EXAMPLES / f"{name}.py"), run_name="__main__")
        for suffix in (".csv", ".png"):
            assert (tmp_path / f"{name}{suffix}").stat().st_size > 0, f"{name}{suffix}"
        return found, pd.read_csv(tmp_path / f"{name}.csv")

    yield example
    import matplotlib.pyplot as plt
    plt.close("all")


def test_own_scene_tables_every_receptor_in_the_scene_it_is_given(run):
    found, table = run("own_scene", BEEOPTICS_EXAMPLES_SCENE="tests/data/scenes/meadow_tiny/scene.yaml")
    assert found["scene"].path.parent.name == "meadow_tiny"
    assert len(table) == len(found["eye"].table.id) and table.id.is_unique
    assert {"azimuth_deg", "elevation_deg", "UV", "se_UV", "G", "hex_r", "se_hex_r", "rnl_dS"} <= set(table.columns)
    assert (table[["UV", "B", "G"]] >= 0).all().all()


def test_own_scene_refuses_a_scene_it_cannot_use_in_one_line(run, tmp_path):
    with pytest.raises(SystemExit, match=r"^error: tests/data/scenes/none/scene.yaml: no such file$"):
        run("own_scene", BEEOPTICS_EXAMPLES_SCENE="tests/data/scenes/none/scene.yaml")
    assert not list(tmp_path.iterdir())


def test_two_species_see_one_flower_through_their_own_receptors(run):
    found, flower = run("two_species")
    assert list(flower.species) == ["honey bee", "bumblebee"]
    # One eye for both when small: the same receptors fall on the flower, their colours differ by their curves.
    assert flower.receptors.iloc[0] == flower.receptors.iloc[1] > 0
    assert flower.hex_x.iloc[0] != flower.hex_x.iloc[1]
    assert (flower.se_hex_r > 0).all()


def test_the_sweep_sees_the_flower_stand_out_less_from_further_away(run):
    _, sweep = run("sweep")
    assert np.all(np.diff(sweep.distance_m) > 0) and np.all(np.diff(sweep.flower_diameter_deg) < 0)
    # Up close the flower fills the receptor's acceptance cone; far off the grass around it mixes in.
    assert sweep.hex_r.iloc[0] > sweep.hex_r.iloc[-1] and sweep.rnl_dS.iloc[0] > sweep.rnl_dS.iloc[-1]
    assert (sweep.se_rnl_dS > 0).all() and (sweep.off_centre_deg < 10).all()
