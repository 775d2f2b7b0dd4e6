"""The human view: a pinhole camera traced with the bee's tracer, shown in sRGB.

Each pixel's spectral radiance is the mean over jittered rays through it,
traced by :func:`beeoptics.trace.trace_paths` exactly as a receptor's cone
is, so the human and the bee images of a scene differ only in the eye. The
spectra become colour through the CIE 1931 2° colour-matching functions
(colour-science), then sRGB.

References
----------
CIE 015:2018 Colorimetry, 4th ed. (CIE 1931 standard colorimetric observer).
IEC 61966-2-1:1999 Multimedia systems and equipment – Colour measurement
and management – Part 2-1: Default RGB colour space – sRGB.
"""

import colour
import numpy as np
from scipy.stats import qmc

from beeoptics.randomness import uniform

#: Random dimensions of a pixel's sub-pixel shift, apart from those of receptor cones.
PIXEL_DIMENSIONS = (252, 253)

_CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]


def pinhole_rays(camera, samples, seed):
    """Jittered rays through every pixel of a pinhole camera.

    Parameters
    ----------
    camera : dict
        ``position_m``, ``look_at_m``, ``vertical_fov_deg``, ``width_px``,
        ``height_px``; world +z is up.
    samples : int
        Rays per pixel, stratified by a scrambled Halton set shifted per pixel.
    seed : int

    Returns
    -------
    origin : ndarray, shape (3,)
    directions : ndarray, shape (h·w, samples, 3)
        Unit directions, pixels in row-major order from the top left.
    """
    w, h = camera["width_px"], camera["height_px"]
    eye = np.asarray(camera["position_m"], float)
    forward = np.asarray(camera["look_at_m"], float) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half_h = np.tan(np.radians(camera["vertical_fov_deg"]) / 2.0)
    half_w = half_h * w / h
    n = w * h
    base = qmc.Halton(2, scramble=True, seed=np.random.default_rng(seed)).random(samples)
    ids = np.arange(n)
    shift = np.stack([uniform(seed, ids, np.zeros(n, np.int64), d) for d in PIXEL_DIMENSIONS], -1)
    u = (base[None] + shift[:, None, :]) % 1.0
    col = (ids % w)[:, None] + u[..., 0]
    row = (ids // w)[:, None] + u[..., 1]
    sx = (2.0 * col / w - 1.0) * half_w
    sy = (1.0 - 2.0 * row / h) * half_h
    d = forward + sx[..., None] * right + sy[..., None] * up
    return eye, d / np.linalg.norm(d, axis=-1, keepdims=True)


def tristimulus(wavelengths_nm, radiance):
    """CIE 1931 XYZ of spectral radiances (..., n_wl), W m⁻² sr⁻¹ (unnormalised, k = 1).

    The colour-matching functions are resampled onto the grid by
    colour-science; below their first wavelength (360 nm) they are zero,
    since light there is invisible to people.
    """
    wl = np.asarray(wavelengths_nm, float)
    step = float(wl[1] - wl[0])
    shape = colour.SpectralShape(wl[0], wl[-1], step)
    cmfs = _CMFS.copy().align(shape, extrapolator_kwargs={"method": "Constant", "left": 0, "right": 0})
    return np.asarray(radiance) @ cmfs.values * step


def srgb(xyz, white_luminance):
    """Display-encoded sRGB in [0, 1] of XYZ, ``white_luminance`` (Y) mapped to 1."""
    linear = colour.XYZ_to_sRGB(np.asarray(xyz) / white_luminance, apply_cctf_encoding=False)
    return colour.cctf_encoding(np.clip(linear, 0.0, 1.0), function="sRGB")
