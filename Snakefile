# beeoptics: what a honey bee sees of a scene, from eye meshes to bee-colour images.
# Stages live in workflow/rules/<stage>.smk; every stage is a function of beeoptics.stages.

from snakemake.utils import min_version, validate

min_version("9.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


validate(config, "workflow/schemas/config.schema.yaml")


include: "workflow/rules/common.smk"
include: "workflow/rules/eyes.smk"
include: "workflow/rules/trace.smk"
include: "workflow/rules/images.smk"


rule all:
    input:
        all_targets(),
    default_target: True
