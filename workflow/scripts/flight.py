from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.pipeline.flights import flight_products
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    flight_products(snakemake.input.receptors, snakemake.params.scene, snakemake.input.frames,
                    snakemake.input.human, snakemake.output, fps=snakemake.params.fps,
                    spectral=snakemake.params.spectral,
                    receptor_set=receptor_set_of(snakemake.params.eye), target=snakemake.params.target,
                    background=snakemake.params.background, receptor_curves=snakemake.params.receptor_curves,
                    title=f"{snakemake.wildcards.eye}, flight {snakemake.wildcards.flight}")
