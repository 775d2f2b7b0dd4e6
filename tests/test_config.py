import copy

import pytest
import yaml
from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from beeoptics.io.validation import CONFIG_SCHEMA
from conftest import ROOT

SCHEMA = str(CONFIG_SCHEMA)


def default():
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def test_default_config_is_valid_and_defaults_fill_gaps():
    validate(default(), SCHEMA, set_default=True)
    cfg = {"eyes": ["worker"]}
    validate(cfg, SCHEMA, set_default=True)
    assert cfg["trace"]["samples_per_receptor"] == 256
    assert cfg["spectral"] == {"start_nm": 300, "end_nm": 700, "step_nm": 5}


@pytest.mark.parametrize(
    "edit, key",
    [
        (lambda c: c["trace"].update(sampels_per_receptor=4), "sampels_per_receptor"),
        (lambda c: c.update(scense=["meadow"]), "scense"),
        (lambda c: c["trace"].update(depth=0), "depth"),
        (lambda c: c["spectral"].update(step_nm=-5), "step_nm"),
        (lambda c: c["eye"]["delta_rho"].update(model="wide"), "model"),
    ],
)
def test_a_wrong_key_or_value_stops_the_run_naming_it(edit, key):
    cfg = copy.deepcopy(default())
    edit(cfg)
    with pytest.raises(WorkflowError, match=key):
        validate(cfg, SCHEMA, set_default=True)
