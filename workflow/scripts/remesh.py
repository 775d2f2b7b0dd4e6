from beeoptics.pipeline.eyes import remesh_eye
from beeoptics.pipeline.logs import logging_to

with logging_to(snakemake.log[0]):
    remesh_eye(snakemake.params.eye, snakemake.output, edge_fraction=snakemake.params.edge_fraction)
