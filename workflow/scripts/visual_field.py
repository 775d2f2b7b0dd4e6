from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.visual_field_maps(snakemake.input.receptors, snakemake.input.responses, snakemake.input.irradiance,
                             snakemake.input.human, dict(snakemake.output), width_px=snakemake.params.width_px)
