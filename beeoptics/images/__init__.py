"""Images: what the eyes saw, shown to people. Retinal images (:mod:`.retina`), visual-field maps
(:mod:`.fieldmaps`), the bee-colour display mappings (:mod:`.display`) and figures (:mod:`.figures`).
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "display": ("bee_colours", "encode", "map3"),
    "retina": ("canvas", "density", "nearest_receptor", "retinal_plane"),
    "fieldmaps": ("paint",),
    "figures": ("angular_sensitivities", "colour_space", "eye_map", "relaxation", "sensitivities", "visual_field"),
})
