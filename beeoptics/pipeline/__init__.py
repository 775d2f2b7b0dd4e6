"""The pipeline: one function per stage, from input files to artifacts, which the Snakemake rules
(``workflow/rules/<stage>.smk``) and the command-line tool call. Each reads its inputs, calls the
library and writes ``outputs``, a mapping of output names to paths, atomically.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "eyes": ("acuity_table", "build_facets", "eye_figures", "remesh_eye"),
    "trace": ("gather_responses", "human_view", "trace_part"),
    "images": ("colour_figures", "retinal_images", "sensitivity_figure", "visual_field_maps"),
    "sweeps": ("sweep_summary", "variant_light", "variant_trace", "variants", "with_delta_rho"),
    "world": ("MEADOW_FILE", "MEADOW_FLOWERS", "MEADOW_MESH", "generate_meadow"),
    "flights": ("flight_products", "flight_views", "frame_count", "human_frames", "shares", "trace_frames"),
    "polarisation": ("compass", "polarisation_maps"),
    "logs": ("logging_to",),
    "outputs": ("COLOUR_FIGURES", "FACET_OUTPUTS", "FIELD_MAPS", "IMAGES"),
})
