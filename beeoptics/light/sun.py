"""The sun: a disc in the sky, its spectral radiance at the ground from 300 nm.

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
ASTM G173-03 Standard tables for reference solar spectral irradiances.
Iqbal M (1983) An introduction to solar radiation. Academic Press.
Kasten F (1966) A new table and approximation formula for the relative
optical air mass. Arch Meteorol Geophys Bioklimatol B 14:206–223.
"""

from typing import NamedTuple

import numpy as np
from colour.plotting.datasets import SD_ASTMG173_ETR

from beeoptics.headframe import direction_from_x_towards_y
from beeoptics.spectra import resample

#: Solid angle of the sun, sr: π/4·(1.39/150)² (Preetham et al. 1999, reference code).
SUN_SOLID_ANGLE_SR = np.pi / 4.0 * (1.39 / 150.0) ** 2
#: Ångström's wavelength exponent for aerosols (Preetham et al. 1999, after Iqbal 1983).
ANGSTROM_ALPHA = 1.3
#: Ozone column, cm at NTP, and precipitable water, cm (Preetham et al. 1999).
OZONE_CM, WATER_CM = 0.35, 2.0

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


def sun_disc(wavelengths, elevation_deg, azimuth_deg, turbidity):
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
    return Sun(direction_from_x_towards_y(azimuth_deg, elevation_deg), cos_radius, radiance)
