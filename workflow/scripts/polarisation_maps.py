from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.pipeline.logs import logging_to
from beeoptics.vision.polarisation import analyser_ps
from beeoptics.pipeline.polarisation import polarisation_maps

pol = snakemake.params.polarisation
with logging_to(snakemake.log[0]):
    polarisation_maps(snakemake.params.eye, snakemake.input.receptors, snakemake.params.scene, snakemake.output,
                      spectral=snakemake.params.spectral,
                      trace=snakemake.params.trace,
                      threads=snakemake.threads, dorsal_rim_ps=analyser_ps(pol["dorsal_rim_ps"]),
                      width_px=snakemake.params.images["width_px"],
                      field_width_px=snakemake.params.images["visual_field_width_px"],
                      title=f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}",
                      receptor_set=receptor_set_of(snakemake.params.eye), receptor_curves=snakemake.params.receptor_curves)
