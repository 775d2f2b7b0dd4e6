from beeoptics.pipeline.detection import survey
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    survey(snakemake.input.receptors, snakemake.params.eye, snakemake.params.scene, snakemake.params.flowers,
           snakemake.output, spectral=snakemake.params.spectral, trace=snakemake.params.trace,
           threads=snakemake.threads, survey=snakemake.params.survey,
           receptor_curves=snakemake.params.receptor_curves)
