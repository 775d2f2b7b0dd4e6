from beeoptics.pipeline.images import visual_field_maps
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    visual_field_maps(snakemake.input.receptors, snakemake.input.responses, snakemake.input.irradiance,
                      snakemake.input.human, snakemake.output, width_px=snakemake.params.width_px)
