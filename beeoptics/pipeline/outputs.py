"""The file names of the stages' outputs, by output name, for the rules and the command-line tool."""

#: What :func:`beeoptics.pipeline.eyes.build_facets` writes for an eye.
FACET_OUTPUTS = {"receptors": "receptors.csv", "quality": "quality.json", "relaxation": "relaxation.npz"}

#: What :func:`beeoptics.pipeline.images.visual_field_maps` writes.
FIELD_MAPS = {"figure": "visual_field.png", "exr": "visual_field.exr"}
#: What :func:`beeoptics.pipeline.images.colour_figures` writes.
COLOUR_FIGURES = {"triangle": "triangle.png", "hexagon": "hexagon.png"}

#: What :func:`beeoptics.pipeline.images.retinal_images` writes for one eye in one scene.
IMAGES = {
    "voronoi_map3": "voronoi_map3.png",
    "voronoi_map2": "voronoi_map2.png",
    "density_map3": "density_map3.png",
    "density_map3_normalised": "density_map3_normalised.png",
    "channel_uv": "channel_uv.png",
    "channel_b": "channel_b.png",
    "channel_g": "channel_g.png",
    "exr": "catches.exr",
}
