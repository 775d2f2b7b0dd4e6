"""What the dielectric coating changes: the worker's catches and polarisation in the meadow, before and after.

    .venv/bin/python benchmarks/coating.py [--samples 64] [--roughness 0.35] [--refractive-index 1.32]

Traces the worker's receptors, polarised, in the generated meadow twice: as shipped (the leaf
material of the grass, dandelion and harebell leaves Lambertian) and with that material given a
coating ``{roughness: α, refractive_index: η}`` (by default the grass measurement Comar et al. 2014
give for wheat leaves: η 1.32, and α 0.35, the RMS of their roughness across (0.46) and along (0.18)
the veins, a Cook–Torrance roughness taken as GGX's α), on a temporary copy of the scene. FReD's
reflectance stays the base's, though it was measured with the leaf's surface reflection in it, so
the coating's reflection is counted on top: the change is an upper bound. Needs the
meadow's mesh (make workflow generates it). The last line printed is one JSON object: per receptor
class, the median and 90th percentile over receptors of the catch's relative change
(``catch_median``, ``catch_p90``, of |after/before − 1|) and of the degree of polarisation's absolute
change (``degree_median``, ``degree_p90``), and the median degree before and after.

Reference: Comar A, Baret F, Obein G, et al. (2014) ACT: a leaf BRDF model taking into account the
azimuthal anisotropy of monocotyledonous leaf surface. Remote Sens Environ 143:112–121.
"""

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=64, help="samples a receptor (default: %(default)s)")
    parser.add_argument("--roughness", type=float, default=0.35, help="the coating's GGX α (default: %(default)s)")
    parser.add_argument("--refractive-index", type=float, default=1.32, help="its η (default: %(default)s)")
    parser.add_argument("--material", default="leaf", help="the meadow's material to coat (default: %(default)s)")
    args = parser.parse_args(argv)
    from beeoptics.io.table import read_table
    from beeoptics.light.batching import TraceSettings
    from beeoptics.pipeline.polarisation import polarisation_maps
    from beeoptics.vision.polarisation import analyser_ps
    from beeoptics.vision.receptorset import receptor_set_of

    meadow = ROOT / "scenes" / "meadow"
    eye = ROOT / "eyes" / "worker" / "eye.yaml"
    receptors = ROOT / "results" / "eyes" / "worker" / "receptors.csv"
    receptor_set = receptor_set_of(eye)
    settings = TraceSettings(samples=args.samples, depth=2, seed=1, batch_rays=131072, threads=2)
    spectral = {"start_nm": 300, "end_nm": 700, "step_nm": 5}
    tables = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        coated = tmp / "coated"
        coated.mkdir()
        for f in meadow.iterdir():
            if f.is_file() and f.name != "scene.yaml":
                (coated / f.name).symlink_to(f)
        scene = yaml.safe_load((meadow / "scene.yaml").read_text())
        scene["materials"][args.material]["coating"] = {"roughness": args.roughness,
                                                       "refractive_index": args.refractive_index}
        (coated / "scene.yaml").write_text(yaml.safe_dump(scene, sort_keys=False))
        for name, path in (("before", meadow / "scene.yaml"), ("after", coated / "scene.yaml")):
            out = {k: tmp / f"{name}_{k}.{ext}" for k, ext in (("table", "csv"), ("field", "png"),
                                                             ("retina", "png"), ("dorsal_rim", "png"))}
            polarisation_maps(eye, receptors, path, out, spectral=spectral, settings=settings,
                              dorsal_rim_ps=analyser_ps(6.6), receptor_set=receptor_set, title=name)
            tables[name] = read_table(out["table"], numeric=["id"], text=["side"])
    summary = {"samples": args.samples, "roughness": args.roughness, "refractive_index": args.refractive_index}
    for c in receptor_set.classes:
        before, after = tables["before"][f"{c}_I"], tables["after"][f"{c}_I"]
        change = np.abs(after / before - 1.0)[before > 0]
        d0, d1 = tables["before"][f"{c}_degree"], tables["after"][f"{c}_degree"]
        summary[c] = {"catch_median": float(np.median(change)), "catch_p90": float(np.percentile(change, 90)),
                      "degree_median": float(np.median(np.abs(d1 - d0))),
                      "degree_p90": float(np.percentile(np.abs(d1 - d0), 90)),
                      "degree_before": float(np.median(d0)), "degree_after": float(np.median(d1))}
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
