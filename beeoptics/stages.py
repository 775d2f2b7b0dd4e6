"""The workflow's stages, one function each, from input files to artifacts.

Each function reads its inputs, calls the library, and writes its outputs
atomically; the Snakemake rules in ``workflow/rules`` and the command-line
tool call nothing else.
"""

import json
import logging
import time
from contextlib import contextmanager

import colour
import igl
import numpy as np

from beeoptics import camera, colourspace, figures, optics
from beeoptics import sky as skies
from beeoptics.errors import InputError
from beeoptics.catches import acceptance_solid_angle, quantum_catches
from beeoptics.imagefile import write_exr, write_png
from beeoptics.receptors import read_receptors
from beeoptics.retina import canvas, density, retinal_plane, voronoi
from beeoptics.scene import load_scene, raycasting_scene, receptors_in_world
from beeoptics.sensitivity import RECEPTORS, overall_sensitivity, receptor_sensitivities
from beeoptics.spectra import grid
from beeoptics.table import read_table, write_table
from beeoptics.trace import trace_paths
from beeoptics.atomic import atomic_path
from beeoptics.eyefile import load_eye, load_eye_mesh
from beeoptics.facetmap import anchor_vertices, diameter_map
from beeoptics.lattice import conformal_map, project_grid
from beeoptics.meshfile import read_mesh_normals, write_mesh
from beeoptics.meshquery import MeshQuery
from beeoptics.quality import checks, lattice_quality, optics_quality, zone_contrast
from beeoptics.receptors import delta_phi, receptor_table, to_head, write_receptors
from beeoptics.relax import relax
from beeoptics.remesh import remesh


log = logging.getLogger("beeoptics")


@contextmanager
def logging_to(path):
    """Send the package's log messages to a file (a rule's log) for the duration."""
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        yield
    finally:
        log.removeHandler(handler)
        handler.close()


def write_json(path, data):
    """Write JSON atomically, keys in order, for stable diffs."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=False) + "\n")


def remesh_eye(eye_file, remeshed_ply, edge_fraction=1 / 3, subdivisions=2):
    """Stage 1: remesh an eye's hand-made mesh isotropically.

    The target edge length is ``edge_fraction`` of the mean facet diameter
    of the eye's anchors: with the default, a third of a typical facet and
    at most half of the smallest (the drone's 17.7 µm against its mean of 27 µm).
    """
    eye = load_eye(eye_file)
    vertices, faces = load_eye_mesh(eye)
    typical_mm = np.mean([a["diameter_um"] for a in eye["facet_diameter"]["anchors"]]) * 1e-3
    v, f, n = remesh(vertices, faces, edge_fraction * typical_mm, subdivisions=subdivisions)
    write_mesh(remeshed_ply, v, f, n)


def place_facets(eye_file, remeshed_ply, receptors_csv, quality_json, relaxation_npz,
                 tolerance_um=0.05, delta_rho=None, progress=None):
    """Stage 2: place the facets on the remeshed eye and describe every receptor.

    Projects the hexagonal grid (count rule), relaxes it, reads the receptor
    axes from the interpolated normals, and writes the receptor table of
    both eyes, the quality figures and the relaxation's snapshots.

    Parameters
    ----------
    delta_rho : dict, optional
        ``model`` ("fixed" or "snyder") and its parameters, as in the config.
    """
    delta_rho = delta_rho or {"model": "fixed"}
    eye = load_eye(eye_file)
    v, f, n = read_mesh_normals(remeshed_ply)
    query = MeshQuery(v, f)
    anchors = eye["facet_diameter"]["anchors"]
    sources = anchor_vertices(n @ eye["rotation"], anchors)
    diameters = diameter_map(
        v, f, sources, [a["diameter_um"] * 1e-3 for a in anchors], eye["facet_diameter"]["power"]
    )
    points, faces, pitch = project_grid(query, eye["facets"]["count"])
    start = time.perf_counter()
    result = relax(query, conformal_map(v, f), diameters, points, faces, tolerance_um * 1e-3,
                   progress=progress)
    seconds = time.perf_counter() - start

    points, faces, edges = result["points"], result["faces"], result["edges"]
    axes = query.interpolate(n, points, faces)
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    facet_um = query.interpolate(diameters, points, faces) * 1e3
    dphi = delta_phi(axes, edges)
    drho = optics.delta_rho(
        facet_um,
        delta_rho["model"],
        fixed_deg=delta_rho.get("fixed_deg", optics.DELTA_RHO_WORKER_DEG),
        wavelength_nm=delta_rho.get("wavelength_nm", optics.SNYDER_WAVELENGTH_NM),
        rhabdom_deg=eye.get("optics", {}).get("rhabdom_acceptance_deg", optics.RHABDOM_ACCEPTANCE_DEG),
    )
    write_receptors(receptors_csv, receptor_table(eye, points, axes, facet_um, dphi, drho))

    points_head, axes_head = to_head(eye, points, axes)
    chord = np.linalg.norm(points[edges[:, 1]] - points[edges[:, 0]], axis=1)
    lattice = lattice_quality(edges, result["boundary"], result["geodesic"], chord, facet_um)
    eye_optics = optics_quality(axes_head, dphi, facet_um, points_head)
    zone = None
    if "acute_zone" in eye.get("published", {}):
        spec = eye["published"]["acute_zone"]
        anchor = next(a for a in anchors if a["name"] == spec["anchor"])
        zone = zone_contrast(axes_head, dphi, facet_um, anchor, spec["radius_deg"])
    count = len(points)
    write_json(quality_json, {
        "eye": eye["name"],
        "facets_per_eye": count,
        "facets_published": eye["facets"]["count"],
        "facets_published_sd": eye["facets"].get("sd"),
        "grid_pitch_um": pitch * 1e3,
        "relaxation": {
            "iterations": result["iterations"],
            "seconds": seconds,
            "tolerance_um": tolerance_um,
            "fill_factor": result["fill_factor"],
        },
        "lattice": lattice,
        "optics": eye_optics,
        "acute_zone": zone,
        "published": {k: v for k, v in eye.get("published", {}).items()},
        "checks": checks(eye, count, lattice, eye_optics, zone),
    })
    with atomic_path(relaxation_npz) as tmp:
        np.savez_compressed(
            tmp,
            iterations=np.array([it for it, _ in result["snapshots"]]),
            snapshots=np.stack([p for _, p in result["snapshots"]]),
            snapshot_diameter_um=np.stack(
                [query.interpolate(diameters, *query.project(p)) * 1e3 for _, p in result["snapshots"]]
            ),
            delta_phi_deg=dphi,
            facet_diameter_um=facet_um,
            boundary_xy=v[igl.boundary_loop(f), :2],
        )


def eye_figures(eye_file, relaxation_npz, outputs):
    """Stage 2b: Collins' Fig. 7 for one eye, and maps of its Δφ and facet diameters.

    ``outputs`` maps ``relaxation``, ``delta_phi`` and ``facet_diameter`` to PNG paths.
    """
    eye = load_eye(eye_file)
    data = np.load(relaxation_npz)
    rest, rim = data["snapshots"][-1], data["boundary_xy"]
    figures.relaxation(data["snapshots"], data["iterations"], data["snapshot_diameter_um"], rim,
                       outputs["relaxation"], eye["name"])
    figures.eye_map(rest, data["delta_phi_deg"], rim, outputs["delta_phi"],
                    "Δφ, degrees", f"{eye['name']}: interommatidial angle Δφ")
    figures.eye_map(rest, data["facet_diameter_um"], rim, outputs["facet_diameter"],
                    "facet diameter, µm", f"{eye['name']}: facet diameter")


def wavelengths(spectral):
    """The spectral grid a config's ``spectral`` section describes."""
    return grid(spectral["start_nm"], spectral["end_nm"], spectral["step_nm"])


def _chunks(first, last, batch_rays, samples):
    """Bounds of consecutive bundles whose rays together fit in one batch."""
    step = max(1, batch_rays // samples)
    return [(lo, min(last, lo + step)) for lo in range(first, last, step)]


def trace_part(receptors_csv, scene_file, part_npz, *, spectral, samples_per_receptor, depth, seed,
               batch_rays, part=0, parts=1, progress=None):
    """Stage 3: trace the acceptance cones of one share of the receptors through a scene.

    Receptors are split into ``parts`` contiguous shares, for running on
    several machines; every receptor draws the same random numbers in any
    share, so the gathered result is bit-identical to a single part's.
    Writes the share's receptor ids and spectral radiance; returns the ray counts.
    """
    wl = wavelengths(spectral)
    scene = load_scene(scene_file, wl)
    table = read_receptors(receptors_csv)
    origins, axes = receptors_in_world(scene, table["position"], table["axis"])
    drho = table["delta_rho_deg"]
    bounds = np.linspace(0, len(origins), parts + 1).round().astype(int)
    first, last = bounds[part], bounds[part + 1]
    rs = raycasting_scene(scene)
    radiance = np.empty((last - first, len(wl)))
    counts = {}
    start = time.perf_counter()
    for lo, hi in _chunks(first, last, batch_rays, samples_per_receptor):
        dirs, weights = optics.cone_samples(axes[lo:hi], drho[lo:hi], samples_per_receptor, seed, first=lo)
        radiance[lo - first:hi - first] = trace_paths(scene, origins[lo:hi], dirs, weights, depth=depth,
                                                      seed=seed, first_stream=lo, rs=rs, counts=counts)
        if progress is not None:
            progress(hi - first, last - first)
    log.info("traced receptors %d to %d: %d rays and %d shadow rays in %.1f s", first, last, counts["cast"],
             counts["shadow"], time.perf_counter() - start)
    with atomic_path(part_npz) as tmp:
        np.savez_compressed(tmp, id=table["id"][first:last], radiance=radiance)
    return counts


def gather_responses(receptors_csv, scene_file, part_npzs, responses_csv, irradiance_npz, *, spectral,
                     background="scene"):
    """Stage 3, gathered: catches and colour-space coordinates of every receptor.

    Parameters
    ----------
    part_npzs : list of path
        The shares written by :func:`trace_part`, in order.
    background : str
        The adapting background of von Kries adaptation: ``"scene"``, the
        mean catch over both eyes, or the name of one of the scene's
        materials, as a Lambertian surface under the scene's sky and sun.
    """
    wl = wavelengths(spectral)
    table = read_receptors(receptors_csv)
    parts = [np.load(p) for p in part_npzs]
    ids = np.concatenate([p["id"] for p in parts])
    if not np.array_equal(ids, table["id"]):
        raise InputError(part_npzs[0], "id", "the traced shares do not cover the receptor table in order")
    radiance = np.concatenate([p["radiance"] for p in parts])
    drho = table["delta_rho_deg"]
    irradiance = radiance * acceptance_solid_angle(drho)[:, None]
    sens = receptor_sensitivities(wl)
    catches = quantum_catches(irradiance, sens, wl)
    # Adaptation compares radiances: the acceptance solid angle cancels in every ratio.
    seen = quantum_catches(radiance, sens, wl)
    if background == "scene":
        reference = seen.mean(axis=0)
    else:
        scene = load_scene(scene_file, wl)
        if background not in scene.material_names:
            raise InputError(scene_file, "materials", f"no material {background!r} to adapt to (colour.background)")
        rho = scene.reflectance[scene.material_names.index(background)]
        lambertian = rho * skies.horizontal_irradiance(scene.sky, scene.sun, len(wl)) / np.pi
        reference = quantum_catches(lambertian[None], sens, wl)[0]
    if not (reference > 0.0).all():
        raise InputError(scene_file, "colour.background",
                         f"the background {background!r} gives no catch in some receptor class; "
                         "von Kries adaptation needs a background every class sees")
    overall = overall_sensitivity(wl)
    brightness = quantum_catches(irradiance, (overall / overall.sum())[:, None], wl)[:, 0]
    write_table(responses_csv, {"id": table["id"], "side": table["side"],
                                **{r: catches[:, k] for k, r in enumerate(RECEPTORS)},
                                "brightness": brightness,
                                **colourspace.describe(seen, reference)})
    with atomic_path(irradiance_npz) as tmp:
        np.savez_compressed(tmp, id=table["id"], wavelength_nm=wl, radiance=radiance.astype(np.float32),
                            irradiance=irradiance.astype(np.float32))


def _display(linear, scale):
    """Linear values to sRGB-encoded display values in [0, 1], NaN (outside the eyes) black."""
    v = np.nan_to_num(np.asarray(linear) / scale, nan=0.0)
    return colour.cctf_encoding(np.clip(v, 0.0, 1.0), function="sRGB")


def human_view(scene_file, png, exr, *, spectral, samples_per_pixel, depth, seed, batch_rays):
    """Stage 3b: what a person sees of a scene through its pinhole camera.

    Traced like the receptors, then mapped through the CIE 1931 observer to
    sRGB (PNG, the 99th percentile of luminance as white) and written as
    linear XYZ (EXR, channels ``X``, ``Y``, ``Z``).
    """
    wl = wavelengths(spectral)
    scene = load_scene(scene_file, wl)
    origin, dirs = camera.pinhole_rays(scene.camera, samples_per_pixel, seed)
    rs = raycasting_scene(scene)
    xyz = np.empty((len(dirs), 3))
    for lo, hi in _chunks(0, len(dirs), batch_rays, samples_per_pixel):
        radiance = trace_paths(scene, np.broadcast_to(origin, (hi - lo, 3)), dirs[lo:hi],
                               np.ones((hi - lo, samples_per_pixel)), depth=depth, seed=seed,
                               first_stream=lo, rs=rs)
        xyz[lo:hi] = camera.tristimulus(wl, radiance)
    shape = (scene.camera["height_px"], scene.camera["width_px"], 3)
    write_png(png, camera.srgb(xyz, np.percentile(xyz[:, 1], 99.0)).reshape(shape))
    write_exr(exr, xyz.reshape(shape), ("X", "Y", "Z"))


def map3(uv, b, g):
    """Collins' map3: UV to red, B to blue, G to green; (1, 1, 1) is white. Linear RGB."""
    return np.stack([uv, g, b], -1)


def retinal_images(eye_file, receptors_csv, responses_csv, irradiance_npz, outputs, width_px=400):
    """Stage 4: Voronoi, density and channel images of one eye in one scene, and the EXR of catches."""
    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    resp = read_table(responses_csv, numeric=["id", *RECEPTORS], text=["side"])
    q = np.column_stack([resp[r] for r in RECEPTORS])
    data = np.load(irradiance_npz)
    xy = retinal_plane(eye, table["position"], table["side"])
    can = canvas(xy, width_px)
    # One exposure for all three channels keeps their relative responses.
    scale = np.percentile(q, 99.5)
    colours = map3(q[:, 0], q[:, 1], q[:, 2])
    write_png(outputs["voronoi_map3"], _display(voronoi(can, xy, table["side"], colours), scale))
    dens = density(can, xy, table["side"], colours, normalise=False)
    write_png(outputs["density_map3"], _display(dens, np.nanpercentile(dens, 99.5)))
    for k, name in enumerate(("channel_uv", "channel_b", "channel_g")):
        write_png(outputs[name], _display(voronoi(can, xy, table["side"], q[:, k]), scale)[..., 0])
    xyz = camera.tristimulus(data["wavelength_nm"], data["radiance"])
    # Nearest-receptor images copy values, so encoding before the Voronoi step is exact.
    srgb = camera.srgb(xyz, np.percentile(xyz[:, 1], 99.5))
    write_png(outputs["voronoi_map2"], np.nan_to_num(voronoi(can, xy, table["side"], srgb), nan=0.0))
    write_exr(outputs["exr"], np.nan_to_num(voronoi(can, xy, table["side"], q), nan=0.0), RECEPTORS)
