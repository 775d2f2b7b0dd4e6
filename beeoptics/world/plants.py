"""Plants built parametrically: grass blades, stems, leaves and four flower forms.

Every builder returns a :class:`Mesh` in the plant's own frame, metres,
+z up, the plant's foot at the origin: vertices, triangles and, per
triangle, the name of the part it belongs to (``"stem"``, ``"leaf"``,
``"ray_tip"``, ...), which the species' table turns into a palette colour
(:mod:`beeoptics.world.species`). Surfaces are single sheets, as petals and
leaves are; a bell has an outer and an inner wall, since the two sides of
a corolla reflect differently. Sizes are the species' (its table names the
flora they come from); the shapes are simple named curves: a blade bends
at constant curvature (an arc), a ray floret and a leaf are tapered
straps, a bell and a funnel are surfaces of revolution.

The proportions inside each form — a disc's dome, a ray floret's outline
and overlap, a bell's flare and lobes, a funnel's profile, the wall
between a bell's two sides — are drawing choices, not measurements: no
flora gives them, and at the distances a bee sees a flower from they set
its outline's detail, not its size or its colour.

Grass blades are built all at once, vectorised over blades; a flowering
plant is built once per variant and placed many times
(:mod:`beeoptics.world.meadow`).
"""

from typing import NamedTuple

import numpy as np


#: A mesh without flowers.
NO_FLOWERS = np.zeros((0, 7))


class Mesh(NamedTuple):
    """Triangles (m, 3) over vertices (n, 3), metres, and each triangle's part name (m,).

    ``flowers`` (k, 7) are the flowers it holds, each the sphere about it
    (centre x, y, z, radius) and the way it faces (a unit vector): what a
    bee approaches and detects (:mod:`beeoptics.vision.detection`).
    """

    vertices: np.ndarray
    faces: np.ndarray
    parts: np.ndarray
    flowers: np.ndarray = NO_FLOWERS


def flower(centre, radius, facing):
    """One flower's row of :attr:`Mesh.flowers`."""
    facing = np.asarray(facing, float)
    return np.array([[*np.asarray(centre, float), float(radius), *(facing / np.linalg.norm(facing))]])


def join(meshes):
    """One mesh of several, their triangles in order."""
    meshes = [m for m in meshes if len(m.faces) or len(m.flowers)]
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    return Mesh(np.vstack([m.vertices for m in meshes]),
                np.vstack([m.faces + o for m, o in zip(meshes, offsets)]),
                np.concatenate([m.parts for m in meshes]),
                np.vstack([NO_FLOWERS, *(m.flowers for m in meshes)]))


def transformed(mesh, rotation, translation, scale=1.0):
    """The mesh scaled, rotated (3, 3) and moved, its flowers with it."""
    rotation = np.asarray(rotation)
    f = mesh.flowers
    flowers = np.column_stack([scale * f[:, :3] @ rotation.T + translation, scale * f[:, 3], f[:, 4:] @ rotation.T])
    return mesh._replace(vertices=scale * mesh.vertices @ rotation.T + translation, flowers=flowers)


def strips(centres, sides, half_widths, part):
    """Strips along curves, ending in a point: one quad per step, a triangle at the tip.

    Parameters
    ----------
    centres, sides : ndarray, shape (n, k, 3)
        n strips of k stations: the midline, and the unit direction across it.
    half_widths : ndarray, shape (n, k)
        Half the strip's width at each station; the last station is the tip
        and gets one vertex.
    part : str
    """
    n, k = half_widths.shape
    left = centres[:, :-1] - sides[:, :-1] * half_widths[:, :-1, None]
    right = centres[:, :-1] + sides[:, :-1] * half_widths[:, :-1, None]
    # Per strip: left[0..k-2], right[0..k-2], tip.
    vertices = np.concatenate([left, right, centres[:, -1:]], axis=1)
    per = 2 * (k - 1) + 1
    i = np.arange(k - 2)
    l0, l1, r0, r1 = i, i + 1, k - 1 + i, k + i
    tip = np.array([[k - 2, 2 * k - 3, 2 * k - 2]])
    local = np.vstack([np.column_stack([l0, r0, r1]), np.column_stack([l0, r1, l1]), tip])
    faces = (local[None] + per * np.arange(n)[:, None, None]).reshape(-1, 3)
    return Mesh(vertices.reshape(-1, 3), faces, np.full(len(faces), part, dtype=object))


def arcs(length, inclination, curvature, azimuth, stations):
    """Midlines that leave the origin at ``inclination`` from vertical and bend at constant curvature.

    All arguments but ``stations`` are arrays of shape (n,): metres,
    radians, radians per metre (positive bends away from vertical), radians
    from +x. Returns the points (n, stations, 3) and the unit horizontal
    direction across each arc (n, 3).
    """
    s = np.linspace(0.0, 1.0, stations)[None, :] * length[:, None]
    theta = inclination[:, None] + curvature[:, None] * s
    # Midpoint rule along the arc: each step follows the angle at its middle.
    ds = np.diff(s, axis=1)
    mid = 0.5 * (theta[:, 1:] + theta[:, :-1])
    horizontal = np.concatenate([np.zeros((len(s), 1)), np.cumsum(np.sin(mid) * ds, axis=1)], axis=1)
    up = np.concatenate([np.zeros((len(s), 1)), np.cumsum(np.cos(mid) * ds, axis=1)], axis=1)
    c, si = np.cos(azimuth)[:, None], np.sin(azimuth)[:, None]
    points = np.stack([horizontal * c, horizontal * si, up], axis=-1)
    across = np.stack([-np.sin(azimuth), np.cos(azimuth), np.zeros_like(azimuth)], axis=-1)
    return points, across


def blades(length, width, inclination, curvature, azimuth, stations=6, part="grass"):
    """Grass blades: tapered strips along arcs (:func:`arcs`), width falling as √(1 − s/L) to a point."""
    points, across = arcs(length, inclination, curvature, azimuth, stations)
    taper = np.sqrt(1.0 - np.linspace(0.0, 1.0, stations))
    return strips(points, np.broadcast_to(across[:, None], points.shape), 0.5 * width[:, None] * taper, part)


def leaf(length, width, inclination, curvature, azimuth, stations=6, part="leaf"):
    """A lanceolate leaf: a strap along an arc, widest at a third of its length, pointed at the tip."""
    points, across = arcs(*(np.atleast_1d(np.asarray(a, float)) for a in (length, inclination, curvature, azimuth)),
                          stations)
    s = np.linspace(0.0, 1.0, stations)
    shape = np.sin(np.pi * s**0.63)  # peak where s^0.63 = 1/2, at s ≈ 1/3
    shape[0] = 0.15  # a petiole's width at the foot, not a point
    return strips(points, np.broadcast_to(across[:, None], points.shape), 0.5 * width * shape[None], part)


def tube(points, radius, part="stem", sides=3):
    """A thin prism of ``sides`` faces round a polyline (k, 3): a stem or a pedicel, open at both ends."""
    points = np.asarray(points, float)
    tangent = np.gradient(points, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    helper = np.where(np.abs(tangent[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    u = np.cross(tangent, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(tangent, u)
    phi = 2.0 * np.pi * np.arange(sides) / sides
    ring = np.cos(phi)[None, :, None] * u[:, None] + np.sin(phi)[None, :, None] * v[:, None]
    vertices = (points[:, None] + radius * ring).reshape(-1, 3)
    k = len(points)
    i, j = np.meshgrid(np.arange(k - 1), np.arange(sides), indexing="ij")
    a, b = i * sides + j, i * sides + (j + 1) % sides
    c, d = a + sides, b + sides
    faces = np.vstack([np.column_stack([a.ravel(), b.ravel(), d.ravel()]),
                       np.column_stack([a.ravel(), d.ravel(), c.ravel()])])
    return Mesh(vertices, faces, np.full(len(faces), part, dtype=object))


def revolution(profile_radius, profile_height, wobble=None, sectors=15, part="corolla", part_of_ring=None):
    """A surface of revolution about +z: radius and height (k,) per ring, ``sectors`` round.

    ``wobble`` (k, sectors) multiplies each ring's radius (lobes of a
    corolla); ``part_of_ring`` (k − 1,) names the part of each band of
    triangles, else all are ``part``. The first ring may have radius 0.
    """
    r = np.asarray(profile_radius, float)
    z = np.asarray(profile_height, float)
    phi = 2.0 * np.pi * np.arange(sectors) / sectors
    radius = r[:, None] * (np.ones(sectors) if wobble is None else wobble)
    vertices = np.stack([radius * np.cos(phi), radius * np.sin(phi), np.broadcast_to(z[:, None], radius.shape)],
                        axis=-1).reshape(-1, 3)
    k = len(r)
    i, j = np.meshgrid(np.arange(k - 1), np.arange(sectors), indexing="ij")
    a, b = i * sectors + j, i * sectors + (j + 1) % sectors
    c, d = a + sectors, b + sectors
    lower = np.column_stack([a.ravel(), b.ravel(), d.ravel()])
    upper = np.column_stack([a.ravel(), d.ravel(), c.ravel()])
    names = np.repeat(np.asarray(part_of_ring if part_of_ring is not None else [part] * (k - 1), dtype=object),
                      sectors)
    faces, parts = np.vstack([lower, upper]), np.concatenate([names, names])
    if r[0] == 0.0:  # the first ring is one point: drop the triangles that collapse onto it
        keep = ~(np.isin(faces, np.arange(sectors)).sum(1) >= 2)
        faces, parts = faces[keep], parts[keep]
    return Mesh(vertices, faces, parts)


def rotation_to(direction):
    """A rotation (3, 3) taking +z to the unit ``direction``, turning about the horizontal."""
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    axis = np.cross([0.0, 0.0, 1.0], d)
    s, c = np.linalg.norm(axis), d[2]
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = axis / s
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * kx + (1 - c) * kx @ kx


def composite_head(head_diameter, disc_diameter, rays, droop, rng, sectors=16):
    """A daisy-like capitulum facing +z at the origin: a domed disc and a ring of ray florets.

    Each ray is a strap from the disc's rim to the head's rim, its inner
    half ``ray_base``, its outer half ``ray_tip`` (the two may differ in the
    ultraviolet, as in a bullseye); ``droop`` lowers the tips, metres.
    """
    rd = disc_diameter / 2.0
    disc = revolution([0.0, 0.55 * rd, rd], [0.35 * rd, 0.25 * rd, 0.0], sectors=sectors, part="disc")
    length = (head_diameter - disc_diameter) / 2.0
    width = min(2.0 * np.pi * rd / rays * 1.6, 0.45 * length)  # neighbouring rays overlap a little
    angle = 2.0 * np.pi * (np.arange(rays) + rng.uniform(-0.15, 0.15, rays)) / rays
    t = np.linspace(0.0, 1.0, 5)
    radial = rd * 0.95 + length * t
    centres = np.stack([np.cos(angle)[:, None] * radial, np.sin(angle)[:, None] * radial,
                        np.broadcast_to(-droop * t**2, (rays, len(t)))], axis=-1)
    across = np.stack([-np.sin(angle), np.cos(angle), np.zeros(rays)], axis=-1)
    half = 0.5 * width * np.array([0.6, 1.0, 1.0, 0.8, 0.0])
    ray = strips(centres, np.broadcast_to(across[:, None], centres.shape), np.broadcast_to(half, (rays, 5)), "ray")
    # Per ray, faces 0–2 and 4 lie in the inner half, 3, 5 and the tip in the outer one.
    inner = np.tile(np.array([True, True, False, True, True, False, False]), rays)
    ray = ray._replace(parts=np.where(inner, "ray_base", "ray_tip").astype(object))
    return join([disc, ray])


def bell(length, mouth_diameter, lobes=5, sectors=15):
    """A bell opening towards +z from its base at the origin: ``bell_outer`` and ``bell_inner`` walls."""
    t = np.linspace(0.0, 1.0, 5)
    radius = mouth_diameter / 2.0 * (0.35 + 0.65 * t**0.8)
    height = length * t
    phi = 2.0 * np.pi * np.arange(sectors) / sectors
    lobing = 1.0 + 0.12 * t[:, None] ** 3 * np.cos(lobes * phi)[None]
    outer = revolution(radius, height, lobing, sectors, "bell_outer")
    inner = revolution(0.92 * radius, height + 0.02 * length, lobing, sectors, "bell_inner")
    # The inner wall faces inwards: reverse its triangles.
    bell = join([outer, inner._replace(faces=inner.faces[:, ::-1])])
    return bell._replace(flowers=flower([0.0, 0.0, length / 2.0], np.hypot(length / 2.0, mouth_diameter / 2.0),
                                        [0.0, 0.0, 1.0]))


def funnel(length, mouth_diameter, lobes=5, sectors=10):
    """A funnel-shaped corolla opening towards +z, its flared last band the ``limb``, with a ``calyx`` below."""
    t = np.array([0.0, 0.35, 0.7, 0.9, 1.0])
    radius = mouth_diameter / 2.0 * np.array([0.15, 0.3, 0.5, 0.8, 1.0])
    height = length * t
    phi = 2.0 * np.pi * np.arange(sectors) / sectors
    lobing = 1.0 + 0.15 * (t[:, None] > 0.85) * np.cos(lobes * phi)[None]
    corolla = revolution(radius, height, lobing, sectors, part_of_ring=["corolla"] * 3 + ["limb"])
    calyx = revolution([0.0, 0.2 * mouth_diameter], [-0.05 * length, 0.25 * length], sectors=5, part="calyx")
    around = flower([0.0, 0.0, length / 2.0], np.hypot(length / 2.0, mouth_diameter / 2.0), [0.0, 0.0, 1.0])
    return join([corolla, calyx])._replace(flowers=around)
