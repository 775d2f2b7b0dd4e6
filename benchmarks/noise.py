"""Benchmark: how noisy an eye pair's catches are with each way of sampling the sky, and at what cost.

    python benchmarks/noise.py --eye worker --scene meadow --spp 256 --depth 3

Traces both eyes of ``--eye`` (results/eyes/<eye>/receptors.csv, built first
if missing) through ``--scene`` (a folder of scenes/, by default the
generated meadow, generated if missing; ``patches``, or ``uniform``, open
grass under a sky of uniform luminance) with ``--seeds`` seeds (eight by
default), once with the sky sampled at every surface (``default``:
next-event estimation weighed by multiple importance sampling,
``trace.sky_sampling: nee``) and once with the sky seen only where paths
escape (``escape``), the two in turns seed by seed. A seed shifts a receptor's cone points by a fresh
random offset (Cranley & Patterson 1976; ``beeoptics.light.sampler``) and
draws its paths' other choices anew, so the seeds' estimates are
independent randomisations of one quasi-Monte Carlo rule (L'Ecuyer &
Lemieux 2002), and their sample standard
deviation (n − 1 in the denominator) estimates the standard error of one
run's catch without bias in its variance. Each receptor's relative standard
error of a class's catch is that deviation over the seeds' mean catch, over
the receptors that caught light. (Two seeds, |q₁ − q₂|/√2, leave one degree
of freedom: for identical receptors its median reads 0.67σ and its 90th
percentile 1.64σ, so its percentiles over the eye are biased.)

The last line printed is one JSON object: per estimator, ``p50_rel_se``,
``p90_rel_se`` and ``p99_rel_se`` of the achromatic (G) catch and
``trace_s`` (the mean of the seeds' trace times), the same for every class
under ``classes``, and ``efficiency_vs_escape``, (p90² · trace_s) of
``escape`` over that of ``default``: how many times fewer seconds the
default needs for the same noise in the noisiest tenth of the receptors;
``efficiency_vs_escape_cpu`` the same from the CPU seconds (``trace_cpu_s``),
which other processes sharing the machine change less; each with its band
(``_band``), the 16th and 84th percentiles of a bootstrap over the seeds.
Both estimators trace a few receptors first, untimed, so that the first
timed does not pay for loading the compiled kernels.

With ``--precision TARGET`` it compares fixed sampling with adaptive
sampling to that relative standard error, or with ``--precision auto`` to
the animal's precision, instead (``trace.precision``,
:mod:`beeoptics.light.precision`; see :func:`precision_comparison`).

What makes that noise: a scene lit by a sky and a sun is traced again,
with the default estimator and the same seeds, lit by the sun alone and by
the sky alone (their catches add up to the whole's), and ``noise_sources``
gives, for
the noisiest tenth of the receptors in the G catch, the medians of the
sun's share of their catch and of each light's standard error over their
whole catch (``sun_rel_se``, ``sky_rel_se``). Sky sampling can lower only
the sky's.

References
----------
Cranley R, Patterson TNL (1976) Randomization of number theoretic methods
for multiple integration. SIAM J Numer Anal 13:904–914.
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In Dror M et al. (eds) Modeling Uncertainty, Kluwer, 419–474.
"""

import argparse
import subprocess
import sys
from pathlib import Path

import numpy as np

import beeoptics
from beeoptics.io.validation import config_defaults
from beeoptics.pipeline.world import MEADOW_FILE, MEADOW_MESH
from beeoptics.light.precision import form_errors
from beeoptics.replicates import standard_error
from beeoptics.vision.receptorset import receptor_set_of
from beeoptics.vision.uncertainty import NOISE_FRACTION, noise_forms

from record import record

ROOT = Path(__file__).resolve().parents[1]
#: Seeds (independent randomisations) whose spread estimates the noise: eight, as the issue's measurement used.
SEEDS = 8
#: Receptors traced each way before the timed seeds, to load the kernels.
WARM_UP = 64
#: Bootstrap draws of the seeds for the efficiency's band.
BOOTSTRAP = 200


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--eye", default="worker", help="eye class (default: %(default)s)")
    parser.add_argument("--scene", default="meadow", help="a folder of scenes/ (default: %(default)s)")
    parser.add_argument("--spp", type=int, default=256, help="samples per receptor (default: %(default)s)")
    parser.add_argument("--depth", type=int, default=3, help="scattering events per path (default: %(default)s)")
    parser.add_argument("--threads", type=int, default=2, help="threads (default: %(default)s)")
    parser.add_argument("--seeds", type=int, default=SEEDS,
                        help="independent seeds, at least 2; their spread is the noise (default: %(default)s)")
    parser.add_argument("--precision", type=lambda text: text if text == "auto" else float(text), default=None,
                        help="compare fixed sampling with adaptive sampling to this relative standard error (0.03), "
                             "or to the animal's precision (auto)")
    args = parser.parse_args(argv)
    if args.seeds < 2:
        parser.error("--seeds: at least 2, for a spread")
    config = config_defaults()
    receptors = ROOT / "results" / "eyes" / args.eye / "receptors.csv"
    if not receptors.exists():
        subprocess.run([sys.executable, "-m", "beeoptics.cli", "build-eye",
                        str(ROOT / "eyes" / args.eye / "eye.yaml"), "-o", str(receptors.parent), "--quiet"], check=True)
    folder = ROOT / "scenes" / args.scene
    if (folder / MEADOW_FILE).exists() and not (folder / MEADOW_MESH).exists():
        subprocess.run([sys.executable, "-m", "beeoptics.cli", "meadow", str(folder / MEADOW_FILE), "-o",
                        str(folder / MEADOW_MESH)], check=True, stdout=subprocess.DEVNULL)
    scene = beeoptics.load_scene(folder / "scene.yaml", **config["spectral"])
    receptor_set = receptor_set_of(ROOT / "eyes" / args.eye / "eye.yaml")
    eye = beeoptics.load_eye(receptors, receptor_set=receptor_set)
    result = {"eye": args.eye, "scene": args.scene, "spp": args.spp, "depth": args.depth, "threads": args.threads,
              "seeds": args.seeds, "receptors": len(eye.table.id)}
    if args.precision is not None:
        _warm_up(eye, scene, args)
        record("noise_precision", {**result, **precision_comparison(args, config, eye, scene)})
        return

    def traced(lit_by, *samplings):
        """Per way of sampling the sky, each seed's catches (seeds, receptors, classes) and trace seconds (wall,
        then CPU). The ways take turns seed by seed, the first of each turn alternating, so that a change in the
        load of the machine, which others share, falls on each alike (traced one after the other, the default
        measured 1.2 times escape's CPU seconds in the meadow where in turns it measured 1.08)."""
        catches, seconds = {s: [] for s in samplings}, {s: [] for s in samplings}
        for seed in range(1, args.seeds + 1):
            for sampling in samplings[::(-1) ** seed]:
                view = beeoptics.look(eye, lit_by, samples=args.spp, depth=args.depth, seed=seed,
                                      trace={"sky_sampling": sampling}, threads=args.threads)
                catches[sampling].append(beeoptics.catches(view.radiance, scene.wavelengths_nm, receptor_set))
                seconds[sampling].append((view.counts["seconds"], view.counts["cpu_seconds"]))
        return {s: (np.array(catches[s]), np.array(seconds[s])) for s in samplings}

    def spread(q):
        """The seeds' mean (receptors, ...) and each receptor's standard error of one run (n − 1)."""
        return q.mean(axis=0), q.std(axis=0, ddof=1)

    g = receptor_set.achromatic
    _warm_up(eye, scene, args)
    both = traced(scene, "nee", "escape")
    runs = {}
    for name, sampling in (("default", "nee"), ("escape", "escape")):
        q, seconds = runs[name] = both[sampling]
        mean, se = spread(q)
        lit = (mean > 0).all(axis=1)
        rel = se[lit] / mean[lit]
        if name == "default":
            whole, noisy = mean[:, g], np.flatnonzero(lit)[rel[:, g] >= np.percentile(rel[:, g], 90)]
        per_class = {c: {f"p{p}_rel_se": float(np.percentile(rel[:, k], p)) for p in (50, 90, 99)}
                     for k, c in enumerate(receptor_set.classes)}
        result[name] = {**per_class[receptor_set.classes[g]], "trace_s": float(np.mean(seconds[:, 0])),
                        "trace_cpu_s": float(np.mean(seconds[:, 1])), "classes": per_class}
        noise = ", ".join(f"{c} p50 {v['p50_rel_se']:.4f}, p90 {v['p90_rel_se']:.4f}, p99 {v['p99_rel_se']:.4f}"
                          for c, v in per_class.items())
        print(f"{name}: {noise}; trace {np.mean(seconds[:, 0]):.1f} s ({np.mean(seconds[:, 1]):.1f} s CPU)",
              flush=True)
    sources = {}
    for light, alone in (("sun", {"sky": "none"}), ("sky", {"sun": False})) if _two_lights(scene) else ():
        mean, se = spread(traced(scene.with_light(**alone), "nee")["nee"][0][:, :, g])
        sources[light] = (mean[noisy], se[noisy])
    if sources:
        result["noise_sources"] = {"receptors": len(noisy),
                                   "sun_share": float(np.median(sources["sun"][0] / whole[noisy])),
                                   "sun_rel_se": float(np.median(sources["sun"][1] / whole[noisy])),
                                   "sky_rel_se": float(np.median(sources["sky"][1] / whole[noisy]))}
        print("noisiest tenth: the sun {sun_share:.0%} of the catch, its noise {sun_rel_se:.2%} and the sky's "
              "{sky_rel_se:.2%} of the catch".format(**result["noise_sources"]), flush=True)
    result.update(_efficiencies(runs, g))
    record("noise", result)


def precision_comparison(args, config, eye, scene):
    """Fixed sampling at ``--spp`` and a quarter of it, and adaptive sampling to ``--precision``, over the seeds.

    For each setting, per class: the 50th, 90th and 99th percentiles over
    the receptors that caught light of the relative standard error of one
    run's catch, both from the runs' own replicates (``own_``: the root mean
    square over the seeds of each run's standard error, over the seeds' mean
    catch) and from the spread over the seeds (``seeds_``); they should agree
    at the median. A run's own variance is unbiased for its estimate, and an
    adaptive run's samples differ from seed to seed, so one run's variance is
    the mean over the seeds of theirs: the root mean square has 8 × 7
    degrees of freedom where the seeds' spread has 7, which at the 99th
    percentile over receptors alike reads the error 1.6 times too high (and
    the median of the runs' own errors would miss the seeds whose pilot
    missed a receptor's rare bright blades). Then ``trace_s`` and
    ``trace_cpu_s`` (the seeds' mean wall and CPU seconds, the pilot's
    included; other processes sharing the machine change the CPU seconds
    less) and ``samples`` (the mean samples a receptor, the pilot's
    included). ``time_to_p99_ratio`` (and ``_cpu``): fitting the own G p99
    of the two fixed runs to c·N^−a, the trace time fixed sampling needs to
    bring its p99 to adaptive's (time taken as proportional to N), over
    adaptive's time. ``jnd``, where the receptor set gives its noise: the
    50th, 90th and 99th percentiles over the receptors of the error, in
    just-noticeable differences, that a run's catches put into a chromatic
    and an achromatic receptor-noise-limited distance (the root mean square
    over the seeds, as above), which ``--precision auto`` holds to a quarter.
    """
    receptor_set = eye.receptor_set
    g = receptor_set.classes[receptor_set.achromatic]
    settings = {f"fixed_{args.spp // 4}": (args.spp // 4, None), f"fixed_{args.spp}": (args.spp, None),
                f"adaptive_{args.precision}": (args.spp, args.precision)}
    # The errors in just-noticeable differences of the receptor-noise-limited distances, where the set gives
    # its noise: a form F of noise_forms measures tr(F C) = (error / NOISE_FRACTION of a JND)².
    forms = noise_forms(receptor_set)
    forms = None if forms is None else forms * NOISE_FRACTION ** 2
    out = {}
    for name, (samples, precision) in settings.items():
        catches, own, seconds, taken, jnd = [], [], [], [], []
        for seed in range(1, args.seeds + 1):
            view = beeoptics.look(eye, scene, samples=samples, depth=args.depth, seed=seed, precision=precision,
                                  threads=args.threads)
            catches.append(view.replicate_catches.mean(axis=1))
            own.append(standard_error(view.replicate_catches))
            if forms is not None:
                jnd.append(form_errors(view.replicate_catches, view.replicate_catches.mean(axis=1), forms))
            seconds.append((view.counts["seconds"], view.counts["cpu_seconds"]))
            # The pilot's samples are not among an adaptive estimate's.
            taken.append(view.samples.mean() + (0 if precision is None else
                                                config["trace"]["precision"]["min_samples"]))
        catches, own, seconds = np.array(catches), np.array(own), np.array(seconds)
        mean = catches.mean(axis=0)
        lit = (mean > 0).all(axis=1)
        rel_seeds = catches.std(axis=0, ddof=1)[lit] / mean[lit]
        rel_own = np.sqrt((own[:, lit] ** 2).mean(axis=0)) / mean[lit]
        out[name] = {"trace_s": float(np.mean(seconds[:, 0])), "trace_cpu_s": float(np.mean(seconds[:, 1])),
                     "samples": float(np.mean(taken)), "classes": {
            c: {f"{how}_p{p}": float(np.nanpercentile(rel[:, k], p)) for how, rel in (("own", rel_own),
                                                                                  ("seeds", rel_seeds))
                for p in (50, 90, 99)} for k, c in enumerate(receptor_set.classes)}}
        if forms is not None:
            # Each run's own error, as for the catches: the root mean square over the seeds.
            error = np.sqrt(np.mean(jnd, axis=0))[lit]
            out[name]["jnd"] = {f"{kind}_p{p}": float(np.nanpercentile(error[:, f], p))
                                for f, kind in enumerate(("chromatic", "achromatic")[:len(forms)]) for p in (50, 90, 99)}
        print(f"{name}: {out[name]['samples']:.0f} samples a receptor, trace {out[name]['trace_s']:.1f} s "
              f"({out[name]['trace_cpu_s']:.1f} s CPU); " +
              "".join(f"{k} {v:.3f} JND; " for k, v in out[name].get("jnd", {}).items()) +
              "; ".join(f"{c} " + ", ".join(f"{k} {v:.4f}" for k, v in d.items())
                        for c, d in out[name]["classes"].items()), flush=True)
    low, high, adaptive = settings
    p99 = {k: out[k]["classes"][g]["own_p99"] for k in settings}
    a = np.log(p99[low] / p99[high]) / np.log(4.0)
    needed = args.spp * (p99[high] / p99[adaptive]) ** (1.0 / a)
    out["fixed_exponent"] = float(a)
    for key, seconds in (("time_to_p99_ratio", "trace_s"), ("time_to_p99_ratio_cpu", "trace_cpu_s")):
        out[key] = float(out[high][seconds] * needed / args.spp / out[adaptive][seconds])
    print(f"fixed sampling's G p99 falls as N^-{a:.2f}: it would need {needed:.0f} samples a receptor for "
          f"adaptive's p99, {out['time_to_p99_ratio']:.1f} times adaptive's time "
          f"({out['time_to_p99_ratio_cpu']:.1f} in CPU seconds)", flush=True)
    return out


def _warm_up(eye, scene, args):
    """Trace a few receptors each way once, untimed, so that neither estimator's first seed pays for loading
    the compiled kernels (the estimator timed first would): the first share of about :data:`WARM_UP`."""
    for sampling in ("nee", "escape"):
        beeoptics.look(eye, scene, samples=args.spp, depth=args.depth, seed=0, trace={"sky_sampling": sampling},
                       threads=args.threads, parts=max(1, len(eye.table.id) // WARM_UP))


def _efficiency(q_default, t_default, q_escape, t_escape, g):
    """(p90² · seconds) of escape over that of the default, from the seeds' catches (seeds, receptors, classes)
    and their seconds: the p90 over the receptors of each one's relative standard error of the catch of class
    ``g``, over the receptors that caught light."""
    p90 = []
    for q in (q_default, q_escape):
        mean, se = q.mean(axis=0), q.std(axis=0, ddof=1)
        lit = (mean > 0).all(axis=1)
        p90.append(np.percentile(se[lit, g] / mean[lit, g], 90))
    return p90[1] ** 2 * np.mean(t_escape) / (p90[0] ** 2 * np.mean(t_default))


def _efficiencies(runs, g):
    """``efficiency_vs_escape`` from the wall seconds and from the CPU seconds (which other processes on the
    machine change less), each with the 16th and 84th percentiles of its bootstrap over the seeds (the same
    seeds drawn for both estimators, which share them): its own noise, a ±1σ band."""
    (q_d, t_d), (q_e, t_e) = runs["default"], runs["escape"]
    rng = np.random.default_rng(0)
    out = {}
    for key, column in (("efficiency_vs_escape", 0), ("efficiency_vs_escape_cpu", 1)):
        out[key] = float(_efficiency(q_d, t_d[:, column], q_e, t_e[:, column], g))
        draws = [_efficiency(q_d[k], t_d[k, column], q_e[k], t_e[k, column], g)
                 for k in rng.integers(0, len(q_d), (BOOTSTRAP, len(q_d)))]
        out[f"{key}_band"] = [float(v) for v in np.percentile(draws, [16, 84])]
    return out


def _two_lights(scene):
    """Whether ``scene`` is lit by both a sky and a sun, whose shares of the noise can be told apart (a scene
    under a sky alone, as ``uniform``, has one light and one share)."""
    return scene.scene.sky is not None and scene.scene.sun is not None


if __name__ == "__main__":
    main()
