"""Benchmark: the closed loop's steps a second, at the views' setting and at low fidelity, and what low fidelity costs in error.

    python benchmarks/loop.py --eye worker --scene meadow --steps 10

Flies the Gymnasium environment (:class:`beeoptics.loop.BeeView`) with both
eyes of ``--eye`` (its ``eye.yaml``, built into the cache on first use) for
``--steps`` steps along one gentle curve over ``--scene`` (0.5 m/s, turning
at 20°/s from the scene's own pose), first at the views' setting (16
samples a receptor, depth 1), then at :data:`beeoptics.loop.LOW_FIDELITY`
(a few samples at depth 1: the first surfaces met, lit directly by the sun
and the sky), each from a seed of its own. The two fly the same poses, so that each
step's catches can be compared: the low-fidelity error of a class is the
root mean square over all receptors and steps of the difference relative
to the views' catch (the views' own noise, independent of it, included in
it), and ``low_fidelity_median_error`` the median of its size.

The last line printed is one JSON object: ``steps_per_s`` and
``low_fidelity_steps_per_s`` (steps over the wall time of the steps, the
scene and eye loaded and a first look taken), ``low_fidelity_error`` (a
relative RMS per class), the settings, each setting's CPU seconds a step
(on a machine shared with other work, the steady figure) and its
``embree_share`` (the share of the steps' wall time in Open3D's ray calls). Bounds (issue 39): ≥ 2 steps a second, and ≥ 10 at low fidelity.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

import beeoptics
from beeoptics.loop import LOW_FIDELITY, BeeView
from beeoptics.raycasting import embree_seconds

from record import record

ROOT = Path(__file__).resolve().parents[1]
#: The views' setting along a flight (the configuration's ``flights.*.views``).
VIEWS = {"samples": 16, "depth": 1}
#: The action every step: forward speed, m/s, and turning rate, deg/s (a gentle curve, no surface met).
ACTION = np.array([0.5, 20.0], np.float32)


def fly(env, steps, seed):
    """Catches at every step (steps, receptors, classes), and the steps' wall, CPU and Embree seconds."""
    env.reset(seed=seed)
    seen = []
    start, cpu, embree = time.perf_counter(), time.process_time(), embree_seconds()[0]
    for _ in range(steps):
        catches, _, terminated, _, _ = env.step(ACTION)
        seen.append(catches)
        if terminated:
            raise SystemExit("the benchmark's flight met a surface: shorten --steps")
    return (np.array(seen), time.perf_counter() - start, time.process_time() - cpu,
            embree_seconds()[0] - embree)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--eye", default="worker", help="a folder of eyes/ (default: %(default)s)")
    parser.add_argument("--scene", default="meadow", help="a folder of scenes/ (default: %(default)s)")
    parser.add_argument("--steps", type=int, default=10, help="steps timed (default: %(default)s)")
    parser.add_argument("--threads", type=int, default=os.cpu_count(), help="threads (default: the cores, %(default)s)")
    args = parser.parse_args(argv)
    eye = beeoptics.load_eye(ROOT / "eyes" / args.eye / "eye.yaml")
    scene = beeoptics.load_scene(ROOT / "scenes" / args.scene / "scene.yaml")
    runs = {}
    # Seeds of their own: the low-fidelity samples are not the first of the views', so that their difference
    # is the two settings' independent noise.
    for name, setting, seed in (("views", VIEWS, 1), ("low", LOW_FIDELITY, 2)):
        env = BeeView(eye, scene, target_m=scene.scene.eye_position, max_steps=args.steps, threads=args.threads,
                      **setting)
        env.reset(seed=seed)  # a first look, untimed: Embree's scene built, every kernel loaded
        runs[name] = fly(env, args.steps, seed)
    (views, wall, cpu, embree), (low, low_wall, low_cpu, low_embree) = runs["views"], runs["low"]
    # Receptor by receptor (a receptor that caught nothing left out): the few with the sun in their cones,
    # some ten thousand times brighter than the rest, would otherwise make the whole of an absolute RMS.
    views, low = views.astype(float), low.astype(float)
    relative = (np.abs(low - views) / np.where(views > 0.0, views, np.nan)).reshape(-1, views.shape[2])
    rms, median = np.sqrt(np.nanmean(relative ** 2, axis=0)), np.nanmedian(relative, axis=0)
    result = {"eye": args.eye, "scene": args.scene, "steps": args.steps, "threads": args.threads,
              "samples": VIEWS["samples"], "depth": VIEWS["depth"], "steps_per_s": args.steps / wall,
              "cpu_s_per_step": cpu / args.steps, "embree_share": embree / wall, "low_fidelity": LOW_FIDELITY,
              "low_fidelity_steps_per_s": args.steps / low_wall, "low_fidelity_cpu_s_per_step": low_cpu / args.steps,
              "low_fidelity_embree_share": low_embree / low_wall,
              "low_fidelity_error": dict(zip(eye.receptor_set.classes, rms.round(4).tolist())),
              "low_fidelity_median_error": dict(zip(eye.receptor_set.classes, median.round(4).tolist()))}
    record("loop", result)


if __name__ == "__main__":
    main()
