# beeoptics: what a honey bee sees of a scene, from eye meshes to bee-colour images.
# Stages live in workflow/rules/<stage>.smk; every stage is a function of beeoptics.stages.

from snakemake.utils import min_version, validate

from beeoptics.validation import CONFIG_SCHEMA, validate_config

min_version("9.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


validate(config, str(CONFIG_SCHEMA))
# Also stop at once, naming the key, when an eye class or scene has no folder.
validate_config(config, CONFIG_SCHEMA,
                source=", ".join(map(str, workflow.configfiles)) or "config")


include: "workflow/rules/common.smk"
include: "workflow/rules/eyes.smk"
include: "workflow/rules/trace.smk"
include: "workflow/rules/images.smk"
include: "workflow/rules/sweeps.smk"


rule all:
    input:
        all_targets(),
    default_target: True
