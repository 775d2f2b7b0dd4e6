"""Showing bee catches to people: Collins's map3 and map2, and the display encoding.

map3 (Collins §4.4) shows the UV, B and G catches as red, blue and green,
so that equal catches are grey to white; map2 shows each receptor's light in
its human colour (CIE 1931, sRGB) on the bee's geometry. Both are a
visualisation, not what the bee perceives. One exposure for all three
channels keeps their relative responses.
"""

import colour
import numpy as np

from beeoptics.vision.human import srgb, tristimulus

#: Percentile of the catches (and of luminance for map2) shown at full brightness.
EXPOSURE_PERCENTILE = 99.5


def map3(uv, b, g):
    """Collins' map3: UV to red, B to blue, G to green; (1, 1, 1) is white. Linear RGB."""
    return np.stack([uv, g, b], -1)


def encode(linear, scale):
    """Linear values to sRGB-encoded display values in [0, 1], ``scale`` at full brightness; NaN black."""
    v = np.nan_to_num(np.asarray(linear) / scale, nan=0.0)
    return colour.cctf_encoding(np.clip(v, 0.0, 1.0), function="sRGB")


def bee_colours(catches, wavelengths_nm, radiance):
    """map3 colours and their exposure, and map2's display sRGB, of each receptor.

    Parameters
    ----------
    catches : ndarray (n, 3)
        UV, B, G catches.
    wavelengths_nm : ndarray
    radiance : ndarray (n, n_wavelengths)
        Each receptor's mean spectral radiance.

    Returns
    -------
    map3 : ndarray (n, 3)
        Linear RGB.
    exposure : float
        The catch shown at full brightness.
    map2 : ndarray (n, 3)
        Display-encoded sRGB.
    """
    xyz = tristimulus(wavelengths_nm, radiance)
    return (map3(catches[:, 0], catches[:, 1], catches[:, 2]), np.percentile(catches, EXPOSURE_PERCENTILE),
            srgb(xyz, np.percentile(xyz[:, 1], EXPOSURE_PERCENTILE)))
