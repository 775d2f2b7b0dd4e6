"""The sky dome, as spectral radiance from 300 nm (the sun is :mod:`beeoptics.light.sun`).

Three skies are offered. ``uniform`` has the same radiance in every
direction of the whole sphere (for tests and for a simple overcast sky).
``preetham`` is the clear sky of Preetham, Shirley & Smits (1999): the
Perez et al. (1993) distributions of luminance Y and chromaticity (x, y),
with Preetham's coefficients as linear functions of turbidity, turned into
a spectrum through the CIE daylight basis S0, S1, S2 (CIE 015:2004), which
colour-science tabulates from 300 nm. Both emit from the upper hemisphere
only when ``hemisphere`` is set; the Preetham sky always does.

Spectral radiance is in W m⁻² sr⁻¹ nm⁻¹.

References
----------
Preetham AJ, Shirley P, Smits B (1999) A practical analytic model for
daylight. Proc SIGGRAPH 99:91–100.
Perez R, Seals R, Michalsky J (1993) All-weather model for sky luminance
distribution — preliminary configuration and validation. Sol Energy 50:235–245.
CIE 015:2004 Colorimetry, 3rd ed. (daylight basis functions S0, S1, S2).
"""

from typing import NamedTuple

import colour
import numpy as np
from colour.constants import CONSTANT_K_M

from beeoptics.spectra import resample

# Perez coefficients A–E as slope·T + intercept (Preetham et al. 1999, appendix A.2).
_PEREZ = {
    "Y": np.array([[0.1787, -1.4630], [-0.3554, 0.4275], [-0.0227, 5.3251], [0.1206, -2.5771], [-0.0670, 0.3703]]),
    "x": np.array([[-0.0193, -0.2592], [-0.0665, 0.0008], [-0.0004, 0.2125], [-0.0641, -0.8989], [-0.0033, 0.0452]]),
    "y": np.array([[-0.0167, -0.2608], [-0.0950, 0.0092], [-0.0079, 0.2102], [-0.0441, -1.6537], [-0.0109, 0.0529]]),
}
# Zenith chromaticity as [T², T, 1]·M·[θs³, θs², θs, 1] (Preetham et al. 1999, appendix A.2).
_ZENITH_X = np.array([[0.00166, -0.00375, 0.00209, 0.0], [-0.02903, 0.06377, -0.03202, 0.00394],
                      [0.11693, -0.21196, 0.06052, 0.25886]])
_ZENITH_Y = np.array([[0.00275, -0.00610, 0.00317, 0.0], [-0.04214, 0.08970, -0.04153, 0.00516],
                      [0.15346, -0.26756, 0.06670, 0.26688]])
class Sky(NamedTuple):
    """Sky radiance as a combination of a few basis spectra.

    ``basis`` is (k, n_wavelengths); :func:`sky_coefficients` gives, for
    directions, the (n, k) weights whose product with it is the radiance.
    """

    model: str
    basis: np.ndarray
    hemisphere: bool
    params: dict


def uniform_sky(radiance, hemisphere=False):
    """A sky of the same spectral radiance everywhere (over the whole sphere unless ``hemisphere``)."""
    return Sky("uniform", np.asarray(radiance, float)[None, :], hemisphere, {})


def _perez(cos_theta, gamma, coeffs):
    """Perez et al.'s sky distribution at zenith cosine ``cos_theta`` and angle ``gamma`` from the sun."""
    a, b, c, d, e = coeffs
    return (1.0 + a * np.exp(b / cos_theta)) * (1.0 + c * np.exp(d * gamma) + e * np.cos(gamma) ** 2)


def preetham_sky(wavelengths, sun_direction, turbidity):
    """Preetham et al.'s clear sky over the upper hemisphere, spectral through the CIE daylight basis."""
    basis = [colour.colorimetry.SDS_BASIS_FUNCTIONS_CIE_ILLUMINANT_D_SERIES[k] for k in ("S0", "S1", "S2")]
    s = resample(basis[0].wavelengths, np.column_stack([b.values for b in basis]), wavelengths,
                 "CIE daylight basis", "S0, S1, S2").T
    # The luminance of each basis spectrum over its whole range, for converting luminance to radiance.
    luminous = np.array([colour.luminous_flux(b, K_m=CONSTANT_K_M) for b in basis])
    theta_s = np.arccos(np.clip(sun_direction[2], -1.0, 1.0))
    t = turbidity
    perez = {k: v[:, 0] * t + v[:, 1] for k, v in _PEREZ.items()}
    chi = (4.0 / 9.0 - t / 120.0) * (np.pi - 2.0 * theta_s)
    zenith_y = ((4.0453 * t - 4.9710) * np.tan(chi) - 0.2155 * t + 2.4192) * 1e3
    powers = np.array([theta_s**3, theta_s**2, theta_s, 1.0])
    tt = np.array([t * t, t, 1.0])
    zenith = {"Y": zenith_y, "x": tt @ _ZENITH_X @ powers, "y": tt @ _ZENITH_Y @ powers}
    norm = {k: zenith[k] / _perez(1.0, theta_s, perez[k]) for k in zenith}
    return Sky("preetham", s, True, {"sun": np.asarray(sun_direction, float), "perez": perez,
                                      "norm": norm, "luminous": luminous})


def sky_coefficients(sky, directions):
    """Weights (n, k) of the sky's basis spectra seen along unit ``directions`` (n, 3)."""
    d = np.asarray(directions, float)
    n = len(d)
    if sky.model == "uniform":
        w = np.ones((n, 1))
    else:
        p = sky.params
        cos_theta = np.maximum(d[:, 2], np.cos(np.pi / 2.0 - 1e-3))  # B/cos θ is singular at the horizon
        gamma = np.arccos(np.clip((d * p["sun"]).sum(1), -1.0, 1.0))
        big_y, x = (p["norm"][k] * _perez(cos_theta, gamma, p["perez"][k]) for k in ("Y", "x"))
        # The daylight basis holds only chromaticities on the daylight locus; Preetham's
        # y strays a little above it (by up to 0.07 with the sun low), enough to drive the
        # spectrum negative below 330 nm. The locus's own y at Preetham's x keeps every
        # spectrum positive (CIE 015:2004, y_D = −3.000 x² + 2.870 x − 0.275).
        y = -3.000 * x**2 + 2.870 * x - 0.275
        # CIE 015:2004: M1, M2 of the daylight basis for chromaticity (x, y).
        m = 0.0241 + 0.2562 * x - 0.7341 * y
        m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m
        m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m
        w = np.column_stack([np.ones(n), m1, m2])
        w *= (big_y / (w * p["luminous"]).sum(1))[:, None]
    if sky.hemisphere:
        w[d[:, 2] <= 0.0] = 0.0
    return w


def cie_daylight(wavelengths, cct):
    """Relative spectral power of the CIE D-series illuminant, 1 at 560 nm.

    ``cct`` in kelvin on the current scale: 6504 K for D65 (CIE 015:2004).
    """
    xy = colour.temperature.CCT_to_xy_CIE_D(cct)
    sd = colour.sd_CIE_illuminant_D_series(xy)
    v = resample(sd.wavelengths, sd.values, wavelengths, f"CIE D{cct:g}")
    return v / np.interp(560.0, sd.wavelengths, sd.values)


def luminance(wavelengths, radiance):
    """Luminance, cd m⁻², of a spectral radiance on the grid: K_m ∫ L V(λ) dλ.

    colour-science's ``luminous_flux`` with the CIE 1924 photopic V(λ) and
    K_m = 683 lm W⁻¹ (CIE 015:2018); only the grid's 360–700 nm part counts.
    """
    return colour.luminous_flux(colour.SpectralDistribution(np.asarray(radiance, float), np.asarray(wavelengths, float)),
                                K_m=CONSTANT_K_M)


def horizontal_irradiance(sky, sun, n_wavelengths, samples=64):
    """Spectral irradiance on an unshaded horizontal surface from the sky and sun, W m⁻² nm⁻¹.

    The sky is integrated over the upper hemisphere by cosine-weighted
    midpoint quadrature on a ``samples`` × ``samples`` grid (E = π × the
    mean radiance over a cosine-distributed set); the sun adds its radiance
    times its disc's solid angle times the cosine of its zenith angle.
    """
    total = np.zeros(n_wavelengths)
    if sky is not None:
        u = (np.arange(samples) + 0.5) / samples
        u1, u2 = np.meshgrid(u, u, indexing="ij")
        sin_t = np.sqrt(u1.ravel())
        phi = 2.0 * np.pi * u2.ravel()
        d = np.column_stack([sin_t * np.cos(phi), sin_t * np.sin(phi), np.sqrt(1.0 - u1.ravel())])
        total += np.pi * sky_coefficients(sky, d).mean(0) @ sky.basis
    if sun is not None and sun.direction[2] > 0.0:
        total += sun.radiance * sun.solid_angle * sun.direction[2]
    return total
