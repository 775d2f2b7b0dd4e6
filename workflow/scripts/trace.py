from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.trace_scene(
        snakemake.input.receptors,
        snakemake.params.scene,
        snakemake.output.responses,
        snakemake.output.irradiance,
        spectral=snakemake.params.spectral,
        **snakemake.params.trace,
    )
