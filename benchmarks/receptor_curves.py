"""Measurement: how far the choice of receptor curves moves an eye's catches and colours.

    python benchmarks/receptor_curves.py --eye worker --scene meadow

Gathers the responses of a traced eye and scene (the workflow's
``results/{eye}/{scene}/parts``) twice, with the Govardovskii template and
with the eye's species' own curves (for the honey bee, the measured curves of
Peitsch et al. 1992), and prints, over the
receptors that caught light, the ratio of raw and von Kries catches and the
shift of each receptor in the colour hexagon (vertex at 1) and of its hue.
"""

import argparse
import tempfile
from pathlib import Path

import numpy as np

from beeoptics.io.table import read_table
from beeoptics.io.validation import config_defaults
from beeoptics.pipeline.trace import gather_responses
from beeoptics.vision.receptorset import SPECIES, TEMPLATE, receptor_set_of

ROOT = Path(__file__).resolve().parents[1]


def responses(eye, scene, curves, config, receptor_set):
    with tempfile.TemporaryDirectory() as tmp:
        out = {"responses": Path(tmp) / "responses.csv", "irradiance": Path(tmp) / "irradiance.npz"}
        gather_responses(ROOT / "results" / "eyes" / eye / "receptors.csv", ROOT / "scenes" / scene / "scene.yaml",
                         sorted((ROOT / "results" / eye / scene / "parts").glob("*.npz")), out,
                         spectral=config["spectral"], receptor_set=receptor_set,
                         background=config["colour"]["background"], receptor_curves=curves)
        return read_table(out["responses"])


def spread(values):
    return f"median {np.median(values):.3f} [5–95 % {np.percentile(values, 5):.3f}–{np.percentile(values, 95):.3f}]"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--eye", default="worker", help="eye class (default: %(default)s)")
    parser.add_argument("--scene", default="meadow", help="a folder of scenes/ (default: %(default)s)")
    args = parser.parse_args()
    config = config_defaults()
    receptor_set = receptor_set_of(ROOT / "eyes" / args.eye / "eye.yaml")
    template, measured = (responses(args.eye, args.scene, c, config, receptor_set) for c in (TEMPLATE, SPECIES))
    lit = (template["lit"] == 1) & (measured["lit"] == 1)
    print(f"{args.eye} in {args.scene}: {lit.sum()} receptors that caught light")
    for r in receptor_set.classes:
        print(f"  catch {r}, measured / template: {spread(measured[r][lit] / template[r][lit])}")
        print(f"  von Kries q_{r}, measured / template: {spread(measured['q_' + r][lit] / template['q_' + r][lit])}")
    shift = np.hypot(*(measured[k][lit] - template[k][lit] for k in ("hex_x", "hex_y")))
    hue = np.abs((measured["hex_hue_deg"][lit] - template["hex_hue_deg"][lit] + 180.0) % 360.0 - 180.0)
    print(f"  hexagon shift: {spread(shift)}, largest {shift.max():.3f}")
    print(f"  hexagon distance from centre: template {spread(template['hex_r'][lit])}, "
          f"measured {spread(measured['hex_r'][lit])}")
    print(f"  hue change, degrees: {spread(hue)}")


if __name__ == "__main__":
    main()
