"""Views for navigation: environment maps traced once at a place, from which any eye at any heading, pitch
and roll there is resampled (:mod:`~beeoptics.navigation.envmap`); image-difference functions over headings
and places (:mod:`~beeoptics.navigation.idf`); catchment areas (:mod:`~beeoptics.navigation.catchment`)."""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "envmap": ("EnvironmentMap", "Grid", "SetCatches", "Weights", "environment_map", "eye_weights", "kernel_sigma",
               "map_catches", "map_spacing_deg", "parallax_corrected", "parallax_matrix", "read_map",
               "resampled_catches", "resampling_matrix", "ring_grid", "turn_order", "write_map"),
    "idf": ("image_difference", "ridf", "signal_names", "signals", "turned_catches", "valley"),
    "catchment": ("catchment", "descent", "extent"),
})
