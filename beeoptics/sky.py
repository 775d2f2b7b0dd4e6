"""Daylight: the sky dome and the sun, as spectral radiance from 300 nm.

Three skies are offered. ``uniform`` has the same radiance in every
direction of the whole sphere (for tests and for a simple overcast sky).
``preetham`` is the clear sky of Preetham, Shirley & Smits (1999): the
Perez et al. (1993) distributions of luminance Y and chromaticity (x, y),
with Preetham's coefficients as linear functions of turbidity, turned into
a spectrum through the CIE daylight basis S0, S1, S2 (CIE 015:2004), which
colour-science tabulates from 300 nm. Both emit from the upper hemisphere
only when ``hemisphere`` is set; the Preetham sky always does.

The sun is a disc of the solid angle Preetham et al. used (the sun,
1.39·10⁶ km across, seen from 1.5·10⁸ km). Its radiance is the ASTM G173
extraterrestrial spectrum, which starts at 280 nm, spread over that disc
and attenuated along the slant path as in Preetham et al.'s appendix:
Rayleigh scattering, aerosols by Ångström's law with Preetham's turbidity
to β relation, ozone and water vapour with the absorption coefficients of
Iqbal (1983), and Kasten's (1966) relative air mass. Preetham's own solar
table starts at 380 nm and so cannot light the bee's UV receptor.

Spectral radiance is in W m⁻² sr⁻¹ nm⁻¹.

References
----------
Preetham AJ, Shirley P, Smits B (1999) A practical analytic model for
daylight. Proc SIGGRAPH 99:91–100.
Perez R, Seals R, Michalsky J (1993) All-weather model for sky luminance
distribution — preliminary configuration and validation. Sol Energy 50:235–245.
CIE 015:2004 Colorimetry, 3rd ed. (daylight basis functions S0, S1, S2).
ASTM G173-03 Standard tables for reference solar spectral irradiances.
Iqbal M (1983) An introduction to solar radiation. Academic Press.
Kasten F (1966) A new table and approximation formula for the relative
optical air mass. Arch Meteorol Geophys Bioklimatol B 14:206–223.
"""

from typing import NamedTuple

import colour
import numpy as np
from colour.plotting.datasets import SD_ASTMG173_ETR

from beeoptics.spectra import resample

#: Luminous efficacy of 555 nm light, lm W⁻¹ (CIE 015:2004).
KM = 683.0
#: Solid angle of the sun, sr: π/4·(1.39/150)² (Preetham et al. 1999, reference code).
SUN_SOLID_ANGLE_SR = np.pi / 4.0 * (1.39 / 150.0) ** 2
#: Ångström's wavelength exponent for aerosols (Preetham et al. 1999, after Iqbal 1983).
ANGSTROM_ALPHA = 1.3
#: Ozone column, cm at NTP, and precipitable water, cm (Preetham et al. 1999).
OZONE_CM, WATER_CM = 0.35, 2.0

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
# Ozone absorption coefficient k_o, cm⁻¹, 300–700 nm (Iqbal 1983 p. 127, as in Preetham et al. 1999).
_OZONE_NM = np.array([300, 305, 310, 315, 320, 325, 330, 335, 340, 345, 350, 355, 445, 450, 455, 460,
                      465, 470, 475, 480, 485, 490, 495, 500, 505, 510, 515, 520, 525, 530, 535, 540,
                      545, 550, 555, 560, 565, 570, 575, 580, 585, 590, 595, 600, 605, 610, 620, 630,
                      640, 650, 660, 670, 680, 690, 700], float)
_OZONE_K = np.array([10.0, 4.8, 2.7, 1.35, 0.8, 0.38, 0.16, 0.075, 0.04, 0.019, 0.007, 0.0, 0.003,
                     0.003, 0.004, 0.006, 0.008, 0.009, 0.012, 0.014, 0.017, 0.021, 0.025, 0.03, 0.035,
                     0.04, 0.045, 0.048, 0.057, 0.063, 0.07, 0.075, 0.08, 0.085, 0.095, 0.103, 0.110,
                     0.12, 0.122, 0.12, 0.118, 0.115, 0.12, 0.125, 0.130, 0.12, 0.105, 0.09, 0.079,
                     0.067, 0.057, 0.048, 0.036, 0.028, 0.023])
# Water-vapour absorption coefficient k_wa, cm⁻¹, up to 700 nm (Iqbal 1983 p. 130, as in Preetham et al. 1999).
_WATER_NM = np.array([689.0, 690.0, 700.0])
_WATER_K = np.array([0.0, 0.016, 0.024])


class Sun(NamedTuple):
    """The sun as a disc: unit direction towards it, its angular radius's cosine, radiance."""

    direction: np.ndarray
    cos_radius: float
    radiance: np.ndarray

    @property
    def solid_angle(self):
        return 2.0 * np.pi * (1.0 - self.cos_radius)


class Sky(NamedTuple):
    """Sky radiance as a combination of a few basis spectra.

    ``basis`` is (k, n_wavelengths); :func:`sky_coefficients` gives, for
    directions, the (n, k) weights whose product with it is the radiance.
    """

    model: str
    basis: np.ndarray
    hemisphere: bool
    params: dict


def direction_from_angles(elevation_deg, azimuth_deg):
    """World unit vector: azimuth from +x towards +y, elevation above the xy-plane (z up)."""
    el, az = np.radians(elevation_deg), np.radians(azimuth_deg)
    return np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])


def uniform_sky(radiance, hemisphere=False):
    """A sky of the same spectral radiance everywhere (over the whole sphere unless ``hemisphere``)."""
    return Sky("uniform", np.asarray(radiance, float)[None, :], hemisphere, {})


def _perez(cos_theta, gamma, coeffs):
    """Perez et al.'s sky distribution at zenith cosine ``cos_theta`` and angle ``gamma`` from the sun."""
    a, b, c, d, e = coeffs
    return (1.0 + a * np.exp(b / cos_theta)) * (1.0 + c * np.exp(d * gamma) + e * np.cos(gamma) ** 2)


def preetham_sky(wavelengths, sun_direction, turbidity):
    """Preetham et al.'s clear sky over the upper hemisphere, spectral through the CIE daylight basis."""
    basis = colour.colorimetry.SDS_BASIS_FUNCTIONS_CIE_ILLUMINANT_D_SERIES
    s = np.stack([resample(basis[k].wavelengths, basis[k].values, wavelengths, "CIE daylight basis", k)
                  for k in ("S0", "S1", "S2")])
    # ∫ S_k ȳ dλ over the visible, for converting luminance to radiance.
    cmf = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    wl5 = np.arange(360.0, 831.0, 5.0)
    y5 = resample(cmf.wavelengths, cmf.values[:, 1], wl5, "CIE 1931 ȳ")
    s5 = np.stack([resample(basis[k].wavelengths, basis[k].values, wl5, "CIE daylight basis", k)
                   for k in ("S0", "S1", "S2")])
    luminous = KM * (s5 * y5).sum(1) * 5.0
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


def sun(wavelengths, elevation_deg, azimuth_deg, turbidity):
    """The sun's disc and its spectral radiance at the ground, for a clear sky of this turbidity."""
    wl = np.asarray(wavelengths, float)
    etr = resample(SD_ASTMG173_ETR.wavelengths, SD_ASTMG173_ETR.values, wl, "ASTM G173 ETR")
    zenith = 90.0 - elevation_deg
    if zenith >= 90.0:
        radiance = np.zeros_like(wl)
    else:
        mass = 1.0 / (np.cos(np.radians(zenith)) + 0.15 * (93.885 - zenith) ** -1.253)
        beta = 0.04608365822050 * turbidity - 0.04586025928522
        um = wl / 1000.0
        tau = np.exp(
            -mass * 0.008735 * um**-4.08
            - mass * beta * um**-ANGSTROM_ALPHA
            - mass * OZONE_CM * np.interp(wl, _OZONE_NM, _OZONE_K)
        )
        kwa = np.interp(wl, _WATER_NM, _WATER_K, left=0.0)
        tau *= np.exp(-0.2385 * kwa * WATER_CM * mass / (1.0 + 20.07 * kwa * WATER_CM * mass) ** 0.45)
        radiance = etr / SUN_SOLID_ANGLE_SR * tau
    cos_radius = 1.0 - SUN_SOLID_ANGLE_SR / (2.0 * np.pi)
    return Sun(direction_from_angles(elevation_deg, azimuth_deg), cos_radius, radiance)


def cie_daylight(wavelengths, cct):
    """Relative spectral power of the CIE D-series illuminant, 1 at 560 nm.

    ``cct`` in kelvin on the current scale: 6504 K for D65 (CIE 015:2004).
    """
    xy = colour.temperature.CCT_to_xy_CIE_D(cct)
    sd = colour.sd_CIE_illuminant_D_series(xy)
    v = resample(sd.wavelengths, sd.values, wavelengths, f"CIE D{cct:g}")
    return v / np.interp(560.0, sd.wavelengths, sd.values)


def luminance(wavelengths, radiance):
    """Luminance, cd m⁻², of a spectral radiance on the grid (only its 360–700 nm part counts)."""
    cmf = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    wl = np.asarray(wavelengths, float)
    inside = wl >= cmf.wavelengths[0]
    ybar = np.zeros_like(wl)
    ybar[inside] = np.interp(wl[inside], cmf.wavelengths, cmf.values[:, 1])
    return KM * np.trapezoid(ybar * radiance, wl)


def horizontal_irradiance(sky, sun_disc, n_wavelengths, samples=64):
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
    if sun_disc is not None and sun_disc.direction[2] > 0.0:
        total += sun_disc.radiance * sun_disc.solid_angle * sun_disc.direction[2]
    return total
