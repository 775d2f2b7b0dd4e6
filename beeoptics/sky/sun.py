"""The sun: a disc in the sky, its spectral radiance at the ground from 300 nm.

The sun is a disc of the solid angle Preetham et al. used (the sun,
1.39·10⁶ km across, seen from 1.5·10⁸ km), of uniform radiance: the
direct normal irradiance of the clear-sky model
(:mod:`beeoptics.sky.daylight`, SPECTRL2) spread over that disc.

Spectral radiance is in W m⁻² sr⁻¹ nm⁻¹.

References
----------
Preetham AJ, Shirley P, Smits B (1999) A practical analytic model for
daylight. Proc SIGGRAPH 99:91–100.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.headframe import direction_from_x_towards_y

#: Solid angle of the sun, sr: π/4·(1.39/150)² (Preetham et al. 1999, reference code).
SUN_SOLID_ANGLE_SR = np.pi / 4.0 * (1.39 / 150.0) ** 2


class Sun(NamedTuple):
    """The sun as a disc: unit direction towards it, its angular radius's cosine, radiance."""

    direction: np.ndarray
    cos_radius: float
    radiance: np.ndarray

    @property
    def solid_angle(self):
        return 2.0 * np.pi * (1.0 - self.cos_radius)


def sun_disc(daylight, azimuth_deg):
    """The sun's disc at ``daylight``'s elevation and this azimuth, carrying its direct normal irradiance."""
    cos_radius = 1.0 - SUN_SOLID_ANGLE_SR / (2.0 * np.pi)
    return Sun(direction_from_x_towards_y(azimuth_deg, daylight.elevation_deg), cos_radius,
               daylight.direct_normal / SUN_SOLID_ANGLE_SR)
