from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.sweep_summary(snakemake.params.runs, snakemake.output[0])
