"""Make the hand-made meshes of the eyes whose ``eye.yaml`` has a ``shape`` section.

    .venv/bin/python eyes/shape_meshes.py [eyes/worker/eye.yaml ...]

Each mesh is the cornea :mod:`beeoptics.eye.shape` builds from the eye's
published facet count, its mean facet diameter and the solid angle its
normals span (all given, with sources, in the eye's ``shape`` section),
written over the eye's ``mesh`` file. Run it after changing those numbers;
the workflow then remeshes and relaxes the new surface.
"""

import sys
from pathlib import Path

import igl
import numpy as np

from beeoptics.eye.description import load_eye
from beeoptics.eye.shape import HEXAGON_AREA, cornea, field_outline
from beeoptics.io.atomic import atomic_path


def main(paths):
    for path in paths or sorted(Path(__file__).parent.glob("*/eye.yaml")):
        eye = load_eye(path)
        shape = eye.document.get("shape")
        if shape is None:
            continue
        diameter = shape["facet_diameter_um"] * 1e-3
        outline = field_outline(eye.facet_count, diameter, eye.lattice_lines)
        vertices, faces = cornea(outline, eye.facet_count * HEXAGON_AREA * diameter**2, shape["normals_sr"],
                                 shape["vertex_spacing_mm"])
        with atomic_path(eye.mesh_path) as tmp:
            igl.writeOBJ(str(tmp), vertices, faces)
        print(f"{eye.mesh_path}: {len(faces)} faces, {np.ptp(vertices[:, 1]):.3f} × {np.ptp(vertices[:, 0]):.3f} mm "
              f"(dorsoventral × anteroposterior, projected)")


if __name__ == "__main__":
    main(sys.argv[1:])
