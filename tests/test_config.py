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


def test_every_door_takes_its_defaults_from_the_schema():
    # The library's keyword defaults are the workflow's and the command line's: one source, the schema.
    import inspect

    import numpy as np

    from beeoptics.eye.fieldofview import visual_field
    from beeoptics.eye.optics import AcceptanceModel
    from beeoptics.io.validation import config_defaults
    from beeoptics.light.batching import TraceSettings
    from beeoptics import tracing
    from beeoptics.pipeline import eyes, flights, images, polarisation, trace
    from beeoptics.spectra import grid
    from beeoptics.vision.receptorset import curves

    config = config_defaults()
    assert AcceptanceModel() == AcceptanceModel.from_config(config["eye"]["delta_rho"])
    np.testing.assert_array_equal(grid(), grid(**config["spectral"]))
    assert TraceSettings(1, 1, 1, 1024).sky_sampling == config["trace"]["sky_sampling"]
    doors = [(trace.gather_responses, {"background": "colour.background", "receptor_curves": "colour.sensitivities"}),
             (tracing.respond, {"background": "colour.background", "receptor_curves": "colour.sensitivities"}),
             (flights.flight_products, {"background": "colour.background"}),
             (curves, {"setting": "colour.sensitivities"}),
             (eyes.remesh_eye, {"edge_fraction": "eye.edge_fraction"}),
             (images.retinal_images, {"width_px": "images.width_px"}),
             (visual_field, {"width_px": "images.visual_field_width_px"}),
             (polarisation.compass, {"headings": "polarisation.compass.headings",
                                     "turbidities": "polarisation.compass.turbidities",
                                     "heights_m": "polarisation.compass.heights_m",
                                     "dorsal_rim_ps": "polarisation.dorsal_rim_ps"})]
    for function, keys in doors:
        parameters = inspect.signature(function).parameters
        for name, key in keys.items():
            value = config
            for part in key.split("."):
                value = value[part]
            assert parameters[name].default == value, f"{function.__name__}({name}=…) is not the schema's {key}"
