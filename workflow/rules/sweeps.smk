# Parameter sweeps (config "sweeps"): every variant of a sweep traced for its eyes and scenes,
# and one summary table per sweep. The eye stages are shared with the main run.


def sweep_variant(wildcards):
    """A variant's parameter values, from its sweep's entry in the config."""
    return sweeps.variants(config["sweeps"][wildcards.sweep])[wildcards.variant]


def sweep_parts(wildcards):
    n = config["trace"]["parts"]
    return [f"results/sweeps/{wildcards.sweep}/{wildcards.variant}/{wildcards.eye}/{wildcards.scene}/"
            f"parts/radiance_{k}_of_{n}.npz" for k in range(n)]


def sweep_runs(name):
    """Every variant × eye × scene of a sweep, in a fixed order, as the summary lists them."""
    sweep = config["sweeps"][name]
    return [{"variant": v, "eye": e, "scene": s, **chosen, "classes": list(RECEPTOR_SETS[e].classes),
             "responses": f"results/sweeps/{name}/{v}/{e}/{s}/responses.csv"}
            for v, chosen in sweeps.variants(sweep).items() for e in sweep["eyes"] for s in sweep["scenes"]]


rule sweep_receptors:
    input:
        "results/eyes/{eye}/receptors.csv",
    output:
        receptors="results/sweeps/{sweep}/{variant}/eyes/{eye}/receptors.csv",
    params:
        delta_rho_deg=lambda w: sweep_variant(w).get("delta_rho_deg"),
    log:
        "results/logs/sweeps/{sweep}/{variant}/receptors_{eye}.log",
    script:
        "../scripts/sweep_receptors.py"


use rule trace as sweep_trace with:
    input:
        receptors="results/sweeps/{sweep}/{variant}/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        curves=sensitivity_files,
    output:
        radiance="results/sweeps/{sweep}/{variant}/{eye}/{scene}/parts/radiance_{part}_of_{parts}.npz",
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        trace=lambda w: {**TRACE, **sweeps.variant_trace(sweep_variant(w))},
        receptor_curves=config["colour"]["sensitivities"],
        light=lambda w: sweeps.variant_light(sweep_variant(w)),
    log:
        "results/logs/sweeps/{sweep}/{variant}/trace/{eye}/{scene}/{part}_of_{parts}.log",


use rule gather as sweep_gather with:
    input:
        receptors="results/sweeps/{sweep}/{variant}/eyes/{eye}/receptors.csv",
        scene=scene_sources,
        parts=sweep_parts,
        curves=sensitivity_files,
    output:
        responses="results/sweeps/{sweep}/{variant}/{eye}/{scene}/responses.csv",
        irradiance="results/sweeps/{sweep}/{variant}/{eye}/{scene}/irradiance.npz",
    params:
        eye=eye_file,
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        spectral=config["spectral"],
        background=config["colour"]["background"],
        receptor_curves=config["colour"]["sensitivities"],
        light=lambda w: sweeps.variant_light(sweep_variant(w)),
    log:
        "results/logs/sweeps/{sweep}/{variant}/gather/{eye}/{scene}.log",


rule sweep_summary:
    input:
        lambda w: [run["responses"] for run in sweep_runs(w.sweep)],
    output:
        summary=report("results/sweeps/{sweep}/summary.csv", caption="../report/sweep.rst", category="Sweeps"),
    params:
        runs=lambda w: sweep_runs(w.sweep),
    log:
        "results/logs/sweeps/{sweep}/summary.log",
    script:
        "../scripts/sweep_summary.py"
