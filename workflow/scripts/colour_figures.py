from beeoptics.pipeline.images import colour_figures
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    colour_figures(snakemake.input.responses, snakemake.input.irradiance, snakemake.output,
                   title=f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}",
                   receptor_curves=snakemake.params.receptor_curves)
