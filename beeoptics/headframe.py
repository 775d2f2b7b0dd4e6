"""The head frame and directions in it.

The head frame is the one every table and image uses: +x anterior, +y to
the bee's left, +z dorsal, in millimetres, origin between the eyes. The
right eye therefore lies at negative y.

Two azimuth conventions are in use, each with its own function. An eye's
azimuth (:func:`eye_direction`) is measured in the horizontal plane from +x,
positive towards the eye's own side (towards -y for the right eye, +y for the
left), the convention of Stürzl et al. (2010) for the field of view of one
eye. The other (:func:`direction_from_x_towards_y`) runs from +x towards +y,
counter-clockwise seen from above, for maps of both eyes and for the world
frame of scenes (the sun's azimuth). Elevation is measured from the xy-plane,
positive dorsal (up), in both.

References
----------
Stürzl W, Boeddeker N, Dittmar L, Egelhaaf M (2010) Mimicking honeybee eyes
with a 280° field of view catadioptric imaging system. Bioinspir Biomim
5:036002.
"""

import numpy as np
from scipy.spatial.transform import Rotation

#: The sizes bee eyes come in, mm: even the smallest bees' eyes are a few tenths of a
#: millimetre long, and the largest, the drone honey bee's, a few millimetres (Streinzer et
#: al. 2013). An eye outside this range is in other units (metres, say).
EYE_SIZE_MM = (0.1, 20.0)
#: The eyes, right first: the order of receptor tables, and the side codes of PLY files.
RIGHT, LEFT = "right", "left"
SIDES = (RIGHT, LEFT)


#: The head's directions, by the names a file's frame is given in (:func:`frame_axes`).
DIRECTIONS = {"anterior": (1.0, 0.0, 0.0), "posterior": (-1.0, 0.0, 0.0), "left": (0.0, 1.0, 0.0),
              "right": (0.0, -1.0, 0.0), "dorsal": (0.0, 0.0, 1.0), "ventral": (0.0, 0.0, -1.0)}
#: Named frames of eye files: this package's head frame, and a camera's (x right, y up, z forward).
FRAMES = {"head": "x=anterior,y=left,z=dorsal", "camera": "x=right,y=dorsal,z=anterior"}


def frame_axes(frame):
    """A file's frame as the head-frame directions of its x, y and z axes, rows of a (3, 3) matrix.

    Parameters
    ----------
    frame : str
        A name of :data:`FRAMES`, or ``"x=<direction>,y=<direction>,z=<direction>"`` with
        directions of :data:`DIRECTIONS`, each axis of the head once: micro-CT eyes come in
        whatever frame their scan was registered in (``x=left,y=ventral,z=posterior``, say).
        A point (x, y, z) of the file is then x·row₀ + y·row₁ + z·row₂ in the head frame.

    Raises
    ------
    ValueError
        If the frame is not of that form, or names a head axis twice.
    """
    spec = FRAMES.get(frame, frame)
    try:
        parts = dict(item.split("=") for item in spec.replace(" ", "").split(","))
        rows = np.array([DIRECTIONS[parts.pop(axis)] for axis in ("x", "y", "z")])
    except (ValueError, KeyError):
        raise ValueError(f"a frame is {' or '.join(FRAMES)}, or x=…,y=…,z=… naming for each of the file's axes one "
                         f"of {', '.join(DIRECTIONS)}; not {frame!r}") from None
    if parts or abs(np.linalg.det(rows)) != 1.0:
        raise ValueError(f"the frame {frame!r} must name each of the file's axes once and each head axis once")
    return rows


def side_sign(side):
    """Return -1 for the right eye and +1 for the left: the sign of y on that side."""
    if side not in SIDES:
        raise ValueError(f"side must be one of {SIDES}, not {side!r}")
    return -1.0 if side == RIGHT else 1.0


def direction_from_x_towards_y(azimuth_deg, elevation_deg):
    """Unit vectors, azimuth from +x towards +y, elevation from the xy-plane towards +z.

    Parameters
    ----------
    azimuth_deg, elevation_deg : array_like
        Degrees.

    Returns
    -------
    ndarray, shape (..., 3)
    """
    az = np.radians(np.asarray(azimuth_deg, float))
    el = np.radians(np.asarray(elevation_deg, float))
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], -1)


def eye_direction(azimuth_deg, elevation_deg, side=RIGHT):
    """Unit vectors in the head frame for azimuths and elevations of one eye.

    Parameters
    ----------
    azimuth_deg, elevation_deg : array_like
        Degrees, azimuth positive towards the eye's own side.
    side : {"right", "left"}

    Returns
    -------
    ndarray, shape (..., 3)
    """
    out = direction_from_x_towards_y(azimuth_deg, elevation_deg)
    out[..., 1] *= side_sign(side)
    return out


def eye_azimuth_elevation(vectors, side=RIGHT):
    """Azimuth and elevation in degrees of head-frame vectors, as seen by one eye."""
    v = np.asarray(vectors, float)
    v = v / np.linalg.norm(v, axis=-1, keepdims=True)
    az = np.degrees(np.arctan2(side_sign(side) * v[..., 1], v[..., 0]))
    el = np.degrees(np.arcsin(np.clip(v[..., 2], -1.0, 1.0)))
    return az, el


def eye_rotation(azimuth_deg, elevation_deg, roll_deg=0.0):
    """Rotation whose rows are the right eye's local x, y, z axes in the head frame.

    Local z points along (azimuth, elevation); local y is the head's dorsal
    direction made perpendicular to z, then turned by ``roll_deg`` about z;
    local x = y × z, which for a laterally facing right eye points anterior.
    """
    z = eye_direction(azimuth_deg, elevation_deg, RIGHT)
    up = np.array([0.0, 0.0, 1.0])
    y = up - z * (up @ z)
    y /= np.linalg.norm(y)
    x = np.cross(y, z)
    r = np.deg2rad(roll_deg)
    x, y = np.cos(r) * x + np.sin(r) * y, -np.sin(r) * x + np.cos(r) * y
    return np.stack([x, y, z])


def head_rotation(heading_deg, pitch_deg, roll_deg=0.0):
    """The head frame's rotation in the world (3, 3), columns its axes: heading about world z (from +x
    towards +y), then pitch (nose up positive), then roll (right side down positive)."""
    return (Rotation.from_euler("z", heading_deg, degrees=True) * Rotation.from_euler("y", -pitch_deg, degrees=True)
            * Rotation.from_euler("x", roll_deg, degrees=True)).as_matrix()


def in_eye_plane(rotation):
    """The head's anterior and dorsal directions in an eye's local xy-plane, unit 2-vectors (2, 2).

    ``rotation`` is the eye's (:func:`eye_rotation`); rows: anterior, dorsal.
    """
    planar = (np.asarray(rotation) @ np.eye(3)[:, [0, 2]])[:2].T
    return planar / np.linalg.norm(planar, axis=1, keepdims=True)


def mirror(points):
    """Mirror head-frame points or vectors through the sagittal (xz) plane."""
    out = np.array(points, float, copy=True)
    out[..., 1] *= -1.0
    return out


def microvillar_angle(axes, directions):
    """The angle of ``directions`` about each axis, from the head's dorsal towards its anterior, degrees in [0, 180).

    Parameters
    ----------
    axes, directions : ndarray (n, 3)
        Head frame; ``axes`` unit vectors.
    """
    axes = np.asarray(axes, float)
    up = _orthogonal([0.0, 0.0, 1.0], axes)
    ahead = _orthogonal([1.0, 0.0, 0.0], axes, up)
    return np.degrees(np.arctan2((directions * ahead).sum(1), (directions * up).sum(1))) % 180.0


def _orthogonal(vector, *against):
    """``vector`` made perpendicular to each row of every array in ``against`` (unit rows), normalised."""
    out = np.broadcast_to(np.asarray(vector, float), against[0].shape).copy()
    for basis in against:
        out -= basis * (out * basis).sum(1, keepdims=True)
    return out / np.linalg.norm(out, axis=1, keepdims=True)
