from beeoptics import stages

with stages.logging_to(snakemake.log[0]):
    stages.place_facets(
        snakemake.params.eye,
        snakemake.input.remeshed,
        snakemake.output.receptors,
        snakemake.output.quality,
        snakemake.output.relaxation,
        tolerance_um=snakemake.params.tolerance_um,
        delta_rho=snakemake.params.delta_rho,
    )
