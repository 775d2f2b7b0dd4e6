from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.sweeps import with_delta_rho

with logging_to(snakemake.log[0]):
    with_delta_rho(snakemake.input[0], snakemake.output, delta_rho_deg=snakemake.params.delta_rho_deg)
