"""A generated meadow: rough ground, tussocks of grass and flowering plants, as one coloured mesh.

The meadow file (``scenes/<name>/meadow.yaml``, checked against
``beeoptics/io/schemas/meadow.schema.yaml``) gives the patch's size, its
ground (:mod:`beeoptics.world.terrain`), the grass and each species'
density and clumping (:mod:`beeoptics.world.placement`), and specimens:
single plants at given places and of given sizes, upright on level ground
with no other plant round them, so that a flight can be written against
the known place of their flower (the flower a flight approaches). Each species is built as a few
variants (:mod:`beeoptics.world.species`) and placed many times, turned at
random about the vertical. The result is a mesh whose faces carry each
part's colour, written as PLY; a scene's ``palette`` maps those colours to
measured spectra, so a generated meadow is an ordinary scene.

Every random draw comes from the meadow's seed and the component it
belongs to (the ground, the grass, the n-th specimen, the n-th species),
so that the same file gives the same meadow, and adding a species leaves
the others as they were.
"""

import os

import numpy as np
import pymeshlab

from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.validation import load_yaml, validate
from beeoptics.world import placement, plants, terrain
from beeoptics.world.species import check_species, plant, species_table


def _rng(seed, component):
    """The random numbers of one component of the meadow (an int, or a tuple of ints)."""
    return np.random.default_rng([seed, *np.atleast_1d(component)])


def _colour(hex_colour):
    return np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)], np.uint8)


def _instances(template, rotations, positions):
    """The template placed at each position (n, 3), turned by each rotation (n, 3, 3): one Mesh, its flowers too."""
    n = len(positions)
    vertices = np.einsum("nij,vj->nvi", rotations, template.vertices) + positions[:, None, :]
    faces = template.faces[None] + len(template.vertices) * np.arange(n)[:, None, None]
    f = template.flowers
    centres = np.einsum("nij,kj->nki", rotations, f[:, :3]) + positions[:, None, :]
    facing = np.einsum("nij,kj->nki", rotations, f[:, 4:])
    flowers = np.concatenate([centres, np.broadcast_to(f[:, 3:4], (n, len(f), 1)), facing], axis=-1)
    return plants.Mesh(vertices.reshape(-1, 3), faces.reshape(-1, 3), np.tile(template.parts, n),
                       flowers.reshape(-1, 7))


def _yaw(angles):
    c, s = np.cos(angles), np.sin(angles)
    r = np.zeros((len(angles), 3, 3))
    r[:, 0, 0], r[:, 0, 1], r[:, 1, 0], r[:, 1, 1], r[:, 2, 2] = c, -s, s, c, 1.0
    return r


def generate(meadow):
    """The meadow described by ``meadow`` (a meadow file as :func:`read_meadow` reads and checks it): a Mesh
    (its ``flowers`` every flower in the meadow), its face colours (m, 3), uint8, and each flower's species (k,).
    """
    table = species_table(meadow["species"])
    extent = np.asarray(meadow["extent_m"], float)
    seed = meadow["seed"]

    specimens = meadow["specimens"]
    clear = np.array([s["position_m"] for s in specimens]).reshape(-1, 2)
    radii = np.array([s["clear_radius_m"] for s in specimens])

    g = meadow["ground"]
    x, y, h = terrain.height_field(extent, g["spacing_m"], g["rms_height_m"], g["correlation_length_m"],
                                   _rng(seed, 0))
    h = h * terrain.level_round(x, y, clear, radii)
    meshes = [terrain.ground_mesh(x, y, h)]
    colours = {"soil": _colour(g["colour"])}
    species = []

    def positions(points):
        points = points[placement.clear_of(points, clear, radii)]
        return np.column_stack([points, terrain.ground_height(x, y, h, points)])

    gr = meadow["grass"]
    rng = _rng(seed, 1)
    feet = positions(placement.thomas(extent, gr["density_per_m2"], gr["per_clump"], gr["spread_m"], rng))
    n = len(feet)
    grass = plants.blades(rng.uniform(*gr["length_m"], n), rng.uniform(*gr["width_m"], n),
                          np.radians(rng.uniform(*gr["inclination_deg"], n)),
                          rng.uniform(*gr["curvature_per_m"], n), rng.uniform(0.0, 2.0 * np.pi, n))
    grass = grass._replace(vertices=grass.vertices + np.repeat(feet, len(grass.vertices) // max(n, 1), axis=0))
    meshes.append(grass)
    colours["grass"] = _colour(gr["colour"])

    # Specimens first, then the plants: a plant added at the end leaves every earlier triangle as it was.
    entries = [("specimens", k, e) for k, e in enumerate(specimens)] + [("plants", k, e) for k, e in
                                                                        enumerate(meadow["plants"])]
    for group, k, entry in entries:
        name = entry["species"]
        spec = {**table[name], **entry.get("sizes", {})}
        rng = _rng(seed, (2 if group == "specimens" else 3, k))
        variants = [plant(spec, rng, upright="position_m" in entry) for _ in range(entry["variants"])]
        # Parts named by their species once per variant, not once per placed triangle.
        variants = [v._replace(parts=(f"{name}." + v.parts.astype(str)).astype(object)) for v in variants]
        if "position_m" in entry:
            xy = np.array([entry["position_m"]])
            feet = np.column_stack([xy, terrain.ground_height(x, y, h, xy)])
        else:
            feet = positions(placement.thomas(extent, entry["density_per_m2"], entry["per_clump"],
                                              entry["spread_m"], rng))
        which = rng.integers(0, len(variants), len(feet))
        turns = _yaw(np.radians(entry["yaw_deg"]) * np.ones(len(feet)) if "yaw_deg" in entry
                     else rng.uniform(0.0, 2.0 * np.pi, len(feet)))
        for v, template in enumerate(variants):
            chosen = which == v
            if chosen.any():
                meshes.append(_instances(template, turns[chosen], feet[chosen]))
                species += [name] * len(meshes[-1].flowers)
        colours.update({f"{name}.{p}": _colour(c) for p, c in spec["colours"].items()})

    mesh = plants.join(meshes)
    names = np.array(sorted(colours), dtype=object)
    index = np.searchsorted(names, mesh.parts)
    return mesh, np.array([colours[n] for n in names])[index], np.array(species, dtype=object)


#: The columns of a meadow's table of flowers (:func:`flower_table`), metres and unit vectors.
FLOWER_COLUMNS = ("species", "x_m", "y_m", "z_m", "radius_m", "facing_x", "facing_y", "facing_z")


def flower_table(mesh, species):
    """Every flower of a generated meadow as columns of :data:`FLOWER_COLUMNS`: the sphere about it, the way it
    faces."""
    f = mesh.flowers
    return {"species": species, **{c: f[:, k] for k, c in enumerate(FLOWER_COLUMNS[1:])}}


def write_ply(path, mesh, face_colours):
    """Write the mesh as binary PLY with a colour per face, as MeshLab does, with pymeshlab, atomically."""
    rgba = np.column_stack([np.asarray(face_colours, float) / 255.0, np.ones(len(face_colours))])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=mesh.vertices, face_matrix=mesh.faces, f_color_matrix=rgba))
    with atomic_path(path) as tmp:
        ms.save_current_mesh(str(tmp), binary=True, save_vertex_color=False, save_face_color=True,
                             save_vertex_quality=False, save_face_quality=False)


#: Peak memory of generating a meadow and writing its PLY, bytes per triangle: measured as the growth of the
#: process's maximum resident set over generate() and write_ply() of scenes/meadow/meadow.yaml at 4 × 4 m
#: (1.18 million triangles, 577 B each) and 8 × 8 m (4.59 million, 568 B each), rounded up.
BYTES_PER_TRIANGLE = 600
#: The share of the machine's physical memory a meadow may take while generated: the rest is left to the
#: system and to the jobs that run beside it (the scene's tracing then holds the mesh again, in Open3D).
MEMORY_SHARE = 0.5


def read_meadow(path):
    """A meadow file, checked against its schema with defaults filled in, its ranges ordered and its size
    within what the machine can hold (:func:`check_work`), before any of it is generated."""
    return check_meadow(validate(load_yaml(path), "meadow", path), path)


def check_meadow(meadow, source):
    """Refuse, naming ``source`` and the field, a meadow file (checked against its schema) that names an
    range whose low end is above its high end, an unknown species or one missing a colour, or is larger
    than the machine can hold (:func:`check_work`); return it."""
    for field, (low, high) in _ranges(meadow):
        if low > high:
            raise InputError(source, field, f"the range [{low:g}, {high:g}] runs backwards; give it as [low, high]")
    table = species_table(meadow["species"])
    for name, spec in meadow["species"].items():
        check_species(spec, name, source, f"species.{name}")
    for group in ("specimens", "plants"):
        for k, entry in enumerate(meadow[group]):
            if entry["species"] not in table:
                raise InputError(source, f"{group}.{k}.species", f"unknown species {entry['species']!r}; there are "
                                 f"{', '.join(sorted(table))}")
    check_work(meadow, source)
    return meadow


def _ranges(meadow):
    """Every [low, high] range of a meadow file: (dotted field, pair)."""
    pairs = [(f"grass.{k}", v) for k, v in meadow["grass"].items()]
    pairs += [(f"specimens.{i}.sizes.{k}", v) for i, s in enumerate(meadow["specimens"]) for k, v in s["sizes"].items()]
    pairs += [(f"species.{n}.{k}", v) for n, spec in meadow["species"].items() for k, v in spec.items()]
    return [(field, v) for field, v in pairs
            if isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) for x in v)]


def expected_triangles(meadow):
    """The triangles a meadow file's mesh will have, estimated without generating it: the ground's grid,
    and each density times the area times the triangles of one blade or one plant of the species (one built,
    from random numbers of seed 0), for each component: a dict of component (as :func:`check_work` names it) to
    triangles."""
    extent = np.asarray(meadow["extent_m"], float)
    area = float(np.prod(extent))
    cells = np.prod(np.ceil(extent / meadow["ground"]["spacing_m"]))
    counts = {"soil": 2.0 * cells}
    # A blade's triangles do not depend on its sizes: one of unit length, width and angles counts them.
    blade = plants.blades(*np.ones((5, 1)))
    counts["grass"] = meadow["grass"]["density_per_m2"] * area * len(blade.faces)
    table = species_table(meadow["species"])
    for k, entry in enumerate(meadow["plants"]):
        built = plant(table[entry["species"]], np.random.default_rng(0))
        counts[f"plants.{k}"] = entry["density_per_m2"] * area * len(built.faces)
    return counts


def memory_limit_bytes():
    """The memory a meadow may take while generated: :data:`MEMORY_SHARE` of the machine's physical memory."""
    return MEMORY_SHARE * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def check_work(meadow, source, limit_bytes=None):
    """Refuse a meadow whose mesh would not fit in memory (:func:`expected_triangles` ×
    :data:`BYTES_PER_TRIANGLE` against :func:`memory_limit_bytes`), naming what takes most of it."""
    limit_bytes = memory_limit_bytes() if limit_bytes is None else limit_bytes
    counts = expected_triangles(meadow)
    total = sum(counts.values())
    if total * BYTES_PER_TRIANGLE <= limit_bytes:
        return
    most = max(counts, key=counts.get)
    field = {"soil": "ground.spacing_m", "grass": "grass.density_per_m2"}.get(most, f"{most}.density_per_m2")
    extent = meadow["extent_m"]
    fits = limit_bytes / BYTES_PER_TRIANGLE / total
    gib = 2.0**30
    raise InputError(source, field, f"a meadow of {extent[0]:g} × {extent[1]:g} m would have about {total:.2g} "
                     f"triangles ({100 * counts[most] / total:.0f} % from {most}), "
                     f"{total * BYTES_PER_TRIANGLE / gib:.3g} GiB to generate at {BYTES_PER_TRIANGLE} bytes each; "
                     f"this machine allows {limit_bytes / gib:.3g} GiB ({MEMORY_SHARE:.0%} of its memory): shrink "
                     f"extent_m or the densities by {1 / fits:.3g} times (to {fits * np.prod(extent):.3g} m² at "
                     "these densities)")
