from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.trace import gather_responses

with logging_to(snakemake.log[0]):
    gather_responses(snakemake.input.receptors, snakemake.params.scene, list(snakemake.input.parts), snakemake.output,
                     spectral=snakemake.params.spectral,
                     receptor_set=receptor_set_of(snakemake.params.eye), background=snakemake.params.background,
                     light=snakemake.params.light, receptor_curves=snakemake.params.receptor_curves)
