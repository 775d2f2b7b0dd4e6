"""Benchmark: how long a scene takes to load, from its files and from the scene cache.

    python benchmarks/load.py --scene meadow

Loads ``--scene`` (a folder of scenes/, by default the generated meadow,
generated if missing) once with the scene cache turned off (``cold_seconds``:
read and checked from its files), once to fill the cache, and three times
from it. The last line printed is one JSON object: ``seconds`` (the median of
the three loads from the cache, the figure bounded at 1.5 s by issue 25),
``cold_seconds``, ``import_seconds`` (importing the Python API's scene loader,
which every job that loads a scene pays once), ``triangles`` and the cache's folder.
"""

import argparse
import subprocess
import sys
import time
from pathlib import Path

from record import record

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="meadow", help="a folder of scenes/ (default: %(default)s)")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    from beeoptics.api import load_scene
    from beeoptics.light import scenecache
    from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_MESH
    imported = time.perf_counter() - start
    folder = ROOT / "scenes" / args.scene
    if (folder / MEADOW_FILE).exists() and not (folder / MEADOW_MESH).exists():
        subprocess.run([sys.executable, "-m", "beeoptics.cli", "meadow", str(folder / MEADOW_FILE), "-o",
                        str(folder / MEADOW_MESH)], check=True, stdout=subprocess.DEVNULL)
    grid = {"start_nm": 300.0, "end_nm": 700.0, "step_nm": 5.0}
    path = folder / "scene.yaml"
    start = time.perf_counter()
    scene = load_scene(path, **grid, cache=False)
    cold = time.perf_counter() - start
    load_scene(path, **grid)
    warm = []
    for _ in range(3):
        start = time.perf_counter()
        load_scene(path, **grid)
        warm.append(time.perf_counter() - start)
    warm.sort()
    record("load", {"scene": args.scene, "seconds": warm[1], "cold_seconds": cold, "import_seconds": imported,
                    "triangles": int(scene.objects.faces.sum()), "cache": str(scenecache.cache_root())})


if __name__ == "__main__":
    main()
