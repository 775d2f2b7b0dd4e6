from beeoptics.light.batching import TraceSettings
from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.trace import trace_part
from beeoptics.vision.receptorset import receptor_set_of

with logging_to(snakemake.log[0]):
    receptor_set = receptor_set_of(snakemake.params.eye)
    trace_part(snakemake.input.receptors, snakemake.params.scene, snakemake.output, spectral=snakemake.params.spectral,
               settings=TraceSettings.from_config(snakemake.params.trace, snakemake.threads, receptor_set=receptor_set),
               receptor_set=receptor_set, part=int(snakemake.wildcards.part),
               parts=int(snakemake.wildcards.parts), light=snakemake.params.light,
               receptor_curves=snakemake.params.receptor_curves)
