"""Species of the meadow: their form, their sizes as floras give them, and the colour of each part.

A species is a mapping (``beeoptics/world/data/species.yaml`` holds the
meadow's own, each size with its source; a meadow file may add more):

``form``
    ``composite`` (a daisy-like capitulum on a stem), ``corymb`` (many
    small capitula in a flat-topped cluster, like an umbel), ``bell``
    (pendent bells on arching pedicels) or ``spike`` (funnel flowers up
    the top of the stem).
sizes
    ``[low, high]`` ranges, metres or counts, drawn uniformly for each
    variant: ``stem_height_m``, ``leaves``, ``leaf_length_m``,
    ``leaf_width_m``, ``leaf_height_fraction``, ``leaf_inclination_deg``, and per form ``head_diameter_m``,
    ``disc_diameter_m``, ``rays``, ``corymb_diameter_m`` (its heads are as
    many as fill it, hexagonally packed), ``flowers``, ``corolla_length_m``, ``corolla_diameter_m``,
    ``spike_fraction``.
``colours``
    ``"#rrggbb"`` for each part the form has (``stem``, ``leaf``, and
    ``disc``, ``ray_base``, ``ray_tip``; ``bell_outer``, ``bell_inner``;
    ``corolla``, ``limb``, ``calyx``). The generated mesh carries them as
    face colours, which a scene's ``palette`` maps to measured spectra.

How a plant is put together — how far a stem leans and bends, how a
corymb domes, how far a pedicel arches, which way a flower faces — is
drawn from ranges that are drawing choices (no flora gives them), marked
where they are used; the sizes are the species'.
"""

from functools import cache
from pathlib import Path

import numpy as np
import yaml

from beeoptics.io.errors import InputError
from beeoptics.world import plants

SPECIES_FILE = Path(__file__).parent / "data" / "species.yaml"
#: The parts each form is made of.
PARTS = {
    "composite": ("stem", "leaf", "disc", "ray_base", "ray_tip"),
    "corymb": ("stem", "leaf", "disc", "ray_base", "ray_tip"),
    "bell": ("stem", "leaf", "bell_outer", "bell_inner"),
    "spike": ("stem", "leaf", "corolla", "limb", "calyx"),
}
#: Radius of a stem, metres, and of a pedicel, as a fraction of its length (shape choices: no
#: flora gives them; stems and pedicels are seen as lines at a bee's distances).
STEM_RADIUS_M, PEDICEL_RADIUS = 0.0015, 0.04
#: Where leaves grow, as a fraction of the stem's height, and their angle from vertical (shape choices).
LEAF_HEIGHT_FRACTION, LEAF_INCLINATION_DEG = [0.0, 0.4], [30.0, 65.0]
#: How far a ray floret's tip droops below its base, as a fraction of the head's diameter (shape choice).
DROOP = 0.1
#: The densest packing of equal discs in the plane, π/(2√3) (Thue's theorem).
HEXAGONAL_PACKING = np.pi / (2.0 * np.sqrt(3.0))


@cache
def _table():
    return yaml.load(SPECIES_FILE.read_text(), Loader=yaml.CSafeLoader)["species"]


def species_table(extra=None):
    """The package's species, with ``extra`` ones (a meadow file's) added or replacing them."""
    return {**_table(), **(extra or {})}


def _draw(rng, spec, key, integer=False):
    low, high = spec[key]
    return int(rng.integers(low, high + 1)) if integer else float(rng.uniform(low, high))


def _stem(rng, height, upright):
    """A stem rising from the origin, leaning and bending a little unless upright: its points and its top's direction."""
    # Drawing choice: up to 0.15 rad of lean and 0.3 rad of bend over the stem.
    lean, bend = (0.0, 0.0) if upright else (rng.uniform(0.0, 0.15), rng.uniform(0.0, 0.3) / height)
    points, _ = plants.arcs(np.array([height]), np.array([lean]), np.array([bend]),
                            np.array([rng.uniform(0, 2 * np.pi)]), 8)
    points = points[0]
    top = points[-1] - points[-2]
    return points, top / np.linalg.norm(top)


def _leaves(rng, spec, stem_points):
    n = _draw(rng, spec, "leaves", integer=True)
    spec = {"leaf_height_fraction": LEAF_HEIGHT_FRACTION, "leaf_inclination_deg": LEAF_INCLINATION_DEG, **spec}
    out = []
    for k in range(n):
        at = stem_points[min(int(_draw(rng, spec, "leaf_height_fraction") * len(stem_points)), len(stem_points) - 1)]
        length = _draw(rng, spec, "leaf_length_m")
        # Leaves arch over: about a radian of bend along their length (shape choice).
        leaf = plants.leaf(length, _draw(rng, spec, "leaf_width_m"), np.radians(_draw(rng, spec, "leaf_inclination_deg")),
                           rng.uniform(0.5, 1.5) / length, 2 * np.pi * (k + rng.uniform()) / n)
        out.append(plants.transformed(leaf, np.eye(3), at))
    return out


def plant(spec, rng, upright=False):
    """One plant of species ``spec`` (a mapping, as described above), foot at the origin: a Mesh.

    An ``upright`` plant's stem is straight and vertical, so that its flower
    (a composite head) sits at the top, facing up.
    """
    height = _draw(rng, spec, "stem_height_m")
    points, top = _stem(rng, height, upright)
    stem = plants.tube(points, STEM_RADIUS_M)
    parts = [stem, *_leaves(rng, spec, points)]
    form = spec["form"]
    if form == "composite":
        diameter = _draw(rng, spec, "head_diameter_m")
        head = plants.composite_head(diameter, _draw(rng, spec, "disc_diameter_m"),
                                     _draw(rng, spec, "rays", integer=True), DROOP * diameter, rng)
        head = head._replace(flowers=plants.flower([0.0, 0.0, 0.0], diameter / 2.0, [0.0, 0.0, 1.0]))
        parts.append(plants.transformed(head, plants.rotation_to(top), points[-1]))
    elif form == "corymb":
        parts += _corymb(rng, spec, points[-1])
    elif form == "bell":
        parts += _bells(rng, spec, points, top)
    elif form == "spike":
        parts += _spike(rng, spec, points)
    else:
        raise ValueError(f"unknown form {form!r}")
    return plants.join(parts)


def _corymb(rng, spec, top):
    """Small capitula over a flat dome, each on a pedicel from the stem's top."""
    radius = _draw(rng, spec, "corymb_diameter_m") / 2.0
    head = np.mean(spec["head_diameter_m"])
    n = max(1, int(HEXAGONAL_PACKING * (2.0 * radius / head) ** 2))
    # Sunflower (Vogel) spiral: evenly spread heads, as a corymb's are.
    r = radius * np.sqrt((np.arange(n) + 0.5) / n)
    a = np.arange(n) * np.pi * (3.0 - np.sqrt(5.0))
    # Drawing choice: the corymb domes a quarter of its radius, 0.3 of it above the stem's top.
    lift = 0.25 * radius * (1.0 - (r / radius) ** 2)
    heads = top + np.column_stack([r * np.cos(a), r * np.sin(a), 0.3 * radius + lift])
    # The corymb, not each of its small heads, is the flower a bee sees from afar: one sphere round it all.
    out = [plants.Mesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros(0, object),
                       plants.flower(top + [0.0, 0.0, 0.3 * radius], radius, [0.0, 0.0, 1.0]))]
    for h in heads:
        out.append(plants.tube([top, 0.5 * (top + h) - [0, 0, 0.1 * radius], h], PEDICEL_RADIUS * 0.3 * radius,
                               sides=3))
        head = plants.composite_head(_draw(rng, spec, "head_diameter_m"), _draw(rng, spec, "disc_diameter_m"),
                                     _draw(rng, spec, "rays", integer=True), 0.0, rng, sectors=6)
        out.append(plants.transformed(head, plants.rotation_to([*(0.2 * (h[:2] - top[:2]) / radius), 1.0]), h))
    return out


def _bells(rng, spec, points, top):
    """Pendent bells on pedicels that arch out and down from the top of the stem."""
    n = _draw(rng, spec, "flowers", integer=True)
    out = []
    for k in range(n):
        base = points[-1 - min(k, len(points) - 2)]
        out_dir = np.array([np.cos(2.4 * k + rng.uniform()), np.sin(2.4 * k + rng.uniform()), 0.0])
        length = _draw(rng, spec, "corolla_length_m")
        # Drawing choice: a pedicel reaches out 1.2 corolla lengths, arching up 0.3 of one.
        tip = base + 1.2 * length * out_dir + [0.0, 0.0, 0.3 * length]
        out.append(plants.tube([base, 0.5 * (base + tip) + [0, 0, 0.3 * length], tip], PEDICEL_RADIUS * length))
        # Hanging (drawing choice): the mouth points down, tilted 11–31° outwards.
        facing = -np.array([0.0, 0.0, 1.0]) + rng.uniform(0.2, 0.6) * out_dir
        bell = plants.bell(length, _draw(rng, spec, "corolla_diameter_m"))
        out.append(plants.transformed(bell, plants.rotation_to(facing), tip))
    return out


def _spike(rng, spec, points):
    """Funnel flowers up the top part of the stem, facing outwards and up."""
    n = _draw(rng, spec, "flowers", integer=True)
    start = 1.0 - _draw(rng, spec, "spike_fraction")
    t = np.linspace(start, 1.0, n)
    s = np.linspace(0.0, 1.0, len(points))
    at = np.column_stack([np.interp(t, s, points[:, i]) for i in range(3)])
    out = []
    for k, p in enumerate(at):
        a = 2.4 * k  # one turn of the golden angle per flower
        facing = [np.cos(a), np.sin(a), rng.uniform(0.3, 1.0)]  # drawing choice: outwards, 17–45° up
        flower = plants.funnel(_draw(rng, spec, "corolla_length_m"), _draw(rng, spec, "corolla_diameter_m"))
        out.append(plants.transformed(flower, plants.rotation_to(facing), p))
    return out


def check_species(spec, name, source, field):
    """Refuse a species whose form is unknown or whose colours miss one of its form's parts."""
    form = spec.get("form")
    if form not in PARTS:
        raise InputError(source, f"{field}.form", f"species {name!r}: form must be one of {', '.join(PARTS)}")
    missing = [p for p in PARTS[form] if p not in spec.get("colours", {})]
    if missing:
        raise InputError(source, f"{field}.colours", f"species {name!r} needs a colour for {', '.join(missing)}")
