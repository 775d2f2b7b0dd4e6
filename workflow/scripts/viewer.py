from beeoptics.pipeline.images import viewer
from beeoptics.pipeline.logs import logging_to
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    viewer(snakemake.input.receptors, snakemake.input.responses, snakemake.input.irradiance, snakemake.output,
           receptor_set=receptor_set_of(snakemake.params.eye),
           polarisation_csv=snakemake.input.get("polarisation"),
           title=f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}",
           receptor_curves=snakemake.params.receptor_curves)
