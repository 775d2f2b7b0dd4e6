from beeoptics.pipeline.flights import flight_views
from beeoptics.pipeline.logs import log, logging_to
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    done = flight_views(snakemake.input.receptors, snakemake.params.scene, snakemake.input.flight,
                        snakemake.input.human, snakemake.output, fps=snakemake.params.fps,
                        spectral=snakemake.params.spectral, trace=snakemake.params.trace, threads=snakemake.threads,
                        receptor_set=receptor_set_of(snakemake.params.eye),
                        receptor_curves=snakemake.params.receptor_curves, width_px=snakemake.params.width_px,
                        title=f"{snakemake.wildcards.eye} along {snakemake.wildcards.flight}: views")
    log.info("%d frames traced in %.1f s, %d rays a frame", done["frames"], done["trace_s"],
             done["rays"] / max(done["frames"], 1))
