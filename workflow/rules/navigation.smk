# Views for navigation: environment maps on a grid of places about a reference, then each eye's image-difference
# functions and catchment areas (beeoptics.pipeline.navigation). The default run's grid is navigation.grids.small;
# `snakemake navigation` runs navigation.grids.full; each grid with its own eyes (navigation.grids.{grid}.eyes).

from beeoptics.pipeline import navigation

NAVIGATION = config["navigation"]
# Checked at once against the eyes' receptor sets: a signal an eye lacks, or a heading off the steps, stops the
# run with one line before any map is traced.
try:
    navigation.check(NAVIGATION, {eye: RECEPTOR_SETS[eye] for eye in NAVIGATION["eyes"]},
                     source=", ".join(map(str, workflow.configfiles)) or "config")
except InputError as e:
    sys.exit(f"beeoptics: error: {e}")
#: What a grid's image differences write, under results/navigation/{scene}/{grid}/.
NAVIGATION_FILES = ["ridf.csv", "tidf.csv", "places.csv", "catchment.csv", "catchment.png"]


def grid_eyes(grid):
    """A grid's eyes: those of navigation.grids.{grid}.eyes among navigation's (all of them where null)."""
    chosen = NAVIGATION["grids"][grid]["eyes"]
    return [eye for eye in NAVIGATION["eyes"] if chosen is None or eye in chosen]


def navigation_places(grid):
    """The places of a grid (beeoptics.pipeline.navigation.grid_places)."""
    spec = NAVIGATION["grids"][grid]
    return navigation.grid_places((0.0, 0.0), 0.0, spec["extent_m"], spec["spacing_m"])[0].size


def navigation_chunks(grid):
    """The jobs of a grid's maps: navigation.map.places_per_job places each."""
    return -(-navigation_places(grid) // NAVIGATION["map"]["places_per_job"])


def chunk_places(grid, chunk):
    """The places (row-major) the job ``chunk`` of a grid's maps traces."""
    per = NAVIGATION["map"]["places_per_job"]
    return list(range(int(chunk) * per, min((int(chunk) + 1) * per, navigation_places(grid))))


def navigation_targets(grid):
    return [f"results/navigation/{scene}/{grid}/{name}" for scene in NAVIGATION["scenes"]
            for name in NAVIGATION_FILES if grid_eyes(grid)]


wildcard_constraints:
    grid="small|full",
    chunk="[0-9]+",


rule navigation_map:
    input:
        receptors=lambda w: expand("results/eyes/{eye}/receptors.csv", eye=grid_eyes(w.grid)),
        scene=scene_sources,
    output:
        maps=directory("results/navigation/{scene}/{grid}/maps/{chunk}"),
    params:
        scene=lambda w: SCENES_DIR / w.scene / "scene.yaml",
        places=lambda w: chunk_places(w.grid, w.chunk),
        eyes=lambda w: [EYES_DIR / eye / "eye.yaml" for eye in grid_eyes(w.grid)],
        # Only what places and traces a map: another grid's size or the signals leave the maps as they are.
        navigation=lambda w: {k: NAVIGATION[k] for k in ("reference_m", "height_m", "map")}
        | {"grids": {w.grid: NAVIGATION["grids"][w.grid]}},
        spectral=config["spectral"],
    priority: AWAITED
    log:
        "results/logs/navigation/{scene}/{grid}/maps/{chunk}.log",
    threads: TRACING_THREADS
    resources:
        mem_mb=4000,
        runtime=60,
    script:
        "../scripts/navigation_map.py"


rule navigation_idf:
    input:
        maps=lambda w: [f"results/navigation/{w.scene}/{w.grid}/maps/{c}" for c in range(navigation_chunks(w.grid))],
        receptors=lambda w: expand("results/eyes/{eye}/receptors.csv", eye=grid_eyes(w.grid)),
    output:
        ridf="results/navigation/{scene}/{grid}/ridf.csv",
        tidf="results/navigation/{scene}/{grid}/tidf.csv",
        places="results/navigation/{scene}/{grid}/places.csv",
        catchment="results/navigation/{scene}/{grid}/catchment.csv",
        figure=report("results/navigation/{scene}/{grid}/catchment.png", caption="../report/catchment.rst",
                      category="Navigation", subcategory="{scene} {grid}"),
    params:
        eyes=lambda w: [EYES_DIR / eye / "eye.yaml" for eye in grid_eyes(w.grid)],
        names=lambda w: grid_eyes(w.grid),
        navigation=NAVIGATION,
    log:
        "results/logs/navigation/{scene}/{grid}/idf.log",
    priority: AWAITED  # started as soon as its maps are, beside the other jobs, not left to run alone at the end
    threads: 1  # so that it shares the cores with another job (its bits are the same for any threads)
    resources:
        mem_mb=4000,
        # Half a minute a place and eye, minutes: a place's 360 headings took 20 s for the worker and 11 s for
        # bombus_terrestris_77970 on their shared maps (0.154° apart), 2.5 s for the worker on its own (0.48°).
        runtime=lambda w: max(60, navigation_places(w.grid) * len(grid_eyes(w.grid)) // 2),
    script:
        "../scripts/navigation_idf.py"


rule navigation:
    input:
        navigation_targets("full"),
