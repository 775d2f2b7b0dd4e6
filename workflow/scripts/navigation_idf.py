from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.navigation import image_differences

with logging_to(snakemake.log[0]):
    image_differences(snakemake.input.maps, snakemake.input.receptors, snakemake.params.eyes,
                      snakemake.params.names, snakemake.output, scene=snakemake.wildcards.scene,
                      navigation=snakemake.params.navigation, grid=snakemake.wildcards.grid,
                      threads=snakemake.threads)
