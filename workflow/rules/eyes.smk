# Eye stages: remesh the hand-made mesh (or reconstruct the measured cornea), then place and relax the
# facet lattice; compare the eyes.
# They depend on the eye's folder only, never on a scene.


rule remesh:
    input:
        eye_sources,
    output:
        remeshed="results/eyes/{eye}/remeshed.ply",
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
        edge_fraction=config["eye"]["edge_fraction"],
    priority: STARTS_CHAINS
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
    priority: STARTS_CHAINS
    log:
        "results/logs/facets/{eye}.log",
    resources:
        mem_mb=2000,
    script:
        "../scripts/facets.py"


rule eye_figures:
    input:
        sources=eye_sources,
        relaxation="results/eyes/{eye}/relaxation.npz",
        receptors="results/eyes/{eye}/receptors.csv",
        quality="results/eyes/{eye}/quality.json",
    output:
        relaxation=report("results/eyes/{eye}/figures/relaxation.png", caption="../report/relaxation.rst", category="Eyes", subcategory="{eye}"),
        delta_phi=report("results/eyes/{eye}/figures/delta_phi.png", caption="../report/delta_phi.rst", category="Eyes", subcategory="{eye}"),
        facet_diameter=report("results/eyes/{eye}/figures/facet_diameter.png", caption="../report/facet_diameter.rst", category="Eyes", subcategory="{eye}"),
        acceptance=report("results/eyes/{eye}/figures/acceptance.png", caption="../report/acceptance.rst", category="Eyes", subcategory="{eye}"),
        field_of_view=report("results/eyes/{eye}/figures/field_of_view.png", caption="../report/field_of_view.rst", category="Eyes", subcategory="{eye}"),
    params:
        eye=lambda w: EYES_DIR / w.eye / "eye.yaml",
    log:
        "results/logs/eye_figures/{eye}.log",
    script:
        "../scripts/eye_figures.py"


def acuity_inputs(eyes):
    return {"receptors": expand("results/eyes/{eye}/receptors.csv", eye=eyes),
            "quality": expand("results/eyes/{eye}/quality.json", eye=eyes),
            "eyes": expand(str(EYES_DIR / "{eye}" / "eye.yaml"), eye=eyes)}


rule acuity:
    input:
        **acuity_inputs(config["eyes"]),
    output:
        acuity=report("results/eyes/acuity.csv", caption="../report/acuity.rst", category="Eyes"),
        fields=report("results/eyes/fields.png", caption="../report/fields.rst", category="Eyes"),
    params:
        eyes=config["eyes"],
        width_px=config["images"]["visual_field_width_px"],
    log:
        "results/logs/acuity.log",
    script:
        "../scripts/acuity.py"


rule comparison:
    input:
        **acuity_inputs(config["comparison"]["eyes"]),
    output:
        acuity=report("results/comparison/acuity.csv", caption="../report/acuity.rst", category="Comparison"),
        fields=report("results/comparison/fields.png", caption="../report/fields.rst", category="Comparison"),
        allometry=report("results/comparison/allometry.png", caption="../report/allometry.rst",
                         category="Comparison"),
    params:
        eyes=config["comparison"]["eyes"],
        width_px=config["images"]["visual_field_width_px"],
    log:
        "results/logs/comparison.log",
    script:
        "../scripts/acuity.py"


def receptor_set_named(wildcards):
    return next(rs for rs in RECEPTOR_SETS.values() if rs.name == wildcards.receptor_set)


rule sensitivities:
    input:
        lambda w: [str(receptor_set_named(w).path)] + ([str(receptor_set_named(w).curves_file)]
                                                      if receptor_set_named(w).curves_file else []),
    output:
        figure=report("results/figures/sensitivities/{receptor_set}.png", caption="../report/sensitivities.rst",
                      category="Receptors"),
    params:
        spectral=config["spectral"],
        receptor_set=receptor_set_named,
        receptor_curves=config["colour"]["sensitivities"],
    log:
        "results/logs/sensitivities/{receptor_set}.log",
    script:
        "../scripts/sensitivities.py"
