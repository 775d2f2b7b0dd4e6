"""The workflow's stages, one function each, from input files to artifacts.

Each function reads its inputs, calls the library, and writes its outputs
atomically; the Snakemake rules in ``workflow/rules`` and the command-line
tool call nothing else.
"""

import json
import logging
import time
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

import colour
import igl
import numpy as np

from beeoptics import camera, colourspace, figures, optics, visualfield
from beeoptics import sky as skies
from beeoptics.errors import InputError
from beeoptics.catches import acceptance_solid_angle, photon_flux, quantum_catches
from beeoptics.imagefile import read_image, write_exr, write_png
from beeoptics.receptors import read_receptors
from beeoptics.retina import canvas, density, retinal_plane, voronoi
from beeoptics.scene import load_scene, raycasting_scene, receptors_in_world
from beeoptics.sensitivity import LAMBDA_MAX_APIS, RECEPTORS, TEMPLATE, overall_sensitivity, sensitivities
from beeoptics.spectra import grid
from beeoptics.table import read_table, write_table
from beeoptics.trace import trace_paths
from beeoptics.validation import check_background
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


def eye_figures(eye_file, relaxation_npz, receptors_csv, outputs):
    """Stage 2b: Collins' Fig. 7 for one eye, maps of its Δφ and facet diameters, its acceptance.

    ``outputs`` maps ``relaxation``, ``delta_phi``, ``facet_diameter`` and
    ``acceptance`` to PNG paths. The acceptance figure draws A(θ) at the 5th,
    50th and 95th percentiles of the eye's Δρ, against its median Δφ.
    """
    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    theta = np.linspace(0.0, 5.0, 501)
    levels = dict(zip(("5th percentile", "median", "95th percentile"),
                      np.percentile(table["delta_rho_deg"], [5, 50, 95])))
    if np.ptp(list(levels.values())) == 0.0:
        levels = {"every receptor": levels["median"]}
    curves = {f"Δρ {v:.2f}° ({k})": optics.acceptance(np.radians(theta), np.radians(v)) for k, v in levels.items()}
    figures.acceptance(theta, curves, float(np.median(table["delta_phi_deg"])), outputs["acceptance"], eye["name"])
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


def _batches(trace, first, last, *, samples, batch_rays, threads):
    """Run ``trace(lo, hi)`` over bundles ``first``..``last`` in batches, on ``threads`` threads.

    A batch is as many consecutive bundles (receptors or pixels) as fit in
    ``batch_rays`` rays of ``samples`` each. Yields ``(lo, hi), trace(lo, hi)``
    in order. numpy and Embree release the GIL, so one thread shades its
    batch while another's rays are cast. A bundle's random numbers depend on
    nothing but its index, so the results do not depend on ``threads``.
    """
    step = max(1, batch_rays // samples)
    bounds = [(lo, min(last, lo + step)) for lo in range(first, last, step)]
    pool = ThreadPoolExecutor(max(1, threads))
    try:
        yield from zip(bounds, pool.map(lambda b: trace(*b), bounds))
    finally:
        # Interrupted: finish only the batches already running.
        pool.shutdown(cancel_futures=True)


def trace_part(receptors_csv, scene_file, part_npz, *, spectral, samples_per_receptor, depth, seed,
               batch_rays, threads=1, part=0, parts=1, light=None, progress=None):
    """Stage 3: trace the acceptance cones of one share of the receptors through a scene.

    Receptors are split into ``parts`` contiguous shares, for running on
    several machines; every receptor draws the same random numbers in any
    share, so the gathered result is bit-identical to a single part's.
    ``threads`` batches of ``batch_rays`` rays are traced at once.
    Writes the share's receptor ids and spectral radiance; returns the ray counts.
    ``light`` overrides the scene's light section (sweeps).
    """
    wl = wavelengths(spectral)
    scene = load_scene(scene_file, wl, light)
    table = read_receptors(receptors_csv)
    origins, axes = receptors_in_world(scene, table["position"], table["axis"])
    drho = table["delta_rho_deg"]
    bounds = np.linspace(0, len(origins), parts + 1).round().astype(int)
    first, last = bounds[part], bounds[part + 1]
    rs = raycasting_scene(scene)
    radiance = np.empty((last - first, len(wl)))
    counts = {"cast": 0, "shadow": 0}
    start = time.perf_counter()

    def trace(lo, hi):
        dirs, weights = optics.cone_samples(axes[lo:hi], drho[lo:hi], samples_per_receptor, seed, first=lo)
        cast = {}
        return trace_paths(scene, origins[lo:hi], dirs, weights, depth=depth, seed=seed, first_stream=lo,
                           rs=rs, counts=cast), cast

    for (lo, hi), (result, cast) in _batches(trace, first, last, samples=samples_per_receptor,
                                             batch_rays=batch_rays, threads=threads):
        radiance[lo - first:hi - first] = result
        counts = {k: counts[k] + cast[k] for k in counts}
        if progress is not None:
            progress(hi - first, last - first)
    log.info("traced receptors %d to %d: %d rays and %d shadow rays in %.1f s", first, last, counts["cast"],
             counts["shadow"], time.perf_counter() - start)
    with atomic_path(part_npz) as tmp:
        # Uncompressed: zlib shrinks these spectra by 6 % and took a sixth of the stage's time.
        np.savez(tmp, id=table["id"][first:last], radiance=radiance)
    return counts


def gather_responses(receptors_csv, scene_file, part_npzs, responses_csv, irradiance_npz, *, spectral,
                     background="scene", light=None, receptor_curves=TEMPLATE):
    """Stage 3, gathered: catches and colour-space coordinates of every receptor.

    Parameters
    ----------
    part_npzs : list of path
        The shares written by :func:`trace_part`, in order.
    background : str
        The adapting background of von Kries adaptation: ``"scene"``, the
        mean catch over both eyes, or the name of one of the scene's
        materials, as a Lambertian surface under the scene's sky and sun.
    light : dict, optional
        Overrides of the scene's light section, as the trace had them.
    receptor_curves : str
        The receptor sensitivities: the template, or a CSV of measured curves
        (:func:`beeoptics.sensitivity.sensitivities`).
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
    sens = sensitivities(wl, receptor_curves)
    catches = quantum_catches(irradiance, sens, wl)
    # Adaptation compares radiances: the acceptance solid angle cancels in every ratio.
    seen = quantum_catches(radiance, sens, wl)
    scene = load_scene(scene_file, wl, light)
    # A white Lambertian surface under the scene's sky and sun: what a named
    # background reflects, and the photon flux of the spectral locus's lights.
    white = skies.horizontal_irradiance(scene.sky, scene.sun, len(wl)) / np.pi
    if background == "scene":
        reference = seen.mean(axis=0)
    else:
        check_background(scene_file, background, scene_file, "materials")
        rho = scene.reflectance[scene.material_names.index(background)]
        reference = quantum_catches((rho * white)[None], sens, wl)[0]
    if not (reference > 0.0).all():
        raise InputError(scene_file, "colour.background",
                         f"the background {background!r} gives no catch in some receptor class; "
                         "von Kries adaptation needs a background every class sees")
    overall = overall_sensitivity(wl, sens)
    brightness = quantum_catches(irradiance, (overall / overall.sum())[:, None], wl)[:, 0]
    write_table(responses_csv, {"id": table["id"], "side": table["side"],
                                **{r: catches[:, k] for k, r in enumerate(RECEPTORS)},
                                "brightness": brightness,
                                **colourspace.describe(seen, reference)})
    with atomic_path(irradiance_npz) as tmp:
        np.savez(tmp, id=table["id"], wavelength_nm=wl, radiance=radiance.astype(np.float32),
                 irradiance=irradiance.astype(np.float32), background_q=reference, white_radiance=white)


def _display(linear, scale):
    """Linear values to sRGB-encoded display values in [0, 1], NaN (outside the eyes) black."""
    v = np.nan_to_num(np.asarray(linear) / scale, nan=0.0)
    return colour.cctf_encoding(np.clip(v, 0.0, 1.0), function="sRGB")


def human_view(scene_file, png, exr, *, spectral, samples_per_pixel, depth, seed, batch_rays, threads=1):
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

    def trace(lo, hi):
        return trace_paths(scene, np.broadcast_to(origin, (hi - lo, 3)), dirs[lo:hi],
                           np.ones((hi - lo, samples_per_pixel)), depth=depth, seed=seed, first_stream=lo, rs=rs)

    for (lo, hi), radiance in _batches(trace, 0, len(dirs), samples=samples_per_pixel, batch_rays=batch_rays,
                                       threads=threads):
        xyz[lo:hi] = camera.tristimulus(wl, radiance)
    shape = (scene.camera["height_px"], scene.camera["width_px"], 3)
    write_png(png, camera.srgb(xyz, np.percentile(xyz[:, 1], 99.0)).reshape(shape))
    write_exr(exr, xyz.reshape(shape), ("X", "Y", "Z"))


def map3(uv, b, g):
    """Collins' map3: UV to red, B to blue, G to green; (1, 1, 1) is white. Linear RGB."""
    return np.stack([uv, g, b], -1)


def _bee_colours(q, irradiance):
    """map3 colours and their exposure, and map2's display sRGB, of each receptor.

    One exposure for all three channels keeps their relative responses.
    """
    xyz = camera.tristimulus(irradiance["wavelength_nm"], irradiance["radiance"])
    return map3(q[:, 0], q[:, 1], q[:, 2]), np.percentile(q, 99.5), camera.srgb(xyz, np.percentile(xyz[:, 1], 99.5))


#: The images :func:`retinal_images` writes for one eye in one scene: output name, file name.
IMAGES = {
    "voronoi_map3": "voronoi_map3.png",
    "voronoi_map2": "voronoi_map2.png",
    "density_map3": "density_map3.png",
    "density_map3_normalised": "density_map3_normalised.png",
    "channel_uv": "channel_uv.png",
    "channel_b": "channel_b.png",
    "channel_g": "channel_g.png",
    "exr": "catches.exr",
}


def retinal_images(eye_file, receptors_csv, responses_csv, irradiance_npz, outputs, width_px=400):
    """Stage 4: Voronoi, density and channel images of one eye in one scene, and the EXR of catches."""
    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    resp = read_table(responses_csv, numeric=["id", *RECEPTORS], text=["side"])
    q = np.column_stack([resp[r] for r in RECEPTORS])
    data = np.load(irradiance_npz)
    xy = retinal_plane(eye, table["position"], table["side"])
    can = canvas(xy, width_px)
    colours, scale, srgb = _bee_colours(q, data)
    write_png(outputs["voronoi_map3"], _display(voronoi(can, xy, table["side"], colours), scale))
    dens = density(can, xy, table["side"], colours, normalise=False)
    write_png(outputs["density_map3"], _display(dens, np.nanpercentile(dens, 99.5)))
    write_png(outputs["density_map3_normalised"],
              _display(density(can, xy, table["side"], colours, normalise=True), scale))
    for k, name in enumerate(("channel_uv", "channel_b", "channel_g")):
        write_png(outputs[name], _display(voronoi(can, xy, table["side"], q[:, k]), scale)[..., 0])
    # Nearest-receptor images copy values, so encoding before the Voronoi step is exact.
    write_png(outputs["voronoi_map2"], np.nan_to_num(voronoi(can, xy, table["side"], srgb), nan=0.0))
    write_exr(outputs["exr"], np.nan_to_num(voronoi(can, xy, table["side"], q), nan=0.0), RECEPTORS)


def visual_field_maps(receptors_csv, responses_csv, irradiance_npz, human_png, outputs, width_px=720):
    """Stage 4b: both eyes' visual field in azimuth and elevation, beside the human view.

    Writes ``figure`` (PNG: map3 and map2 on the sphere, the binocular
    overlap outlined, the human render beside them) and ``exr``
    (equirectangular catches ``UV``, ``B``, ``G`` and ``eyes``, the bits of
    the eyes that see each direction: 1 right, 2 left, 3 both; zero catches
    where none sees).
    """
    table = read_receptors(receptors_csv)
    resp = read_table(responses_csv, numeric=["id", *RECEPTORS], text=["side"])
    q = np.column_stack([resp[r] for r in RECEPTORS])
    colours, scale, srgb = _bee_colours(q, np.load(irradiance_npz))
    field = visualfield.visual_field(table["axis"], table["side"], table["delta_rho_deg"],
                                     table["delta_phi_deg"], width_px)
    seen = field.receptor >= 0
    panels = {
        "bee colours (map3: UV→R, B→B, G→G)": np.where(seen[..., None], _display(visualfield.paint(field, colours), scale), np.nan),
        "human colours on the bee's geometry (map2)": visualfield.paint(field, srgb),
    }
    figures.visual_field(panels, field.eyes, field.azimuth_deg, field.elevation_deg, read_image(human_png)[0][..., :3],
                         outputs["figure"], "visual field of both eyes, equirectangular")
    catches = np.nan_to_num(visualfield.paint(field, q), nan=0.0)
    write_exr(outputs["exr"], np.concatenate([catches, field.eyes[..., None].astype(float)], -1),
              (*RECEPTORS, "eyes"))


def colour_figures(responses_csv, irradiance_npz, outputs, title="", receptor_curves=TEMPLATE):
    """Stage 4c: every receptor's colour in the bee colour triangle and hexagon (Collins Fig. 5b).

    The spectral locus is isoquantal, as the lights of bee colour-vision
    experiments are (von Helversen 1972): each monochromatic light carries
    the whole photon flux of a white Lambertian surface under the scene's sky
    and sun, and is adapted to the same background as the receptors.
    ``outputs`` maps ``triangle`` and ``hexagon`` to PNG paths.
    """
    resp = read_table(responses_csv, numeric=["id", "tri_x", "tri_y", "hex_x", "hex_y", *RECEPTORS], text=["side"])
    data = np.load(irradiance_npz)
    wl = data["wavelength_nm"]
    q = np.column_stack([resp[r] for r in RECEPTORS])
    srgb = _bee_colours(q, data)[2]
    white = photon_flux(data["white_radiance"], wl).sum()
    locus = colourspace.spectral_locus(sensitivities(wl, receptor_curves), wl, data["background_q"], white)
    figures.colour_space(np.column_stack([resp["tri_x"], resp["tri_y"]]), srgb, colourspace.TRIANGLE_VERTICES,
                         (locus.wavelengths, locus.triangle), outputs["triangle"],
                         f"{title}: receptor colours in the bee colour triangle")
    figures.colour_space(np.column_stack([resp["hex_x"], resp["hex_y"]]), srgb, colourspace.HEXAGON_OUTLINE,
                         (locus.wavelengths, locus.hexagon), outputs["hexagon"],
                         f"{title}: receptor colours in the colour hexagon (Chittka 1992)")


def sensitivity_figure(spectral, path, receptor_curves=TEMPLATE):
    """Collins Fig. 6 and 5a: the receptor sensitivities and the overall S(λ), on the config's grid."""
    wl = wavelengths(spectral)
    sens = sensitivities(wl, receptor_curves)
    source = (f"Govardovskii A1, λmax {'/'.join(f'{lam:g}' for lam in LAMBDA_MAX_APIS)} nm"
              if receptor_curves == TEMPLATE else f"measured, {Path(receptor_curves).name}")
    figures.sensitivities(wl, sens, overall_sensitivity(wl, sens), path, source)


#: Peak wavelengths at which the Rayleigh limit is given, nm (Peitsch et al. 1992).
RAYLEIGH_NM = dict(zip(RECEPTORS, LAMBDA_MAX_APIS))


def acuity_table(receptors_csvs, path, width_px=720):
    """Acuity figures of each eye, one row per eye class (both eyes together).

    Columns: receptor count; percentiles 5/50/95 of Δφ and Δρ (°); the
    highest spatial frequency the lattice resolves, f_max = 1/(2Δφ)
    (cycles/°, Nyquist; Snyder 1977) at the median and 5th-percentile Δφ;
    median facet diameter D (µm); the Rayleigh limit 1.22 λ/D (°; the first
    zero of the Airy pattern, Airy 1835, Rayleigh 1879; Land 1997 for compound eyes) at each
    receptor's λmax for the median and largest facet; the solid angle each
    eye sees and the binocular overlap (sr, at half sensitivity, see
    :mod:`beeoptics.visualfield`).

    Parameters
    ----------
    receptors_csvs : dict of str to path
        Eye class to its receptor table.
    """
    rows = {}
    for name, csv in receptors_csvs.items():
        t = read_receptors(csv)
        dphi, drho, d_um = t["delta_phi_deg"], t["delta_rho_deg"], t["facet_diameter_um"]
        row = {"eye": name, "receptors": len(dphi)}
        for label, values in (("delta_phi_deg", dphi), ("delta_rho_deg", drho)):
            row.update({f"{label}_p{p}": np.percentile(values, p) for p in (5, 50, 95)})
        row["f_max_cpd_median"] = 1.0 / (2.0 * np.median(dphi))
        row["f_max_cpd_p5"] = 1.0 / (2.0 * np.percentile(dphi, 5))
        row["facet_diameter_um_median"] = np.median(d_um)
        for receptor, lam in RAYLEIGH_NM.items():
            for label, d in (("median", np.median(d_um)), ("largest", d_um.max())):
                row[f"rayleigh_deg_{receptor}_{label}_facet"] = np.degrees(1.22 * lam * 1e-9 / (d * 1e-6))
        field = visualfield.visual_field(t["axis"], t["side"], drho, dphi, width_px)
        extent = visualfield.extent(field)
        row.update({k: extent[k] for k in ("right_sr", "left_sr", "binocular_sr", "total_fraction")})
        for k, v in row.items():
            rows.setdefault(k, []).append(v)
    write_table(path, {k: np.asarray(v) if k != "eye" else v for k, v in rows.items()})


def with_delta_rho(receptors_csv, out_csv, delta_rho_deg=None):
    """A receptor table whose every receptor has acceptance angle ``delta_rho_deg`` (a copy if None)."""
    table = read_receptors(receptors_csv)
    if delta_rho_deg is not None:
        table["delta_rho_deg"] = np.full(len(table["id"]), float(delta_rho_deg))
    write_receptors(out_csv, table)


#: Columns of responses.csv summarised per sweep variant, eye and scene.
SUMMARISED = ("UV", "B", "G", "brightness", "hex_r", "rnl_dS")


def sweep_summary(runs, path):
    """One row per sweep variant, eye and scene: its parameters and its receptors' responses.

    Parameters
    ----------
    runs : list of dict
        ``variant``, ``eye``, ``scene``, ``responses`` (path) and the
        variant's parameter values, in the order the rows are written.

    The responses are summarised by their mean and their 5th, 50th and 95th
    percentiles over both eyes' receptors.
    """
    rows = []
    for run in runs:
        resp = read_table(run["responses"], numeric=list(SUMMARISED), text=["side"])
        row = {k: v for k, v in run.items() if k != "responses"}
        for name in SUMMARISED:
            row[f"{name}_mean"] = np.mean(resp[name])
            row.update({f"{name}_p{p}": np.percentile(resp[name], p) for p in (5, 50, 95)})
        rows.append(row)
    text = ("variant", "eye", "scene")
    write_table(path, {k: [r[k] for r in rows] if k in text else np.array([r[k] for r in rows], float)
                       for k in rows[0]})
