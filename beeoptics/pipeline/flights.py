"""The flight stages: trace each frame of a flight, render its human view, and turn the frames into
an animation, a table of responses, the optic flow and the approached flower's catches.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically. A frame is traced exactly as
a scene is (:func:`beeoptics.pipeline.trace.trace_receptors`), with the scene's
eye moved to the flight's pose at the frame's time
(:mod:`beeoptics.world.flight`), so frames are cached and spread over jobs
one by one.
"""

import numpy as np

from beeoptics.eye.fieldofview import visual_field
from beeoptics.images import figures
from beeoptics.images.display import bee_colours, encode
from beeoptics.images.fieldmaps import paint
from beeoptics.io.atomic import atomic_path
from beeoptics.io.imagefile import read_image, write_gif
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import write_table
from beeoptics.light.scene import load_scene, raycasting_scene, receptors_in_world
from beeoptics.pipeline.trace import human_view, respond, trace_receptors
from beeoptics.raycasting import first_hits
from beeoptics.spectra import grid
from beeoptics.vision.sensitivity import PEITSCH_1992, RECEPTORS
from beeoptics.world.flight import (azimuth_elevation_components, disc_angular_diameter, disc_hits, frame_times,
                                    optic_flow, pose, read_flight)

#: Width of the equirectangular maps of the animation, pixels (one degree each).
MAP_WIDTH_PX = 360


def frame_count(flight_file, fps):
    """How many frames a flight has at ``fps``."""
    return len(frame_times(read_flight(flight_file), fps))


def frame_pose(flight_file, fps, frame):
    """The head's pose at a frame."""
    flight = read_flight(flight_file)
    return pose(flight, frame_times(flight, fps)[frame])


def trace_frame(receptors_csv, scene_file, flight_file, outputs, *, frame, fps, spectral, settings):
    """Trace every receptor at one frame of a flight: ``outputs["radiance"]`` (as a trace share) and
    ``outputs["geometry"]`` (the pose, and each receptor's distance along its axis to the first surface,
    infinite for the sky)."""
    p = frame_pose(flight_file, fps, frame)
    wl = grid(**spectral)
    scene = load_scene(scene_file, wl, eye=p.eye())
    table = read_receptors(receptors_csv)
    rs = raycasting_scene(scene)
    radiance, _ = trace_receptors(scene, table, 0, len(table.id), settings, len(wl), rs=rs)
    with atomic_path(outputs["radiance"]) as tmp:
        np.savez(tmp, id=table.id, radiance=radiance)
    origins, axes = receptors_in_world(scene, table.position, table.axis)
    depth = first_hits(rs, np.column_stack([origins, axes]).astype(np.float32))["t_hit"].astype(np.float64)
    with atomic_path(outputs["geometry"]) as tmp:
        np.savez(tmp, id=table.id, depth_m=depth, time_s=p.time, position_m=p.position, rotation=p.rotation,
                 velocity_m_s=p.velocity, angular_velocity_rad_s=p.angular_velocity)


def human_frame(scene_file, flight_file, outputs, *, frame, fps, spectral, settings, size_px):
    """The human view from the bee's head at one frame of a flight: ``outputs["png"]``."""
    human_view(scene_file, outputs, spectral=spectral, settings=settings,
               eye=frame_pose(flight_file, fps, frame).eye(), size_px=size_px)


def flight_products(receptors_csv, scene_file, radiance_npzs, geometry_npzs, human_pngs, outputs, *, fps,
                    spectral, target=None, background="scene", receptor_curves=PEITSCH_1992, title=""):
    """The frames of one eye's flight, gathered.

    Writes ``responses`` (every receptor's catches and colour coordinates at
    every frame, with ``frame`` and ``t_s``), ``optic_flow`` (every
    receptor's distance along its axis and its optic flow, head frame,
    degrees per second along azimuth and elevation), ``target`` (per frame:
    the distance to the target's centre, its angular diameter, how many
    receptors' axes meet it and their mean catches relative to white),
    ``animation`` (GIF at ``fps``: map3 and the UV channel on the visual
    field beside the human view) and ``flow_figure`` (the middle frame's
    flow field).

    Parameters
    ----------
    target : dict, optional
        The flower the flight approaches, as a disc: ``position_m`` (3,)
        of its centre, ``radius_m`` and ``normal`` (3,), the way it faces.
    """
    wl = grid(**spectral)
    table = read_receptors(receptors_csv)
    scene = load_scene(scene_file, wl)
    field = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, MAP_WIDTH_PX)
    seen = field.receptor >= 0
    # Receptor axes in the head frame: azimuth and elevation of each, for the flow's components.
    head_axes = table.axis / np.linalg.norm(table.axis, axis=1, keepdims=True)
    az = np.degrees(np.arctan2(head_axes[:, 1], head_axes[:, 0]))
    el = np.degrees(np.arcsin(np.clip(head_axes[:, 2], -1.0, 1.0)))
    responses, flows, targets, frames = [], [], [], []
    for k, (radiance_npz, geometry_npz, human_png) in enumerate(zip(radiance_npzs, geometry_npzs, human_pngs)):
        g = np.load(geometry_npz)
        radiance = np.load(radiance_npz)["radiance"]
        columns, arrays = respond(table, radiance, scene, wl, scene_file, background=background,
                                  receptor_curves=receptor_curves)
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
        catches = np.column_stack([columns[r] for r in RECEPTORS])
        relative, colours, _ = bee_colours(catches, arrays["white_q"], wl, radiance)
        if target is not None:
            origins = table.position * 1e-3 @ rotation.T + g["position_m"]
            disc = (target["position_m"], target["normal"], target["radius_m"])
            on = disc_hits(origins, world_axes, *disc)
            distance = float(np.linalg.norm(np.asarray(target["position_m"]) - g["position_m"]))
            targets.append({"frame": k, "t_s": float(g["time_s"]), "distance_m": distance,
                            "angular_diameter_deg": np.degrees(disc_angular_diameter(g["position_m"], *disc)),
                            "receptors": int(on.sum()),
                            **{f"{r}_relative": float(relative[on, j].mean()) if on.any() else np.nan
                               for j, r in enumerate(RECEPTORS)}})
        panels = {"bee colours (map3)": np.where(seen[..., None], encode(paint(field, colours)), np.nan),
                  "UV catch over white's": np.repeat(np.clip(paint(field, relative[:, :1]), 0.0, 1.0), 3, -1)}
        frames.append(figures.visual_field_frame(panels, field.eyes, field.azimuth_deg, field.elevation_deg,
                                                 read_image(human_png)[0][..., :3],
                                                 f"{title}, t = {float(g['time_s']):.2f} s"))
    write_table(outputs["responses"], {c: np.concatenate([r[c] for r in responses]) for c in responses[0]})
    write_table(outputs["optic_flow"], {c: np.concatenate([f[c] for f in flows]) for c in flows[0]})
    if targets:
        write_table(outputs["target"], {c: np.array([t[c] for t in targets]) for c in targets[0]})
    else:
        write_table(outputs["target"], {"frame": np.arange(len(frames))})
    write_gif(outputs["animation"], frames, fps)
    middle = flows[len(flows) // 2]
    figures.optic_flow(az, el, np.column_stack([middle["flow_azimuth_deg_s"], middle["flow_elevation_deg_s"]]),
                       outputs["flow_figure"], f"{title}: optic flow at t = {middle['t_s'][0]:.2f} s "
                       "(Koenderink & van Doorn 1987), every receptor")
