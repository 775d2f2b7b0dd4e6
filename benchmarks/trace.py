"""Benchmark: how fast an eye pair is traced through a scene, against bare Embree.

    python benchmarks/trace.py --eye worker --scene meadow --spp 256 --depth 3
    python benchmarks/trace.py --eye drone --spp 1024 --scene tests/data/scenes/meadow_tiny/scene.yaml

Uses results/eyes/<eye>/receptors.csv, building the eye first (in a child
process, so that its memory is not counted) when it is missing, and a
generated scene's mesh (the default meadow's), generating it when missing. Then traces
both eyes on the full spectral grid, exactly as the workflow's trace stage
does with ``--cores all`` (the config's batch size, one batch per core), and
casts the same number of rays as the trace cast through Open3D's
``RaycastingScene.cast_rays`` alone, in batches of 2^20 receptor-cone rays,
where Embree is fastest.

``--scene`` names a folder of scenes/ (by default the generated meadow of
1.2 million triangles) or a scene file, such as the toy meadow of the tests
(tests/data/scenes/meadow_tiny/scene.yaml, 233 triangles).

The last line printed is one JSON object: eye, scene, scene_triangles, spp,
depth, threads, receptors, rays (every ray the trace cast: primary, bounce
and shadow), wall_s (the wall time of the trace stage, traced and
gathered), trace_s (the tracing alone, without loading the scene),
embree_fraction (the time the threads spent in Open3D's ray calls, summed,
over trace_s times the threads), embree_cpu_share (on one thread only: the
share of the trace's CPU time, on all cores, spent in Open3D's ray calls,
which run on every core while the shading between them runs on one; with
more threads one thread shades during another's call and the two cannot be
told apart, so it is null),
pipeline_rays_per_s (rays / wall_s), bare_rays_per_s (bare ``cast_rays``
throughput on the same scene), ratio (their quotient) and peak_memory_mb
(the process's peak resident memory). The first run after an install also
compiles the tracer's kernels (printed once): run twice to time the trace.
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import beeoptics
from beeoptics.io.validation import config_defaults
from beeoptics.pipeline.trace import gather_responses, trace_part
from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_MESH
from beeoptics.raycasting import cast_rate, embree_seconds
from beeoptics.vision.receptorset import receptor_set_of

from record import record

ROOT = Path(__file__).resolve().parents[1]
BARE_BATCH_RAYS = 1 << 20


def build_eye(eye, receptors_csv):
    """Build an eye's receptor table in a child process, with the command-line tool's defaults."""
    subprocess.run([sys.executable, "-m", "beeoptics.cli", "build-eye", str(eye), "-o", str(receptors_csv.parent),
                    "--quiet"], check=True)


def bare_rays_per_s(eye, scene, rays, seed):
    """Throughput of ``cast_rays`` alone on receptor-cone rays, :data:`BARE_BATCH_RAYS` at a time (256 of each
    of the eye's first receptors), in a :class:`beeoptics.Scene`'s Embree scene."""
    per = max(1, BARE_BATCH_RAYS // 256)
    return cast_rate(scene.raycasting, beeoptics.cone_rays(eye, scene, 256, seed=seed, receptors=slice(0, per)), rays)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--eye", default="worker", help="eye class (default: worker)")
    parser.add_argument("--scene", default="meadow", help="a folder of scenes/ or a scene file (default: meadow)")
    parser.add_argument("--spp", type=int, default=256, help="samples per receptor (default: 256)")
    parser.add_argument("--depth", type=int, default=3, help="scattering events per path (default: 3)")
    parser.add_argument("--seed", type=int, default=1, help="the random numbers' seed (default: %(default)s)")
    parser.add_argument("--threads", type=int, default=os.cpu_count(), help="threads (default: the cores, %(default)s)")
    defaults = config_defaults()
    parser.add_argument("--batch-rays", type=int, default=defaults["trace"]["batch_rays"],
                        help="rays per batch (default: the config's, %(default)s)")
    args = parser.parse_args()
    receptors_csv = ROOT / "results" / "eyes" / args.eye / "receptors.csv"
    if not receptors_csv.exists():
        build_eye(ROOT / "eyes" / args.eye / "eye.yaml", receptors_csv)
    scene_file = Path(args.scene) if Path(args.scene).is_file() else ROOT / "scenes" / args.scene / "scene.yaml"
    # A generated scene's mesh, as the workflow's meadow rule makes it, when it is not there yet
    # (in a child process, as the eye, so that its memory is not counted).
    if (scene_file.parent / MEADOW_FILE).exists() and not (scene_file.parent / MEADOW_MESH).exists():
        subprocess.run([sys.executable, "-m", "beeoptics.cli", "meadow", str(scene_file.parent / MEADOW_FILE), "-o",
                        str(scene_file.parent / MEADOW_MESH)], check=True)
    spectral = defaults["spectral"]

    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        part = Path(tmp) / "radiance.npz"
        trace = {**{k: v for k, v in defaults["trace"].items() if k != "parts"}, "samples_per_receptor": args.spp,
                 "depth": args.depth, "seed": args.seed, "batch_rays": args.batch_rays}
        before = embree_seconds()
        receptor_set = receptor_set_of(ROOT / "eyes" / args.eye / "eye.yaml")
        counts = trace_part(receptors_csv, scene_file, {"radiance": part}, spectral=spectral, trace=trace,
                            threads=args.threads, receptor_set=receptor_set)
        gather_responses(receptors_csv, scene_file, [part], {"responses": Path(tmp) / "responses.csv",
                                                             "irradiance": Path(tmp) / "irradiance.npz"},
                         spectral=spectral, receptor_set=receptor_set)
        wall = time.perf_counter() - start
        embree, embree_cpu = np.subtract(embree_seconds(), before)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    rays = counts["cast"] + counts["shadow"]

    eye = beeoptics.load_eye(receptors_csv)
    scene = beeoptics.load_scene(scene_file, **spectral)
    bare = bare_rays_per_s(eye, scene, rays, args.seed)
    pipeline = rays / wall
    print(f"{args.eye} pair in {args.scene}: {len(eye.table.id)} receptors, {rays} rays in {wall:.1f} s; "
          f"{pipeline / 1e6:.2f} M rays/s against {bare / 1e6:.2f} M bare")
    record("trace", {
        "eye": args.eye, "scene": args.scene, "scene_triangles": int(scene.objects.faces.sum()),
        "spp": args.spp, "depth": args.depth, "threads": args.threads, "batch_rays": args.batch_rays,
        "receptors": len(eye.table.id), "rays": rays, "wall_s": round(wall, 2),
        "trace_s": round(counts["seconds"], 2),
        "embree_fraction": round(embree / (counts["seconds"] * args.threads), 3),
        "embree_cpu_share": round(embree_cpu / counts["cpu_seconds"], 3) if args.threads == 1 else None,
        "pipeline_rays_per_s": round(pipeline), "bare_rays_per_s": round(bare),
        "ratio": round(pipeline / bare, 3), "peak_memory_mb": round(peak, 1),
    })


if __name__ == "__main__":
    main()
