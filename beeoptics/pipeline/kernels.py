"""Set-up: every compiled kernel compiled once, into numba's cache, before any stage runs.

numba compiles a kernel on its first call and keeps it on disk
(:mod:`beeoptics.jit`): some forty seconds for the tracer's and the facet
relaxation's kernels, which the first stage to call them would otherwise pay,
and, in a workflow's first run, every job that starts before that one has
finished. :func:`compile_kernels` (``beeoptics compile-kernels``, which
``make`` runs at set-up) calls them as the stages do, on a toy: a 300-facet
eye (a spherical cap, no insect's) remeshed and relaxed, its receptors traced
with intensity and with polarisation through a scene of each kind of surface
(Lambertian, glossy, coated) under a polarised Hosek–Wilkie sky and the sun,
a camera's pixels traced through it, and the sky compass's template made.
"""

import tempfile
from pathlib import Path

import numpy as np
import yaml

from beeoptics.api import human_view, load_eye, load_scene, look
from beeoptics.eye.optics import AcceptanceModel
from beeoptics.io.validation import config_defaults
from beeoptics.pipeline.eyes import build_facets, remesh_eye
from beeoptics.pipeline.outputs import FACET_OUTPUTS
from beeoptics.sky.skypolarisation import patterns

#: The toy eye: a cap of a sphere 0.8 mm in radius, 300 facets of 40–46 µm (test values, no insect's).
EYE = {"name": "toy", "description": "A toy eye, only to compile the kernels.", "mesh": "mesh.obj",
       "placement": {"axis_azimuth_deg": 70.0, "axis_elevation_deg": 0.0, "origin_mm": [0.0, -1.35, 0.0]},
       "facets": {"count": 300}, "dorsal_rim": {"count": 12},
       "facet_diameter": {"anchors": [{"name": "dorsal", "azimuth_deg": 70.0, "elevation_deg": 60.0, "diameter_um": 40.0},
                                      {"name": "frontal", "azimuth_deg": 10.0, "elevation_deg": -45.0,
                                       "diameter_um": 46.0}]}}
#: The toy scene: a Lambertian ground, a glossy ball and a coated one under a clear sky and the sun.
SCENE = {"name": "toy", "light": {"sky": "hosek_wilkie", "sun": True, "sun_elevation_deg": 50.0},
         "eye": {"position_m": [0.0, 0.0, 0.1]},
         "camera": {"position_m": [0.0, 0.0, 0.1], "look_at_m": [0.3, 0.0, 0.0], "width_px": 8, "height_px": 6},
         "materials": {"ground": {"reflectance": 0.2}, "glossy": {"reflectance": 0.3, "gloss": {"specular": 0.5}},
                       "coated": {"reflectance": 0.3, "coating": {"roughness": 0.3, "refractive_index": 1.5,
                                                                  "in_reflectance": True}}},
         "objects": [{"primitive": {"plane": {"size_m": 10.0}}, "material": "ground"},
                     {"primitive": {"sphere": {"radius_m": 0.05}}, "material": "glossy", "translate_m": [0.3, 0.1, 0.05]},
                     {"primitive": {"sphere": {"radius_m": 0.05}}, "material": "coated",
                      "translate_m": [0.3, -0.1, 0.05]}]}


def cap_mesh(radius_mm=0.8, rings=8):
    """A cap of the sphere about +z, 60° across, as an OBJ's text: a height field over xy, as eye meshes are."""
    lines, rows = ["v 0 0 0"], [[0]]
    for r in range(1, rings + 1):
        theta = np.radians(30.0) * r / rings
        phi = 2.0 * np.pi * np.arange(6 * r) / (6 * r)
        start = len(lines)
        lines += [f"v {radius_mm * np.sin(theta) * np.cos(p):.6f} {radius_mm * np.sin(theta) * np.sin(p):.6f} "
                  f"{radius_mm * (np.cos(theta) - 1.0):.6f}" for p in phi]
        rows.append(list(range(start, start + 6 * r)))
    for inner, outer in zip(rows, rows[1:]):
        # Each ring's vertices to its outer neighbours': a triangle fan between the two rings.
        for j, v in enumerate(outer):
            w = outer[(j + 1) % len(outer)]
            a = inner[round(j * len(inner) / len(outer)) % len(inner)]
            b = inner[round((j + 1) * len(inner) / len(outer)) % len(inner)]
            lines.append(f"f {v + 1} {w + 1} {a + 1}")
            if a != b:
                lines.append(f"f {w + 1} {b + 1} {a + 1}")
    return "\n".join(lines) + "\n"


def compile_kernels():
    """Call every compiled kernel as the stages do, on the toy, so that numba compiles and caches each."""
    config = config_defaults()
    # A few samples on two threads, down to the depth at which every kind of surface scatters the light.
    settings = {"samples": 4, "depth": 3, "seed": 1, "threads": 2}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        (tmp / "mesh.obj").write_text(cap_mesh())
        (tmp / "eye.yaml").write_text(yaml.safe_dump(EYE, sort_keys=False))
        (tmp / "scene.yaml").write_text(yaml.safe_dump(SCENE, sort_keys=False))
        outputs = {"remeshed": tmp / "remeshed.ply", **{k: tmp / name for k, name in FACET_OUTPUTS.items()}}
        remesh_eye(tmp / "eye.yaml", outputs, edge_fraction=config["eye"]["edge_fraction"])
        build_facets(tmp / "eye.yaml", outputs["remeshed"], outputs, tolerance_um=config["eye"]["tolerance_um"],
                     acceptance=AcceptanceModel.from_config(config["eye"]["delta_rho"]))
        eye = load_eye(outputs["receptors"])
        scene = load_scene(tmp / "scene.yaml", cache=False)
        for polarised in (False, True):
            look(eye, scene, polarised=polarised, target=(np.array([0.3, 0.0, 0.0]), 0.1), **settings)
        human_view(scene, **settings)
        patterns(eye.table.axis, eye.table.axis[:2], np.zeros(2), 1.0)
