from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.pipeline.images import colour_figures, retinal_images, viewer, visual_field_maps
from beeoptics.pipeline.logs import logging_to
from beeoptics.pipeline.outputs import colour_figures as colour_outputs

title = f"{snakemake.wildcards.eye} in {snakemake.wildcards.scene}"
out = snakemake.output
with logging_to(snakemake.log[0]):
    receptor_set = receptor_set_of(snakemake.params.eye)
    retinal_images(snakemake.params.eye, snakemake.input.receptors, snakemake.input.responses,
                   snakemake.input.irradiance, out, receptor_set=receptor_set, width_px=snakemake.params.width_px,
                   title=title)
    visual_field_maps(snakemake.input.receptors, snakemake.input.responses, snakemake.input.irradiance,
                      snakemake.input.human, {"figure": out.figure, "exr": out.field_exr},
                      receptor_set=receptor_set, width_px=snakemake.params.field_width_px)
    colour_figures(snakemake.input.responses, snakemake.input.irradiance,
                   {k: getattr(out, k) for k in colour_outputs(receptor_set)}, receptor_set=receptor_set,
                   title=title, receptor_curves=snakemake.params.receptor_curves)
    viewer(snakemake.input.receptors, snakemake.input.responses, snakemake.input.irradiance,
           {"viewer": out.viewer}, receptor_set=receptor_set, polarisation_csv=snakemake.input.get("polarisation"),
           title=title, receptor_curves=snakemake.params.receptor_curves)
