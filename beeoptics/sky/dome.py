"""The sky dome, as spectral radiance from 300 nm (the sun is :mod:`beeoptics.sky.sun`).

Three skies are offered. ``uniform`` has the same radiance in every
direction of the whole sphere (for tests, an overcast sky or a measured
daylight spectrum), or of the upper hemisphere when ``hemisphere`` is set.
The two clear skies take the diffuse irradiance of a clear-sky spectral
model (:mod:`beeoptics.sky.daylight`, SPECTRL2) and spread it over the
upper hemisphere, wavelength by wavelength, the way a sky-dome model does:
``hosek_wilkie`` by Hosek & Wilkie's (2012) spectral model, whose
distribution changes with wavelength (:mod:`beeoptics.sky.hosekwilkie`),
``preetham`` by the Perez et al. (1993) luminance distribution with
Preetham et al.'s (1999) coefficients, the same at every wavelength. So the
sky's brightness and colour are the measured atmosphere's, and its shape
the sky-dome model's: at each wavelength the radiance over the hemisphere,
weighted by the cosine of its zenith angle, integrates to the diffuse
irradiance. (Preetham's own zenith luminance makes the sky 1.5–3.3 times too
bright at 550 nm against SPECTRL2, and its colours, turned into spectra by
the CIE daylight basis far outside that basis's range, 55–105% too rich at
320–340 nm; it is no longer used.)

Spectral radiance is in W m⁻² sr⁻¹ nm⁻¹.

References
----------
Hosek L, Wilkie A (2012) An analytic model for full spectral sky-dome
radiance. ACM Trans Graph 31(4):95.
Preetham AJ, Shirley P, Smits B (1999) A practical analytic model for
daylight. Proc SIGGRAPH 99:91–100.
Perez R, Seals R, Michalsky J (1993) All-weather model for sky luminance
distribution — preliminary configuration and validation. Sol Energy 50:235–245.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.sky import hosekwilkie, skypolarisation
from beeoptics.spectra import resample

#: The clear skies, by the model that shapes them.
CLEAR_SKIES = ("hosek_wilkie", "preetham")
#: Perez's cos θ is held above this, since his B/cos θ is singular at the horizon.
PEREZ_COS_FLOOR = float(np.cos(np.pi / 2.0 - 1e-3))
# Perez coefficients A–E of luminance as slope·T + intercept (Preetham et al. 1999, appendix A.2).
_PEREZ_Y = np.array([[0.1787, -1.4630], [-0.3554, 0.4275], [-0.0227, 5.3251], [0.1206, -2.5771], [-0.0670, 0.3703]])
#: Cosine-weighted quadrature points per side over the hemisphere, for the sky's irradiance.
QUADRATURE = 128


class Sky(NamedTuple):
    """Sky radiance as a combination of a few basis spectra.

    ``basis`` is (k, n_wavelengths). Each basis spectrum's weight along a
    direction is Hosek & Wilkie's extended Perez formula
    (:func:`beeoptics.sky.hosekwilkie.shape_radiance`) with its row of
    ``shape`` (k, 10: A–I and a scale), ``cos_floor`` and ``cos_offset``,
    under a sun in direction ``sun`` (3,); a ``hemisphere`` sky is dark
    below the horizon. :func:`sky_coefficients` gives the weights (n, k)
    along directions, whose product with the basis is the radiance.
    A clear sky is polarised (:mod:`beeoptics.sky.skypolarisation`), with
    its neutral points ``neutral_rad`` (2,) from the sun, maximum degree
    ``max_degree`` and the air's depolarisation factor at each basis
    spectrum (``depolarisation``, (k,)); a uniform sky is not (``max_degree`` 0).
    """

    model: str
    basis: np.ndarray
    hemisphere: bool
    shape: np.ndarray
    sun: np.ndarray
    cos_floor: float = 0.0
    cos_offset: float = 0.0
    neutral_rad: np.ndarray = np.zeros(2)
    max_degree: float = 0.0
    depolarisation: np.ndarray = np.zeros(1)


#: The formula's row of a sky that is the same everywhere: C = 1, scale 1.
_FLAT = np.array([[0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]])


def uniform_sky(radiance, hemisphere=False):
    """A sky of the same spectral radiance everywhere (over the whole sphere unless ``hemisphere``)."""
    return Sky("uniform", np.asarray(radiance, float)[None, :], hemisphere, _FLAT, np.array([0.0, 0.0, 1.0]))


def _hemisphere(samples=QUADRATURE):
    """Cosine-distributed directions over the upper hemisphere, midpoints of a ``samples`` × ``samples`` grid."""
    u = (np.arange(samples) + 0.5) / samples
    u1, u2 = np.meshgrid(u, u, indexing="ij")
    sin_t = np.sqrt(u1.ravel())
    phi = 2.0 * np.pi * u2.ravel()
    return np.column_stack([sin_t * np.cos(phi), sin_t * np.sin(phi), np.sqrt(1.0 - u1.ravel())])


def clear_sky_dome(model, daylight, sun_direction, turbidity, albedo, polarisation="berry"):
    """A clear sky shaped by ``model`` (:data:`CLEAR_SKIES`) carrying ``daylight``'s diffuse irradiance.

    Parameters
    ----------
    model : str
        ``hosek_wilkie`` or ``preetham``.
    daylight : beeoptics.sky.daylight.Daylight
        Its ``diffuse`` is the horizontal irradiance the sky must give.
    sun_direction : ndarray, shape (3,)
        Unit vector towards the sun, above the horizon.
    turbidity : float
    albedo : ndarray, shape (n_wavelengths,)
        The ground's albedo on the daylight's grid (Hosek & Wilkie's sky depends on it).
    polarisation : str
        Its polarisation's model (:data:`beeoptics.sky.skypolarisation.MODELS`).
    """
    wl = daylight.wavelengths
    sun = np.asarray(sun_direction, float)
    if model == "hosek_wilkie":
        albedo = np.interp(hosekwilkie.CHANNELS_NM, wl, albedo)
        shape = Sky(model, None, True, hosekwilkie.channel_shape(sun, turbidity, albedo), sun, 0.0,
                    hosekwilkie.COS_OFFSET)
        weights = hosekwilkie.channel_weights(wl)
        basis_nm = hosekwilkie.CHANNELS_NM
    else:
        a, b, c, d, e = _PEREZ_Y[:, 0] * turbidity + _PEREZ_Y[:, 1]
        shape = Sky(model, None, True, np.array([[a, b, 1.0, c, d, e, 0.0, 0.0, 0.0, 1.0]]), sun, PEREZ_COS_FLOOR)
        weights = np.ones((len(wl), 1))
        # One basis spectrum at every wavelength: its polarisation is air's at 555 nm, where
        # Perez's luminance distribution is defined (the peak of the photopic V(λ), CIE 1924).
        basis_nm = np.array([555.0])
    # Each basis spectrum's irradiance, then the wavelength-by-wavelength scale that
    # makes their blend integrate to the diffuse irradiance.
    per_basis = np.pi * sky_coefficients(shape, _hemisphere()).mean(0)
    scale = daylight.diffuse / np.maximum(weights @ per_basis, 1e-300)
    neutral, degree = skypolarisation.sky_polarisation(polarisation, np.degrees(np.arcsin(sun[2])), turbidity)
    return shape._replace(basis=(weights * scale[:, None]).T, neutral_rad=neutral, max_degree=degree,
                          depolarisation=skypolarisation.basis_depolarisation(polarisation, basis_nm))


def sky_coefficients(sky, directions):
    """Weights (n, k) of the sky's basis spectra seen along unit ``directions`` (n, 3)."""
    return hosekwilkie.shape_radiances(np.asarray(directions, float), sky.sun, sky.shape, sky.cos_floor,
                                       sky.cos_offset, sky.hemisphere)


def cie_daylight(wavelengths, cct):
    """Relative spectral power of the CIE D-series illuminant, 1 at 560 nm.

    ``cct`` in kelvin on the current scale: 6504 K for D65 (CIE 015:2004).
    """
    import colour  # imported where used: it takes a second (matplotlib with it), which most stages need not pay

    xy = colour.temperature.CCT_to_xy_CIE_D(cct)
    sd = colour.sd_CIE_illuminant_D_series(xy)
    v = resample(sd.wavelengths, sd.values, wavelengths, f"CIE D{cct:g}")
    return v / np.interp(560.0, sd.wavelengths, sd.values)


def luminance(wavelengths, radiance):
    """Luminance, cd m⁻², of a spectral radiance on the grid: K_m ∫ L V(λ) dλ.

    colour-science's ``luminous_flux`` with the CIE 1924 photopic V(λ) and
    K_m = 683 lm W⁻¹ (CIE 015:2018); only the grid's 360–700 nm part counts.
    """
    import colour  # imported where used, as in cie_daylight

    return colour.luminous_flux(colour.SpectralDistribution(np.asarray(radiance, float), np.asarray(wavelengths, float)),
                                K_m=colour.constants.CONSTANT_K_M)


def horizontal_irradiance(sky, sun, n_wavelengths, samples=QUADRATURE):
    """Spectral irradiance on an unshaded horizontal surface from the sky and sun, W m⁻² nm⁻¹.

    The sky is integrated over the upper hemisphere by cosine-weighted
    midpoint quadrature on a ``samples`` × ``samples`` grid (E = π × the
    mean radiance over a cosine-distributed set); the sun adds its radiance
    times its disc's solid angle times the cosine of its zenith angle.
    """
    total = np.zeros(n_wavelengths)
    if sky is not None:
        total += np.pi * sky_coefficients(sky, _hemisphere(samples)).mean(0) @ sky.basis
    if sun is not None and sun.direction[2] > 0.0:
        total += sun.radiance * sun.solid_angle * sun.direction[2]
    return total


def white_radiance(sky, sun, n_wavelengths):
    """The spectral radiance of a white Lambertian surface lying unshaded under the sky and sun, W m⁻² sr⁻¹ nm⁻¹:
    their horizontal irradiance over π (:func:`horizontal_irradiance`), what the catches of a white reference
    and a named adapting background are taken from."""
    return horizontal_irradiance(sky, sun, n_wavelengths) / np.pi
