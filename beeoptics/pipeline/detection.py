"""The detection stages: approach a meadow's flowers with each eye and find from how far it detects them.

For each flower of a sample of a generated meadow's flowers (the table the
meadow stage writes beside its mesh, :func:`beeoptics.world.meadow.flower_table`)
the bee approaches from several directions along a line descending
towards it, facing along it, as the approach flight does
(:func:`beeoptics.world.flight.approach`), and stops at a series of
distances. At each it traces only the receptors round the flower: those
whose axes lie within the flower's angular radius, half their acceptance
angle and the local background's rings of it
(:func:`beeoptics.vision.detection.local_background`), every receptor of
both eyes that could see it or its surround. The trace gives each receptor's
catches and the share of its acceptance the flower fills, and
:func:`beeoptics.vision.detection.detect` the verdicts. An approach's
detection distance is the farthest of its distances at which a criterion
holds, approaching from the farthest.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically.
"""

import numpy as np

from beeoptics.api import catches as catches_of, load_eye, load_scene, look_cones
from beeoptics.headframe import head_rotation
from beeoptics.io.table import read_table, write_table
from beeoptics.io.errors import InputError
from beeoptics.light.sampler import STREAMS
from beeoptics.pipeline.logs import log
from beeoptics.vision.detection import COLUMNS, RING_DELTA_PHI, detect, local_background
from beeoptics.vision.receptorset import DEFAULT_CURVES, lacking, ommatidium_types, receptor_set_of
from beeoptics.world.meadow import FLOWER_COLUMNS

#: The criteria whose first distances an approach reports: a verdict column, and the receptor-level
#: measure's (at least one receptor's own contrast at the criterion's threshold).
FIRST = {"achromatic_m": "achromatic_detectable", "chromatic_m": "chromatic_detectable",
         "receptor_green_m": "receptors_green_above_threshold", "receptor_colour_m": "receptors_colour_above_threshold"}
#: The verdicts whose first distance comes with an interval, and the flag that noise could flip each: the
#: first distance lies between the first at which the verdict holds and noise could not flip it (near) and
#: the first at which it holds or noise could make it (far).
FLAGS = {"achromatic_m": "achromatic_uncertain", "chromatic_m": "chromatic_uncertain"}


def sample_flowers(flowers, per_species, seed):
    """Row indices of up to ``per_species`` flowers of each species, drawn at random from ``seed``, in order."""
    rng = np.random.default_rng(seed)
    species = np.asarray(flowers["species"]).astype(str)
    chosen = [rng.choice(np.flatnonzero(species == s), min(per_species, int((species == s).sum())), replace=False)
              for s in sorted(set(species))]
    return np.sort(np.concatenate(chosen)) if chosen else np.zeros(0, int)


def approach_poses(centre, azimuth_deg, descent_deg, distances_m):
    """Where the head is, and how it is turned, on an approach: positions (k, 3) and rotations (k, 3, 3).

    The head comes towards ``centre`` from ``azimuth_deg`` (world, from +x
    towards +y: where it comes from, seen from the flower) along a line
    descending at ``descent_deg``, facing along it.
    """
    a, d = np.radians(azimuth_deg), np.radians(descent_deg)
    towards = np.array([-np.cos(a) * np.cos(d), -np.sin(a) * np.cos(d), -np.sin(d)])
    positions = np.asarray(centre, float) - np.asarray(distances_m, float)[:, None] * towards
    rotation = head_rotation(np.degrees(np.arctan2(towards[1], towards[0])), -descent_deg)
    return positions, np.broadcast_to(rotation, (len(positions), 3, 3))


def survey(receptors_csv, eye_file, scene_file, flowers_csv, outputs, *, spectral, trace, threads, survey,
           receptor_curves=DEFAULT_CURVES):
    """Approach a sample of a meadow's flowers with one eye: ``outputs["views"]`` and ``outputs["approaches"]``.

    ``views`` has a row per flower, direction and distance (the flower, its
    ``azimuth_deg``, ``distance_m`` and every column of
    :data:`beeoptics.vision.detection.COLUMNS`); ``approaches`` a row per
    flower and direction, with the first distance at which each criterion
    holds (``first_achromatic_m``, ``first_chromatic_m``, and the
    receptor-level ``first_receptor_green_m``, ``first_receptor_colour_m``;
    empty where it never does), the rule's with their intervals
    (``first_achromatic_near_m``, ``first_achromatic_far_m``, the same for
    chromatic: :data:`FLAGS`).

    Parameters
    ----------
    trace : dict
        A config's ``trace`` section, as the survey traces (:func:`beeoptics.api.look_cones`).
    threads : int
    survey : dict
        The config's ``detection``: ``flowers_per_species``,
        ``directions``, ``descent_deg``, ``distances`` (``farthest_radii``,
        ``nearest_radii``, in the flower's radii, and ``steps``, spaced
        geometrically) and ``seed``.
    """
    scene = load_scene(scene_file, **spectral)
    eye = load_eye(receptors_csv, receptor_set=receptor_set_of(eye_file))
    table = eye.table
    flowers = read_table(flowers_csv, numeric=FLOWER_COLUMNS[1:], text=FLOWER_COLUMNS[:1])
    chosen = sample_flowers(flowers, survey["flowers_per_species"], survey["seed"])
    spacing = survey["distances"]
    steps = np.geomspace(spacing["farthest_radii"], spacing["nearest_radii"], spacing["steps"])
    # Every pose's receptors draw random numbers of their own (detect_views): the survey's poses times the
    # receptors must fit the streams the sampler numbers.
    poses = len(chosen) * survey["directions"] * spacing["steps"]
    if poses * (int(table.id.max()) + 1) > STREAMS:
        raise InputError("config", "detection", f"{poses} poses of {len(chosen)} flowers, {survey['directions']} "
                         f"directions and {spacing['steps']} steps, each of {int(table.id.max()) + 1} receptors, "
                         f"exceed the {STREAMS} random-number streams a run has: fewer flowers, directions or steps")
    turns = np.random.default_rng(survey["seed"]).uniform(0.0, 360.0, len(chosen))
    views, approaches = [], []
    for count, (f, turn) in enumerate(zip(chosen, turns)):
        centre = np.array([flowers[c][f] for c in ("x_m", "y_m", "z_m")])
        radius = float(flowers["radius_m"][f])
        # In the flower's radii: every flower is seen over the same range of angular sizes.
        distances = radius * steps
        about = {"species": flowers["species"][f], "flower": int(f)}
        for k in range(survey["directions"]):
            azimuth = (turn + 360.0 * k / survey["directions"]) % 360.0
            rows = detect_views(eye, scene, centre, radius, *approach_poses(centre, azimuth, survey["descent_deg"],
                                                                            distances),
                                count * survey["directions"] + k, trace=trace, threads=threads,
                                sensitivities=receptor_curves)
            views += [{**about, "azimuth_deg": azimuth, "distance_m": d, **r} for d, r in zip(distances, rows)]
            first = {f"first_{name}": _first(distances, [r[column] >= 1 for r in rows])
                     for name, column in FIRST.items()}
            for name, flag in FLAGS.items():
                holds, unsure = [r[FIRST[name]] >= 1 for r in rows], [r[flag] >= 1 for r in rows]
                base = f"first_{name.removesuffix('_m')}"
                first[f"{base}_near_m"] = _first(distances, [h and not u for h, u in zip(holds, unsure)])
                first[f"{base}_far_m"] = _first(distances, [h or u for h, u in zip(holds, unsure)])
            approaches.append({**about, "x_m": centre[0], "y_m": centre[1], "z_m": centre[2], "radius_m": radius,
                               "azimuth_deg": azimuth, "descent_deg": survey["descent_deg"], **first})
    log.info("%s: %d flowers approached from %d directions, %d distances each", eye_file, len(chosen),
             survey["directions"], len(steps))
    text = ("species",)
    write_table(outputs["views"], {c: [v[c] for v in views] if c in text else np.array([v[c] for v in views], float)
                                   for c in views[0]} if views else {"species": []})
    write_table(outputs["approaches"], {c: [a[c] for a in approaches] if c in text else
                                        np.array([a[c] for a in approaches], float) for c in approaches[0]}
                if approaches else {"species": []})


def _first(distances, holds):
    """The first of ``distances`` (farthest first) at which ``holds``, NaN where it never does."""
    hits = [d for d, h in zip(distances, holds) if h]
    return hits[0] if hits else np.nan


def detect_views(eye, scene, centre, radius, positions, rotations, index=0, *, trace=None, threads=None,
                 sensitivities=DEFAULT_CURVES):
    """Detection of a target (a sphere, ``centre``, ``radius``, m) from each of several head poses:
    a row of :func:`beeoptics.vision.detection.detect` per pose.

    At each pose only the receptors round the target are traced, every
    receptor of both eyes whose axis lies within the target's angular
    radius, half its acceptance angle and the local background's rings of
    it. Each pose draws random numbers of its own (its receptors' ids
    offset by the pose's place among ``index``'s), so that a series of poses
    traces the same in any run that holds it.

    Parameters
    ----------
    eye : beeoptics.api.Eye
    scene : beeoptics.api.Scene
    centre : array_like (3,)
    radius : float
    positions, rotations : ndarray (k, 3), (k, 3, 3)
        The head's poses: position (m) and rotation (columns its axes), world frame.
    trace : dict, optional
        A config's ``trace`` section (:func:`beeoptics.api.look_cones`).
    threads : int, optional
    sensitivities : str
        The receptor curves (``colour.sensitivities``).
    """
    table, receptor_set, wl = eye.table, eye.receptor_set, scene.wavelengths_nm
    types = ommatidium_types(receptor_set, len(table.id))
    absent = (lacking(receptor_set, types) if types is not None else
              np.zeros((len(table.id), len(receptor_set.classes)), bool))
    drho, dphi = table.delta_rho_deg, table.delta_phi_deg
    distances = np.linalg.norm(np.asarray(centre, float) - positions, axis=1)
    picked, origins, axes, streams, toward = [], [], [], [], []
    width = int(table.id.max()) + 1
    for j, (p, r) in enumerate(zip(positions, rotations)):
        o, a = table.position * 1e-3 @ r.T + p, table.axis @ r.T
        to = centre - o
        to /= np.linalg.norm(to, axis=1, keepdims=True)
        angle = np.degrees(np.arccos(np.clip((a * to).sum(1), -1.0, 1.0)))
        reach = np.degrees(np.arcsin(min(1.0, radius / distances[j]))) + 0.5 * drho + (RING_DELTA_PHI + 0.5) * dphi
        rows = np.flatnonzero(angle <= reach)
        picked.append(rows)
        origins.append(o[rows])
        axes.append(a[rows])
        streams.append((index * len(positions) + j) * width + table.id[rows])
        toward.append(to[rows])
    if not sum(len(r) for r in picked):
        return [{**dict.fromkeys(COLUMNS, np.nan), "receptors_touched": 0, "receptors_covered": 0} for _ in picked]
    every = np.concatenate(picked)
    cones = look_cones(scene, np.vstack(origins), np.vstack(axes), drho[every], streams=np.concatenate(streams),
                       receptor_set=receptor_set, sensitivities=sensitivities, trace=trace, threads=threads,
                       target=(centre, radius))
    cover = cones.cover
    # Catches of the receptors' radiance, not their irradiance: receptors of unequal Δρ compare alike.
    catches = catches_of(cones.radiance, wl, receptor_set, sensitivities=sensitivities)
    catches[absent[every]] = np.nan
    replicates = np.where(absent[every][:, None, :], np.nan, cones.replicate_catches)
    out, start = [], 0
    for j, rows in enumerate(picked):
        part = slice(start, start + len(rows))
        start += len(rows)
        angular_radius = np.degrees(np.arcsin(min(1.0, radius / distances[j])))
        # The target's direction from each receptor: the receptors of both eyes differ by a few mm.
        ring = local_background(axes[j], cover[part], toward[j], angular_radius, drho[rows], dphi[rows])
        out.append(detect(catches[part], cover[part], ring, 2.0 * angular_radius,
                          rotations[j].T @ (centre - positions[j]), receptor_set, replicates[part]))
    return out


def summarise(approaches, outputs, *, scene=""):
    """Detection distances by species and eye: ``outputs["summary"]`` (CSV) and ``outputs["figure"]`` (PNG).

    Parameters
    ----------
    approaches : dict of str to path
        Eye class to its approaches table (:func:`survey`).

    ``summary`` has a row per species and eye: the approaches, the share of
    them in which each criterion held at some distance, and the median,
    10th and 90th percentiles of the first distances where it did; for the
    rule's verdicts each with its 95 % interval, the same percentile of the
    approaches' near and far ends (``_near_m``, ``_far_m``: :data:`FLAGS`).
    """
    from beeoptics.images import figures  # imported where drawn: the survey's jobs need no matplotlib

    rows, tables = [], {}
    for eye, path in approaches.items():
        t = read_table(path, text=("species",))
        tables[eye] = t
        species = np.asarray(t["species"]).astype(str)
        for s in sorted(set(species)):
            mine = species == s
            row = {"species": s, "eye": eye, "approaches": int(mine.sum())}
            for name in FIRST:
                base = name.removesuffix("_m")
                d = np.asarray(t[f"first_{name}"], float)[mine]
                row[f"{base}_share"] = np.isfinite(d).sum() / d.size
                ends = ("", "_near", "_far") if name in FLAGS else ("",)
                for label, q in (("median", 50), ("p10", 10), ("p90", 90)):
                    for end in ends:
                        seen = np.asarray(t[f"first_{base}{end}_m"], float)[mine]
                        seen = seen[np.isfinite(seen)]
                        row[f"{base}_{label}{end}_m"] = float(np.percentile(seen, q)) if seen.size else np.nan
            rows.append(row)
    text = ("species", "eye")
    write_table(outputs["summary"], {c: [r[c] for r in rows] if c in text else np.array([r[c] for r in rows], float)
                                     for c in rows[0]} if rows else {"species": [], "eye": []})
    figures.detection_distances(tables, outputs["figure"], scene)
