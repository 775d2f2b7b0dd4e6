from beeoptics.light.batching import TraceSettings
from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.trace import human_view

with logging_to(snakemake.log[0]):
    human_view(snakemake.params.scene, snakemake.output, spectral=snakemake.params.spectral,
               settings=TraceSettings.from_config(snakemake.params.trace, snakemake.threads,
                                                  samples=snakemake.params.samples_per_pixel))
