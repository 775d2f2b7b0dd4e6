"""What the dielectric coating changes: the worker's catches and polarisation in the meadow, with and without it.

    .venv/bin/python benchmarks/coating.py [--samples 256] [--figures docs/]

Traces the worker's receptors, polarised, in the generated meadow as the polarisation stage does
(the config's samples and depth): as shipped, its grass under the coating Comar et al. (2014)
measured for a grass leaf (scenes/meadow/scene.yaml: η 1.32, α 0.35, FReD's spectrum measured
whole), and, on a temporary copy of the scene, with the grass Lambertian (its coating removed, the
same spectrum its base: the meadow before the coating); that one again with another seed, for the
Monte Carlo noise of such a comparison. Needs the meadow's mesh and the worker's eye (make workflow
makes them). The last line printed is one JSON object: per receptor class, the median and 90th
percentile of the catch's relative change (``catch_median``, ``catch_p90``, of |coated/Lambertian − 1|)
and of the degree of polarisation's absolute change (``degree_median``, ``degree_p90``), the same between
the two seeds (``noise_*``), and the median degree with and without the coating, over the receptors
looking below the head's horizon (``below``: their number), where the grass is; the sky's receptors,
some half of the eye, see no change (``all``: the same over every receptor). With ``--figures`` the
two polarisation maps of the visual field are written there (coating_lambertian.png,
coating_coated.png).

Reference: Comar A, Baret F, Obein G, et al. (2014) ACT: a leaf BRDF model taking into account the
azimuthal anisotropy of monocotyledonous leaf surface. Remote Sens Environ 143:112–121.
"""

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

from record import record

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, help="samples a receptor (default: the config's polarisation "
                        "samples)")
    parser.add_argument("--figures", type=Path, help="write the polarisation maps with and without the coating here")
    args = parser.parse_args(argv)
    from beeoptics.io.receptortable import read_receptors
    from beeoptics.io.table import read_table
    from beeoptics.io.validation import config_defaults
    from beeoptics.pipeline.polarisation import polarisation_maps
    from beeoptics.vision.polarisation import analyser_ps
    from beeoptics.vision.receptorset import receptor_set_of

    config = config_defaults()
    meadow = ROOT / "scenes" / "meadow"
    eye = ROOT / "eyes" / "worker" / "eye.yaml"
    receptors = ROOT / "results" / "eyes" / "worker" / "receptors.csv"
    if not (meadow / "meadow.ply").exists() or not receptors.exists():
        sys.exit("the meadow's mesh and the worker's eye are missing: make workflow makes them")
    receptor_set = receptor_set_of(eye)
    samples = args.samples or config["polarisation"]["samples_per_receptor"]
    tables = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        bare = tmp / "lambertian"
        bare.mkdir()
        for f in meadow.iterdir():
            if f.is_file() and f.name != "scene.yaml":
                (bare / f.name).symlink_to(f)
        scene = yaml.safe_load((meadow / "scene.yaml").read_text())
        del scene["materials"]["grass"]["coating"]
        (bare / "scene.yaml").write_text(yaml.safe_dump(scene, sort_keys=False))
        for name, path, seed in (("coated", meadow, 1), ("lambertian", bare, 1), ("lambertian_again", bare, 2)):
            out = {k: tmp / f"{name}_{k}.{ext}" for k, ext in (("table", "csv"), ("field", "png"),
                                                             ("retina", "png"), ("dorsal_rim", "png"))}
            polarisation_maps(eye, receptors, path / "scene.yaml", out, spectral=config["spectral"],
                              trace={**config["trace"], "samples_per_receptor": samples, "seed": seed}, threads=2,
                              dorsal_rim_ps=analyser_ps(config["polarisation"]["dorsal_rim_ps"]),
                              receptor_set=receptor_set, title=f"worker in meadow, grass {name.split('_')[0]}")
            tables[name] = read_table(out["table"], numeric=["id"], text=["side"])
            if args.figures is not None and name != "lambertian_again":
                args.figures.mkdir(parents=True, exist_ok=True)
                shutil.copy(out["field"], args.figures / f"coating_{name}.png")
    axes = read_receptors(receptors)
    row = {i: k for k, i in enumerate(axes.id)}
    below = axes.axis[[row[i] for i in tables["coated"]["id"]], 2] < 0.0
    summary = {"samples": samples, "depth": config["trace"]["depth"], "below": int(below.sum())}

    def changes(c, a, b, where):
        before, after = tables[a][f"{c}_I"][where], tables[b][f"{c}_I"][where]
        catch = np.abs(after / before - 1.0)[before > 0]
        degree = np.abs(tables[b][f"{c}_degree"][where] - tables[a][f"{c}_degree"][where])
        return catch, degree

    def summarise(c, where):
        catch, degree = changes(c, "lambertian", "coated", where)
        noise_catch, noise_degree = changes(c, "lambertian", "lambertian_again", where)
        return {"catch_median": float(np.median(catch)), "catch_p90": float(np.percentile(catch, 90)),
                "degree_median": float(np.median(degree)), "degree_p90": float(np.percentile(degree, 90)),
                "noise_catch_median": float(np.median(noise_catch)),
                "noise_catch_p90": float(np.percentile(noise_catch, 90)),
                "noise_degree_median": float(np.median(noise_degree)),
                "noise_degree_p90": float(np.percentile(noise_degree, 90)),
                "degree_lambertian": float(np.median(tables["lambertian"][f"{c}_degree"][where])),
                "degree_coated": float(np.median(tables["coated"][f"{c}_degree"][where]))}

    for c in receptor_set.classes:
        summary[c] = summarise(c, below) | {"all": summarise(c, np.ones_like(below))}
    record("coating", summary)


if __name__ == "__main__":
    main()
