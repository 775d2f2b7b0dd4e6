"""The world stage: generate a meadow's mesh from its meadow file.

Reads ``scenes/<name>/meadow.yaml``, builds the meadow
(:func:`beeoptics.world.meadow.generate`) and writes ``outputs["mesh"]``,
the PLY the scene's ``meadow.ply`` object reads, and ``outputs["flowers"]``,
the table of its flowers (:func:`beeoptics.world.meadow.flower_table`), atomically.
"""

import collections

from beeoptics.io.table import write_table
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
