from beeoptics.pipeline.flights import trace_frames
from beeoptics.pipeline.logs import logging_to
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    trace_frames(snakemake.input.receptors, snakemake.params.scene, snakemake.input.flight, snakemake.output,
                 first=int(snakemake.wildcards.first), count=snakemake.params.frames_per_job,
                 fps=snakemake.params.fps, spectral=snakemake.params.spectral, trace=snakemake.params.trace,
                 threads=snakemake.threads, receptor_set=receptor_set_of(snakemake.params.eye),
                 target=snakemake.params.target, receptor_curves=snakemake.params.receptor_curves)
