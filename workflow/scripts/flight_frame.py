from beeoptics.light.batching import TraceSettings
from beeoptics.pipeline.flights import trace_frame
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    trace_frame(snakemake.input.receptors, snakemake.params.scene, snakemake.input.flight, snakemake.output,
                frame=int(snakemake.wildcards.frame), fps=snakemake.params.fps, spectral=snakemake.params.spectral,
                settings=TraceSettings.from_config(snakemake.params.trace, snakemake.threads))
