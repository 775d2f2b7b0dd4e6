from beeoptics.pipeline.flights import human_frames
from beeoptics.pipeline.logs import logging_to

view = snakemake.params.view
with logging_to(snakemake.log[0]):
    human_frames(snakemake.params.scene, snakemake.input.flight, snakemake.output,
                 first=int(snakemake.wildcards.first), count=snakemake.params.frames_per_job,
                 fps=snakemake.params.fps, spectral=snakemake.params.spectral, trace=snakemake.params.trace,
                 threads=snakemake.threads, samples=view["samples_per_pixel"],
                 size_px=(view["width_px"], view["height_px"]))
