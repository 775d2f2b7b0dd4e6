# Eye stages: remesh the hand-made mesh, then place and relax the facet lattice.
# They depend on the eye's folder only, never on a scene.


rule remesh:
    input:
        eye_sources,
    output:
        "results/eyes/{eye}/remeshed.ply",
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
        edge_fraction=config["eye"]["edge_fraction"],
    log:
        "results/logs/remesh/{eye}.log",
    resources:
        mem_mb=4000,
    script:
        "../scripts/remesh.py"


rule facets:
    input:
        sources=eye_sources,
        remeshed="results/eyes/{eye}/remeshed.ply",
    output:
        receptors="results/eyes/{eye}/receptors.csv",
        quality="results/eyes/{eye}/quality.json",
        relaxation="results/eyes/{eye}/relaxation.npz",
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
        tolerance_um=config["eye"]["tolerance_um"],
        delta_rho=config["eye"]["delta_rho"],
    log:
        "results/logs/facets/{eye}.log",
    resources:
        mem_mb=2000,
    script:
        "../scripts/facets.py"
