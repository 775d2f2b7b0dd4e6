"""Benchmark: how long the facet lattice of one eye takes to relax, and the memory it needs.

    python benchmarks/relax.py --eye drone

Remeshes the eye (not timed), then places and relaxes its facets. The last
line printed is one JSON object: eye, facets (per eye), seconds (the
relaxation alone), iterations, stage_seconds (the whole facet stage, with
grid projection, facet map, receptor table and quality figures) and
peak_memory_mb (the process's peak resident memory). With ``--quality``, the
eye's quality figures are kept in that file, to compare a change's lattice
with the one before it.
"""

import argparse
import json
import resource
import tempfile
import time
from pathlib import Path

from beeoptics.eye.optics import AcceptanceModel
from beeoptics.pipeline.eyes import build_facets, remesh_eye
from beeoptics.pipeline.outputs import FACET_OUTPUTS
from record import record


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--eye", default="worker", help="eye class, a folder of --eyes-dir (default: worker)")
    parser.add_argument("--eyes-dir", default=Path(__file__).resolve().parents[1] / "eyes", type=Path,
                        help="the folder of eye classes (default: the repository's eyes/)")
    parser.add_argument("--tolerance-um", type=float, default=0.05, help="relaxation tolerance, µm (default 0.05)")
    parser.add_argument("--quality", type=Path, help="copy the eye's quality.json here")
    args = parser.parse_args()
    eye = args.eyes_dir / args.eye / "eye.yaml"
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        remesh_eye(eye, {"remeshed": out / "remeshed.ply"})
        start = time.perf_counter()
        seconds = build_facets(eye, out / "remeshed.ply", {k: out / name for k, name in FACET_OUTPUTS.items()},
                     tolerance_um=args.tolerance_um, acceptance=AcceptanceModel())
        stage_seconds = time.perf_counter() - start
        quality = json.loads((out / "quality.json").read_text())
        if args.quality is not None:
            args.quality.write_text((out / "quality.json").read_text())
    print(f"{args.eye}: {quality['facets_per_eye']} facets relaxed in {seconds:.1f} s "
          f"({quality['relaxation']['iterations']} iterations)")
    record("relax", {
        "eye": args.eye,
        "facets": quality["facets_per_eye"],
        "seconds": round(seconds, 2),
        "iterations": quality["relaxation"]["iterations"],
        "stage_seconds": round(stage_seconds, 2),
        "peak_memory_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
    })


if __name__ == "__main__":
    main()
