from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.trace import trace_part
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    trace_part(snakemake.input.receptors, snakemake.params.scene, snakemake.output, spectral=snakemake.params.spectral,
               trace=snakemake.params.trace, threads=snakemake.threads,
               receptor_set=receptor_set_of(snakemake.params.eye), part=int(snakemake.wildcards.part),
               parts=int(snakemake.wildcards.parts), light=snakemake.params.light,
               receptor_curves=snakemake.params.receptor_curves)
