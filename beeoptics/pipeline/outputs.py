"""The file names of the stages' outputs, by output name, for the rules and the command-line tool."""

#: What :func:`beeoptics.pipeline.eyes.build_facets` writes for an eye.
FACET_OUTPUTS = {"receptors": "receptors.csv", "quality": "quality.json", "relaxation": "relaxation.npz"}

#: What :func:`beeoptics.pipeline.images.visual_field_maps` writes.
FIELD_MAPS = {"figure": "visual_field.png", "exr": "visual_field.exr"}
#: What :func:`beeoptics.pipeline.images.viewer` writes for one eye in one scene, and a flight's views for an eye.
VIEWER = {"viewer": "viewer.html"}
#: The colour-space figures :func:`beeoptics.pipeline.images.colour_figures` can write, for the spaces a
#: receptor set has (:func:`colour_figures`).
COLOUR_FIGURES = {"triangle": "triangle.png", "hexagon": "hexagon.png"}

#: What :func:`beeoptics.pipeline.images.retinal_images` writes for one eye in one scene, besides one channel
#: image per receptor class (:func:`retinal_images`).
IMAGES = {
    "voronoi_map3": "voronoi_map3.png",
    "voronoi_map2": "voronoi_map2.png",
    "density_map3": "density_map3.png",
    "density_map3_normalised": "density_map3_normalised.png",
    "exr": "catches.exr",
}


def channel(receptor_class):
    """The output name of a receptor class's channel image: ``channel_uv`` for UV."""
    return f"channel_{receptor_class.lower()}"


def retinal_images(receptor_set):
    """Output name → file of :func:`beeoptics.pipeline.images.retinal_images` for an eye of ``receptor_set``."""
    return {**IMAGES, **{channel(c): f"{channel(c)}.png" for c in receptor_set.classes}}


def colour_figures(receptor_set):
    """Output name → file of :func:`beeoptics.pipeline.images.colour_figures`: the set's triangle and hexagon."""
    return {k: v for k, v in COLOUR_FIGURES.items() if k in receptor_set.spaces}
