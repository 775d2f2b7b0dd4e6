"""Flights: a bee's path through a scene, its frames, and the optic flow it sees.

A flight is a CSV of ``t_s, x_m, y_m, z_m, heading_deg, pitch_deg,
roll_deg``: time, the head's position in the scene (metres, world +z up)
and its orientation as the scene's ``eye`` gives it (heading from +x
towards +y, nose up positive, right side down positive). Between rows the
position is interpolated linearly and the orientation by spherical linear
interpolation, so that the bee moves at constant velocity and turns at
constant angular velocity along each segment. Frames are taken at a fixed
rate from the first row's time.

Optic flow is the angular velocity of the image in each viewing
direction d (unit, world) at distance D, for the head moving at velocity
v and turning at angular velocity ω (Koenderink & van Doorn 1987):

    ṗ = −(v − (v·d) d) / D − ω × d,

in radians per second, tangent to the sphere of directions; where nothing
is hit (D infinite) only the rotational part remains.

References
----------
Koenderink JJ, van Doorn AJ (1987) Facts on optic flow. Biol Cybern
56:247–254.
"""

from typing import NamedTuple

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from beeoptics.io.errors import InputError
from beeoptics.io.table import read_table
from beeoptics.headframe import head_rotation

COLUMNS = ["t_s", "x_m", "y_m", "z_m", "heading_deg", "pitch_deg", "roll_deg"]
#: How far from the origin a flight may go, m: honey bees forage up to about 10 km from the hive (Beekman &
#: Ratnieks 2000, Funct Ecol 14:490).
REACH_M = 10000.0
#: The fastest a flight may go, m/s: honey bees fly at up to about 8 m/s (von Frisch 1967, The Dance Language
#: and Orientation of Bees); no insect flies at 50 m/s (180 km/h), which a flight written in millimetres, or
#: with its times in milliseconds, exceeds.
SPEED_MAX_M_S = 50.0


class Flight(NamedTuple):
    """A flight's rows: times (n,), s; positions (n, 3), m; head rotations (n, 3, 3)."""

    time: np.ndarray
    position: np.ndarray
    rotation: np.ndarray


class Pose(NamedTuple):
    """The head at one instant: position (3,), rotation (3, 3), velocity (3,), m/s, angular velocity (3,), rad/s (world)."""

    time: float
    position: np.ndarray
    rotation: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray

    def eye(self):
        """The scene ``eye`` section this pose gives (position, heading, pitch, roll)."""
        z, y, x = Rotation.from_matrix(self.rotation).as_euler("ZYX", degrees=True)
        return {"position_m": [float(v) for v in self.position], "heading_deg": float(z), "pitch_deg": float(-y),
                "roll_deg": float(x)}


def read_flight(path):
    """A flight CSV, checked: every column present and finite, time strictly increasing, two rows at least,
    positions within :data:`REACH_M` of the origin and no faster than :data:`SPEED_MAX_M_S` between rows
    (angles may take any value: they are turns, and a flight may turn round more than once)."""
    table = read_table(path, numeric=COLUMNS)
    missing = [c for c in COLUMNS if c not in table]
    if missing:
        raise InputError(path, missing[0], f"a flight needs the columns {', '.join(COLUMNS)}")
    for c in COLUMNS:
        bad = np.flatnonzero(~np.isfinite(np.asarray(table[c], float)))
        if bad.size:
            raise InputError(path, c, f"row {bad[0] + 1} is not a finite number")
    t = np.asarray(table["t_s"], float)
    if len(t) < 2:
        raise InputError(path, "t_s", "a flight needs at least two rows")
    if np.any(np.diff(t) <= 0):
        raise InputError(path, "t_s", f"time must increase from row to row (row {np.argmax(np.diff(t) <= 0) + 2})")
    position = np.column_stack([table[c] for c in ("x_m", "y_m", "z_m")]).astype(float)
    far = np.flatnonzero(np.abs(position).max(axis=1) > REACH_M)
    if far.size:
        raise InputError(path, "x_m, y_m, z_m", f"row {far[0] + 1} is more than {REACH_M:g} m from the origin, "
                         "farther than bees forage: is the flight in millimetres?")
    speed = np.linalg.norm(np.diff(position, axis=0), axis=1) / np.diff(t)
    if speed.max() > SPEED_MAX_M_S:
        raise InputError(path, "t_s", f"rows {np.argmax(speed) + 1}–{np.argmax(speed) + 2} fly at "
                         f"{speed.max():.3g} m/s; no insect flies faster than {SPEED_MAX_M_S:g} m/s: are the "
                         "positions in millimetres, or the times in milliseconds?")
    rotation = np.array([head_rotation(h, p, r) for h, p, r in
                         zip(table["heading_deg"], table["pitch_deg"], table["roll_deg"])])
    return Flight(t, position, rotation)


def frame_times(flight, fps):
    """The times of the frames, ``fps`` a second from the flight's first row to its last."""
    n = int(np.floor((flight.time[-1] - flight.time[0]) * fps + 1e-9)) + 1
    return flight.time[0] + np.arange(n) / fps


def pose(flight, t):
    """The head's pose at time ``t`` (within the flight), with the velocities of the segment it is on."""
    k = int(np.clip(np.searchsorted(flight.time, t, side="right") - 1, 0, len(flight.time) - 2))
    t0, t1 = flight.time[k], flight.time[k + 1]
    r = Rotation.from_matrix(flight.rotation[k:k + 2])
    u = (t - t0) / (t1 - t0)
    position = (1.0 - u) * flight.position[k] + u * flight.position[k + 1]
    rotation = Slerp([t0, t1], r)([t]).as_matrix()[0]
    velocity = (flight.position[k + 1] - flight.position[k]) / (t1 - t0)
    # World-frame angular velocity: the segment's relative rotation R1 R0ᵀ as a rotation vector, per second.
    angular = (r[1] * r[0].inv()).as_rotvec() / (t1 - t0)
    return Pose(float(t), position, rotation, velocity, angular)


def optic_flow(directions, distances, velocity, angular_velocity):
    """Optic flow (n, 3), rad/s, world frame, of unit viewing ``directions`` (n, 3) at ``distances`` (n,), m.

    Koenderink & van Doorn's (1987) flow for a head translating at
    ``velocity`` (3,) and rotating at ``angular_velocity`` (3,); infinite
    distances (the sky) have the rotational part only.
    """
    d = np.asarray(directions, float)
    v = np.asarray(velocity, float)
    along = (d * v).sum(1, keepdims=True)
    with np.errstate(divide="ignore"):
        inverse = np.where(np.isfinite(distances), 1.0 / np.asarray(distances, float), 0.0)[:, None]
    return -(v - along * d) * inverse - np.cross(np.asarray(angular_velocity, float), d)


def azimuth_elevation_components(directions, vectors):
    """Components (n, 2) of tangent ``vectors`` along increasing azimuth and elevation at ``directions`` (n, 3)."""
    d = np.asarray(directions, float)
    az = np.arctan2(d[:, 1], d[:, 0])
    el = np.arcsin(np.clip(d[:, 2], -1.0, 1.0))
    e_az = np.column_stack([-np.sin(az), np.cos(az), np.zeros_like(az)])
    e_el = np.column_stack([-np.sin(el) * np.cos(az), -np.sin(el) * np.sin(az), np.cos(el)])
    return np.column_stack([(vectors * e_az).sum(1), (vectors * e_el).sum(1)])


def disc_hits(origins, directions, centre, normal, radius):
    """Which rays (n,) from ``origins`` along unit ``directions`` meet a disc (centre, unit normal, radius), ahead."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    denominator = directions @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((np.asarray(centre, float) - origins) @ n) / denominator
    at = origins + t[:, None] * directions
    return (t > 0.0) & (np.linalg.norm(at - centre, axis=1) <= radius)


def disc_angular_diameter(point, centre, normal, radius, samples=180):
    """The largest angle, radians, between two points of a disc's rim seen from ``point``."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    u = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    phi = 2.0 * np.pi * np.arange(samples) / samples
    rim = np.asarray(centre, float) + radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)
    rays = rim - np.asarray(point, float)
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    return float(np.arccos(np.clip(rays @ rays.T, -1.0, 1.0)).max())


def approach(target_m, start_m, end_m, descent_deg, time_constant_s, step_s):
    """A flight straight at a point, slowing as it nears: rows of :data:`COLUMNS` (a dict of arrays).

    The bee flies along the line that descends at ``descent_deg`` towards
    ``target_m`` from the −x side, facing along it, its distance falling
    exponentially from ``start_m`` to ``end_m`` with ``time_constant_s``:
    a constant relative rate of approach, the constant rate of image
    expansion with which bees land (Baird et al. 2013, PNAS 110:18686).
    Rows come every ``step_s`` seconds, and at the end.
    """
    duration = time_constant_s * np.log(start_m / end_m)
    t = np.append(np.arange(0.0, duration, step_s), duration)
    d = start_m * np.exp(-t / time_constant_s)
    a = np.radians(descent_deg)
    offset = np.column_stack([-np.cos(a) * d, np.zeros_like(d), np.sin(a) * d])
    p = np.asarray(target_m, float) + offset
    return {"t_s": t, "x_m": p[:, 0], "y_m": p[:, 1], "z_m": p[:, 2], "heading_deg": np.zeros_like(t),
            "pitch_deg": np.full_like(t, -descent_deg), "roll_deg": np.zeros_like(t)}
