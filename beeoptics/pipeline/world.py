"""The world stage: generate a meadow's mesh from its meadow file.

Reads ``scenes/<name>/meadow.yaml``, builds the meadow
(:func:`beeoptics.world.meadow.generate`) and writes ``outputs["mesh"]``,
the PLY the scene's ``meadow.ply`` object reads, and ``outputs["flowers"]``,
the table of its flowers (:func:`beeoptics.world.meadow.flower_table`), atomically.
"""

import collections
from pathlib import Path

from beeoptics.io.table import write_table
from beeoptics.io.validation import load_yaml
from beeoptics.pipeline.logs import log
from beeoptics.world.meadow import flower_table, generate, read_meadow, write_ply

#: The mesh a meadow file is turned into, and the table of its flowers, beside it in the scene's folder.
MEADOW_FILE, MEADOW_MESH, MEADOW_FLOWERS = "meadow.yaml", "meadow.ply", "meadow_flowers.csv"


def generate_meadow(meadow_file, outputs):
    """Generate the meadow of ``meadow_file``; return the number of triangles of each species (and the grass, soil)."""
    mesh, colours, species = generate(read_meadow(meadow_file))
    write_ply(outputs["mesh"], mesh, colours)
    if "flowers" in outputs:
        write_table(outputs["flowers"], flower_table(mesh, species))
    counts = collections.Counter(p.split(".")[0] for p in mesh.parts)
    log.info("meadow %s: %d triangles (%s)", meadow_file, len(mesh.faces),
             ", ".join(f"{k} {v}" for k, v in counts.most_common()))
    return counts


def missing_meadow(scene_file, starting=None):
    """Generate a scene's meadow if the scene places it and it is not there yet; the mesh's path, or None.

    A fresh clone holds a generated meadow's description (``meadow.yaml``)
    but not its mesh, which the workflow's meadow rule writes; a command
    run on the scene writes it as that rule does, with its flowers' table,
    the same bytes as ``beeoptics meadow`` (the generation is seeded by the
    meadow file).

    Parameters
    ----------
    scene_file : str or Path
    starting : callable, optional
        Called with the mesh's path before generating it (the shipped meadow takes some 15 s).
    """
    folder = Path(scene_file).parent
    mesh = folder / MEADOW_MESH
    scene = load_yaml(scene_file)
    objects = scene.get("objects") if isinstance(scene, dict) else None
    placed = isinstance(objects, list) and any(isinstance(o, dict) and o.get("mesh") == MEADOW_MESH for o in objects)
    if not placed or mesh.exists() or not (folder / MEADOW_FILE).is_file():
        return None
    if starting is not None:
        starting(mesh)
    generate_meadow(folder / MEADOW_FILE, {"mesh": mesh, "flowers": folder / MEADOW_FLOWERS})
    return mesh
