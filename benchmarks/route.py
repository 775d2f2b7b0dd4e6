"""Benchmark: views along a route, how many frames a second, against bare Embree.

    python benchmarks/route.py --eye worker --scene meadow --flight flights/scan.csv

Traces every frame of the shipped scanning flight (scenes/meadow/flights/scan.csv:
three 1 m legs 0.5 m up, looking 20° down) for both eyes of ``--eye``, as
the workflow's ``flight_views`` stage does (beeoptics.pipeline.flights.flight_views),
with the views' defaults (depth 1, 16 samples a receptor, the config's frame
rate), and writes the catches and the video into a scratch folder. Then
casts, with Open3D's ``cast_rays`` alone on the same scene, as many
receptor-cone rays as the frames cast.

Then traces the same frames through the Python API alone
(``beeoptics.looks`` over the flight's poses, each view's catches over
white's, as the stage writes them), the scene and eye held in memory.

The last line printed is one JSON object: ``frames``, ``frames_per_s``
(frames over the stage's wall time once the scene is loaded: tracing,
catches and the video), ``api_frames_per_s`` (frames over the API's wall
time: tracing and catches), ``trace_s``, ``rays`` (the rays one frame casts:
primary, bounce and shadow, the sun's and the sky's), ``bare_rays_per_s``,
``embree_share`` (the time bare ``cast_rays`` needs for all the frames' rays
over the tracing's time), ``load_s`` (loading the scene). Bounds (issue 25):
≥ 2 frames a second and an Embree share ≥ 0.7; the API within 10 % of the
stage's frames a second (issue 39).
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import beeoptics
from beeoptics.io.validation import CONFIG_SCHEMA, validate_config
from beeoptics.pipeline import flights
from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_MESH
from beeoptics.raycasting import cast_rate
from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.world.flight import frame_times, pose, read_flight

from record import record

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--eye", default="worker", help="eye class (default: %(default)s)")
    parser.add_argument("--scene", default="meadow", help="a folder of scenes/ (default: %(default)s)")
    parser.add_argument("--flight", default="flights/scan.csv",
                        help="the flight's CSV, relative to the scene's folder (default: %(default)s)")
    parser.add_argument("--threads", type=int, default=os.cpu_count(), help="threads (default: the cores, %(default)s)")
    args = parser.parse_args(argv)
    # The views' settings as the config's defaults give them to a flight.
    # A run of this eye in this scene, so that the flight is not narrowed away as outside the default run's.
    config = validate_config({"eyes": [args.eye], "scenes": [args.scene],
                              "flights": {"route": {"scene": args.scene, "path": args.flight, "eyes": [args.eye]}}},
                             CONFIG_SCHEMA, folders=False)
    views = config["flights"]["route"]["views"]
    receptors = ROOT / "results" / "eyes" / args.eye / "receptors.csv"
    if not receptors.exists():
        subprocess.run([sys.executable, "-m", "beeoptics.cli", "build-eye", str(ROOT / "eyes" / args.eye / "eye.yaml"),
                        "-o", str(receptors.parent), "--quiet"], check=True)
    folder = ROOT / "scenes" / args.scene
    if (folder / MEADOW_FILE).exists() and not (folder / MEADOW_MESH).exists():
        subprocess.run([sys.executable, "-m", "beeoptics.cli", "meadow", str(folder / MEADOW_FILE), "-o",
                        str(folder / MEADOW_MESH)], check=True, stdout=subprocess.DEVNULL)
    start = time.perf_counter()
    scene = beeoptics.load_scene(folder / "scene.yaml", **config["spectral"])
    load_s = time.perf_counter() - start
    # The views' settings as the workflow gives them (workflow/rules/flights.smk).
    trace = {**{k: v for k, v in config["trace"].items() if k != "parts"},
             **{k: views[k] for k in ("samples_per_receptor", "depth")},
             "precision": {**config["trace"]["precision"], "target": views["precision"]}}
    receptor_set = receptor_set_of(ROOT / "eyes" / args.eye / "eye.yaml")
    fps = 10.0
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        out = flights.flight_views(receptors, folder / "scene.yaml", folder / args.flight, [],
                                   {"catches": Path(tmp) / "views.npz", "video": Path(tmp) / "views.mp4",
                                    "viewer": Path(tmp) / "viewer.html"}, fps=fps, spectral=config["spectral"],
                                   trace=trace, threads=args.threads, receptor_set=receptor_set)
        wall = time.perf_counter() - start - load_s  # the stage loads the scene itself: counted apart
    eye = beeoptics.load_eye(receptors, receptor_set=receptor_set)
    flight = read_flight(folder / args.flight)
    poses = [{"position_m": p.position, "rotation": p.rotation} for p in
             (pose(flight, t) for t in frame_times(flight, fps))]
    start = time.perf_counter()
    for view in beeoptics.looks(eye, scene, poses, trace=trace, threads=args.threads):
        view.relative
    api_wall = time.perf_counter() - start
    # Bare Embree, the yardstick: the frames' count of receptor-cone rays cast alone on the same scene.
    bare = cast_rate(scene.raycasting, beeoptics.cone_rays(eye, scene, views["samples_per_receptor"]), out["rays"])
    result = {"eye": args.eye, "scene": args.scene, "flight": args.flight, "threads": args.threads,
              "frames": out["frames"], "frames_per_s": out["frames"] / wall,
              "api_frames_per_s": len(poses) / api_wall, "trace_s": out["trace_s"],
              "rays": out["rays"] / out["frames"], "bare_rays_per_s": bare,
              "embree_share": out["rays"] / bare / out["trace_s"], "load_s": load_s}
    record("route", result)


if __name__ == "__main__":
    main()
