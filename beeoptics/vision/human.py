"""The human observer: CIE 1931 XYZ of spectral radiance, and its sRGB display.

The human view of a scene and the human colours of each receptor's light
(map2) are computed through the CIE 1931 2° colour-matching functions, as
colour-science tabulates them, then shown in sRGB.

References
----------
CIE 015:2018 Colorimetry, 4th ed. (CIE 1931 standard colorimetric observer).
IEC 61966-2-1:1999 Multimedia systems and equipment – Colour measurement
and management – Part 2-1: Default RGB colour space – sRGB.
"""

from functools import cache

import numpy as np

#: The CIE 1931 2° standard observer, 360–830 nm, as colour-science names it.
OBSERVER = "CIE 1931 2 Degree Standard Observer"


def tristimulus(wavelengths_nm, radiance):
    """CIE 1931 XYZ of spectral radiances (..., n_wl), W m⁻² sr⁻¹ (unnormalised, k = 1).

    The colour-matching functions are resampled onto the grid by
    colour-science; below their first wavelength (360 nm) they are zero,
    since light there is invisible to people.
    """
    wl = np.asarray(wavelengths_nm, float)
    step = float(wl[1] - wl[0])
    return np.asarray(radiance) @ _cmfs(float(wl[0]), float(wl[-1]), step) * step


@cache
def _cmfs(start_nm, end_nm, step_nm):
    """The colour-matching functions on a grid, (n_wl, 3): aligned once per grid, as every frame of a
    flight needs them."""
    # colour-science is imported where used: it takes a second (matplotlib with it), which stages
    # that show nothing to people need not pay.
    import colour

    shape = colour.SpectralShape(start_nm, end_nm, step_nm)
    values = colour.MSDS_CMFS[OBSERVER].copy().align(shape, extrapolator_kwargs={"method": "Constant", "left": 0,
                                                                                 "right": 0}).values
    values.flags.writeable = False
    return values


def srgb(xyz, white_luminance):
    """Display-encoded sRGB in [0, 1] of XYZ, ``white_luminance`` (Y) mapped to 1."""
    import colour  # as in tristimulus

    linear = colour.XYZ_to_sRGB(np.asarray(xyz) / white_luminance, apply_cctf_encoding=False)
    return colour.cctf_encoding(np.clip(linear, 0.0, 1.0), function="sRGB")
