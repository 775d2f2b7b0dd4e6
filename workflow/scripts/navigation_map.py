from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.navigation import trace_map

with logging_to(snakemake.log[0]):
    trace_map(snakemake.params.scene, snakemake.input.receptors, snakemake.params.eyes, snakemake.output,
              place=int(snakemake.wildcards.place), navigation=snakemake.params.navigation,
              grid=snakemake.wildcards.grid, spectral=snakemake.params.spectral, threads=snakemake.threads)
