# Paths, wildcards and targets shared by the stages.

import sys
from pathlib import Path

from beeoptics.io.errors import InputError
from beeoptics.pipeline import sweeps
from beeoptics.pipeline.outputs import FIELD_MAPS, VIEWER, colour_figures, retinal_images
from beeoptics.pipeline.flights import shares
from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_FLOWERS, MEADOW_MESH
from beeoptics.vision.receptorset import SPECIES, TEMPLATE, receptor_set_of

EYES_DIR = Path(config["eyes_dir"])
SCENES_DIR = Path(config["scenes_dir"])


#: The pond's eye and scene (`snakemake pond`, workflow/rules/polarisation.smk), run on request only, where
#: the eyes and scenes folders hold them.
POND = {"eye": "worker", "scene": "pond"}
POND_THERE = (EYES_DIR / POND["eye"] / "eye.yaml").is_file() and (SCENES_DIR / POND["scene"] / "scene.yaml").is_file()


def named_eyes():
    """Every eye class the config names (in the run, its sweeps, flights, polarisation and detection), and the
    pond's."""
    return list(dict.fromkeys([*config["eyes"], *(e for s in config["sweeps"].values() for e in s["eyes"]),
                               *(e for f in config["flights"].values() for e in f["eyes"]),
                               *config["polarisation"]["eyes"], *config["detection"]["eyes"],
                               *([POND["eye"]] if POND_THERE else [])]))


# Each eye's receptor set (its eye.yaml's receptors), which decides the columns and images of its outputs.
try:
    RECEPTOR_SETS = {eye: receptor_set_of(EYES_DIR / eye / "eye.yaml") for eye in named_eyes()}
except InputError as e:
    sys.exit(f"beeoptics: error: {e}")


def eye_images(eye):
    """The images written for an eye in every scene: the retinal plane's, the visual field's, the colour spaces'."""
    rs = RECEPTOR_SETS[eye]
    return [*retinal_images(rs).values(), *FIELD_MAPS.values(), *colour_figures(rs).values(), *VIEWER.values()]


wildcard_constraints:
    eye="[A-Za-z0-9_-]+",
    scene="[A-Za-z0-9_-]+",
    part="[0-9]+",
    sweep="[A-Za-z0-9_-]+",
    variant="[A-Za-z0-9_.-]+",
    parts="[0-9]+",


#: Threads of the jobs that trace rays, each a batch of rays at a time (beeoptics.light.batching). One: Open3D
#: casts each batch on every core by itself, and two such jobs side by side keep a machine's cores busier than
#: one job's two batches (on this project's two cores, two meadow traces at once take 12.5 s against 17.3 s one
#: after the other). On a cluster each job has its node's cores: profiles/slurm sets their threads.
TRACING_THREADS = 1

#: Priorities: of the jobs ready to run, Snakemake starts those of higher priority first. Jobs that begin long
#: chains (an eye's, a meadow's, and a trace's and its gathering, which the eye's images wait for) come first, then
#: those whose products other jobs wait for, so that a run's last minute is not one job on one core while the
#: others idle: the images' chains, last in the run before, ended with a trace, its gathering and an image job
#: alone some 12 core-seconds idle, where short jobs now fill the end.
STARTS_CHAINS, AWAITED = 2, 1

# The trace settings jobs trace with. `parts` only splits a trace into jobs (its results are
# bit-identical), so it is left out: changing it reruns the trace's shares, not what reads them.
TRACE = {k: v for k, v in config["trace"].items() if k != "parts"}


def section_trace(section, keys=("samples_per_receptor",)):
    """The trace settings of a section that names its own samples (a flight, its views, the detection survey,
    the polarisation maps, the compass): its ``keys`` over the trace section's, traced to the section's own
    precision (null, its default: its samples each), with trace.precision's floor and bounds."""
    return {**TRACE, **{k: section[k] for k in keys},
            "precision": {**TRACE["precision"], "target": section["precision"]}}


#: What a folder holds for people, not for the stages that read it: its READMEs, and a scene's flights
#: (which the flight rules read as their own input).
NOT_READ = ("README.md", "flights")


def folder_files(folder):
    """Every file of an eye's or a scene's folder the stages read: editing any of them reruns what uses it."""
    folder = Path(folder)
    return sorted(str(p) for p in folder.rglob("*")
                  if p.is_file() and not set(p.relative_to(folder).parts) & set(NOT_READ))


def eye_sources(wildcards):
    return folder_files(EYES_DIR / wildcards.eye)


def scene_files(scene):
    """A scene's files, and the mesh of its meadow file, which the meadow rule generates."""
    folder = SCENES_DIR / scene
    generated = [str(folder / MEADOW_MESH), str(folder / MEADOW_FLOWERS)] if (folder / MEADOW_FILE).exists() else []
    return sorted(set(folder_files(folder)) | set(generated))


def scene_sources(wildcards):
    return scene_files(wildcards.scene)


def eye_file(wildcards):
    return EYES_DIR / wildcards.eye / "eye.yaml"


def sensitivity_files(wildcards):
    """The eye's eye.yaml (which names its receptor set), the set's file and curves, and a CSV of curves the
    config names: editing any reruns what uses them."""
    rs = RECEPTOR_SETS[wildcards.eye]
    curves = config["colour"]["sensitivities"]
    return [str(eye_file(wildcards)), str(rs.path), *([str(rs.curves_file)] if rs.curves_file else []),
            *([] if curves in (SPECIES, TEMPLATE) else [curves])]


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
    ) + ["results/eyes/acuity.csv", "results/eyes/fields.png"] + [f"results/figures/sensitivities/{name}.png"
                                       for name in dict.fromkeys(RECEPTOR_SETS[e].name for e in config["eyes"])]
    views = [f"results/{eye}/{scene}/{name}" for eye in config["eyes"] for scene in config["scenes"]
             for name in ["responses.csv", "irradiance.npz", *eye_images(eye)]]
    humans = expand("results/scenes/{scene}/human.{ext}", scene=config["scenes"], ext=["png", "exr"])
    summaries = expand("results/sweeps/{sweep}/summary.csv", sweep=list(config["sweeps"]))
    flights = [f"results/flights/{name}/{eye}/{product}" for name, flight in config["flights"].items()
               for eye in flight["eyes"]
               for product in ("responses.csv", "optic_flow.csv", "target.csv", "animation.gif", "optic_flow.png",
                               "views.npz", "views.mp4", "viewer.html",
                               *(("detection.csv", "detection.json", "detection.png") if "target" in flight else ()))]
    polarisation = expand("results/{eye}/{scene}/polarisation/{name}", eye=config["polarisation"]["eyes"],
                          scene=config["polarisation"]["scenes"],
                          name=["polarisation.csv", "field.png", "retina.png", "dorsal_rim.png", "compass.csv",
                                "compass.json", "compass.png"])
    detection = [f"results/detection/{scene}/{name}" for scene in config["detection"]["scenes"]
                 for name in ("summary.csv", "detection.png")]
    return eyes + figures + views + humans + summaries + flights + polarisation + detection
