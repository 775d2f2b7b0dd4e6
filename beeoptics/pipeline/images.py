"""The image stages: retinal images, visual-field maps, colour-space figures and the sensitivity figure.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically.
"""

import numpy as np

from beeoptics.eye.description import load_eye
from beeoptics.eye.fieldofview import MAP_WIDTH_PX, visual_field
from beeoptics.images import figures
from beeoptics.images.display import bee_colours, display_words, encode, polarisation_colours
from beeoptics.images.fieldmaps import field_images, paint
from beeoptics.pipeline.outputs import channel
from beeoptics.images.retina import retinal_images as retina_images
from beeoptics.io.imagefile import read_image, write_exr
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import read_table
from beeoptics.io.validation import config_default
from beeoptics.spectra import grid
from beeoptics.vision import colourspace
from beeoptics.vision.catches import photon_flux
from beeoptics.vision.receptorset import DEFAULT_CURVES, curves, describe, overall


def _responses(responses_csv, irradiance_npz, receptor_set, columns=()):
    """The responses table, the irradiance file, every receptor's catches (n, classes), and its catches
    relative to white, map3 colour and map2 colour (:func:`beeoptics.images.display.bee_colours`)."""
    resp = read_table(responses_csv, numeric=["id", *receptor_set.classes, *columns], text=["side"])
    data = np.load(irradiance_npz)
    catches = np.column_stack([resp[r] for r in receptor_set.classes])
    return resp, data, catches, bee_colours(catches, data["white_q"], data["wavelength_nm"], data["radiance"],
                                            receptor_set.display)


#: How each retinal image maps values to grey levels, for its caption.
_SURROUND = "Light grey: outside the eyes; black: a receptor that caught no light."
_WHITE = ("each catch over the catch of a white Lambertian surface under the scene's light (von Kries to "
          "white), so a white surface shows white; above 1 clipped; sRGB-encoded.")
RETINAL_CAPTIONS = {
    "voronoi_map3": f"map3 (Collins §4.4), each pixel its nearest receptor: {{display}}, {_WHITE}",
    "voronoi_map2": "map2, each pixel its nearest receptor: the receptor's light in its human colour "
                    "(CIE 1931, sRGB), the 99.5th percentile of luminance shown white.",
    "density_map3": "map3 colours summed with a Gaussian kernel (σ: the median neighbour distance), the "
                    "99.5th percentile shown white: brightness follows receptor density (Collins Colour Plate 2).",
    "density_map3_normalised": "map3 colours, Gaussian kernel estimate divided by the kernel-spread receptor "
                               f"count (Nadaraya–Watson), {_WHITE}",
}


def retinal_images(eye_file, receptors_csv, responses_csv, irradiance_npz, outputs, *, receptor_set,
                   width_px=config_default("images.width_px"), title=""):
    """Voronoi, density and channel images of one eye in one scene, and the EXR of catches.

    The PNGs are figures: both eyes in the retinal plane in millimetres,
    the head's dorsal and anterior directions marked, and a caption stating
    the exposure (:data:`RETINAL_CAPTIONS`). The EXR holds the raw catches
    on the same pixels. ``outputs`` maps the names of
    :data:`beeoptics.pipeline.outputs.IMAGES` to paths.
    """
    table = read_receptors(receptors_csv)
    _, _, catches, (relative, colours, srgb) = _responses(responses_csv, irradiance_npz, receptor_set)
    retina = retina_images(load_eye(eye_file), table, relative, colours, srgb, receptor_set.classes, width_px)
    shown = dict(retina.images)
    captions = {k: v.format(display=display_words(receptor_set)) for k, v in RETINAL_CAPTIONS.items()}
    for name, image in retina.channels.items():
        shown[channel(name)] = image
        captions[channel(name)] = (f"{name} receptor catch over a white surface's under the scene's light, linear, "
                                   "0 black, 1 white, above 1 clipped.")
    figures.retinas([(image, outputs[name], f"{title}: {name.replace('_', ' ')}", f"{captions[name]} {_SURROUND}",
                      "catch ÷ white's catch" if image.ndim == 2 else None) for name, image in shown.items()],
                    retina.extents, retina.anterior, retina.dorsal)
    write_exr(outputs["exr"], np.nan_to_num(paint(retina.nearest, catches), nan=0.0), receptor_set.classes)


def visual_field_maps(receptors_csv, responses_csv, irradiance_npz, human_png, outputs, *, receptor_set,
                      width_px=MAP_WIDTH_PX):
    """Both eyes' visual field in azimuth and elevation, beside the human view.

    Writes ``figure`` (PNG: map3 and map2 on the sphere, the binocular
    overlap outlined, the human render beside them if ``human_png`` is given) and ``exr``
    (equirectangular catches of each receptor class, ``UV``, ``B``, ``G``
    for a bee, and ``eyes``, the bits of the eyes that see each direction:
    1 right, 2 left, 3 both; zero catches where none sees).
    """
    table = read_receptors(receptors_csv)
    _, _, catches, (_, colours, srgb) = _responses(responses_csv, irradiance_npz, receptor_set)
    field = visual_field(table.axis, table.side, table.delta_rho_deg, table.delta_phi_deg, width_px)
    maps = field_images(field.receptor, colours, srgb)
    panels = {f"bee colours (map3: {display_words(receptor_set)}, white = 1)": maps["map3"],
              "human colours on the bee's geometry (map2)": maps["map2"]}
    human = None if human_png is None else read_image(human_png)[0][..., :3]
    figures.visual_field(panels, field.eyes, field.azimuth_deg, field.elevation_deg, human, outputs["figure"],
                         "visual field of both eyes, equirectangular")
    painted = np.nan_to_num(paint(field.receptor, catches), nan=0.0)
    write_exr(outputs["exr"], np.concatenate([painted, field.eyes[..., None].astype(float)], -1),
              (*receptor_set.classes, "eyes"))


def colour_figures(responses_csv, irradiance_npz, outputs, *, receptor_set, title="", receptor_curves=DEFAULT_CURVES):
    """Every receptor's colour in the bee colour triangle and hexagon (Collins Fig. 5b), those the set has.

    The spectral locus's lights are adapted to the same background as the
    receptors. In the triangle their intensity does not matter. In the
    hexagon it does (excitation saturates), so the locus is drawn, as in
    pavo, at one stated intensity: each monochromatic light carrying the
    photon flux of a white Lambertian surface under the scene's sky and sun
    (:func:`hexagon_locus`); a second, dashed line takes each light at the
    intensity that puts it furthest from the centre
    (:func:`beeoptics.vision.colourspace.widest_spectral_locus`), the edge of
    what monochromatic lights can reach, its legend stating the range.
    ``outputs`` maps ``triangle`` and ``hexagon`` (as the set has them) to PNG paths.
    """
    if not outputs:  # a set without the bee colour spaces (not a trichromat's): nothing to draw
        return
    columns = [c for space, names in (("triangle", ["tri_x", "tri_y"]), ("hexagon", ["hex_x", "hex_y"]))
               if space in outputs for c in names]
    resp, data, _, (_, _, srgb) = _responses(responses_csv, irradiance_npz, receptor_set, columns)
    locus, label = hexagon_locus(data, receptor_set, receptor_curves)
    labels = [receptor_set.classes[k] for k in receptor_set.chromatic]
    if "triangle" in outputs:
        figures.colour_space(np.column_stack([resp["tri_x"], resp["tri_y"]]), srgb, colourspace.TRIANGLE_VERTICES,
                             [(locus.wavelengths, locus.triangle, "spectral locus: monochromatic lights (any "
                               "intensity)")], outputs["triangle"],
                             f"{title}: receptor colours in the bee colour triangle", labels)
    if "hexagon" in outputs:
        widest, intensity = widest_locus(data, receptor_set, receptor_curves)
        figures.colour_space(np.column_stack([resp["hex_x"], resp["hex_y"]]), srgb, colourspace.HEXAGON_OUTLINE,
                             [(locus.wavelengths, locus.hexagon, label),
                              (widest.wavelengths, widest.hexagon,
                               "furthest out: each light at the intensity that puts it furthest from the centre,\n"
                               f"{intensity.min():.2g}–{intensity.max():.2g} × that flux")],
                             outputs["hexagon"], f"{title}: receptor colours in the colour hexagon (Chittka 1992)",
                             labels)


#: The stated intensity of the hexagon's spectral locus, for the legends.
LOCUS_WORDS = ("spectral locus: monochromatic lights, each with the photon flux of a white surface under the "
               "scene's light")


def _locus_inputs(data, receptor_set, receptor_curves):
    wl = data["wavelength_nm"]
    colour = receptor_set.chromatic
    return (curves(receptor_set, wl, receptor_curves)[:, colour], wl, data["background_q"][colour],
            photon_flux(data["white_radiance"], wl).sum())


def hexagon_locus(data, receptor_set, receptor_curves=DEFAULT_CURVES):
    """The spectral locus at one stated intensity, and its legend.

    Each light is a spike of one grid bin carrying the whole photon flux of
    a white Lambertian surface under the scene's light (the irradiance
    file's ``white_radiance``), adapted to the scene's background: a light
    as bright, in photons, as white paper beside the receptors.
    """
    return colourspace.spectral_locus(*_locus_inputs(data, receptor_set, receptor_curves)), LOCUS_WORDS


def widest_locus(data, receptor_set, receptor_curves=DEFAULT_CURVES):
    """:func:`beeoptics.vision.colourspace.widest_spectral_locus` relative to the flux of :func:`hexagon_locus`."""
    return colourspace.widest_spectral_locus(*_locus_inputs(data, receptor_set, receptor_curves))


def sensitivity_figure(outputs, *, spectral, receptor_set, receptor_curves=DEFAULT_CURVES):
    """Collins Fig. 6 and 5a, ``outputs["figure"]``: a receptor set's curves and, where it has one, its
    overall S(λ)."""
    wl = grid(**spectral)
    sens = curves(receptor_set, wl, receptor_curves)
    figures.sensitivities(wl, sens, receptor_set.classes, overall(receptor_set, wl, sens), outputs["figure"],
                          describe(receptor_set, receptor_curves))


def viewer(receptors_csv, responses_csv, irradiance_npz, outputs, *, receptor_set, polarisation_csv=None, title="",
           receptor_curves=DEFAULT_CURVES):
    """The interactive viewer of one eye in one scene: ``outputs["viewer"]``, a self-contained HTML page
    (:func:`beeoptics.images.viewer.receptor_viewer`).

    Coloured by map3, each receptor class over white's catch, map2 and, with
    ``polarisation_csv`` (a polarisation stage's table), polarisation; the
    hexagon, for a species that has one, linked to the map, its spectral
    locus the monochromatic lights of a white surface's photon flux.
    """
    from beeoptics.images.viewer import receptor_viewer

    table = read_receptors(receptors_csv)
    columns = ["hex_x", "hex_y"] if "hexagon" in receptor_set.spaces else []
    resp, data, catches, (relative, colours, srgb) = _responses(responses_csv, irradiance_npz, receptor_set, columns)
    shown = {"map3": encode(colours)}
    for k, name in enumerate(receptor_set.classes):
        shown[name] = np.repeat(np.clip(relative[:, k:k + 1], 0.0, 1.0), 3, axis=1)
    shown["map2"] = srgb
    # A number with its standard error where the table gives one (se_<column>), shown as value ± error.
    def with_error(name, values):
        return (values, np.asarray(resp[f"se_{name}"], float)) if f"se_{name}" in resp else values

    hover = {"Δφ, °": table.delta_phi_deg, "Δρ, °": table.delta_rho_deg, "facet, µm": table.facet_diameter_um,
             **{f"{c} catch": with_error(c, catches[:, k]) for k, c in enumerate(receptor_set.classes)},
             **{f"{c} ÷ white's": relative[:, k] for k, c in enumerate(receptor_set.classes)}}
    for name in ("hex_x", "hex_y", "rnl_dS"):
        if name in resp:
            hover[name] = with_error(name, resp[name])
    space = None
    if columns:
        locus, label = hexagon_locus(data, receptor_set, receptor_curves)
        space = {"x": resp["hex_x"], "y": resp["hex_y"], "outline": colourspace.HEXAGON_OUTLINE,
                 "locus": locus.hexagon, "name": "colour hexagon (Chittka 1992): select receptors here or on the map",
                 "locus_label": label}
    pol = None
    if polarisation_csv is not None:
        p = read_table(polarisation_csv, numeric=["id"], text=["side"])
        klass = receptor_set.classes[receptor_set.polarisation] if receptor_set.polarisation is not None else None
        if klass is not None and f"{klass}_degree" in p:
            pol = polarisation_colours(p[f"{klass}_degree"], p[f"{klass}_angle_deg"])
            hover[f"{klass} polarisation degree"] = p[f"{klass}_degree"]
            hover[f"{klass} e-vector angle, °"] = p[f"{klass}_angle_deg"]
    caption = (f"map3 (Collins §4.4): {display_words(receptor_set)}, each catch over a white Lambertian surface's "
               "under the scene's light, so white shows white; a class alone: its catch over white's, 0 black, "
               "1 white; map2: the receptor's light in human colour (CIE 1931, sRGB). Every receptor of both "
               "eyes at its axis; hover for its numbers.")
    receptor_viewer(outputs["viewer"], table, shown, hover, title, caption, space, pol)
