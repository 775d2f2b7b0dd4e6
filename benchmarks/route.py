"""Benchmark: views along a route, how many frames a second, against bare Embree.

    python benchmarks/route.py --eye worker --scene meadow --flight flights/scan.csv

Traces every frame of the shipped scanning flight (scenes/meadow/flights/scan.csv:
three 1 m legs 0.5 m up, looking 20° down) for both eyes of ``--eye``, as
the workflow's ``flight_views`` stage does (beeoptics.pipeline.flights.flight_views),
with the views' defaults (depth 1, 16 samples a receptor, the config's frame
rate), and writes the catches and the video into a scratch folder. Then
casts, with Open3D's ``cast_rays`` alone on the same scene, as many
receptor-cone rays as the frames cast.

The last line printed is one JSON object: ``frames``, ``frames_per_s``
(frames over the stage's wall time once the scene is loaded: tracing,
catches and the video), ``trace_s``, ``rays`` (the rays one frame casts:
primary, bounce and shadow, the sun's and the sky's), ``bare_rays_per_s``,
``embree_share`` (the time bare ``cast_rays`` needs for all the frames' rays
over the tracing's time), ``load_s`` (loading the scene). Bounds (issue 25):
≥ 2 frames a second and an Embree share ≥ 0.7.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from beeoptics.io.receptortable import read_receptors
from beeoptics.io.validation import CONFIG_SCHEMA, validate_config
from beeoptics.light.batching import TraceSettings
from beeoptics.light.scene import load_scene, raycasting_scene, receptors_in_world
from beeoptics.light.sensors import cone_samples
from beeoptics.pipeline import flights
from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_MESH
from beeoptics.raycasting import cast_rate
from beeoptics.spectra import grid
from beeoptics.vision.receptorset import receptor_set_of

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
    config = validate_config({"flights": {"route": {"scene": args.scene, "path": args.flight, "eyes": [args.eye]}}},
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
    wl = grid(**config["spectral"])
    start = time.perf_counter()
    scene = load_scene(folder / "scene.yaml", wl)
    load_s = time.perf_counter() - start
    settings = TraceSettings(views["samples_per_receptor"], views["depth"], config["trace"]["seed"],
                             config["trace"]["batch_rays"], args.threads, config["trace"]["sky_sampling"])
    fps = 10.0
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        out = flights.flight_views(receptors, folder / "scene.yaml", folder / args.flight, [],
                                   {"catches": Path(tmp) / "views.npz", "video": Path(tmp) / "views.mp4",
                                    "viewer": Path(tmp) / "viewer.html"}, fps=fps,
                                   spectral=config["spectral"], settings=settings,
                                   receptor_set=receptor_set_of(ROOT / "eyes" / args.eye / "eye.yaml"))
        wall = time.perf_counter() - start - load_s  # the stage loads the scene itself: counted apart
    table = read_receptors(receptors)
    origins, axes = receptors_in_world(scene, table.position, table.axis)
    dirs, _ = cone_samples(axes, table.delta_rho_deg, views["samples_per_receptor"], 1)
    batch = np.hstack([np.repeat(origins, views["samples_per_receptor"], axis=0), dirs.reshape(-1, 3)])
    bare = cast_rate(raycasting_scene(scene), batch, out["rays"])
    result = {"eye": args.eye, "scene": args.scene, "flight": args.flight, "threads": args.threads,
              "frames": out["frames"], "frames_per_s": out["frames"] / wall, "trace_s": out["trace_s"],
              "rays": out["rays"] / out["frames"], "bare_rays_per_s": bare,
              "embree_share": out["rays"] / bare / out["trace_s"], "load_s": load_s}
    record("route", result)


if __name__ == "__main__":
    main()
