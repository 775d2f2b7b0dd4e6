from beeoptics.pipeline.eyes import acuity_table
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    acuity_table(dict(zip(snakemake.params.eyes, zip(snakemake.input.eyes, snakemake.input.receptors,
                                                     snakemake.input.quality))),
                 dict(snakemake.output), width_px=snakemake.params.width_px)
