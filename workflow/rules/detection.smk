# Detection: a generated meadow's flowers approached by each eye of the survey, and from how far it
# detects them (beeoptics.pipeline.detection).


rule detection_survey:
    input:
        receptors="results/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        curves=sensitivity_files,
    output:
        approaches="results/detection/{scene}/{eye}/detection.csv",
        views="results/detection/{scene}/{eye}/views.csv",
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        flowers=lambda w: SCENES_DIR / w.scene / MEADOW_FLOWERS,
        spectral=config["spectral"],
        trace=section_trace(config["detection"], ("samples_per_receptor", "depth")),
        survey=config["detection"],
        receptor_curves=config["colour"]["sensitivities"],
    priority: AWAITED
    log:
        "results/logs/detection/{scene}/{eye}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
        runtime=60,
    script:
        "../scripts/detection_survey.py"


rule detection_summary:
    input:
        approaches=lambda w: expand("results/detection/{scene}/{eye}/detection.csv", scene=w.scene,
                                    eye=config["detection"]["eyes"]),
    output:
        summary=report("results/detection/{scene}/summary.csv", caption="../report/detection_summary.rst",
                       category="Detection", subcategory="{scene}"),
        figure=report("results/detection/{scene}/detection.png", caption="../report/detection.rst",
                      category="Detection", subcategory="{scene}"),
    params:
        eyes=config["detection"]["eyes"],
    log:
        "results/logs/detection/{scene}/summary.log",
    script:
        "../scripts/detection_summary.py"
