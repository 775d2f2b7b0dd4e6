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
tables are ``light/data/sky_hosek_wilkie2012.csv``, BSD licence). Between
channels the radiance is interpolated linearly in wavelength, as in the
authors' reference implementation; outside 320–720 nm each end channel's
distribution is kept.

References
----------
Hosek L, Wilkie A (2012) An analytic model for full spectral sky-dome
radiance. ACM Trans Graph 31(4):95.
"""

from functools import cache
from pathlib import Path

import numpy as np
import pandas as pd

TABLE_FILE = Path(__file__).parent / "data" / "sky_hosek_wilkie2012.csv"
#: Centres of the model's channels, nm (Hosek & Wilkie 2012).
CHANNELS_NM = np.arange(320.0, 721.0, 40.0)
_PARAMS = list("ABCDEFGHI")


@cache
def _tables():
    """Coefficients (11, 2, 10, 6, 9) and mean radiance (11, 2, 10, 6): channel, albedo, turbidity, control point."""
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
    coeffs, mean = _tables()
    elevation = np.arcsin(np.clip(sun_direction[2], 0.0, 1.0))
    c = _cook(coeffs, turbidity, albedo, elevation)  # (11, 9)
    l_m = _cook(mean, turbidity, albedo, elevation)  # (11,)
    d = np.asarray(directions, float)
    cos_theta = np.clip(d[:, 2], 0.0, 1.0)[:, None]
    # Row by row, not by BLAS, whose blocking would make a direction's value depend on its batch.
    cos_gamma = np.clip((d * sun_direction).sum(1), -1.0, 1.0)[:, None]
    gamma = np.arccos(cos_gamma)
    a, b, cc, dd, e, f, g, h, i = c.T
    mie = (1.0 + cos_gamma**2) / (1.0 + h**2 - 2.0 * h * cos_gamma) ** 1.5
    radiance = ((1.0 + a * np.exp(b / (cos_theta + 0.01)))
                * (cc + dd * np.exp(e * gamma) + f * cos_gamma**2 + g * mie + i * np.sqrt(cos_theta)) * l_m)
    # The fitted formula dips a little below zero in a few corners (down to −0.002 of
    # a zenith radiance near 0.04, for the sun at the horizon): no light is negative.
    radiance[d[:, 2] <= 0.0] = 0.0
    return np.maximum(radiance, 0.0)


def channel_weights(wavelengths):
    """Linear-interpolation weights (n_wavelengths, 11) of the channels at each wavelength; ends held."""
    wl = np.clip(np.asarray(wavelengths, float), CHANNELS_NM[0], CHANNELS_NM[-1])
    return np.column_stack([np.interp(wl, CHANNELS_NM, np.eye(len(CHANNELS_NM))[j])
                            for j in range(len(CHANNELS_NM))])
