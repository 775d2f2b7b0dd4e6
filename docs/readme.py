"""Write the README's passages that come from a run's files, from those files.

Each such passage lies between ``<!-- from the run: NAME -->`` and ``<!-- end NAME -->`` in the
README, and :data:`PASSAGES` says which files make it: the worker's eye against Collins's and the
published values (``worker_eye``), every shipped eye (``eyes``, after ``snakemake comparison``),
the compass and pond captions (``compass``, ``pond``, after ``snakemake pond``), the default
workflow's jobs and time (``workflow``, from Snakemake's log of the run), and the benchmarks'
tables (``daylight``, ``noise``, ``speed``, ``coating``, ``layered``, from the lines each benchmark keeps in
``results/benchmarks/<name>.jsonl``: benchmarks/record.py). A
passage whose files are not in the results folder is left as it is, and said so. Run after
``make workflow`` (and ``snakemake comparison``, and the benchmarks)::

    .venv/bin/python docs/readme.py            # rewrite README.md
    .venv/bin/python docs/readme.py --check    # exit 1 if README.md is not what the run gives
"""

import argparse
import json
import math
import re
import sys
from datetime import datetime
from pathlib import Path

import numpy as np
import yaml

from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import read_table

ROOT = Path(__file__).resolve().parents[1]
# The benchmarks' kept runs, read as benchmarks/record.py keeps them.
sys.path.insert(0, str(ROOT / "benchmarks"))
from record import commit, kept  # noqa: E402


def _quality(results, eye):
    return json.loads((results / "eyes" / eye / "quality.json").read_text())


def _delta_rho(results, eye):
    """The eye's receptors' Δρ, degrees, from its receptors.csv."""
    return read_receptors(results / "eyes" / eye / "receptors.csv").delta_rho_deg


def _commit(results):
    """The commit of the checkout whose run made ``results`` (the folder beside its ``results``): its commit now, so
    write the passages before that checkout moves on."""
    return commit(results.parent) or "this checkout"


def worker_eye(results, eyes_dir):
    """The worker's right eye: Collins's (as this code builds it from his mesh), ours and the published values, from
    both eyes' quality.json."""
    now, before = _quality(results, "worker"), _quality(results, "worker_collins")

    def outline(q):
        return f"{q['size']['eye_length_mm']:.2f} × {q['size']['eye_width_mm']:.2f} mm"

    def area(q):
        size = q["size"]
        return f"{size['corneal_area_mm2']:.2f} mm² = {q['facets_per_eye']:,} × {size['mean_facet_area_um2']:.0f} µm²"

    def covered(q):
        c = q["field"]["coverage"]
        return f"{100 * c['covered']:.0f} % ({100 * c['outside']:.2f} % of ours beyond it)"

    def vertical(q, who="ours"):
        v = q["field"]["anisotropy"]["delta_phi_v_deg"]
        return f"{v['equator'][who]:.2f}° → {v['elevation_45_75'][who]:.2f}°"

    def ratios(q):
        a = q["field"]["anisotropy"]
        h, v = a["delta_phi_h_deg"], a["delta_phi_v_deg"]
        return f"{h['median_ratio']:.2f} ({h['correlation']:.2f}) / {v['median_ratio']:.2f} ({v['correlation']:.2f})"

    def ratio(q, who="ours"):
        return f"{q['field']['anisotropy']['horizontal_over_vertical'][who]:.2f}"

    def rows(q):
        a = q["field"]["anisotropy"]
        along = "horizontal" if a["lines"] == "rows" else "vertical"
        return f"{a['lines']} {abs(a['lines_off_deg']):.1f}° from {along}"

    def delta_rho(eye):
        values = _delta_rho(results, eye)
        low, high = values.min(), values.max()
        return f"{low:.2f}° everywhere" if math.isclose(low, high) else f"{low:.2f}–{high:.2f}°"

    def rim(q):
        r = q.get("dorsal_rim")
        return f"{r['facets']} facets, looking up at {r['elevation_deg'][0]:.0f}–{r['elevation_deg'][2]:.0f}°" \
            if r else "–"

    table = [
        ("facets per eye", lambda q: f"{q['facets_per_eye']:,}", "5,432 (Seidl & Kaiser 1981)"),
        ("eye outline, length × width (projected)", outline,
         "2.64 mm long (Ribi et al. 1989); vertical about twice horizontal (Jander & Jander 2002)"),
        ("corneal area = facets × mean facet area", area, "not found"),
        ("share of the measured field covered (Stürzl et al. 2010 border)", covered, "100 %"),
        ("vertical Δφ, equator → \\|elevation\\| 45–75°", vertical,
         f"{vertical(now, 'model')} (Seidl 1982 as Stürzl et al. model it, at our axes)"),
        ("median ratio of our Δφ to the model's, horizontal / vertical (correlation)", ratios, "1"),
        ("ratio of horizontal to vertical Δφ", ratio, f"{ratio(now, 'model')} (at our axes)"),
        ("lattice orientation", rows, "vertical columns of ommatidia"),
        ("facet diameter, maximum", lambda q: f"{q['size']['facet_diameter_max_um']:.1f} µm",
         "about 20 µm (Greiner et al. 2004; Somanathan et al. 2009)"),
        ("acceptance angle Δρ", None,
         "1.9° fronto-ventrally (Rigosi et al. 2017), 2.57° centrally (Eheim & Wehner 1972)"),
        ("dorsal rim area", rim, "at least 60 ommatidia, skyward (Schinz 1975)"),
    ]
    lines = [f"| worker, right eye (`quality.json` of {_commit(results)}'s run) | Collins's eye (`worker_collins`) | ours "
             "(`worker`) | published |",
             "|---|---|---|---|"]
    for label, value, published in table:
        cells = (delta_rho("worker_collins"), delta_rho("worker")) if value is None else (value(before), value(now))
        lines.append(f"| {label} | {cells[0]} | {cells[1]} | {published} |")
    return "\n".join(lines)


def eyes(results, eyes_dir):
    """Every compared eye's facets, corneal area, Δφ, Δρ and fields, the published values in brackets where they
    differ."""
    names = read_table(results / "comparison" / "acuity.csv")["eye"].tolist()
    lines = ["| eye | facets an eye (published) | corneal area, mm² (published) | Δφ median, ° | Δρ median, ° "
             "| one eye's field, sr (published) | binocular, sr |", "|---|---|---|---|---|---|---|"]
    for name in names:
        q = _quality(results, name)
        described = yaml.safe_load((eyes_dir / name / "eye.yaml").read_text())
        # A micro-CT cornea's field is its normals' (README, "Other species").
        field = q["fields"]["normals" if "cornea" in described else "axes"]
        published = q.get("published", {})

        def given(key, value, scale=1.0):
            """The value, and in brackets the published one where it differs."""
            spec = published.get(key)
            ours = f"{value:.2f}"
            return f"{ours} ({spec['value'] * scale:.1f})" if spec and f"{spec['value'] * scale:.2f}" != ours else ours

        facets = f"{q['facets_per_eye']:,}"
        if q.get("facets_published") and q["facets_published"] != q["facets_per_eye"]:
            facets += f" ({q['facets_published']:,})"
        area = q["size"]["corneal_area_mm2"]
        lines.append(" | ".join([
            f"| {name}", facets, given("corneal_area_mm2", area),
            f"{q['optics']['delta_phi_deg']['p50']:.2f}", f"{np.median(_delta_rho(results, name)):.2f}",
            given("field_fraction", field["right_sr"], 4 * math.pi),
            f"{field['binocular_sr']:.2f} |"]))
    return "\n".join(lines)


def compass(results, eyes_dir):
    """The compass figure's caption, from the meadow's compass.json."""
    s = json.loads((results / "worker" / "meadow" / "polarisation" / "compass.json").read_text())
    low = min((k for k in s if k.startswith("clear sky, in the scene at")),
              key=lambda k: float(re.search(r"at ([\d.]+) cm", k).group(1)))
    cm = re.search(r"at ([\d.]+) cm", low).group(1)

    def errs(key):
        return f"{s[key]['median_abs_error_deg']:.2f}° (median, {s[key]['max_abs_error_deg']:.2f}° at most)"

    return (f"*`results/worker/meadow/polarisation/compass.png`: the compass's estimate of the solar azimuth over a "
            f"full\nturn, from {_commit(results)}'s default run. Under Rayleigh's sky it errs by {errs('Rayleigh sky, open')}"
            f";\nunder the clear sky, whose neutral points Rayleigh's map lacks, by {errs('clear sky, open')}; "
            f"lowered to\n{cm} cm among the grass, where the plants hide {100 * s[low]['sky_hidden']:.0f} % of the "
            f"dorsal rim's view, by\n{errs(low)}. Turbidity only scales the sky's degree here, which a read-out free "
            "of\nreceptor noise does not feel.*")


def _span(values, digits):
    """Values as a range, "low–high", or one value where they agree to ``digits``."""
    low, high = f"{min(values):,.{digits}f}", f"{max(values):,.{digits}f}"
    return low if low == high else f"{low}–{high}"


def daylight(results, eyes_dir):
    """The clear-sky daylight against measured daylight, from benchmarks/daylight.py's last run."""
    run = kept(results, "daylight")[-1]
    lines = [f"| sun | UV/VIS photons, model | Granada (records) | UV/G catch, model | Granada | from 360 nm: UV/G, "
             f"model | Spitschan (records) |", "|---|---|---|---|---|---|---|"]

    def measured(m, key):
        low, median, high = m[key]
        return f"{median:.3f} [{low:.3f}–{high:.3f}]"

    for elevation, sun in run["suns"].items():
        g, s = sun["granada"], sun["spitschan"]
        late = (f"{s['model_uv_g']:.3f} | {measured(s, 'uv_g')} ({s['n']})" if s["n"] else
                f"{s['model_uv_g']:.3f} | none within 5° of the sun")
        lines.append(f"| {elevation}° | {g['model_uv_vis']:.3f} | {measured(g, 'uv_vis')} ({g['n']}) | "
                     f"{g['model_uv_g']:.3f} | {measured(g, 'uv_g')} | {late} |")
    return f"*`benchmarks/daylight.py` at {run['commit']}:*\n\n" + "\n".join(lines)


def noise(results, eyes_dir):
    """The noise of each way of sampling the sky, from benchmarks/noise.py's last run in each scene."""
    runs = {r["scene"]: r for r in kept(results, "noise")}
    lines = ["| scene | estimator | G p50 | G p90 | G p99 | trace, s | efficiency (escape's p90² · time over the "
             "default's) |", "|---|---|---|---|---|---|---|"]
    for scene, run in runs.items():
        for name, label in (("default", "nee (default)"), ("escape", "escape")):
            e = run[name]
            ratio = _efficiency(run) if name == "default" else ""
            lines.append(f"| {scene} | {label} | {100 * e['p50_rel_se']:.2f} % | {100 * e['p90_rel_se']:.2f} % | "
                         f"{100 * e['p99_rel_se']:.2f} % | {e['trace_s']:.1f} | {ratio} |")
    sources = [f"{scene}: the sun {100 * r['noise_sources']['sun_share']:.0f} % of the catch, its noise "
               f"{100 * r['noise_sources']['sun_rel_se']:.1f} % of it and the sky's {100 * r['noise_sources']['sky_rel_se']:.1f} %"
               for scene, r in runs.items() if "noise_sources" in r]
    commits = ", ".join(sorted({r["commit"] for r in runs.values()}))
    first = next(iter(runs.values()))
    return (f"*`benchmarks/noise.py` at {commits}: the worker pair, {first['spp']} samples, depth {first['depth']}, "
            f"{first['seeds']} seeds; each receptor's relative standard error of one run's catch, percentiles over "
            "the receptors; an efficiency's band the 16th–84th percentiles of a bootstrap over the seeds, and its "
            "CPU figure from the CPU seconds, which other processes change less.*\n\n" + "\n".join(lines)
            + ("\n\nWhat makes the noisiest tenth's noise (the same receptors lit by the sun alone and by the sky "
               "alone): " + "; ".join(sources) + "." if sources else ""))


def _efficiency(run):
    """A noise run's efficiency against escape, and from its CPU seconds, each with its band where the run has it."""
    parts = []
    for key, label in (("efficiency_vs_escape", ""), ("efficiency_vs_escape_cpu", "CPU ")):
        if key in run:
            band = f" ({run[key + '_band'][0]:.2f}–{run[key + '_band'][1]:.2f})" if key + "_band" in run else ""
            parts.append(f"{label}{run[key]:.2f}{band}")
    return "; ".join(parts)


def speed(results, eyes_dir):
    """The tracer's speed, from benchmarks/trace.py's last three runs of each setting."""
    groups = {}
    for r in kept(results, "trace"):
        groups.setdefault((r["eye"], r["spp"], r["depth"], r["scene"], r["threads"]), []).append(r)
    lines = ["| eye pair, samples, depth | scene | threads | trace, s | whole stage, s | Embree share (CPU, one "
             "thread) | bare Embree, M rays/s | peak, MB |", "|---|---|---|---|---|---|---|---|"]
    commits = set()
    for (eye, spp, depth, scene, threads), runs in groups.items():
        runs = runs[-3:]
        commits |= {r["commit"] for r in runs}
        triangles = runs[-1]["scene_triangles"]
        cpu = [r["embree_cpu_share"] for r in runs if r.get("embree_cpu_share") is not None]
        share = _span([r["embree_fraction"] for r in runs], 2) + (f" ({_span(cpu, 2)})" if cpu else "")
        lines.append(f"| {eye}, {spp:,}, {depth} | {Path(scene).parent.name if scene.endswith('.yaml') else scene} "
                     f"({triangles:,} triangles) | {threads} | {_span([r['trace_s'] for r in runs], 1)} | "
                     f"{_span([r['wall_s'] for r in runs], 1)} | {share} | "
                     f"{_span([r['bare_rays_per_s'] / 1e6 for r in runs], 2)} | "
                     f"{_span([r['peak_memory_mb'] for r in runs], 0)} |")
    return (f"*`benchmarks/trace.py` at {', '.join(sorted(commits))}, the last three runs of each setting:*\n\n"
            + "\n".join(lines))


def workflow(results, eyes_dir):
    """The default workflow's jobs and time, from Snakemake's log of the newest run of the default target (its
    rule ``all``) that did every job it planned."""
    logs = sorted((results.parent / ".snakemake" / "log").glob("*.snakemake.log"))
    finished = [p for p in logs if re.search(r"(\d+) of \1 steps \(100%\) done", p.read_text())
                and re.search(r"^localrule all:$", p.read_text(), re.M)]
    text = finished[-1].read_text()
    stamps = [datetime.strptime(t, "%a %b %d %H:%M:%S %Y") for t in re.findall(r"^\[(\w{3} \w{3} +\d+ [\d:]+ \d{4})\]",
                                                                             text, re.M)]
    jobs = int(re.findall(r"(\d+) of \1 steps \(100%\) done", text)[-1])
    minutes, seconds = divmod(round((stamps[-1] - stamps[0]).total_seconds()), 60)
    return (f"In {_commit(results)}'s run of {stamps[0]:%Y-%m-%d}, after set-up: {jobs} jobs in {minutes} min {seconds:02d} s "
            f"(Snakemake's log, {finished[-1].name}).")


def coating(results, eyes_dir):
    """What the grass's coating changes, from benchmarks/coating.py's last run: over the receptors looking below the
    horizon, where the grass is, and over all."""
    run = kept(results, "coating")[-1]
    lines = [f"| receptor class | receptors | catch change, median / 90th percentile | between two seeds (noise) | "
             f"degree of polarisation change, median / 90th percentile | between two seeds | median degree, "
             f"Lambertian → coated |", "|---|---|---|---|---|---|---|"]
    for c, v in run.items():
        if isinstance(v, dict):
            for label, w in ((f"below the horizon ({run['below']:,})", v), ("all", v["all"])):
                lines.append(f"| {c} | {label} | {100 * w['catch_median']:.1f} % / {100 * w['catch_p90']:.1f} % | "
                             f"{100 * w['noise_catch_median']:.1f} % / {100 * w['noise_catch_p90']:.1f} % | "
                             f"{w['degree_median']:.3f} / {w['degree_p90']:.3f} | {w['noise_degree_median']:.3f} / "
                             f"{w['noise_degree_p90']:.3f} | {w['degree_lambertian']:.3f} → {w['degree_coated']:.3f} |")
    return (f"*`benchmarks/coating.py` at {run['commit']}: the worker in the meadow, {run['samples']} samples, depth "
            f"{run['depth']}, its grass Lambertian and coated:*\n\n" + "\n".join(lines))


def layered(results, eyes_dir):
    """The coating's base coupling, and Mitsuba's, against the layered model's random walk, from benchmarks/layered.py's
    last run: per roughness, each model's relative error, median and largest over angles and albedos."""
    run = kept(results, "layered")[-1]

    def cell(v):
        return f"{100 * v['median']:+.1f} % ({100 * v['largest']:+.0f} %)"

    lines = ["| α | Kelemen, ρ (before) | roughplastic, nonlinear | roughplastic, linear (its default) | the coating, ρ' "
             "(now) | dependence on ρ: Kelemen | dependence on ρ: the coating | the walk's white base at 0°, η "
             + " / ".join(f"{eta:g}" for eta in run["etas"]) + " |", "|---|---|---|---|---|---|---|---|"]
    for alpha, v in run["by_alpha"].items():
        white = " / ".join(f"{run['white'][f'{alpha} {eta}']:.2f}" for eta in run["etas"])
        lines.append(f"| {alpha} | {cell(v['kelemen']['error'])} | {cell(v['roughplastic']['error'])} | "
                     f"{cell(v['roughplastic_linear']['error'])} | {cell(v['coating']['error'])} | "
                     f"{cell(v['kelemen']['albedo'])} | {cell(v['coating']['albedo'])} | {white} |")
    return (f"*`benchmarks/layered.py` at {run['commit']}: the base's light against the random walk's ({run['paths']} "
            f"paths a setting, its own error at most {100 * run['walk_error']:.1f} %), median (largest) over "
            f"incidence and view {run['angles_deg'][0]:g}–{run['angles_deg'][-1]:g}°, base albedos "
            + ", ".join(f"{r:g}" for r in run["albedos"]) + " and η " + " and ".join(f"{e:g}" for e in run["etas"])
            + ":*\n\n" + "\n".join(lines))


def pond(results, eyes_dir):
    """The pond figure's caption, from the worker's polarisation at the pond."""
    table = read_table(results / "worker" / "pond" / "polarisation" / "polarisation.csv", numeric=["id"],
                       text=["side"])
    axes = read_receptors(results / "eyes" / "worker" / "receptors.csv")
    by_id = {i: k for k, i in enumerate(axes.id)}
    axis = axes.axis[[by_id[i] for i in table["id"]]]
    elevation = np.degrees(np.arcsin(axis[:, 2]))
    ahead = np.degrees(np.arccos(np.clip(axis[:, 0] / np.hypot(axis[:, 0], axis[:, 1]), -1, 1))) <= 30.0
    degree, angle = table["UV_degree"], table["UV_angle_deg"]

    def looking(low, high):
        return ahead & (elevation >= low) & (elevation < high)

    at_brewster = looking(-45.0, -25.0)
    p10, p50, p90 = np.percentile(degree[at_brewster], [10, 50, 90])
    return (f"*`results/worker/pond/polarisation/field.png` ({_commit(results)}'s run): the water ahead and below is "
            f"polarised with the\ne-vector horizontal (hue: {np.median(angle[at_brewster]):.0f}°, the head's "
            f"anterior direction 90°), most strongly 25–45° below the\nhorizon, where the water is seen at 45–65° "
            f"incidence around Brewster's 53°: median degree {p50:.2f}\n(10th–90th percentile {p10:.2f}–{p90:.2f}) "
            f"over the {int(at_brewster.sum())} receptors looking there within 30° of ahead;\n"
            f"{np.median(degree[looking(-70.0, -50.0)]):.2f} looking 50–70° down, "
            f"{np.median(degree[looking(-10.0, 0.0)]):.2f} within 10° below the horizon. This is the reflection aquatic "
            "insects\nfind water by (Schwind 1991; Horváth & Varjú 2004).*")


#: Passage name → (what writes it, the files it reads, relative to the results folder or the repository).
PASSAGES = {
    "worker_eye": (worker_eye, ["eyes/worker/quality.json", "eyes/worker_collins/quality.json"]),
    "eyes": (eyes, ["comparison/acuity.csv"]),
    "compass": (compass, ["worker/meadow/polarisation/compass.json"]),
    "workflow": (workflow, ["../.snakemake/log"]),
    "daylight": (daylight, ["benchmarks/daylight.jsonl"]),
    "noise": (noise, ["benchmarks/noise.jsonl"]),
    "speed": (speed, ["benchmarks/trace.jsonl"]),
    "coating": (coating, ["benchmarks/coating.jsonl"]),
    "layered": (layered, ["benchmarks/layered.jsonl"]),
    "pond": (pond, ["worker/pond/polarisation/polarisation.csv"]),
}
BLOCK = re.compile(r"(<!-- from the run: (\w+) -->\n)(.*?)(\n<!-- end \2 -->)", re.S)


def rewrite(text, results, eyes_dir=ROOT / "eyes", log=print):
    """``text`` with every passage the results folder has the files for written afresh (the eyes' descriptions
    in ``eyes_dir``)."""
    def passage(m):
        name = m.group(2)
        write, needs = PASSAGES[name]
        missing = [n for n in needs if not (results / n).exists()]
        if missing:
            log(f"{name}: left as it is ({results / missing[0]} is missing)")
            return m.group(0)
        return m.group(1) + write(results, eyes_dir) + m.group(4)
    return BLOCK.sub(passage, text)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--results", type=Path, default=ROOT / "results", help="the run's results folder")
    parser.add_argument("--eyes", type=Path, default=ROOT / "eyes", help="the run's eyes folder")
    parser.add_argument("--readme", type=Path, default=ROOT / "README.md")
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if the README differs")
    args = parser.parse_args(argv)
    text = args.readme.read_text()
    new = rewrite(text, args.results, args.eyes, log=lambda line: print(line, file=sys.stderr))
    if args.check:
        return int(new != text)
    args.readme.write_text(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
