# The world: generated meadows, as meshes beside their meadow file in the scene's folder.


rule meadow:
    input:
        SCENES_DIR / "{scene}" / MEADOW_FILE,
    output:
        mesh=SCENES_DIR / "{scene}" / MEADOW_MESH,
    log:
        "results/logs/meadow/{scene}.log",
    resources:
        mem_mb=3000,
        runtime=30,
    script:
        "../scripts/meadow.py"
