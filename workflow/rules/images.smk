# Images of what each eye saw: Voronoi, density and channel images in the retinal plane.


rule images:
    input:
        eye=eye_sources,
        receptors="results/eyes/{eye}/receptors.csv",
        responses="results/{eye}/{scene}/responses.csv",
        irradiance="results/{eye}/{scene}/irradiance.npz",
    output:
        voronoi_map3=report("results/{eye}/{scene}/voronoi_map3.png", caption="../report/voronoi_map3.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        voronoi_map2=report("results/{eye}/{scene}/voronoi_map2.png", caption="../report/voronoi_map2.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        density_map3=report("results/{eye}/{scene}/density_map3.png", caption="../report/density_map3.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        channel_uv=report("results/{eye}/{scene}/channel_uv.png", caption="../report/channel.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        channel_b=report("results/{eye}/{scene}/channel_b.png", caption="../report/channel.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        channel_g=report("results/{eye}/{scene}/channel_g.png", caption="../report/channel.rst", category="Retinal images", subcategory="{eye} in {scene}"),
        exr="results/{eye}/{scene}/catches.exr",
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
        width_px=config["images"]["width_px"],
    log:
        "results/logs/images/{eye}/{scene}.log",
    script:
        "../scripts/images.py"
