"""Showing bee catches to people: Collins's map3 and map2, and the display encoding.

map3 (Collins §4.4) shows the UV, B and G catches as red, blue and green,
"a white sum on the display when all channels are at unity"; for another
species, the three receptor classes its receptor set names for red, green
and blue (:mod:`beeoptics.vision.receptorset`). Unity is the
catch of a white Lambertian surface under the scene's sky and sun, through
the same receptor: each channel is divided by it (von Kries adaptation to
white), so a white surface in the scene's light is white, a grey one grey,
and a colour shows how its catches stand against white's. map2 shows each
receptor's light in its human colour (CIE 1931, sRGB) on the bee's
geometry, the 99.5th percentile of luminance as white. Both are a
visualisation, not what the bee perceives. Where no eye sees, values are
NaN, which images show transparent, so that a receptor that caught no
light (black) stands apart from the space outside the eye.
"""

import numpy as np

from beeoptics.vision.human import srgb, tristimulus

#: Percentile of the luminance map2 shows as white.
EXPOSURE_PERCENTILE = 99.5


def map3(relative, display):
    """Collins' map3 of catches relative to white (n, classes): the ``display`` classes (for each of the red,
    green and blue channels, the indices of its classes; a bee's UV, G and B) as linear RGB, (1, 1, 1) white.

    A channel of several classes shows the one the receptor's ommatidium has
    (the others' catches NaN, :func:`beeoptics.vision.receptorset.lacking`);
    a channel none of whose classes it has shows dark.
    """
    relative = np.asarray(relative)
    channels = [np.fmax.reduce(relative[..., list(classes)], axis=-1) for classes in display]
    rgb = np.stack(channels, axis=-1)
    return np.where(np.isnan(rgb) & ~np.isnan(relative).all(axis=-1, keepdims=True), 0.0, rgb)


def display_words(receptor_set):
    """map3's channels in words: "red UV, green G, blue B"."""
    return ", ".join(f"{c} {' or '.join(receptor_set.classes[k] for k in ks)}"
                     for c, ks in zip(("red", "green", "blue"), receptor_set.display))


def encode(linear, scale=1.0):
    """Linear values to sRGB-encoded display values in [0, 1], ``scale`` at full brightness; NaN kept."""
    import colour  # imported where used, as in beeoptics.vision.human

    return colour.cctf_encoding(np.clip(np.asarray(linear) / scale, 0.0, 1.0), function="sRGB")


def bee_colours(catches, white_catches, wavelengths_nm, radiance, display):
    """Each receptor's catches relative to white, its map3 colour, and map2's display sRGB.

    Parameters
    ----------
    catches, white_catches : ndarray (n, classes)
        Each class's catch of each receptor, and what it would catch of a
        white Lambertian surface under the scene's light.
    wavelengths_nm : ndarray
    radiance : ndarray (n, n_wavelengths)
        Each receptor's mean spectral radiance.
    display : sequence of int
        The classes shown as red, green and blue (:func:`map3`).

    Returns
    -------
    relative : ndarray (n, classes)
        Catches over white's: 1 is white.
    map3 : ndarray (n, 3)
        Linear RGB.
    map2 : ndarray (n, 3)
        Display-encoded sRGB.
    """
    relative = np.asarray(catches) / np.asarray(white_catches)
    xyz = tristimulus(wavelengths_nm, radiance)
    return (relative, map3(relative, display),
            srgb(xyz, np.percentile(xyz[:, 1], EXPOSURE_PERCENTILE)))


def polarisation_colours(degree, angle_deg):
    """Polarisation as colour, linear RGB (n, 3): hue the angle (cyclic over 0–180°), saturation the degree."""
    from matplotlib.colors import hsv_to_rgb

    hsv = np.stack([np.asarray(angle_deg) / 180.0, np.clip(degree, 0.0, 1.0), np.ones(np.shape(degree))], -1)
    return hsv_to_rgb(np.nan_to_num(hsv))
