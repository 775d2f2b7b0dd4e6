"""The Hosek & Wilkie (2012) spectral sky-dome model: how the sky's radiance is spread over the dome.

Hosek & Wilkie fitted an extended Perez formula to brute-force
path-traced skies, per wavelength channel (11 channels, 320–720 nm at
40 nm), for turbidity 1–10, ground albedo 0–1 and every solar elevation:

    F(θ, γ) = (1 + A e^{B / (cos θ + 0.01)})
              · (C + D e^{E γ} + F cos²γ + G χ(H, γ) + I cos^{1/2} θ),
    χ(g, α) = (1 + cos²α) / (1 + g² − 2 g cos α)^{3/2},
    L_λ(θ, γ) = F(θ, γ) · L_M,

with θ the view's zenith angle, γ its angle from the sun, and L_M the
channel's mean radiance (W m⁻² sr⁻¹ nm⁻¹). Each coefficient is a quintic
Bézier curve in (solar elevation / 90°)^{1/3}, interpolated linearly in
turbidity and ground albedo (their paper, section 5; the coefficient
tables are ``sky/data/sky_hosek_wilkie2012.csv``, BSD licence). Between
channels the radiance is interpolated linearly in wavelength, as in the
authors' reference implementation; outside 320–720 nm each end channel's
distribution is kept.

The formula (:func:`extended_perez`) is evaluated in compiled code one
direction at a time by the tracer (:func:`shape_radiance`), and in numpy
over arrays of directions by the sky's quadrature (:func:`shape_radiances`).
With C = 1 and G = I = 0 it is Perez et al.'s (1993), which the Preetham
sky uses.

References
----------
Hosek L, Wilkie A (2012) An analytic model for full spectral sky-dome
radiance. ACM Trans Graph 31(4):95.
"""

from functools import cache
from pathlib import Path

import numpy as np

from beeoptics.jit import kernel

TABLE_FILE = Path(__file__).parent / "data" / "sky_hosek_wilkie2012.csv"
#: Centres of the model's channels, nm (Hosek & Wilkie 2012).
CHANNELS_NM = np.arange(320.0, 721.0, 40.0)
_PARAMS = list("ABCDEFGHI")
#: Added to cos θ under B, which keeps e^{B / cos θ} finite at the horizon, as in Hosek & Wilkie's (2012) formula.
COS_OFFSET = 0.01


@cache
def _tables():
    """Coefficients (11, 2, 10, 6, 9) and mean radiance (11, 2, 10, 6): channel, albedo, turbidity, control point."""
    import pandas as pd  # imported where used: only a Hosek–Wilkie sky reads the table

    t = pd.read_csv(TABLE_FILE, comment="#").sort_values(["wavelength_nm", "albedo", "turbidity", "control_point"])
    shape = (len(CHANNELS_NM), 2, 10, 6)
    return t[_PARAMS].to_numpy().reshape(*shape, 9), t["radiance"].to_numpy().reshape(shape)


def _cook(table, turbidity, albedo, elevation_rad):
    """A table's values (channel, ...) at this turbidity, per-channel albedo and solar elevation."""
    s = (elevation_rad / (np.pi / 2.0)) ** (1.0 / 3.0)
    k = np.arange(6)
    bernstein = np.array([1, 5, 10, 10, 5, 1]) * (1.0 - s) ** (5 - k) * s**k
    at_elevation = np.einsum("k,cabk...->cab...", bernstein, table)
    low = int(np.clip(np.floor(turbidity), 1, 9))
    frac = turbidity - low
    by_albedo = (1.0 - frac) * at_elevation[:, :, low - 1] + frac * at_elevation[:, :, low]
    a = np.reshape(albedo, (-1,) + (1,) * (by_albedo.ndim - 2))
    return (1.0 - a) * by_albedo[:, 0] + a * by_albedo[:, 1]


@kernel
def extended_perez(cos_t, cos_g, gamma, a, b, c, d, e, f, g, h, i, l_m, cos_offset):
    """The extended Perez formula F(θ, γ)·L_M, its dips below zero read as 0: of scalars in the tracer's
    kernels, of arrays of directions in numpy (``extended_perez.py_func``), one formula for both."""
    t = 1.0 + h * h - 2.0 * h * cos_g
    mie = (1.0 + cos_g * cos_g) / (t * np.sqrt(t))
    # A = 0 (a uniform sky) leaves B/cos θ out, which is undefined at the horizon.
    gradation = 1.0 + a * np.exp(b / (cos_t + cos_offset)) if a != 0.0 else 1.0
    return np.maximum(gradation * (c + d * np.exp(e * gamma) + f * cos_g * cos_g + g * mie + i * np.sqrt(cos_t))
                      * l_m, 0.0)


@kernel
def shape_radiance(x, y, z, sun, shape, cos_floor, cos_offset, hemisphere, out):
    """The formula's value along the unit direction (x, y, z), one per row of ``shape``, into ``out``.

    Parameters
    ----------
    x, y, z : float
        The view direction, world +z up.
    sun : ndarray, shape (3,)
        Unit direction towards the sun.
    shape : ndarray, shape (k, 10)
        A–I and L_M of each row (channel or basis spectrum).
    cos_floor, cos_offset : float
        cos θ is held at or above ``cos_floor``, and ``cos_offset`` is added
        to it under B (0 and 0.01 for Hosek & Wilkie, cos(π/2 − 10⁻³) and 0
        for Perez, whose B/cos θ is singular at the horizon).
    hemisphere : bool
        Dark below the horizon.
    out : ndarray, shape (k,)
        W m⁻² sr⁻¹ nm⁻¹ (the fitted formula's few dips below zero read as 0).
    """
    if hemisphere and z <= 0.0:
        out[:] = 0.0
        return
    cos_t = min(max(z, cos_floor), 1.0)
    cos_g = min(max(x * sun[0] + y * sun[1] + z * sun[2], -1.0), 1.0)
    gamma = np.arccos(cos_g)
    for k in range(shape.shape[0]):
        a, b, c, d, e, f, g, h, i, l_m = shape[k]
        out[k] = extended_perez(cos_t, cos_g, gamma, a, b, c, d, e, f, g, h, i, l_m, cos_offset)


def shape_radiances(directions, sun, shape, cos_floor, cos_offset, hemisphere):
    """:func:`shape_radiance` along each of ``directions`` (n, 3): shape (n, k), in numpy (no compiling:
    a job that only tabulates its sky, as gathering a trace's responses does, never loads numba)."""
    d = np.asarray(directions, float).reshape(-1, 3)
    cos_t = np.clip(d[:, 2], cos_floor, 1.0)
    cos_g = np.clip(d @ np.asarray(sun, float), -1.0, 1.0)
    gamma = np.arccos(cos_g)
    out = np.stack([extended_perez.py_func(cos_t, cos_g, gamma, *row, cos_offset) for row in np.asarray(shape, float)],
                   axis=-1) if len(shape) else np.zeros((len(d), 0))
    if hemisphere:
        out[d[:, 2] <= 0.0] = 0.0
    return out


def channel_shape(sun_direction, turbidity, albedo):
    """The formula's A–I and L_M (11, 10) in each channel for this sun, turbidity and albedo (11,)."""
    coeffs, mean = _tables()
    elevation = np.arcsin(np.clip(sun_direction[2], 0.0, 1.0))
    return np.column_stack([_cook(coeffs, turbidity, albedo, elevation), _cook(mean, turbidity, albedo, elevation)])


def channel_radiance(directions, sun_direction, turbidity, albedo):
    """The model's radiance in each channel along unit ``directions``, W m⁻² sr⁻¹ nm⁻¹.

    Parameters
    ----------
    directions : ndarray, shape (n, 3)
        Unit view directions, world +z up; those below the horizon get 0.
    sun_direction : ndarray, shape (3,)
        Unit direction towards the sun, above the horizon.
    turbidity : float
        Atmospheric turbidity, 1–10.
    albedo : ndarray, shape (11,)
        Ground albedo at each channel's centre, :data:`CHANNELS_NM`.

    Returns
    -------
    ndarray, shape (n, 11)
    """
    sun = np.asarray(sun_direction, float)
    return shape_radiances(np.asarray(directions, float), sun, channel_shape(sun, turbidity, albedo), 0.0,
                           COS_OFFSET, True)


def channel_weights(wavelengths):
    """Linear-interpolation weights (n_wavelengths, 11) of the channels at each wavelength; ends held."""
    wl = np.clip(np.asarray(wavelengths, float), CHANNELS_NM[0], CHANNELS_NM[-1])
    return np.column_stack([np.interp(wl, CHANNELS_NM, np.eye(len(CHANNELS_NM))[j])
                            for j in range(len(CHANNELS_NM))])
