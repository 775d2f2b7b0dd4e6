"""World: generated scenes and flights through them.

A meadow (:mod:`.meadow`) is built from plants (:mod:`.plants`) of
species whose sizes floras give (:mod:`.species`), placed by a clustered
point process (:mod:`.placement`) on rough ground (:mod:`.terrain`), and
written as one coloured mesh that a scene maps to spectra. A flight
(:mod:`.flight`) is a path of head poses through a scene, with the optic
flow it makes.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "plants": ("Mesh", "arcs", "bell", "blades", "composite_head", "funnel", "join", "leaf", "revolution",
               "strips", "transformed", "tube"),
    "species": ("PARTS", "check_species", "plant", "species_table"),
    "placement": ("clear_of", "thomas"),
    "terrain": ("ground_height", "ground_mesh", "height_field", "level_round"),
    "meadow": ("generate", "read_meadow", "write_ply"),
    "flight": ("COLUMNS", "Flight", "Pose", "approach", "azimuth_elevation_components", "frame_times",
               "optic_flow", "pose", "read_flight", "disc_angular_diameter", "disc_hits"),
})
