from beeoptics.light.batching import TraceSettings
from beeoptics.pipeline.flights import trace_frames
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    trace_frames(snakemake.input.receptors, snakemake.params.scene, snakemake.input.flight, snakemake.output,
                 first=int(snakemake.wildcards.first), count=snakemake.params.frames_per_job,
                 fps=snakemake.params.fps, spectral=snakemake.params.spectral,
                 settings=TraceSettings.from_config(snakemake.params.trace, snakemake.threads),
                 target=snakemake.params.target)
