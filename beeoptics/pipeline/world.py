"""The world stage: generate a meadow's mesh from its meadow file.

Reads ``scenes/<name>/meadow.yaml``, builds the meadow
(:func:`beeoptics.world.meadow.generate`) and writes ``outputs["mesh"]``,
the PLY the scene's ``meadow.ply`` object reads, atomically.
"""

import collections

from beeoptics.pipeline.logs import log
from beeoptics.world.meadow import generate, read_meadow, write_ply

#: The mesh a meadow file is turned into, beside it in the scene's folder.
MEADOW_FILE, MEADOW_MESH = "meadow.yaml", "meadow.ply"


def generate_meadow(meadow_file, outputs):
    """Generate the meadow of ``meadow_file``; return the number of triangles of each species (and the grass, soil)."""
    mesh, colours = generate(read_meadow(meadow_file), meadow_file)
    write_ply(outputs["mesh"], mesh, colours)
    counts = collections.Counter(p.split(".")[0] for p in mesh.parts)
    log.info("meadow %s: %d triangles (%s)", meadow_file, len(mesh.faces),
             ", ".join(f"{k} {v}" for k, v in counts.most_common()))
    return counts
