"""The polarisation stages: what polarisation each receptor sees of a scene, and the bee's sky compass in it.

Each reads its inputs, calls the library and writes ``outputs``, a mapping
of output names to paths, atomically.
"""

import json

import numpy as np

from beeoptics.api import catches as catches_of, load_eye, load_scene, look, look_cones
from beeoptics.eye.description import load_eye as describe_eye
from beeoptics.eye.fieldofview import MAP_WIDTH_PX, visual_field
from beeoptics.headframe import head_rotation, in_eye_plane
from beeoptics.images import figures
from beeoptics.images.display import polarisation_colours
from beeoptics.images.fieldmaps import paint
from beeoptics.images.retina import canvas, nearest_receptor, panel_extents, retinal_plane
from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import write_table
from beeoptics.io.validation import config_default
from beeoptics.pipeline.logs import log
from beeoptics.raycasting import first_hits
from beeoptics.sky.skypolarisation import patterns
from beeoptics.vision import compass as sky_compass
from beeoptics.vision.polarisation import DORSAL_RIM_PS, degree_and_angle, head_frame_stokes, receptor_catch
from beeoptics.vision.receptorset import DEFAULT_CURVES

#: The colour map of polarisation: hue the angle (0–180°, cyclic), saturation the degree, full value.
POLARISATION_CAPTION = ("Polarisation each receptor sees, UV receptors' catch: hue is the angle of polarisation about "
                        "the receptor's axis (0° along the head's dorsal direction, 90° along the anterior; cyclic "
                        "over 180°), saturation is the degree (white unpolarised, full colour 100 %). Measured "
                        "towards the anterior, as the eyes' microvilli are, angles mirror between the eyes and "
                        "jump where a receptor looks across the midline.")


def _dorsal_rim(table, source):
    if table.dorsal_rim is None or not table.dorsal_rim.any():
        raise InputError(source, "dorsal_rim",
                         "the eye has no dorsal rim area: its eye.yaml needs a dorsal_rim section")
    return table.dorsal_rim.astype(bool)


def _analysers(receptor_set, source):
    """The index of the class whose microvilli analyse polarisation in the dorsal rim (the bee's UV)."""
    if receptor_set.polarisation is None:
        raise InputError(source, "receptors", f"the receptor set {receptor_set.name!r} names no class that "
                         "analyses polarisation (its polarisation section)")
    return receptor_set.polarisation


def polarisation_maps(eye_file, receptors_csv, scene_file, outputs, *, spectral, trace, threads, dorsal_rim_ps,
                      receptor_set, width_px=config_default("images.width_px"),
                      field_width_px=MAP_WIDTH_PX, title="", receptor_curves=DEFAULT_CURVES):
    """Trace every receptor's Stokes vector; write the table and maps of the polarisation it sees.

    Outputs: ``table`` (CSV, one row per receptor: each class's catch of I,
    Q and U in the eye's frame, degree, angle; the analysing class's (the
    bee's UV receptors') response with their polarisation sensitivity; the
    dorsal rim's POL units),
    ``field`` (the visual field, equirectangular), ``retina`` (the retinal
    plane) and ``dorsal_rim`` (the POL units where they look, with their
    microvilli), PNG figures.

    Parameters
    ----------
    trace : dict
        A config's ``trace`` section, as every receptor's Stokes vector is traced (:func:`beeoptics.api.look`).
    threads : int
    dorsal_rim_ps : float
        The dorsal rim UV receptors' polarisation sensitivity (``inf``: ideal analysers);
        the main retina's is 1 (:mod:`beeoptics.vision.polarisation`).
    """
    scene = load_scene(scene_file, **spectral)
    eye = load_eye(receptors_csv, receptor_set=receptor_set)
    table = eye.table
    rim = _dorsal_rim(table, receptors_csv)
    a = _analysers(receptor_set, eye_file)
    view = look(eye, scene, polarised=True, trace=trace, threads=threads, sensitivities=receptor_curves)
    # Each class's catch of I, Q and U over the acceptance (n, classes, 3), turned into the head's frame.
    catches = head_frame_stokes(catches_of(view.stokes, scene.wavelengths_nm, receptor_set,
                                           sensitivities=receptor_curves,
                                           delta_rho_deg=table.delta_rho_deg).transpose(0, 2, 1), table.axis)
    degree, angle = degree_and_angle(catches)
    degree = np.where(catches[..., 0] > 0.0, degree, 0.0)  # no light: none of it polarised
    microvilli = np.where(rim, table.microvilli_deg, 0.0)
    uv = catches[:, a]
    pol = np.full(len(table.id), np.nan)
    pol[rim] = sky_compass.pol_responses(uv[rim], microvilli[rim], dorsal_rim_ps)
    columns = {"id": table.id, "side": table.side, "dorsal_rim": rim.astype(int),
               "microvilli_deg": np.where(rim, table.microvilli_deg, np.nan)}
    for k, r in enumerate(receptor_set.classes):
        columns.update({f"{r}_I": catches[:, k, 0], f"{r}_Q": catches[:, k, 1], f"{r}_U": catches[:, k, 2],
                        f"{r}_degree": degree[:, k], f"{r}_angle_deg": angle[:, k]})
    columns[f"{receptor_set.classes[a]}_response"] = receptor_catch(uv, microvilli, np.where(rim, dorsal_rim_ps, 1.0))
    columns["pol"] = pol
    write_table(outputs["table"], columns)

    colours = polarisation_colours(degree[:, a], angle[:, a])
    name = receptor_set.classes[a]
    field = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, field_width_px)
    panels = {f"{name}: angle (hue) and degree (saturation) of polarisation": paint(field.receptor, colours),
              f"{name}: degree of polarisation": np.repeat(paint(field.receptor, degree[:, a:a + 1]), 3, -1)}
    figures.visual_field(panels, field.eyes, field.azimuth_deg, field.elevation_deg, None, outputs["field"],
                         f"{title}: polarisation over the visual field")
    description = describe_eye(eye_file)
    xy = retinal_plane(description, table.position, table.side)
    can = canvas(xy, width_px)
    anterior, dorsal = in_eye_plane(description.rotation)
    figures.retinas([(paint(nearest_receptor(can, xy, table.side), colours), outputs["retina"],
                      f"{title}: polarisation in the retinal plane", POLARISATION_CAPTION, None)],
                    panel_extents(can), anterior, dorsal)
    axes = table.axis[rim]
    figures.dorsal_rim(np.degrees(np.arctan2(axes[:, 1], axes[:, 0])), np.degrees(np.arcsin(axes[:, 2])),
                       table.microvilli_deg[rim], pol[rim], outputs["dorsal_rim"],
                       f"{title}: the dorsal rim's POL units")


def compass(receptors_csv, scene_file, outputs, *, spectral, trace, threads,
            headings=config_default("polarisation.compass.headings"),
            turbidities=config_default("polarisation.compass.turbidities"),
            heights_m=config_default("polarisation.compass.heights_m"), dorsal_rim_ps=DORSAL_RIM_PS, receptor_set,
            title="", receptor_curves=DEFAULT_CURVES):
    """The sky compass of the dorsal rim over a full turn of the bee, in a scene, and as turbidity grows.

    The head turns about the vertical through ``headings`` evenly spaced
    headings from the scene's own, keeping its pitch and roll. Only the
    dorsal rim's receptors are traced, with polarisation, and their POL
    units read out (:mod:`beeoptics.vision.compass`) under an unobstructed
    Rayleigh sky (the reference), the scene's sky as it is (its polarisation model and turbidity, with
    whatever the scene hides), the open sky of the same model, the scene
    with the bee lowered to each of ``heights_m`` above the world's origin
    (into the vegetation, where it hides more of the sky), and the scene at
    each of ``turbidities``. Outputs: ``table`` (CSV, one row per
    condition and heading), ``summary`` (JSON: each condition's median and
    largest error) and ``figure`` (PNG). ``trace``, a config's ``trace``
    section, as the dorsal rim is traced (:func:`beeoptics.api.look_cones`).
    """
    table = read_receptors(receptors_csv)
    rim = _dorsal_rim(table, receptors_csv)
    turns = 360.0 * np.arange(headings) / headings
    analyser = [receptor_set.classes[_analysers(receptor_set, receptors_csv)]]
    n = int(rim.sum())
    base = load_scene(scene_file, **spectral)
    wl, loaded, head = base.wavelengths_nm, base.scene, base.scene.eye_position
    if loaded.sun is None or loaded.sky is None or loaded.sky.max_degree == 0.0:
        raise InputError(scene_file, "light", "the compass needs a clear, polarised sky and the sun")
    # The head at every heading (heading, 3, 3); the sun in its frame, and so the template, is the same in
    # every condition, which changes only the sky's polarisation, its turbidity and the bee's height.
    rotations = np.array([head_rotation(turn, 0.0) @ loaded.eye_rotation for turn in turns])
    suns = np.einsum("hji,j->hi", rotations, loaded.sun.direction)
    truth = np.degrees(np.arctan2(suns[:, 1], suns[:, 0]))
    templates = []
    for sun in suns:
        candidates, azimuths = sky_compass.candidate_suns(np.degrees(np.arcsin(sun[2])))
        templates.append(sky_compass.expected_responses(*patterns(table.axis[rim], candidates, np.zeros(2), 1.0),
                                                        table.axis[rim], table.microvilli_deg[rim]))
    # Every heading's dorsal rim traced at once, each receptor drawing its own random numbers at every heading.
    axes = np.einsum("nj,hij->hni", table.axis[rim], rotations).reshape(-1, 3)
    streams = np.tile(np.arange(n), headings)
    drho = np.tile(table.delta_rho_deg[rim], headings)
    dorsal = np.repeat(rotations[:, :, 2], n, axis=0)

    def read(scene, position):
        origins = (np.einsum("nj,hij->hni", table.position[rim] * 1e-3, rotations) + position).reshape(-1, 3)
        stokes = look_cones(scene, origins, axes, drho, streams=streams, receptor_set=receptor_set, classes=analyser,
                            sensitivities=receptor_curves, trace=trace, threads=threads, dorsal=dorsal).radiance
        catches = head_frame_stokes(catches_of(stokes, wl, receptor_set, sensitivities=receptor_curves,
                                               classes=analyser)[..., 0], np.tile(table.axis[rim], (headings, 1)))
        pol = sky_compass.pol_responses(catches, np.tile(table.microvilli_deg[rim], headings), dorsal_rim_ps)
        estimate, confidence = np.array([sky_compass.read_out(p, t, azimuths)
                                         for p, t in zip(pol.reshape(headings, n), templates)]).T
        hidden = np.isfinite(first_hits(scene.raycasting, np.hstack([origins, axes]).astype(np.float32))["t_hit"])
        return estimate, confidence, truth, hidden.reshape(headings, n).mean(axis=1)

    def traced_alike(scene, position):
        """What a condition is traced as: its light and, among objects, the bee's place (in the open, or a
        scene of none, anywhere). The sky scene's conditions in the scene and the meadow's own turbidity
        are traced once."""
        lit = b"".join(np.asarray(v).tobytes() for part in (scene.scene.sky, scene.scene.sun) for v in part)
        return lit + (position.tobytes() if scene.scene.objects else b"open")

    # The same light with nothing to hide it.
    conditions = [("Rayleigh sky, open", np.nan, base.with_light(polarisation="rayleigh").without_objects(), head),
                  ("clear sky, open", np.nan, base.without_objects(), head),
                  ("clear sky, in the scene", np.nan, base, head)]
    conditions += [(f"clear sky, in the scene at {h * 100:g} cm", np.nan, base, np.array([*head[:2], h]))
                   for h in heights_m]
    conditions += [(f"turbidity {t:g}, in the scene", t, base.with_light(turbidity=t), head) for t in turbidities]
    rows = {k: [] for k in ("condition", "turbidity", "max_degree", "heading_deg", "solar_azimuth_deg",
                            "estimate_deg", "error_deg", "confidence", "sky_hidden")}
    summary, read_before = {}, {}
    for name, turbidity, scene, position in conditions:
        log.info("compass: %s", name)
        key = traced_alike(scene, position)
        if key not in read_before:
            read_before[key] = read(scene, position)
        estimate, confidence, truth, hidden = read_before[key]
        error = sky_compass.wrap_deg(estimate - truth)
        rows["condition"] += [name] * headings
        rows["turbidity"] += [turbidity] * headings
        rows["max_degree"] += [scene.scene.sky.max_degree] * headings
        rows["heading_deg"] += list(turns)
        rows["solar_azimuth_deg"] += list(sky_compass.wrap_deg(truth))
        rows["estimate_deg"] += list(estimate)
        rows["error_deg"] += list(error)
        rows["confidence"] += list(confidence)
        rows["sky_hidden"] += list(hidden)
        summary[name] = {"max_degree": scene.scene.sky.max_degree, "median_abs_error_deg": float(np.median(np.abs(error))),
                         "max_abs_error_deg": float(np.abs(error).max()), "sky_hidden": float(np.mean(hidden))}
    write_table(outputs["table"], {k: np.asarray(v) for k, v in rows.items()})
    with atomic_path(outputs["summary"]) as tmp:
        tmp.write_text(json.dumps(summary, indent=1) + "\n")
    figures.compass(rows, outputs["figure"], f"{title}: the dorsal rim's sky compass")
