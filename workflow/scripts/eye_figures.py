from beeoptics.pipeline.eyes import eye_figures
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    eye_figures(snakemake.params.eye, snakemake.input.relaxation, snakemake.input.receptors,
                snakemake.input.quality, snakemake.output)
