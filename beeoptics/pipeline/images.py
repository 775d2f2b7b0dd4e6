"""The image stages: retinal images, visual-field maps, colour-space figures and the sensitivity figure.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically.
"""

from pathlib import Path

import numpy as np

from beeoptics.eye.description import load_eye
from beeoptics.eye.fieldofview import visual_field
from beeoptics.images import figures
from beeoptics.images.display import bee_colours, encode
from beeoptics.images.fieldmaps import paint
from beeoptics.images.retina import canvas, density, retinal_plane, voronoi
from beeoptics.io.imagefile import read_image, write_exr, write_png
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import read_table
from beeoptics.spectra import grid
from beeoptics.vision import colourspace
from beeoptics.vision.catches import photon_flux
from beeoptics.vision.sensitivity import LAMBDA_MAX_APIS, RECEPTORS, TEMPLATE, overall_sensitivity, sensitivities

def _responses(responses_csv, irradiance_npz, columns=()):
    """The responses table, the irradiance file, and every receptor's catches relative to white,
    map3 colour and map2 colour (:func:`beeoptics.images.display.bee_colours`)."""
    resp = read_table(responses_csv, numeric=["id", *RECEPTORS, *columns], text=["side"])
    data = np.load(irradiance_npz)
    catches = np.column_stack([resp[r] for r in RECEPTORS])
    return resp, data, bee_colours(catches, data["white_q"], data["wavelength_nm"], data["radiance"])


def retinal_images(eye_file, receptors_csv, responses_csv, irradiance_npz, outputs, *, width_px=400):
    """Voronoi, density and channel images of one eye in one scene, and the EXR of catches.

    ``outputs`` maps the names of :data:`beeoptics.pipeline.outputs.IMAGES` to paths.
    """
    eye = load_eye(eye_file)
    table = read_receptors(receptors_csv)
    resp, _, (relative, colours, srgb) = _responses(responses_csv, irradiance_npz)
    catches = np.column_stack([resp[r] for r in RECEPTORS])
    xy = retinal_plane(eye, table.position, table.side)
    can = canvas(xy, width_px)
    write_png(outputs["voronoi_map3"], encode(voronoi(can, xy, table.side, colours)))
    dens = density(can, xy, table.side, colours, normalise=False)
    # Summed rather than averaged colours: shown to their own 99.5th percentile, to show the artefact.
    write_png(outputs["density_map3"], encode(dens, np.nanpercentile(dens, 99.5)))
    write_png(outputs["density_map3_normalised"], encode(density(can, xy, table.side, colours, normalise=True)))
    for k, name in enumerate(("channel_uv", "channel_b", "channel_g")):
        write_png(outputs[name], encode(voronoi(can, xy, table.side, relative[:, k]))[..., 0])
    # Nearest-receptor images copy values, so encoding before the Voronoi step is exact.
    write_png(outputs["voronoi_map2"], voronoi(can, xy, table.side, srgb))
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


def colour_figures(responses_csv, irradiance_npz, outputs, *, title="", receptor_curves=TEMPLATE):
    """Every receptor's colour in the bee colour triangle and hexagon (Collins Fig. 5b).

    The spectral locus is isoquantal, as the lights of bee colour-vision
    experiments are (von Helversen 1972): each monochromatic light carries
    the whole photon flux of a white Lambertian surface under the scene's sky
    and sun, and is adapted to the same background as the receptors.
    ``outputs`` maps ``triangle`` and ``hexagon`` to PNG paths.
    """
    resp, data, (_, _, srgb) = _responses(responses_csv, irradiance_npz, ["tri_x", "tri_y", "hex_x", "hex_y"])
    wl = data["wavelength_nm"]
    white = photon_flux(data["white_radiance"], wl).sum()
    locus = colourspace.spectral_locus(sensitivities(wl, receptor_curves), wl, data["background_q"], white)
    figures.colour_space(np.column_stack([resp["tri_x"], resp["tri_y"]]), srgb, colourspace.TRIANGLE_VERTICES,
                         (locus.wavelengths, locus.triangle), outputs["triangle"],
                         f"{title}: receptor colours in the bee colour triangle")
    figures.colour_space(np.column_stack([resp["hex_x"], resp["hex_y"]]), srgb, colourspace.HEXAGON_OUTLINE,
                         (locus.wavelengths, locus.hexagon), outputs["hexagon"],
                         f"{title}: receptor colours in the colour hexagon (Chittka 1992)")


def sensitivity_figure(outputs, *, spectral, receptor_curves=TEMPLATE):
    """Collins Fig. 6 and 5a, ``outputs["figure"]``: the receptor sensitivities and the overall S(λ)."""
    wl = grid(**spectral)
    sens = sensitivities(wl, receptor_curves)
    source = (f"Govardovskii A1, λmax {'/'.join(f'{lam:g}' for lam in LAMBDA_MAX_APIS)} nm"
              if receptor_curves == TEMPLATE else f"measured, {Path(receptor_curves).name}")
    figures.sensitivities(wl, sens, overall_sensitivity(wl, sens), outputs["figure"], source)
