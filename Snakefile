# beeoptics: what a honey bee sees of a scene, from eye meshes to bee-colour images.
# Stages live in workflow/rules/<stage>.smk; each calls one function of beeoptics.pipeline.

import sys
from pathlib import Path

from snakemake.utils import min_version

from beeoptics.io.errors import InputError
from beeoptics.io.validation import CONFIG_SCHEMA, load_yaml, validate_config
from beeoptics.world.flight import read_flight

min_version("9.0")

# Parsed first by our loader, so that a syntax error names the file, line and column
# (Snakemake's own message names neither).
try:
    if Path("config/config.yaml").exists():
        load_yaml("config/config.yaml")
except InputError as e:
    sys.exit(f"beeoptics: error: {e}")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


# Checked once, defaults filled in; a wrong key or value, an eye class or scene
# without its folder, or a bad line in a flight's CSV (which the flight rules' input
# functions read, where Snakemake would bury it in a traceback) stops the run at once
# with one line naming it.
try:
    validate_config(config, CONFIG_SCHEMA, source=", ".join(map(str, workflow.configfiles)) or "config",
                    overrides=workflow.config_settings.config)
    for flight in config["flights"].values():
        read_flight(Path(config["scenes_dir"]) / flight["scene"] / flight["path"])
except InputError as e:
    sys.exit(f"beeoptics: error: {e}")


include: "workflow/rules/common.smk"
include: "workflow/rules/world.smk"
include: "workflow/rules/eyes.smk"
include: "workflow/rules/trace.smk"
include: "workflow/rules/images.smk"
include: "workflow/rules/sweeps.smk"
include: "workflow/rules/flights.smk"
include: "workflow/rules/polarisation.smk"
include: "workflow/rules/detection.smk"
include: "workflow/rules/navigation.smk"


rule all:
    input:
        all_targets(),
        navigation_targets("small"),
    default_target: True
