# Images of what each eye saw, one job per eye and scene: Voronoi, density and channel images in
# the retinal plane, the visual field beside the human view, and the colour-space figures.


rule images:
    input:
        eye=eye_sources,
        receptors="results/eyes/{eye}/receptors.csv",
        responses="results/{eye}/{scene}/responses.csv",
        irradiance="results/{eye}/{scene}/irradiance.npz",
        human="results/scenes/{scene}/human.png",
        curves=sensitivity_files,
    output:
        voronoi_map3=report("results/{eye}/{scene}/voronoi_map3.png", caption="../report/voronoi_map3.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        voronoi_map2=report("results/{eye}/{scene}/voronoi_map2.png", caption="../report/voronoi_map2.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        density_map3=report("results/{eye}/{scene}/density_map3.png", caption="../report/density_map3.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        density_map3_normalised=report("results/{eye}/{scene}/density_map3_normalised.png", caption="../report/density_map3_normalised.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        channel_uv=report("results/{eye}/{scene}/channel_uv.png", caption="../report/channel.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        channel_b=report("results/{eye}/{scene}/channel_b.png", caption="../report/channel.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        channel_g=report("results/{eye}/{scene}/channel_g.png", caption="../report/channel.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        exr="results/{eye}/{scene}/catches.exr",
        figure=report("results/{eye}/{scene}/visual_field.png", caption="../report/visual_field.rst", category="Visual field", subcategory="{eye} in {scene}"),
        field_exr="results/{eye}/{scene}/visual_field.exr",
        triangle=report("results/{eye}/{scene}/triangle.png", caption="../report/colour_space.rst", category="Colour spaces", subcategory="{eye} in {scene}"),
        hexagon=report("results/{eye}/{scene}/hexagon.png", caption="../report/colour_space.rst", category="Colour spaces", subcategory="{eye} in {scene}"),
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
        width_px=config["images"]["width_px"],
        field_width_px=config["images"]["visual_field_width_px"],
        receptor_curves=config["colour"]["sensitivities"],
    log:
        "results/logs/images/{eye}/{scene}.log",
    script:
        "../scripts/images.py"
