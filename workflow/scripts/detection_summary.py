from beeoptics.pipeline.detection import summarise
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    summarise(dict(zip(snakemake.params.eyes, snakemake.input.approaches)), snakemake.output,
              scene=snakemake.wildcards.scene)
