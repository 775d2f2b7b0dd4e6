from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.eye_figures(snakemake.params.eye, snakemake.input.relaxation, snakemake.input.receptors,
                       dict(snakemake.output))
