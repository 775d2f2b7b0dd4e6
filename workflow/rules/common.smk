# Paths, wildcards and targets shared by the stages.

from pathlib import Path

from beeoptics.pipeline import sweeps
from beeoptics.pipeline.outputs import COLOUR_FIGURES, FIELD_MAPS, IMAGES as RETINAL_IMAGES
from beeoptics.pipeline.flights import shares
from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_MESH
from beeoptics.vision.sensitivity import PEITSCH_1992, TEMPLATE

EYES_DIR = Path(config["eyes_dir"])
SCENES_DIR = Path(config["scenes_dir"])

# Images written for every eye and scene: the retinal plane's, the visual field's, the colour spaces'.
IMAGES = [*RETINAL_IMAGES.values(), *FIELD_MAPS.values(), *COLOUR_FIGURES.values()]


wildcard_constraints:
    eye="[A-Za-z0-9_-]+",
    scene="[A-Za-z0-9_-]+",
    part="[0-9]+",
    sweep="[A-Za-z0-9_-]+",
    variant="[A-Za-z0-9_.-]+",
    parts="[0-9]+",


def folder_files(folder):
    """Every file of an eye's or a scene's folder: editing any of them reruns what uses it."""
    return sorted(str(p) for p in Path(folder).rglob("*") if p.is_file())


def eye_sources(wildcards):
    return folder_files(EYES_DIR / wildcards.eye)


def scene_files(scene):
    """A scene's files, and the mesh of its meadow file, which the meadow rule generates."""
    folder = SCENES_DIR / scene
    generated = [str(folder / MEADOW_MESH)] if (folder / MEADOW_FILE).exists() else []
    return sorted(set(folder_files(folder)) | set(generated))


def scene_sources(wildcards):
    return scene_files(wildcards.scene)


def sensitivity_files(wildcards=None):
    """A CSV of measured receptor curves is an input: editing it reruns what uses it."""
    curves = config["colour"]["sensitivities"]
    return [] if curves in (TEMPLATE, PEITSCH_1992) else [curves]


def trace_parts(wildcards):
    """The shares the trace of one eye in one scene is split into (config trace.parts)."""
    n = config["trace"]["parts"]
    return [f"results/{wildcards.eye}/{wildcards.scene}/parts/radiance_{k}_of_{n}.npz" for k in range(n)]


def all_targets():
    eyes = expand(
        "results/eyes/{eye}/{name}",
        eye=config["eyes"],
        name=["remeshed.ply", "receptors.csv", "quality.json"],
    )
    figures = expand(
        "results/eyes/{eye}/figures/{name}.png",
        eye=config["eyes"],
        name=["relaxation", "delta_phi", "facet_diameter", "acceptance", "field_of_view"],
    ) + ["results/eyes/acuity.csv", "results/figures/sensitivities.png"]
    views = expand(
        "results/{eye}/{scene}/{name}",
        eye=config["eyes"],
        scene=config["scenes"],
        name=["responses.csv", "irradiance.npz"] + IMAGES,
    )
    humans = expand("results/scenes/{scene}/human.{ext}", scene=config["scenes"], ext=["png", "exr"])
    summaries = expand("results/sweeps/{sweep}/summary.csv", sweep=list(config["sweeps"]))
    flights = [f"results/flights/{name}/{eye}/{product}" for name, flight in config["flights"].items()
               for eye in flight["eyes"]
               for product in ("responses.csv", "optic_flow.csv", "target.csv", "animation.gif", "optic_flow.png")]
    polarisation = expand("results/{eye}/{scene}/polarisation/{name}", eye=config["polarisation"]["eyes"],
                          scene=config["polarisation"]["scenes"],
                          name=["polarisation.csv", "field.png", "retina.png", "dorsal_rim.png", "compass.csv",
                                "compass.json", "compass.png"])
    return eyes + figures + views + humans + summaries + flights + polarisation
