from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.trace import human_view

with logging_to(snakemake.log[0]):
    human_view(snakemake.params.scene, snakemake.output, spectral=snakemake.params.spectral,
               trace=snakemake.params.trace, threads=snakemake.threads, samples=snakemake.params.samples_per_pixel)
