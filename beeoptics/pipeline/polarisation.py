"""The polarisation stages: what polarisation each receptor sees of a scene, and the bee's sky compass in it.

Each reads its inputs, calls the library and writes ``outputs``, a mapping
of output names to paths, atomically.
"""

import json

import numpy as np

from beeoptics.eye.description import load_eye
from beeoptics.eye.fieldofview import MAP_WIDTH_PX, visual_field
from beeoptics.eye.optics import acceptance_solid_angle
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
from beeoptics.light.scene import load_scene, raycasting_scene, relit
from beeoptics.pipeline.logs import log
from beeoptics.tracing import trace_cones, trace_receptors
from beeoptics.raycasting import first_hits
from beeoptics.sky.skypolarisation import patterns
from beeoptics.spectra import grid
from beeoptics.vision import compass as sky_compass
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.polarisation import DORSAL_RIM_PS, degree_and_angle, head_frame_stokes, receptor_catch
from beeoptics.vision.receptorset import DEFAULT_CURVES, curves

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


def stokes_catches(stokes, delta_rho_deg, wavelengths, receptor_set, receptor_curves=DEFAULT_CURVES):
    """Each receptor class's catch of the spectral Stokes vectors (n, 3, wl): (n, classes, 3), in their frame."""
    sens = curves(receptor_set, wavelengths, receptor_curves)
    irradiance = stokes * acceptance_solid_angle(delta_rho_deg)[:, None, None]
    return quantum_catches(irradiance, sens, wavelengths).transpose(0, 2, 1)


def _analysers(receptor_set, source):
    """The index of the class whose microvilli analyse polarisation in the dorsal rim (the bee's UV)."""
    if receptor_set.polarisation is None:
        raise InputError(source, "receptors", f"the receptor set {receptor_set.name!r} names no class that "
                         "analyses polarisation (its polarisation section)")
    return receptor_set.polarisation


def polarisation_maps(eye_file, receptors_csv, scene_file, outputs, *, spectral, settings, dorsal_rim_ps,
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
    dorsal_rim_ps : float
        The dorsal rim UV receptors' polarisation sensitivity (``inf``: ideal analysers);
        the main retina's is 1 (:mod:`beeoptics.vision.polarisation`).
    """
    wl = grid(**spectral)
    scene = load_scene(scene_file, wl)
    table = read_receptors(receptors_csv)
    rim = _dorsal_rim(table, receptors_csv)
    a = _analysers(receptor_set, eye_file)
    radiance, _ = trace_receptors(scene, table, 0, len(table.id), settings, len(wl), polarised=True,
                                  sensitivities=(wl, curves(receptor_set, wl, receptor_curves)))
    catches = head_frame_stokes(stokes_catches(radiance, table.delta_rho_deg, wl, receptor_set, receptor_curves),
                                table.axis)
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
    eye = load_eye(eye_file)
    xy = retinal_plane(eye, table.position, table.side)
    can = canvas(xy, width_px)
    anterior, dorsal = in_eye_plane(eye.rotation)
    figures.retinas([(paint(nearest_receptor(can, xy, table.side), colours), outputs["retina"],
                      f"{title}: polarisation in the retinal plane", POLARISATION_CAPTION, None)],
                    panel_extents(can), anterior, dorsal)
    axes = table.axis[rim]
    figures.dorsal_rim(np.degrees(np.arctan2(axes[:, 1], axes[:, 0])), np.degrees(np.arcsin(axes[:, 2])),
                       table.microvilli_deg[rim], pol[rim], outputs["dorsal_rim"],
                       f"{title}: the dorsal rim's POL units")


def compass(receptors_csv, scene_file, outputs, *, spectral, settings,
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
    largest error) and ``figure`` (PNG).
    """
    wl = grid(**spectral)
    table = read_receptors(receptors_csv)
    rim = _dorsal_rim(table, receptors_csv)
    turns = 360.0 * np.arange(headings) / headings
    a = _analysers(receptor_set, receptors_csv)
    uv = curves(receptor_set, wl, receptor_curves)[:, a:a + 1]
    n = int(rim.sum())
    base = load_scene(scene_file, wl)
    if base.sun is None or base.sky is None or base.sky.max_degree == 0.0:
        raise InputError(scene_file, "light", "the compass needs a clear, polarised sky and the sun")
    # The head at every heading (heading, 3, 3); the sun in its frame, and so the template, is the same in
    # every condition, which changes only the sky's polarisation, its turbidity and the bee's height.
    rotations = np.array([head_rotation(turn, 0.0) @ base.eye_rotation for turn in turns])
    suns = np.einsum("hji,j->hi", rotations, base.sun.direction)
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

    def read(scene):
        rs = raycasting_scene(scene)
        origins = (np.einsum("nj,hij->hni", table.position[rim] * 1e-3, rotations) + scene.eye_position).reshape(-1, 3)
        stokes = trace_cones(scene, origins, axes, drho, streams, 0, len(axes), settings, len(wl), rs=rs,
                             dorsal=dorsal, sensitivities=(wl, uv))[0]
        catches = head_frame_stokes(quantum_catches(stokes, uv, wl)[..., 0], np.tile(table.axis[rim], (headings, 1)))
        pol = sky_compass.pol_responses(catches, np.tile(table.microvilli_deg[rim], headings), dorsal_rim_ps)
        estimate, confidence = np.array([sky_compass.read_out(p, t, azimuths)
                                         for p, t in zip(pol.reshape(headings, n), templates)]).T
        hidden = np.isfinite(first_hits(rs, np.hstack([origins, axes]).astype(np.float32))["t_hit"])
        return estimate, confidence, truth, hidden.reshape(headings, n).mean(axis=1)

    def traced_alike(scene):
        """What a condition is traced as: its light and, among objects, the bee's place (in the open, or a
        scene of none, anywhere). The sky scene's conditions in the scene and the meadow's own turbidity
        are traced once."""
        light = b"".join(np.asarray(v).tobytes() for part in (scene.sky, scene.sun) for v in part)
        return light + (scene.eye_position.tobytes() if scene.objects else b"open")

    # The same light with nothing to hide it.
    rayleigh = relit(base, wl, {"polarisation": "rayleigh"})._replace(objects=[])
    conditions = [("Rayleigh sky, open", np.nan, rayleigh), ("clear sky, open", np.nan, base._replace(objects=[])),
                  ("clear sky, in the scene", np.nan, base)]
    conditions += [(f"clear sky, in the scene at {h * 100:g} cm", np.nan,
                    base._replace(eye_position=np.array([*base.eye_position[:2], h]))) for h in heights_m]
    conditions += [(f"turbidity {t:g}, in the scene", t, relit(base, wl, {"turbidity": t})) for t in turbidities]
    rows = {k: [] for k in ("condition", "turbidity", "max_degree", "heading_deg", "solar_azimuth_deg",
                            "estimate_deg", "error_deg", "confidence", "sky_hidden")}
    summary, read_before = {}, {}
    for name, turbidity, scene in conditions:
        log.info("compass: %s", name)
        key = traced_alike(scene)
        if key not in read_before:
            read_before[key] = read(scene)
        estimate, confidence, truth, hidden = read_before[key]
        error = sky_compass.wrap_deg(estimate - truth)
        rows["condition"] += [name] * headings
        rows["turbidity"] += [turbidity] * headings
        rows["max_degree"] += [scene.sky.max_degree] * headings
        rows["heading_deg"] += list(turns)
        rows["solar_azimuth_deg"] += list(sky_compass.wrap_deg(truth))
        rows["estimate_deg"] += list(estimate)
        rows["error_deg"] += list(error)
        rows["confidence"] += list(confidence)
        rows["sky_hidden"] += list(hidden)
        summary[name] = {"max_degree": scene.sky.max_degree, "median_abs_error_deg": float(np.median(np.abs(error))),
                         "max_abs_error_deg": float(np.abs(error).max()), "sky_hidden": float(np.mean(hidden))}
    write_table(outputs["table"], {k: np.asarray(v) for k, v in rows.items()})
    with atomic_path(outputs["summary"]) as tmp:
        tmp.write_text(json.dumps(summary, indent=1) + "\n")
    figures.compass(rows, outputs["figure"], f"{title}: the dorsal rim's sky compass")
