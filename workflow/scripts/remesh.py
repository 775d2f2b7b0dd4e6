from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.remesh_eye(snakemake.params.eye, snakemake.output[0], edge_fraction=snakemake.params.edge_fraction)
