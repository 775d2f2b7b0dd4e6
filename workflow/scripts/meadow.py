from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.world import generate_meadow

with logging_to(snakemake.log[0]):
    generate_meadow(snakemake.input[0], dict(snakemake.output))
