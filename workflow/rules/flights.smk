# Flights: every frame of a flight traced for each of its eyes, a share of frames a job, then gathered.


def flight_file(wildcards):
    f = config["flights"][wildcards.flight]
    return SCENES_DIR / f["scene"] / f["path"]


def flight_scene_sources(wildcards):
    return scene_files(config["flights"][wildcards.flight]["scene"])


def flight_shares(wildcards):
    """The files of one eye's flight, share by share, in order."""
    f = config["flights"][wildcards.flight]
    firsts = shares(flight_file(wildcards), f["fps"], f["frames_per_job"])
    base = f"results/flights/{wildcards.flight}"
    return {
        "frames": [f"{base}/{wildcards.eye}/frames/{k}.npz" for k in firsts],
        "human": [f"{base}/human/{k}.npz" for k in firsts],
    }


rule flight_frames:
    input:
        receptors="results/eyes/{eye}/receptors.csv",
        scene=flight_scene_sources,
        flight=flight_file,
        curves=sensitivity_files,
    output:
        frames="results/flights/{flight}/{eye}/frames/{first}.npz",
    wildcard_constraints:
        first="[0-9]+",
    params:
        eye=eye_file,
        receptor_curves=config["colour"]["sensitivities"],
        scene=lambda w: SCENES_DIR / config["flights"][w.flight]["scene"] / "scene.yaml",
        spectral=config["spectral"],
        trace=lambda w: section_trace(config["flights"][w.flight]),
        fps=lambda w: config["flights"][w.flight]["fps"],
        frames_per_job=lambda w: config["flights"][w.flight]["frames_per_job"],
        target=lambda w: config["flights"][w.flight].get("target"),
    priority: AWAITED
    log:
        "results/logs/flights/{flight}/{eye}/{first}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
        runtime=60,
    script:
        "../scripts/flight_frames.py"


rule flight_human_frames:
    input:
        scene=flight_scene_sources,
        flight=flight_file,
    output:
        frames="results/flights/{flight}/human/{first}.npz",
    wildcard_constraints:
        first="[0-9]+",
    params:
        scene=lambda w: SCENES_DIR / config["flights"][w.flight]["scene"] / "scene.yaml",
        spectral=config["spectral"],
        trace=TRACE,
        view=lambda w: config["flights"][w.flight]["human_view"],
        fps=lambda w: config["flights"][w.flight]["fps"],
        frames_per_job=lambda w: config["flights"][w.flight]["frames_per_job"],
    priority: AWAITED
    log:
        "results/logs/flights/{flight}/human/{first}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
        runtime=30,
    script:
        "../scripts/flight_human_frames.py"


rule flight:
    input:
        unpack(flight_shares),
        receptors="results/eyes/{eye}/receptors.csv",
        scene=flight_scene_sources,
        curves=sensitivity_files,
    output:
        responses="results/flights/{flight}/{eye}/responses.csv",
        optic_flow="results/flights/{flight}/{eye}/optic_flow.csv",
        target="results/flights/{flight}/{eye}/target.csv",
        animation=report("results/flights/{flight}/{eye}/animation.gif", caption="../report/flight.rst",
                         category="Flights", subcategory="{flight}"),
        flow_figure=report("results/flights/{flight}/{eye}/optic_flow.png", caption="../report/optic_flow.rst",
                           category="Flights", subcategory="{flight}"),
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / config["flights"][w.flight]["scene"] / "scene.yaml",
        spectral=config["spectral"],
        fps=lambda w: config["flights"][w.flight]["fps"],
        target=lambda w: config["flights"][w.flight].get("target"),
        background=config["colour"]["background"],
        receptor_curves=config["colour"]["sensitivities"],
    log:
        "results/logs/flights/{flight}/{eye}/gather.log",
    resources:
        mem_mb=4000,
        runtime=60,
    script:
        "../scripts/flight.py"


rule flight_detection:
    input:
        frames=lambda w: flight_shares(w)["frames"],
        receptors="results/eyes/{eye}/receptors.csv",
        curves=sensitivity_files,
    output:
        detection="results/flights/{flight}/{eye}/detection.csv",
        first="results/flights/{flight}/{eye}/detection.json",
        figure=report("results/flights/{flight}/{eye}/detection.png", caption="../report/flight_detection.rst",
                      category="Flights", subcategory="{flight}"),
    params:
        eye=eye_file,
        spectral=config["spectral"],
        target=lambda w: config["flights"][w.flight]["target"],
        receptor_curves=config["colour"]["sensitivities"],
    log:
        "results/logs/flights/{flight}/{eye}/detection.log",
    script:
        "../scripts/flight_detection.py"


rule flight_views:
    input:
        receptors="results/eyes/{eye}/receptors.csv",
        scene=flight_scene_sources,
        flight=flight_file,
        human=lambda w: flight_shares(w)["human"],
        curves=sensitivity_files,
    output:
        catches="results/flights/{flight}/{eye}/views.npz",
        video=report("results/flights/{flight}/{eye}/views.mp4", caption="../report/views.rst",
                     category="Flights", subcategory="{flight}"),
        # Linked from the video's caption, not embedded in the report (as the scenes' viewers).
        viewer="results/flights/{flight}/{eye}/viewer.html",
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / config["flights"][w.flight]["scene"] / "scene.yaml",
        spectral=config["spectral"],
        trace=lambda w: section_trace(config["flights"][w.flight]["views"], ("samples_per_receptor", "depth")),
        fps=lambda w: config["flights"][w.flight]["fps"],
        width_px=lambda w: config["flights"][w.flight]["views"]["width_px"],
        receptor_curves=config["colour"]["sensitivities"],
    log:
        "results/logs/flights/{flight}/{eye}/views.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
        runtime=60,
    script:
        "../scripts/flight_views.py"
