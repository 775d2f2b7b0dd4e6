from beeoptics.pipeline.images import sensitivity_figure
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    sensitivity_figure(snakemake.output, spectral=snakemake.params.spectral,
                       receptor_set=snakemake.params.receptor_set, receptor_curves=snakemake.params.receptor_curves)
