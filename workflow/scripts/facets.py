from beeoptics.eye.optics import AcceptanceModel
from beeoptics.pipeline.eyes import build_facets
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    build_facets(snakemake.params.eye, snakemake.input.remeshed, snakemake.output,
                 tolerance_um=snakemake.params.tolerance_um,
                 acceptance=AcceptanceModel.from_config(snakemake.params.delta_rho))
