from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.colour_figures(snakemake.input.responses, snakemake.input.irradiance, dict(snakemake.output),
                          title=f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}",
                          receptor_curves=snakemake.params.receptor_curves)
