from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    t = snakemake.params.trace
    stages.human_view(
        snakemake.params.scene,
        snakemake.output.png,
        snakemake.output.exr,
        spectral=snakemake.params.spectral,
        samples_per_pixel=snakemake.params.samples_per_pixel,
        depth=t["depth"],
        seed=t["seed"],
        batch_rays=t["batch_rays"],
        threads=snakemake.threads,
    )
