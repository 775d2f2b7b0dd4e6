from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.with_delta_rho(snakemake.input[0], snakemake.output[0], snakemake.params.delta_rho_deg)
