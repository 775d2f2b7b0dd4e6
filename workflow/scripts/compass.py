from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.pipeline.logs import logging_to
from beeoptics.vision.polarisation import analyser_ps
from beeoptics.pipeline.polarisation import compass

pol = snakemake.params.polarisation
with logging_to(snakemake.log[0]):
    compass(snakemake.input.receptors, snakemake.params.scene, snakemake.output, spectral=snakemake.params.spectral,
            trace=snakemake.params.trace,
            threads=snakemake.threads, headings=pol["compass"]["headings"],
            turbidities=pol["compass"]["turbidities"], heights_m=pol["compass"]["heights_m"],
            dorsal_rim_ps=analyser_ps(pol["dorsal_rim_ps"]), title=f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}",
            receptor_set=receptor_set_of(snakemake.params.eye), receptor_curves=snakemake.params.receptor_curves)
