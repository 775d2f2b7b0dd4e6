from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.sweeps import sweep_summary

with logging_to(snakemake.log[0]):
    sweep_summary(snakemake.params.runs, snakemake.output)
