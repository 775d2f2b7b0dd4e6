"""Clear-sky daylight at the ground: direct and diffuse spectral irradiance from 300 nm.

The spectra are those of the Bird & Riordan (1986) simple spectral model,
SPECTRL2, as pvlib implements it: the extraterrestrial spectrum attenuated
by Rayleigh scattering, aerosols (Ångström's law), ozone, water vapour and
mixed gases along Kasten's (1966) relative air mass, and the diffuse sky
from Rayleigh and aerosol scattering plus the light bounced between ground
and sky. The scene's turbidity T is Preetham et al.'s (1999), the one the
sky-dome models take, turned into Ångström's β by their relation; the
aerosol's wavelength exponent is SPECTRL2's rural one. The sun and the sky
dome of a scene (:mod:`beeoptics.sky.sun`, :mod:`beeoptics.sky.dome`)
are scaled to these irradiances wavelength by wavelength.

Spectral irradiance is in W m⁻² nm⁻¹, on SPECTRL2's own grid (about
10 nm apart, 5 nm in the UV) resampled linearly onto the scene's.

References
----------
Bird RE, Riordan C (1986) Simple solar spectral model for direct and
diffuse irradiance on horizontal and tilted planes at the earth's surface
for cloudless atmospheres. J Clim Appl Meteorol 25:87–97.
Preetham AJ, Shirley P, Smits B (1999) A practical analytic model for
daylight. Proc SIGGRAPH 99:91–100.
Kasten F (1966) A new table and approximation formula for the relative
optical air mass. Arch Meteorol Geophys Bioklimatol B 14:206–223.
Holmgren WF, Hansen CW, Mikofski MA (2018) pvlib python: a python package
for modeling solar energy systems. J Open Source Softw 3:884.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.spectra import resample, write_pavo_csv

#: Surface pressure, Pa: the ICAO standard atmosphere at sea level (ISO 2533:1975).
PRESSURE_PA = 101325.0
#: Ozone column, atm-cm, and precipitable water, cm (Preetham et al. 1999, after Iqbal 1983).
OZONE_ATM_CM, WATER_CM = 0.35, 2.0
#: Ångström's wavelength exponent of a rural aerosol (Bird & Riordan 1986).
ANGSTROM_ALPHA = 1.14
#: 21 June, the middle of the bees' foraging season in the northern summer (Earth–Sun distance).
DAY_OF_YEAR = 172


class Daylight(NamedTuple):
    """Clear-sky daylight on the scene's grid, W m⁻² nm⁻¹.

    ``direct_normal`` is the sun's irradiance on a surface facing it;
    ``diffuse`` the sky's on a horizontal surface; ``elevation_deg`` the
    sun's elevation. :attr:`direct_horizontal` is the sun's on the ground,
    :attr:`global_horizontal` the two together.
    """

    wavelengths: np.ndarray
    direct_normal: np.ndarray
    diffuse: np.ndarray
    elevation_deg: float

    @property
    def direct_horizontal(self):
        return self.direct_normal * np.sin(np.radians(self.elevation_deg))

    @property
    def global_horizontal(self):
        return self.direct_horizontal + self.diffuse


def angstrom_beta(turbidity):
    """Ångström's turbidity coefficient β of Preetham et al.'s (1999) turbidity T: 0.04608 T − 0.04586."""
    return 0.04608365822050 * turbidity - 0.04586025928522


def clear_sky(wavelengths, elevation_deg, turbidity, albedo=0.0, day_of_year=DAY_OF_YEAR):
    """SPECTRL2's direct and diffuse irradiance for the sun at this elevation, on the grid.

    Parameters
    ----------
    wavelengths : ndarray, shape (n,)
        The grid, nm, within 300–4000 nm.
    elevation_deg : float
        The sun's elevation above the horizon; at or below it there is no daylight.
    turbidity : float
        Preetham et al.'s turbidity, 1.7–10 (2 very clear, 3 clear, 6 hazy).
    albedo : float or ndarray, shape (n,)
        The ground's albedo, one value or one per wavelength of the grid.
    day_of_year : int
        For the Earth–Sun distance.

    Returns
    -------
    Daylight
    """
    import pvlib  # imported where used: only stages that compute daylight pay for it

    wl = np.asarray(wavelengths, float)
    if elevation_deg <= 0.0:
        return Daylight(wl, np.zeros_like(wl), np.zeros_like(wl), float(elevation_deg))
    zenith = 90.0 - elevation_deg
    args = dict(apparent_zenith=zenith, aoi=zenith, surface_tilt=0.0, surface_pressure=PRESSURE_PA,
                relative_airmass=pvlib.atmosphere.get_relative_airmass(zenith, model="kasten1966"),
                precipitable_water=WATER_CM, ozone=OZONE_ATM_CM,
                aerosol_turbidity_500nm=angstrom_beta(turbidity) * 0.5**-ANGSTROM_ALPHA,
                dayofyear=day_of_year, alpha=ANGSTROM_ALPHA)
    # SPECTRL2 wants the albedo on its own grid: learn the grid, then hold the
    # scene's albedo constant beyond the scene's ends.
    grid = pvlib.spectrum.spectrl2(ground_albedo=0.0, **args)["wavelength"]
    rg = np.interp(grid, wl, np.broadcast_to(np.asarray(albedo, float), wl.shape))[:, None]
    out = pvlib.spectrum.spectrl2(ground_albedo=rg, **args)
    dni, dhi = (resample(grid, np.asarray(out[k]).ravel(), wl, "SPECTRL2", k) for k in ("dni", "dhi"))
    return Daylight(wl, np.maximum(dni, 0.0), np.maximum(dhi, 0.0), float(elevation_deg))


def write_daylight(path, wavelengths, direct, diffuse):
    """Write horizontal irradiance in pavo's layout: ``wl``, then ``global``, ``direct`` and ``diffuse``."""
    write_pavo_csv(path, wavelengths, {"global": np.asarray(direct) + diffuse, "direct": direct, "diffuse": diffuse})
