# The world: generated meadows, as meshes and tables of their flowers beside their meadow file in the
# scene's folder.


rule meadow:
    input:
        SCENES_DIR / "{scene}" / MEADOW_FILE,
    output:
        mesh=SCENES_DIR / "{scene}" / MEADOW_MESH,
        flowers=SCENES_DIR / "{scene}" / MEADOW_FLOWERS,
    priority: STARTS_CHAINS
    log:
        "results/logs/meadow/{scene}.log",
    resources:
        mem_mb=3000,
        runtime=30,
    script:
        "../scripts/meadow.py"
