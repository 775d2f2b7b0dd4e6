"""The image stages: retinal images, visual-field maps, colour-space figures and the sensitivity figure.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically.
"""

import numpy as np

from beeoptics.eye.description import load_eye
from beeoptics.eye.fieldofview import visual_field
from beeoptics.images import figures
from beeoptics.images.display import bee_colours, encode
from beeoptics.images.fieldmaps import paint
from beeoptics.headframe import in_eye_plane
from beeoptics.images.retina import canvas, density, panel_extents, retinal_plane, voronoi
from beeoptics.io.imagefile import read_image, write_exr
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import read_table
from beeoptics.spectra import grid
from beeoptics.vision import colourspace
from beeoptics.vision.catches import photon_flux
from beeoptics.vision.sensitivity import PEITSCH_1992, RECEPTORS, describe, overall_sensitivity, sensitivities

def _responses(responses_csv, irradiance_npz, columns=()):
    """The responses table, the irradiance file, and every receptor's catches relative to white,
    map3 colour and map2 colour (:func:`beeoptics.images.display.bee_colours`)."""
    resp = read_table(responses_csv, numeric=["id", *RECEPTORS, *columns], text=["side"])
    data = np.load(irradiance_npz)
    catches = np.column_stack([resp[r] for r in RECEPTORS])
    return resp, data, bee_colours(catches, data["white_q"], data["wavelength_nm"], data["radiance"])


#: How each retinal image maps values to grey levels, for its caption.
_SURROUND = "Light grey: outside the eyes; black: a receptor that caught no light."
_WHITE = ("each catch over the catch of a white Lambertian surface under the scene's light (von Kries to "
          "white), so a white surface shows white; above 1 clipped; sRGB-encoded.")
RETINAL_CAPTIONS = {
    "voronoi_map3": f"map3 (Collins §4.4), each pixel its nearest receptor: red UV, green G, blue B, {_WHITE}",
    "voronoi_map2": "map2, each pixel its nearest receptor: the receptor's light in its human colour "
                    "(CIE 1931, sRGB), the 99.5th percentile of luminance shown white.",
    "density_map3": "map3 colours summed with a Gaussian kernel (σ: the median neighbour distance), the "
                    "99.5th percentile shown white: brightness follows receptor density (Collins Colour Plate 2).",
    "density_map3_normalised": "map3 colours, Gaussian kernel estimate divided by the kernel-spread receptor "
                               f"count (Nadaraya–Watson), {_WHITE}",
    "channel_uv": "UV receptor catch over a white surface's under the scene's light, linear, 0 black, 1 white, "
                  "above 1 clipped.",
    "channel_b": "B receptor catch over a white surface's under the scene's light, linear, 0 black, 1 white, "
                 "above 1 clipped.",
    "channel_g": "G receptor catch over a white surface's under the scene's light, linear, 0 black, 1 white, "
                 "above 1 clipped.",
}


def retinal_images(eye_file, receptors_csv, responses_csv, irradiance_npz, outputs, *, width_px=400, title=""):
    """Voronoi, density and channel images of one eye in one scene, and the EXR of catches.

    The PNGs are figures: both eyes in the retinal plane in millimetres,
    the head's dorsal and anterior directions marked, and a caption stating
    the exposure (:data:`RETINAL_CAPTIONS`). The EXR holds the raw catches
    on the same pixels. ``outputs`` maps the names of
    :data:`beeoptics.pipeline.outputs.IMAGES` to paths.
    """
    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    resp, _, (relative, colours, srgb) = _responses(responses_csv, irradiance_npz)
    catches = np.column_stack([resp[r] for r in RECEPTORS])
    xy = retinal_plane(eye, table.position, table.side)
    can = canvas(xy, width_px)
    extents = panel_extents(can)
    anterior, dorsal = in_eye_plane(eye.rotation)
    dens = density(can, xy, table.side, colours, normalise=False)
    shown = {
        "voronoi_map3": encode(voronoi(can, xy, table.side, colours)),
        # Nearest-receptor images copy values, so encoding before the Voronoi step is exact.
        "voronoi_map2": voronoi(can, xy, table.side, srgb),
        "density_map3": encode(dens, np.nanpercentile(dens, 99.5)),
        "density_map3_normalised": encode(density(can, xy, table.side, colours, normalise=True)),
    }
    for k, name in enumerate(("channel_uv", "channel_b", "channel_g")):
        shown[name] = np.clip(voronoi(can, xy, table.side, relative[:, k])[..., 0], 0.0, 1.0)
    for name, image in shown.items():
        figures.retina(image, extents, anterior, dorsal, outputs[name], f"{title}: {name.replace('_', ' ')}",
                       f"{RETINAL_CAPTIONS[name]} {_SURROUND}",
                       "catch ÷ white's catch" if image.ndim == 2 else None)
    write_exr(outputs["exr"], np.nan_to_num(voronoi(can, xy, table.side, catches), nan=0.0), RECEPTORS)


def visual_field_maps(receptors_csv, responses_csv, irradiance_npz, human_png, outputs, *, width_px=720):
    """Both eyes' visual field in azimuth and elevation, beside the human view.

    Writes ``figure`` (PNG: map3 and map2 on the sphere, the binocular
    overlap outlined, the human render beside them if ``human_png`` is given) and ``exr``
    (equirectangular catches ``UV``, ``B``, ``G`` and ``eyes``, the bits of
    the eyes that see each direction: 1 right, 2 left, 3 both; zero catches
    where none sees).
    """
    table = read_receptors(receptors_csv)
    resp, _, (_, colours, srgb) = _responses(responses_csv, irradiance_npz)
    catches = np.column_stack([resp[r] for r in RECEPTORS])
    field = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, width_px)
    seen = field.receptor >= 0
    panels = {
        "bee colours (map3: UV→R, B→B, G→G, white = 1)": np.where(seen[..., None], encode(paint(field, colours)),
                                                                  np.nan),
        "human colours on the bee's geometry (map2)": paint(field, srgb),
    }
    human = None if human_png is None else read_image(human_png)[0][..., :3]
    figures.visual_field(panels, field.eyes, field.azimuth_deg, field.elevation_deg, human, outputs["figure"],
                         "visual field of both eyes, equirectangular")
    painted = np.nan_to_num(paint(field, catches), nan=0.0)
    write_exr(outputs["exr"], np.concatenate([painted, field.eyes[..., None].astype(float)], -1),
              (*RECEPTORS, "eyes"))


def colour_figures(responses_csv, irradiance_npz, outputs, *, title="", receptor_curves=PEITSCH_1992):
    """Every receptor's colour in the bee colour triangle and hexagon (Collins Fig. 5b).

    The spectral locus's lights are adapted to the same background as the
    receptors. In the triangle their intensity does not matter; in the
    hexagon each is drawn at the intensity that puts it furthest from the
    centre (:func:`beeoptics.vision.colourspace.widest_spectral_locus`),
    relative to the photon flux of a white Lambertian surface under the
    scene's sky and sun, and the figure's legend states the range.
    ``outputs`` maps ``triangle`` and ``hexagon`` to PNG paths.
    """
    resp, data, (_, _, srgb) = _responses(responses_csv, irradiance_npz, ["tri_x", "tri_y", "hex_x", "hex_y"])
    wl = data["wavelength_nm"]
    white = photon_flux(data["white_radiance"], wl).sum()
    locus, intensity = colourspace.widest_spectral_locus(sensitivities(wl, receptor_curves), wl,
                                                         data["background_q"], white)
    figures.colour_space(np.column_stack([resp["tri_x"], resp["tri_y"]]), srgb, colourspace.TRIANGLE_VERTICES,
                         (locus.wavelengths, locus.triangle), outputs["triangle"],
                         f"{title}: receptor colours in the bee colour triangle",
                         "spectral locus: monochromatic lights (any intensity)")
    figures.colour_space(np.column_stack([resp["hex_x"], resp["hex_y"]]), srgb, colourspace.HEXAGON_OUTLINE,
                         (locus.wavelengths, locus.hexagon), outputs["hexagon"],
                         f"{title}: receptor colours in the colour hexagon (Chittka 1992)",
                         "spectral locus: each monochromatic light at the intensity that puts it furthest out,\n"
                         f"{intensity.min():.2g}–{intensity.max():.2g} × a white surface's photon flux "
                         "under the scene's light")


def sensitivity_figure(outputs, *, spectral, receptor_curves=PEITSCH_1992):
    """Collins Fig. 6 and 5a, ``outputs["figure"]``: the receptor sensitivities and the overall S(λ)."""
    wl = grid(**spectral)
    sens = sensitivities(wl, receptor_curves)
    figures.sensitivities(wl, sens, overall_sensitivity(wl, sens), outputs["figure"], describe(receptor_curves))
