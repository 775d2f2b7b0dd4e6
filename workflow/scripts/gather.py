from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.gather_responses(
        snakemake.input.receptors,
        snakemake.params.scene,
        list(snakemake.input.parts),
        snakemake.output.responses,
        snakemake.output.irradiance,
        spectral=snakemake.params.spectral,
        background=snakemake.params.background,
        light=snakemake.params.light,
        receptor_curves=snakemake.params.receptor_curves,
    )
