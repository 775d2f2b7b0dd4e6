from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.navigation import trace_maps

with logging_to(snakemake.log[0]):
    trace_maps(snakemake.params.scene, snakemake.input.receptors, snakemake.params.eyes, snakemake.output.maps,
               places=snakemake.params.places, navigation=snakemake.params.navigation,
               grid=snakemake.wildcards.grid, spectral=snakemake.params.spectral, threads=snakemake.threads)
