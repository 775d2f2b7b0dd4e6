from beeoptics.light.batching import TraceSettings
from beeoptics.pipeline.detection import survey
from beeoptics.pipeline.logs import logging_to
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    survey(snakemake.input.receptors, snakemake.params.eye, snakemake.params.scene, snakemake.params.flowers,
           snakemake.output, spectral=snakemake.params.spectral,
           settings=TraceSettings.from_config(snakemake.params.trace, snakemake.threads,
                                              receptor_set=receptor_set_of(snakemake.params.eye)),
           survey=snakemake.params.survey, receptor_curves=snakemake.params.receptor_curves)
