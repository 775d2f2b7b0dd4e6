from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    t = snakemake.params.trace
    stages.trace_part(
        snakemake.input.receptors,
        snakemake.params.scene,
        snakemake.output[0],
        spectral=snakemake.params.spectral,
        samples_per_receptor=t["samples_per_receptor"],
        depth=t["depth"],
        seed=t["seed"],
        batch_rays=t["batch_rays"],
        threads=snakemake.threads,
        part=int(snakemake.wildcards.part),
        parts=int(snakemake.wildcards.parts),
        light=snakemake.params.light,
    )
