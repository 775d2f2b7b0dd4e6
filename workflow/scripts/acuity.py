from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.acuity_table(dict(zip(snakemake.params.eyes, snakemake.input)), snakemake.output[0],
                        width_px=snakemake.params.width_px)
