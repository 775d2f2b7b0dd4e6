from beeoptics.pipeline.flights import flight_detection
from beeoptics.pipeline.logs import logging_to
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    flight_detection(snakemake.input.receptors, snakemake.input.frames, snakemake.output,
                     spectral=snakemake.params.spectral, receptor_set=receptor_set_of(snakemake.params.eye),
                     target=snakemake.params.target, receptor_curves=snakemake.params.receptor_curves,
                     title=f"{snakemake.wildcards.eye}, flight {snakemake.wildcards.flight}: detecting its target")
