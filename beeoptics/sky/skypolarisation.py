"""The polarisation of skylight: its degree and angle along every direction, for a sun and a turbidity.

Single scattering by molecules (Rayleigh) polarises skylight perpendicular
to the scattering plane (sun, observer, sky point) by
p = sin²γ / (1 + cos²γ), γ the angle from the sun: nothing at the sun and
the anti-sun, everything at 90° from it. The real sky is less polarised and
has four neutral points instead of two: Babinet's above the sun, Brewster's
below it, Arago's above the anti-sun and a fourth below it, where multiple
scattering cancels the polarisation. Berry, Dennis & Lee (2004) give the
whole pattern in closed form: on the stereographic chart of the sky,
ξ = tan(θ/2) e^{iφ} (θ zenith angle, φ azimuth), the complex field

    w(ξ) = −4 (ξ − ξ_Br)(ξ − ξ_Ba)(ξ + 1/ξ̄_Br)(ξ + 1/ξ̄_Ba)
           / [(1 + |ξ|²)² |ξ_Br + 1/ξ̄_Br| |ξ_Ba + 1/ξ̄_Ba|]

(their eq. 4.2; evaluated as −4 (ξ − ξ_Br)(ξ − ξ_Ba)(1 + ξ ξ̄_Br)(1 + ξ ξ̄_Ba)
/ [(1 + |ξ|²)² (1 + |ξ_Br|²)(1 + |ξ_Ba|²)] e^{2iφ_sun}, the same for points on the
sun's side of the zenith, finite with a point at the zenith, and continuous
as Babinet's point crosses it under a high sun) vanishes at the Brewster and Babinet points ξ_Br and ξ_Ba and
at their antipodes (Arago's and the fourth), its argument is twice the
angle of the electric vector on the chart (made independent of the sun's
azimuth by the factor e^{−2iφ_sun}, as in OpenSky, Moutenet et al. 2024) and
|w| is the polarised intensity, sin²γ when the points merge into the sun and
the anti-sun. The degree is |w| over Rayleigh's unpolarised intensity,
p = p_max |w| / (2 − |w|) (OpenSky's normalisation, Rayleigh's formula when
the points merge). The points' distances from the sun follow Pan et al.'s
(2023) fits to all-sky polarimetry against the sun's elevation h (degrees,
fitted for 0–64°, held at the ends beyond):
δ_Babinet = 42.53 − 0.56 h; δ_Brewster = 37.34 + 0.49 h up to 27°, then
56.84 − 0.25 h. The maximum degree falls with turbidity T as
p_max = exp(−(T − 0.6)/4) (Wilkie et al. 2004, as implemented in the
skylight model of Gkanias et al. 2019): 0.70 at T = 2, 0.55 at T = 3.

The degree depends on wavelength through the anisotropy of the air's
molecules, which depolarises even single scattering: with the
depolarisation factor ρ (the ratio of the parallel to the perpendicular
intensity at 90°), Rayleigh's degree becomes
p = (1 − ρ) sin²γ / (1 + ρ + (1 − ρ) cos²γ) (from the phase matrix of
Hansen & Travis 1974, eqs. 2.14–2.15), (1 − ρ)/(1 + ρ) at 90°. ρ of air
follows from its King factor F (Bodhaine et al. 1999, eqs. 5, 6 and 23: the
N₂ and O₂ factors of Bates 1984, weighted by volume, 360 ppm CO₂) as
ρ = 6(F − 1)/(3 + 7F): 0.0317 at 320 nm, 0.0283 at 550 nm, 0.0278 at
700 nm, so the degree at 90° is 0.939 in the UV and 0.946 in the red. In
Berry et al.'s pattern the same factor scales its |w| (sin²γ when the
points merge): p = p_max (1 − ρ)|w| / (2 − (1 − ρ)|w|), with Wilkie et al.'s
p_max (1 at T = 0.6, so without the molecules' share) the turbidity's. This is
the only wavelength dependence modelled: measured skies lose more of their
polarisation in the UV than molecular anisotropy explains, to multiple
scattering (Barta & Horváth 2004; Brines & Gould 1982), for which no model
or table with numbers was found, so none is made up. The ``rayleigh``
model stays the textbook reference (isotropic molecules, ρ = 0). The sun's
own light is unpolarised.

References
----------
Berry MV, Dennis MR, Lee RL (2004) Polarization singularities in the clear
sky. New J Phys 6:162.
Pan P, Wang X, Yang T, et al. (2023) Opt Express 31:15189 (neutral points'
positions against solar elevation, their eqs. 25–26, as transcribed in
pyskylumos).
Moutenet A, et al. (2024) OpenSky. IEEE Trans Instrum Meas 73.
Wilkie A, Ulbricht C, Tobler RF, Zotti G, Purgathofer W (2004) An
analytical model for skylight polarisation. Proc EGSR 2004:387–398.
Gkanias E, Risse B, Mangan M, Webb B (2019) From skylight input to
behavioural output: a computational model of the insect polarised light
compass. PLoS Comput Biol 15:e1007123.
Barta A, Horváth G (2004) Why is it advantageous for animals to detect
celestial polarization in the ultraviolet? J Theor Biol 226:429–437.
Brines ML, Gould JL (1982) Skylight polarization patterns and animal
orientation. J Exp Biol 96:69–91.
Hansen JE, Travis LD (1974) Light scattering in planetary atmospheres.
Space Sci Rev 16:527–610.
Bodhaine BA, Wood NB, Dutton EG, Slusser JR (1999) On Rayleigh optical
depth calculations. J Atmos Ocean Technol 16:1854–1861 (as implemented in
libRadtran's rayleigh.c).
Bates DR (1984) Rayleigh scattering by air. Planet Space Sci 32:785–790.
"""

import numpy as np

from beeoptics.jit import kernel

#: Sky polarisation models: single-scattering Rayleigh, and Berry et al.'s with four neutral points.
MODELS = ("rayleigh", "berry")
#: Air's gases by volume, percent, and their King factors where constant (Bodhaine et al. 1999, eq. 23:
#: N₂, O₂, Ar with F = 1.00, CO₂ at their 360 ppm with F = 1.15).
_N2, _O2, _AR, _CO2 = 78.084, 20.946, 0.934, 0.036
_F_AR, _F_CO2 = 1.00, 1.15


def king_factor(wavelength_nm):
    """The King factor F of air at wavelengths in nm (Bodhaine et al. 1999, eqs. 5, 6, 23; Bates 1984)."""
    um2 = (np.asarray(wavelength_nm, float) / 1000.0) ** 2
    f_n2 = 1.034 + 3.17e-4 / um2
    f_o2 = 1.096 + 1.385e-3 / um2 + 1.448e-4 / um2 ** 2
    return (_N2 * f_n2 + _O2 * f_o2 + _AR * _F_AR + _CO2 * _F_CO2) / (_N2 + _O2 + _AR + _CO2)


def depolarisation_factor(wavelength_nm):
    """Air's depolarisation factor ρ at wavelengths in nm, from its King factor F = (6 + 3ρ)/(6 − 7ρ)."""
    f = king_factor(wavelength_nm)
    return 6.0 * (f - 1.0) / (3.0 + 7.0 * f)


def basis_depolarisation(model, wavelengths_nm):
    """The depolarisation factor a sky's polarisation ``model`` has at each of its basis spectra's wavelengths:
    air's for ``berry``, none for ``rayleigh`` (isotropic molecules, the analytic reference)."""
    wl = np.atleast_1d(np.asarray(wavelengths_nm, float))
    return depolarisation_factor(wl) if model == "berry" else np.zeros(len(wl))


def neutral_points_deg(sun_elevation_deg):
    """The Babinet and Brewster points' angular distances from the sun, degrees (Pan et al. 2023, eqs. 25–26)."""
    h = float(np.clip(sun_elevation_deg, 0.0, 64.0))
    return 42.53 - 0.56 * h, (37.34 + 0.49 * h) if h <= 27.0 else (56.84 - 0.25 * h)


def max_degree(turbidity):
    """The sky's maximum degree of polarisation at turbidity T (Wilkie et al. 2004): exp(−(T − 0.6)/4)."""
    return float(np.exp(-(turbidity - 0.6) / 4.0))


def sky_polarisation(model, sun_elevation_deg, turbidity):
    """A sky's polarisation parameters for the tracer: the neutral points' distances (2,), radians, and p_max.

    ``rayleigh`` is the analytic reference (points at the sun and anti-sun,
    p_max 1); ``berry`` has Pan et al.'s neutral points and Wilkie et al.'s
    maximum degree at ``turbidity``.
    """
    if model == "rayleigh":
        return np.zeros(2), 1.0
    return np.radians(neutral_points_deg(sun_elevation_deg)), max_degree(turbidity)


@kernel
def _chart(x, y, z):
    """The stereographic chart's ξ = tan(θ/2) e^{iφ} of the unit direction (x, y, z)."""
    return complex(x, y) / (1.0 + z)


@kernel
def degree(size, max_deg, depolarisation):
    """The degree of polarisation of a sky point of Berry et al.'s |w| ``size`` (:func:`polarisation`), under a
    maximum degree ``max_deg`` and at a wavelength of the air's depolarisation factor ``depolarisation``."""
    a = (1.0 - depolarisation) * size
    return max_deg * a / (2.0 - a)


@kernel
def polarisation(x, y, z, sun, neutral, e_vector):
    """Berry et al.'s |w| of skylight along (x, y, z) (sin²γ in Rayleigh's pattern), and its electric vector's
    line in ``e_vector`` (3,): the degree is :func:`degree` of it.

    Parameters
    ----------
    x, y, z : float
        A unit direction, world frame (+z up).
    sun : ndarray (3,)
        Unit vector towards the sun.
    neutral : ndarray (2,)
        The Babinet and Brewster points' distances from the sun, radians
        (zero: Rayleigh's pattern).
    e_vector : ndarray (3,)
        Written: a unit vector perpendicular to (x, y, z) along the electric
        vector's line.
    """
    if z < 0.0:
        # The pattern is the same along opposite directions (its neutral points come in
        # antipodal pairs, Berry et al. 2004 §2): the lower half from the upper, away from
        # the chart's singular nadir.
        x, y, z = -x, -y, -z
    theta_sun = np.arccos(min(max(sun[2], -1.0), 1.0))
    turn = complex(sun[0], sun[1])
    turn = turn / abs(turn) if abs(turn) > 0.0 else complex(1.0, 0.0)
    babinet = turn * np.tan(0.5 * (theta_sun - neutral[0]))
    brewster = turn * np.tan(0.5 * (theta_sun + neutral[1]))
    xi = _chart(x, y, z)
    w = -4.0 * (xi - brewster) * (xi - babinet) * (1.0 + xi * np.conj(brewster)) * (1.0 + xi * np.conj(babinet))
    w /= (1.0 + abs(xi) ** 2) ** 2 * (1.0 + abs(brewster) ** 2) * (1.0 + abs(babinet) ** 2)
    size = min(abs(w), 1.0)
    # The electric vector's angle on the chart, carried onto the sphere by the chart's
    # (conformal) derivative at ξ.
    chi = 0.5 * np.angle(w)
    c, s = np.cos(chi), np.sin(chi)
    u, v = xi.real, xi.imag
    q = 1.0 + u * u + v * v
    ex = c * 2.0 * (q - 2.0 * u * u) - s * 4.0 * u * v
    ey = -c * 4.0 * u * v + s * 2.0 * (q - 2.0 * v * v)
    ez = -c * 4.0 * u - s * 4.0 * v
    norm = np.sqrt(ex * ex + ey * ey + ez * ez)
    if norm > 0.0:
        e_vector[0], e_vector[1], e_vector[2] = ex / norm, ey / norm, ez / norm
    else:
        e_vector[0], e_vector[1], e_vector[2] = 1.0, 0.0, 0.0
    return size


@kernel
def polarisations(directions, sun, neutral, max_deg, depolarisation=0.0):
    """The degree (n,) and electric vector (n, 3) of skylight along each unit direction (n, 3), at a wavelength
    of air's ``depolarisation`` factor (0 by default: isotropic molecules)."""
    degrees, e_vectors = np.empty(len(directions)), np.empty((len(directions), 3))
    for i in range(len(directions)):
        size = polarisation(directions[i, 0], directions[i, 1], directions[i, 2], sun, neutral, e_vectors[i])
        degrees[i] = degree(size, max_deg, depolarisation)
    return degrees, e_vectors


@kernel
def patterns(directions, suns, neutral, max_deg, depolarisation=0.0):
    """:func:`polarisations` along ``directions`` (n, 3) under each of ``suns`` (k, 3): degrees (k, n) and
    electric vectors (k, n, 3)."""
    degrees, e_vectors = np.empty((len(suns), len(directions))), np.empty((len(suns), len(directions), 3))
    for j in range(len(suns)):
        degrees[j], e_vectors[j] = polarisations(directions, suns[j], neutral, max_deg, depolarisation)
    return degrees, e_vectors
