# Tracing: each receptor's acceptance cone through the scene, spectrally.


rule trace:
    input:
        receptors="results/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        curves=sensitivity_files,
    output:
        radiance="results/{eye}/{scene}/parts/radiance_{part}_of_{parts}.npz",
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        trace=TRACE,
        receptor_curves=config["colour"]["sensitivities"],
        light={},
    priority: STARTS_CHAINS
    log:
        "results/logs/trace/{eye}/{scene}/{part}_of_{parts}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
        runtime=60,
    script:
        "../scripts/trace.py"


rule gather:
    input:
        receptors="results/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        parts=trace_parts,
        curves=sensitivity_files,
    output:
        responses="results/{eye}/{scene}/responses.csv",
        irradiance="results/{eye}/{scene}/irradiance.npz",
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        background=config["colour"]["background"],
        receptor_curves=config["colour"]["sensitivities"],
        light={},
    priority: STARTS_CHAINS
    log:
        "results/logs/gather/{eye}/{scene}.log",
    resources:
        mem_mb=2000,
    script:
        "../scripts/gather.py"


rule human_view:
    input:
        scene_sources,
    output:
        png=report("results/scenes/{scene}/human.png", caption="../report/human.rst", category="Scenes", subcategory="{scene}"),
        exr="results/scenes/{scene}/human.exr",
    params:
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        trace=TRACE,
        samples_per_pixel=config["human_view"]["samples_per_pixel"],
    log:
        "results/logs/human_view/{scene}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
    script:
        "../scripts/human_view.py"
