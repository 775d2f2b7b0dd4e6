"""The flight stages: trace each frame of a flight, render its human view, and turn the frames into
an animation, a table of responses, the optic flow and the approached flower's catches.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically. A frame is traced exactly as
a scene is (:func:`beeoptics.tracing.trace_receptors`), with the scene's
eye moved to the flight's pose at the frame's time
(:mod:`beeoptics.world.flight`). A flight's frames are traced in shares of
a few frames a job (``frames_per_job``): each job reads the scene once, and
the shares are cached and spread over a cluster's nodes.
"""

import numpy as np

from beeoptics.eye.fieldofview import visual_field
from beeoptics.headframe import LEFT, eye_azimuth_elevation
from beeoptics.images.display import bee_colours, display_words, encode, map3
from beeoptics.images.viewer import flight_viewer
from beeoptics.images.fieldmaps import paint
from beeoptics.api import View, catches as catches_of, human_srgb, human_view, load_eye, load_scene, look, looks
from beeoptics.io.atomic import atomic_path, write_json
from beeoptics.io.imagefile import write_gif, write_mp4
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import write_table
from beeoptics.io.validation import config_default
from beeoptics.spectra import grid
from beeoptics.vision.detection import detect, local_background
from beeoptics.vision.receptorset import DEFAULT_CURVES, lacking, ommatidium_types
from beeoptics.world.flight import (azimuth_elevation_components, disc_angular_diameter, disc_hits, frame_times,
                                    optic_flow, pose, read_flight)

#: Width of the equirectangular maps of the animation, pixels (one degree each).
MAP_WIDTH_PX = 360


def frame_count(flight_file, fps):
    """How many frames a flight has at ``fps``."""
    return len(frame_times(read_flight(flight_file), fps))


def shares(flight_file, fps, frames_per_job):
    """The first frame of each job's share of a flight's frames."""
    return list(range(0, frame_count(flight_file, fps), frames_per_job))


def _poses(flight_file, fps, first, count):
    """The head's poses at frames ``first`` … ``first + count − 1`` (those the flight has)."""
    flight = read_flight(flight_file)
    return [pose(flight, t) for t in frame_times(flight, fps)[first:first + count]]


def trace_frames(receptors_csv, scene_file, flight_file, outputs, *, first, count, fps, spectral, trace, threads,
                 receptor_set, target=None, receptor_curves=DEFAULT_CURVES):
    """Trace every receptor at a share of a flight's frames: ``outputs["frames"]`` (npz).

    The share is frames ``first`` … ``first + count − 1``; the scene and its
    Embree scene are made once for all of them, and each frame is a
    :func:`beeoptics.api.look` from its pose. The file holds, per frame,
    each receptor's radiance (as a trace share), the pose, and each
    receptor's distance along its axis to the first surface (infinite for
    the sky); with a ``target`` (the flight's, see :func:`flight_products`),
    also each receptor's share of its acceptance that met it first
    (``cover``), within the sphere of its radius about its centre. A
    precision asked of the trace (``trace``, a config's trace section) is
    asked of the catches of ``receptor_set``.
    """
    eye = load_eye(receptors_csv, receptor_set=receptor_set)
    scene = load_scene(scene_file, **spectral)
    sphere = None if target is None else (np.asarray(target["position_m"], float), float(target["radius_m"]))
    poses = _poses(flight_file, fps, first, count)
    # Of each frame's view only what the file keeps: a view holds its trace's replicates (eight times its
    # radiance) until asked for its errors, which a flight's frames never are.
    kept = [(v.radiance, np.zeros(len(eye.table.id)) if v.cover is None else v.cover, v.distance_m)
            for v in (look(eye, scene, **p.eye(), target=sphere, trace=trace, threads=threads,
                           sensitivities=receptor_curves) for p in poses)]
    radiance, cover, depth = (np.array(column) for column in zip(*kept))
    with atomic_path(outputs["frames"]) as tmp:
        np.savez(tmp, id=eye.table.id, frame=first + np.arange(len(poses)), radiance=radiance, cover=cover,
                 depth_m=depth, time_s=np.array([p.time for p in poses]),
                 position_m=np.array([p.position for p in poses]), rotation=np.array([p.rotation for p in poses]),
                 velocity_m_s=np.array([p.velocity for p in poses]),
                 angular_velocity_rad_s=np.array([p.angular_velocity for p in poses]))


def human_frames(scene_file, flight_file, outputs, *, first, count, fps, spectral, trace, threads, samples, size_px):
    """The human view from the bee's head at a share of a flight's frames (as :func:`trace_frames`), ``samples``
    rays a pixel: ``outputs["frames"]`` (npz: ``srgb``, display sRGB in [0, 1], frames × height × width × 3)."""
    scene = load_scene(scene_file, **spectral)
    images = [human_srgb(human_view(scene, **p.eye(), size_px=size_px, samples=samples, trace=trace, threads=threads))
              for p in _poses(flight_file, fps, first, count)]
    with atomic_path(outputs["frames"]) as tmp:
        np.savez(tmp, srgb=np.array(images, np.float32))


def first_detections(columns):
    """Where along a flight each criterion first holds, approaching: for each of the verdicts and the
    receptor-level measures of :func:`beeoptics.vision.detection.detect`, the first frame at which it
    does (1, or at least one receptor), its time and its distance to the target; None where it never does."""
    out = {}
    for name in ("achromatic_detectable", "chromatic_detectable", "receptors_green_above_threshold",
                 "receptors_colour_above_threshold"):
        hit = np.flatnonzero(np.nan_to_num(columns[name], nan=0.0) >= 1)
        out[name] = None if not hit.size else {
            "frame": int(columns["frame"][hit[0]]), "t_s": float(columns["t_s"][hit[0]]),
            "distance_m": float(columns["distance_m"][hit[0]]),
            "angular_diameter_deg": float(columns["angular_diameter_deg"][hit[0]])}
    return out


def flight_products(receptors_csv, scene_file, frame_npzs, human_npzs, outputs, *, fps, spectral, receptor_set,
                    target=None, background=config_default("colour.background"), receptor_curves=DEFAULT_CURVES,
                    title=""):
    """The frames of one eye's flight, gathered from the shares of :func:`trace_frames` and
    :func:`human_frames` (``frame_npzs``, ``human_npzs``, in order).

    Writes ``responses`` (every receptor's catches and colour coordinates at
    every frame, with ``frame`` and ``t_s``), ``optic_flow`` (every
    receptor's distance along its axis and its optic flow, head frame,
    degrees per second along azimuth and elevation), ``target`` (per frame:
    the distance to the target's centre, its angular diameter, how many
    receptors' axes meet it and their mean catches relative to white),
    ``animation`` (GIF at ``fps``: map3 and the shortest-peaked class, the
    bee's UV, on the visual field beside the human view) and
    ``flow_figure`` (the middle frame's flow field).

    Parameters
    ----------
    target : dict, optional
        The flower the flight approaches, as a disc: ``position_m`` (3,)
        of its centre, ``radius_m`` and ``normal`` (3,), the way it faces.
    """
    from beeoptics.images import figures  # imported where drawn: the jobs tracing frames need no matplotlib

    eye = load_eye(receptors_csv, receptor_set=receptor_set)
    table, scene = eye.table, load_scene(scene_file, **spectral, geometry=False)
    wl = scene.wavelengths_nm
    field = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, MAP_WIDTH_PX)
    seen = field.receptor >= 0
    # Receptor axes in the head frame: azimuth and elevation of each, for the flow's components.
    head_axes = table.axis / np.linalg.norm(table.axis, axis=1, keepdims=True)
    az, el = eye_azimuth_elevation(head_axes, LEFT)  # azimuth + to the bee's left
    responses, flows, targets, frames = [], [], [], []
    # The animation's second panel: the class of the shortest peak (the bee's UV, which the sky fills).
    shortest = int(np.argmin(np.where(np.isnan(receptor_set.lambda_max_nm), np.inf, receptor_set.lambda_max_nm)))
    # Each share read once, whole: an npz file would read an array again on every access.
    shares = [dict(np.load(f)) for f in frame_npzs]
    humans = np.concatenate([np.load(f)["srgb"] for f in human_npzs])
    every = [(s, j) for s in shares for j in range(len(s["frame"]))]
    for k, ((share, j), human) in enumerate(zip(every, humans)):
        g = {name: share[name][j] for name in ("depth_m", "time_s", "position_m", "rotation", "velocity_m_s",
                                               "angular_velocity_rad_s")}
        radiance = share["radiance"][j]
        view = View(eye, scene, radiance, background=background, sensitivities=receptor_curves)
        columns, arrays = view.columns, view.spectra
        n = len(table.id)
        responses.append({"frame": np.full(n, k), "t_s": np.full(n, float(g["time_s"])), **columns})
        rotation = g["rotation"]
        world_axes = head_axes @ rotation.T
        flow = optic_flow(world_axes, g["depth_m"], g["velocity_m_s"], g["angular_velocity_rad_s"]) @ rotation
        flow_deg = np.degrees(azimuth_elevation_components(head_axes, flow))
        flows.append({"frame": np.full(n, k), "t_s": np.full(n, float(g["time_s"])), "id": table.id,
                      "side": table.side, "azimuth_deg": az, "elevation_deg": el, "depth_m": g["depth_m"],
                      "flow_azimuth_deg_s": flow_deg[:, 0], "flow_elevation_deg_s": flow_deg[:, 1],
                      "flow_deg_s": np.hypot(*flow_deg.T)})
        catches = np.column_stack([columns[r] for r in receptor_set.classes])
        relative, colours, _ = bee_colours(catches, arrays["white_q"], wl, radiance, receptor_set.display)
        if target is not None:
            origins = table.position * 1e-3 @ rotation.T + g["position_m"]
            disc = (target["position_m"], target["normal"], target["radius_m"])
            on = disc_hits(origins, world_axes, *disc)
            distance = float(np.linalg.norm(np.asarray(target["position_m"]) - g["position_m"]))
            targets.append({"frame": k, "t_s": float(g["time_s"]), "distance_m": distance,
                            "angular_diameter_deg": np.degrees(disc_angular_diameter(g["position_m"], *disc)),
                            "receptors": int(on.sum()),
                            **{f"{r}_relative": float(relative[on, j].mean()) if on.any() else np.nan
                               for j, r in enumerate(receptor_set.classes)}})
        frames.append((colours, relative[:, shortest:shortest + 1], human, f"{title}, t = {float(g['time_s']):.2f} s"))
    write_table(outputs["responses"], {c: np.concatenate([r[c] for r in responses]) for c in responses[0]})
    write_table(outputs["optic_flow"], {c: np.concatenate([f[c] for f in flows]) for c in flows[0]})
    if targets:
        write_table(outputs["target"], {c: np.array([t[c] for t in targets]) for c in targets[0]})
    else:
        write_table(outputs["target"], {"frame": np.arange(len(frames))})
    # The maps of each frame made as the animation draws it, not held for every frame at once.
    maps = (({"bee colours (map3)": np.where(seen[..., None], encode(paint(field.receptor, colours)), np.nan),
              f"{receptor_set.classes[shortest]} catch over white's":
                  np.repeat(np.clip(paint(field.receptor, short), 0.0, 1.0), 3, -1)}, human, frame_title)
            for colours, short, human, frame_title in frames)
    write_gif(outputs["animation"], list(figures.visual_field_frames(maps, field.eyes, field.azimuth_deg,
                                                                     field.elevation_deg)), fps)
    middle = flows[len(flows) // 2]
    figures.optic_flow(az, el, np.column_stack([middle["flow_azimuth_deg_s"], middle["flow_elevation_deg_s"]]),
                       outputs["flow_figure"], f"{title}: optic flow at t = {middle['t_s'][0]:.2f} s "
                       "(Koenderink & van Doorn 1987), every receptor")


def flight_detection(receptors_csv, frame_npzs, outputs, *, spectral, receptor_set, target,
                     receptor_curves=DEFAULT_CURVES, title=""):
    """Whether, and how, an eye detects a flight's target along it, from the shares of
    :func:`trace_frames` (``frame_npzs``, in order, traced with the target).

    Writes ``detection`` (per frame: ``frame``, ``t_s``, ``distance_m`` and
    :func:`beeoptics.vision.detection.detect`'s columns, the target's share
    of each receptor's acceptance as the trace met it), ``first`` (JSON:
    where each criterion first holds, :func:`first_detections`) and
    ``figure`` (the target's angular size and contrasts along the flight,
    the first detections marked).

    Parameters
    ----------
    target : dict
        The flight's target (:func:`flight_products`).
    """
    from beeoptics.images import figures  # as in flight_products

    wl = grid(**spectral)
    table = read_receptors(receptors_csv)
    absent = lacking(receptor_set, ommatidium_types(receptor_set, len(table.id)))
    centre = np.asarray(target["position_m"], float)
    disc = (centre, np.asarray(target["normal"], float), float(target["radius_m"]))
    rows, k = [], 0
    for path in frame_npzs:
        share = dict(np.load(path))
        for j in range(len(share["frame"])):
            position, rotation = share["position_m"][j], share["rotation"][j]
            origins = table.position * 1e-3 @ rotation.T + position
            toward = centre - origins
            toward /= np.linalg.norm(toward, axis=1, keepdims=True)
            alpha = float(np.degrees(disc_angular_diameter(position, *disc)))
            # Catches of the receptors' radiance, not their irradiance: receptors of unequal Δρ compare alike.
            catches = catches_of(share["radiance"][j], wl, receptor_set, sensitivities=receptor_curves)
            if absent.size:
                catches[absent] = np.nan
            cover = share["cover"][j]
            ring = local_background(table.axis @ rotation.T, cover, toward, alpha / 2.0, table.delta_rho_deg,
                                    table.delta_phi_deg)
            rows.append({"frame": k, "t_s": float(share["time_s"][j]),
                         "distance_m": float(np.linalg.norm(centre - position)),
                         **detect(catches, cover, ring, alpha, rotation.T @ (centre - position), receptor_set)})
            k += 1
    columns = {c: np.array([r[c] for r in rows], float) for c in rows[0]}
    write_table(outputs["detection"], columns)
    first = first_detections(columns)
    write_json(outputs["first"], first)
    figures.flight_detection(columns, first, receptor_set.detection, outputs["figure"], title)


def flight_views(receptors_csv, scene_file, flight_file, human_npzs, outputs, *, fps, spectral, trace, threads,
                 receptor_set, receptor_curves=DEFAULT_CURVES, width_px=MAP_WIDTH_PX, title="", progress=None):
    """Views along a route, light and long: every receptor's catches at every frame of a flight, in one job.

    The scene is loaded once and every frame's receptors are traced with
    the flight's ``views`` settings (``trace``, a config's trace section: by
    default depth 1, 16 samples: direct light, the sun and the sky), as
    :func:`beeoptics.api.looks` traces a sequence of poses.
    Writes ``catches`` (npz: ``catches`` frames × receptors × classes,
    float32, each class's quantum catch of the receptor's radiance over
    that of a white Lambertian surface under the scene's light, map3's
    unit; ``classes``, ``id``, ``side``, ``t_s``, ``position_m``,
    ``rotation``), ``video`` (MP4 at ``fps``: map3 on the visual field
    beside the human view of ``human_npzs``, the shares of
    :func:`human_frames`, when given) and ``viewer``
    (:func:`beeoptics.images.viewer.flight_viewer`: the frames on the
    visual field with a slider, titled ``title``).

    Returns
    -------
    dict
        ``frames``, ``rays`` (every ray cast), ``trace_s`` (the tracing's wall time).
    """
    eye = load_eye(receptors_csv, receptor_set=receptor_set)
    table = eye.table
    flight = read_flight(flight_file)
    poses = [pose(flight, t) for t in frame_times(flight, fps)]
    counts = {}
    catches = np.array([view.relative for view in looks(eye, load_scene(scene_file, **spectral),
                                                        [{"position_m": p.position, "rotation": p.rotation}
                                                         for p in poses], sensitivities=receptor_curves, trace=trace,
                                                        threads=threads, progress=progress, counts=counts)],
                       np.float32).reshape(len(poses), len(table.id), len(receptor_set.classes))
    with atomic_path(outputs["catches"]) as tmp:
        np.savez(tmp, catches=catches, classes=np.array(receptor_set.classes), id=table.id,
                 side=np.asarray(table.side).astype(str), t_s=np.array([p.time for p in poses]),
                 position_m=np.array([p.position for p in poses]), rotation=np.array([p.rotation for p in poses]))
    field = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, width_px)
    humans = np.concatenate([np.load(f)["srgb"] for f in human_npzs]) if human_npzs else None
    frames = [video_frame(field, map3(catches[k], receptor_set.display), None if humans is None else humans[k])
              for k in range(len(poses))]
    write_mp4(outputs["video"], frames, fps)
    flight_viewer(outputs["viewer"], table, [encode(map3(c, receptor_set.display)) for c in catches], catches,
                  receptor_set.classes, [p.time for p in poses], title,
                  f"map3 (Collins §4.4): {display_words(receptor_set)}, each catch over a white Lambertian "
                  "surface's under the scene's light, so white shows white; traced with the flight's views settings "
                  f"({trace['samples_per_receptor']} samples a receptor, depth {trace['depth']}). Every receptor of "
                  "both eyes at its axis in the head's frame; hover for its catches at the frame shown.")
    return {"frames": len(poses), "rays": counts["cast"] + counts["shadow"], "trace_s": counts["seconds"]}


def video_frame(field, colours, human=None):
    """One frame of a views video, uint8 (h, w, 3): map3 of each receptor on the equirectangular visual
    field, azimuth running to the bee's left as on the animation's maps, grey where no receptor sees, and
    the human view (sRGB in [0, 1]) beside it, scaled to the map's height."""
    rgb = encode(paint(field.receptor, colours))
    rgb = np.where(np.isnan(rgb), 0.35, rgb)[:, ::-1]
    image = np.rint(rgb * 255.0).astype(np.uint8)
    if human is None:
        return image
    h = image.shape[0]
    rows = np.minimum((np.arange(h) * human.shape[0] / h).astype(int), human.shape[0] - 1)
    width = int(round(human.shape[1] * h / human.shape[0]))
    cols = np.minimum((np.arange(width) * human.shape[1] / width).astype(int), human.shape[1] - 1)
    beside = np.rint(np.clip(human[rows][:, cols], 0.0, 1.0) * 255.0).astype(np.uint8)
    return np.hstack([image, np.full((h, 4, 3), 255, np.uint8), beside])
