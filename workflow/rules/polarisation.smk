# Polarisation vision: the polarisation each receptor sees, and the dorsal rim's sky compass.


rule polarisation_maps:
    input:
        eye=eye_sources,
        receptors="results/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        curves=sensitivity_files,
    output:
        table="results/{eye}/{scene}/polarisation/polarisation.csv",
        field=report("results/{eye}/{scene}/polarisation/field.png", caption="../report/polarisation_field.rst", category="Polarisation", subcategory="{eye} in {scene}"),
        retina=report("results/{eye}/{scene}/polarisation/retina.png", caption="../report/polarisation_retina.rst", category="Polarisation", subcategory="{eye} in {scene}"),
        dorsal_rim=report("results/{eye}/{scene}/polarisation/dorsal_rim.png", caption="../report/dorsal_rim.rst", category="Polarisation", subcategory="{eye} in {scene}"),
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        trace=section_trace(config["polarisation"]),
        polarisation=config["polarisation"],
        images=config["images"],
        receptor_curves=config["colour"]["sensitivities"],
    priority: AWAITED
    log:
        "results/logs/polarisation_maps/{eye}/{scene}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
    script:
        "../scripts/polarisation_maps.py"


rule compass:
    input:
        receptors="results/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        curves=sensitivity_files,
    output:
        table="results/{eye}/{scene}/polarisation/compass.csv",
        summary="results/{eye}/{scene}/polarisation/compass.json",
        figure=report("results/{eye}/{scene}/polarisation/compass.png", caption="../report/compass.rst", category="Polarisation", subcategory="{eye} in {scene}"),
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        trace=section_trace(config["polarisation"]["compass"]),
        polarisation=config["polarisation"],
        receptor_curves=config["colour"]["sensitivities"],
    log:
        "results/logs/compass/{eye}/{scene}.log",
    resources:
        mem_mb=4000,
    script:
        "../scripts/compass.py"


# The pond (scenes/pond): water's horizontally polarised reflection as the worker sees it, with its
# images and viewer. Not in the default run, for its time: `snakemake pond`.
if POND_THERE:

    rule pond:
        input:
            expand("results/{eye}/{scene}/polarisation/{name}", **POND,
                   name=["polarisation.csv", "field.png", "retina.png"]),
            expand("results/{eye}/{scene}/{name}", **POND, name=["visual_field.png", "viewer.html"]),
