from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.retinal_images(
        snakemake.params.eye,
        snakemake.input.receptors,
        snakemake.input.responses,
        snakemake.input.irradiance,
        dict(snakemake.output),
        width_px=snakemake.params.width_px,
    )
