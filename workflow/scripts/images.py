from beeoptics.pipeline.images import retinal_images
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    retinal_images(snakemake.params.eye, snakemake.input.receptors, snakemake.input.responses,
                   snakemake.input.irradiance, snakemake.output, width_px=snakemake.params.width_px,
                   title=f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}")
