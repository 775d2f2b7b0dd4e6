from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.sensitivity_figure(snakemake.params.spectral, snakemake.output[0],
                              receptor_curves=snakemake.params.receptor_curves)
