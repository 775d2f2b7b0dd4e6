"""The navigation stages: environment maps on a grid of places, then image differences and catchment areas.

A square grid of places about the reference place, level at the configured
height, each traced once as an environment map
(:func:`beeoptics.navigation.envmap.environment_map`, at the finest spacing
the grid's eyes ask for and with the catches of each of their receptor
sets, so that one map serves them all). Then for
each eye: every place's view at every heading resampled from its map
(:func:`beeoptics.navigation.idf.turned_catches`), the rIDF of each against
the reference view (the reference place's view at the reference heading) in
each signal, the tIDF (each place's view at the reference heading, as Zeil
et al. 2003 took their grids' images: the camera's orientation held), the
rIDF's valley, and the tIDF's catchment area
(:mod:`beeoptics.navigation.catchment`).

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically.
"""

from pathlib import Path

import numpy as np

from beeoptics.api import Eye, load_scene
from beeoptics.images import figures
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import write_table
from beeoptics.navigation import catchment, idf
from beeoptics.navigation.envmap import (HEADING_STEP_DEG, clamped, environment_map, eye_weights, map_catches,
                                        read_map, write_map)
from beeoptics.pipeline.logs import log
from beeoptics.vision.receptorset import receptor_set_of


def grid_places(reference_xy, height_m, extent_m, spacing_m):
    """The grid's places: x and y (rows, columns), m, centred on the reference, its side the extent rounded to
    an even number of spacings, and the places' height; the reference is the middle place."""
    half = int(round(extent_m / 2.0 / spacing_m))
    steps = np.arange(-half, half + 1) * spacing_m
    y, x = np.meshgrid(reference_xy[1] + steps, reference_xy[0] + steps, indexing="ij")
    return x, y, float(height_m)


def reference_xy(scene, navigation):
    """The configured reference place (x, y), m, or the scene's own eye position's."""
    given = navigation["reference_m"]
    return np.asarray(scene.scene.eye_position[:2] if given is None else given, float)


def check(navigation, receptor_sets, source="config"):
    """Refuse, in one :class:`InputError`, a navigation section whose heading step does not divide a turn,
    whose reference heading is not a whole number of steps, or whose signals an eye lacks.

    Parameters
    ----------
    navigation : dict
        The configuration's checked ``navigation`` section.
    receptor_sets : dict of str to ReceptorSet
        Each of its eyes' receptor set.
    """
    step, heading = navigation["heading_step_deg"], navigation["heading_deg"]
    turns, steps = 360.0 / step, step / HEADING_STEP_DEG
    if abs(turns - round(turns)) > 1e-9 or abs(steps - round(steps)) > 1e-9:
        raise InputError(source, "navigation.heading_step_deg", f"{step}°: 360° over it, and it over the maps' "
                         f"heading step {HEADING_STEP_DEG}°, must be whole numbers")
    if abs(heading / step - round(heading / step)) > 1e-9:
        raise InputError(source, "navigation.heading_deg", f"{heading}° is not a whole number of "
                         f"navigation.heading_step_deg ({step}°)")
    for eye, rs in receptor_sets.items():
        unknown = sorted(set(navigation["signals"]) - set(idf.signal_names(rs)))
        if unknown:
            raise InputError(source, "navigation.signals", f"{unknown[0]!r} is not a signal of eye {eye} "
                             f"({', '.join(idf.signal_names(rs))})")


def eyes_of(receptor_files, eye_files):
    """The eyes, each its receptor table and its eye.yaml's receptor set."""
    return [Eye(r, read_receptors(r), receptor_set_of(e), e) for r, e in zip(receptor_files, eye_files)]


def trace_maps(scene_file, receptor_files, eye_files, folder, *, places, navigation, grid, spectral, threads=None):
    """Trace the environment maps of grid places ``places`` (row-major) into ``folder``, ``{place}.npz`` each.

    The scene and the eyes are read once for all of them (a job's start and
    the meadow's reading cost several maps' tracing). Each map is traced for
    all the eyes at once: at the finest of the rule's spacings for them
    (each one's Δρ at its 2nd percentile over four), with the catches of each of their
    receptor sets; their spectral radiance only where ``navigation.map.radiance``
    asks for it.
    """
    scene = load_scene(scene_file, **spectral)
    spec = navigation["grids"][grid]
    x, y, z = grid_places(reference_xy(scene, navigation), navigation["height_m"], spec["extent_m"], spec["spacing_m"])
    eyes = eyes_of(receptor_files, eye_files)
    m = navigation["map"]
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for place in places:
        env = environment_map(scene, (x.flat[place], y.flat[place], z), eyes, samples=m["samples"], depth=m["depth"],
                              seed=m["seed"], radiance=m["radiance"], threads=threads)
        write_map(folder / f"{place}.npz", env)
        log.info("place %d at (%.3f, %.3f, %.3f) m: %d directions %.3g° apart, the catches of %s", place,
                 x.flat[place], y.flat[place], z, len(env.nearness), env.spacing_deg, ", ".join(env.catches))


def eye_differences(files, eye, reference, navigation, threads=None):
    """One eye's rIDFs and valleys at every place (a map file each, read when its turn comes) against the
    reference view, in every signal.

    Returns
    -------
    ridf : dict of str to ndarray (places, headings)
    valleys : dict of str to (heading_deg, depth, width_deg), each (places,)
    clamped : int
        The eye's receptors narrower than the maps resolve, resampled at the narrowest they do
        (:func:`beeoptics.navigation.envmap.clamped`).
    """
    step, heading = navigation["heading_step_deg"], navigation["heading_deg"]
    reference_map = read_map(files[reference])
    weights = eye_weights(reference_map, eye)
    at = round(heading / step)
    own = turned(reference_map, eye, weights, step, threads)
    base = own[at]
    names = [s for s in idf.signal_names(eye.receptor_set) if s in navigation["signals"]]
    ridf = {s: [] for s in names}
    # Place by place, a map at a time: a place's views at every heading are (headings × receptors × classes),
    # some 100 MB, and the full grid's maps some 10 GB.
    for place, file in enumerate(files):
        views = own if place == reference else turned(read_map(file), eye, weights, step, threads)
        differences = idf.ridf(views, base, eye.receptor_set)
        for s in names:
            ridf[s].append(differences[s])
    ridf = {s: np.array(v) for s, v in ridf.items()}
    narrow = int(clamped(reference_map, eye.table.delta_rho_deg).sum())
    log.info("%d of the eye's %d receptors are narrower than the maps' %.3g° spacing resolves (Δρ under %.3g°): "
             "resampled at that Δρ", narrow, len(eye.table.id), reference_map.spacing_deg,
             reference_map.resolved_deg)
    return ridf, {s: idf.valley(v, step) for s, v in ridf.items()}, narrow


def turned(env, eye, weights, step, threads):
    """A map's views at every heading ``step`` apart, (headings, receptors, k)."""
    return idf.turned_catches(env, eye, heading_step_deg=step, weights=weights, q=map_catches(env, eye),
                              threads=threads)


def image_differences(map_folders, receptor_files, eye_files, eye_names, outputs, *, scene, navigation, grid,
                      threads=None):
    """The rIDFs, tIDFs, valleys and catchment areas of every eye over a grid's maps (``{place}.npz`` in the
    folders of :func:`trace_maps`): ``outputs`` ``ridf``, ``tidf``, ``places``, ``catchment`` (CSV) and
    ``figure`` (PNG)."""
    files = sorted((f for d in map_folders for f in Path(d).glob("*.npz")), key=lambda f: int(f.stem))
    # The places first, a map at a time (each map read whole, and so checked).
    x, y = np.array([read_map(f).position_m[:2] for f in files]).T
    spec = navigation["grids"][grid]
    side = int(round(np.sqrt(len(files))))
    reference = len(files) // 2
    step, heading = navigation["heading_step_deg"], navigation["heading_deg"]
    ridf_rows, tidf_rows, place_rows, catch_rows, panels = [], [], [], [], []
    eyes = eyes_of(receptor_files, eye_files)
    check(navigation, dict(zip(eye_names, (e.receptor_set for e in eyes))))
    for name, eye in zip(eye_names, eyes):
        ridf, valleys, narrow = eye_differences(files, eye, reference, navigation, threads)
        for s, r in ridf.items():
            headings = np.arange(r.shape[1]) * step
            ridf_rows.append({"eye": np.full(r.size, name), "signal": np.full(r.size, s),
                              "place": np.repeat(np.arange(len(files)), r.shape[1]),
                              "heading_deg": np.tile(headings, len(files)), "idf": r.ravel()})
            tidf = r[:, round(heading / step)]
            best, depth, width = valleys[s]
            field = tidf.reshape(side, side)
            inside = catchment.catchment(field, np.unravel_index(reference, field.shape))
            area, along, across = catchment.extent(inside, x.reshape(side, side), y.reshape(side, side), heading,
                                                   spec["spacing_m"])
            n = len(files)
            tidf_rows.append({"eye": np.full(n, name), "signal": np.full(n, s), "place": np.arange(n), "x_m": x,
                              "y_m": y, "tidf": tidf, "tidf_best": r.min(axis=1),
                              "in_catchment": inside.ravel().astype(int)})
            place_rows.append({"eye": np.full(n, name), "signal": np.full(n, s), "place": np.arange(n), "x_m": x,
                               "y_m": y, "heading_of_min_deg": best, "depth": depth, "width_deg": width})
            catch_rows.append({"eye": [name], "signal": [s], "places": [int(inside.sum())], "area_m2": [area],
                               "along_m": [along], "across_m": [across], "receptors": [len(eye.table.id)],
                               "clamped": [narrow]})
            panels.append((f"{name}: {s}", x.reshape(side, side), y.reshape(side, side), field, inside,
                           catchment.descent(field)))
    for key, rows in (("ridf", ridf_rows), ("tidf", tidf_rows), ("places", place_rows), ("catchment", catch_rows)):
        write_table(outputs[key], {k: np.concatenate([r[k] for r in rows]) for k in rows[0]})
    figures.catchment_areas(panels, (x[reference], y[reference]), heading, outputs["figure"],
                            f"{scene}: catchment areas of the reference view by signal")
