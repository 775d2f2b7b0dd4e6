"""Receptor optics: the angular acceptance of one ommatidium, and sampling it.

Each receptor accepts light from around its axis with the Gaussian angular
sensitivity of Snyder (1977),

    A(θ) = exp(−4 ln 2 · θ² / Δρ²) ≈ exp(−2.77 θ² / Δρ²),

θ being the angle from the axis and Δρ the full width at half maximum,
A(Δρ/2) = ½. Collins prints Δρ where Snyder has Δρ²; Eheim & Wehner's
(1972) fit, exp(−0.41 θ²) with θ in degrees for Δρ = 2.57°, confirms the
square. Δρ is either fixed, 2.6° (Laughlin & Horridge 1971; Rigosi et al.
2017 give the same mean for dark-adapted workers), or follows the facet
diameter D through Snyder's

    Δρ² = (λ/D)² + (d/f)²,

with the rhabdom's angular width d/f = 1.7° for workers (Somanathan et al.
2009, Table 1, after Greiner et al. 2004) and λ = 500 nm (the wavelength
Land 1990 and Collins use for the bee's diffraction limit), or is
measured: an eye description may give Δρ measured in named regions
(``optics.delta_rho_anchors``), spread over the receptors by Shepard's
inverse-distance weighting of the angles between their axes and the
anchors' directions (:func:`measured_delta_rho`), or is a published
multiple of each receptor's Δφ (``delta_phi``: Taylor et al. 2019 take
Δρ = Δφ for bumblebees; Buchner 1984, as strawlab's eye map does, 1.1 Δφ
for Drosophila). Which of these an eye follows is its own, named in its
``optics.delta_rho`` (the ``species`` model, the default); ``fixed`` and
``snyder`` apply one model to every eye, and an eye that names none keeps
the fixed value.

The acceptance function's solid angle, π Δρ²/(4 ln 2), turns a receptor's
acceptance-weighted mean radiance into its irradiance. The eye's resolving
power is given by two limits: the highest spatial frequency its lattice
samples, f_max = 1/(2Δφ) (Nyquist; Snyder 1977, Collins §3.1), and the
Rayleigh limit 1.22 λ/D of a facet lens of diameter D (the first zero of
the Airy pattern; Airy 1835, Rayleigh 1879; Land 1997 for compound eyes).

References
----------
Snyder AW (1977) Acuity of compound eyes: physical limitations and design.
J Comp Physiol 116:161–182.
Eheim WP, Wehner R (1972) Die Sehfelder der zentralen Ommatidien in den
Appositionsaugen von Apis mellifica und Cataglyphis bicolor. Kybernetik
10:168–179.
Laughlin SB, Horridge GA (1971) Angular sensitivity of the retinula cells
of dark-adapted worker bee. Z Vergl Physiol 74:329–335.
Somanathan H, Warrant EJ, Borges RM, Wallén R, Kelber A (2009) Resolution
and sensitivity of the eyes of the Asian honeybees Apis florea, Apis cerana
and Apis dorsata. J Exp Biol 212:2448–2453.
Land MF (1990) The design of compound eyes. In Blakemore C (ed) Vision:
coding and efficiency. Cambridge University Press, 55–64.
Land MF (1997) Visual acuity in insects. Annu Rev Entomol 42:147–177.
Airy GB (1835) On the diffraction of an object-glass with circular
aperture. Trans Camb Philos Soc 5:283–291.
Rayleigh (Strutt JW) (1879) Investigations in optics, with special
reference to the spectroscope. Philos Mag 8:261–274.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.headframe import eye_direction
from beeoptics.io.validation import config_default

#: 4 ln 2, the "2.77" of Snyder's Gaussian.
FOUR_LN2 = 4.0 * np.log(2.0)
#: Rhabdom angular width d/f of workers, degrees (Somanathan et al. 2009, Table 1).
RHABDOM_ACCEPTANCE_DEG = 1.7
#: Wavelength for the diffraction term, nm (Land 1990): the config schema's ``eye.delta_rho.wavelength_nm``.
SNYDER_WAVELENGTH_NM = config_default("eye.delta_rho.wavelength_nm")
#: The config's acceptance model, the default of every door (``eye.delta_rho`` in the config schema).
_DEFAULT = config_default("eye.delta_rho")
#: The Rayleigh criterion's factor: the first zero of the Airy pattern, in λ/D (Airy 1835).
RAYLEIGH_FACTOR = 1.22


class AcceptanceModel(NamedTuple):
    """How each receptor's acceptance angle Δρ is set: ``model`` "species", "fixed" or "snyder".

    "species" follows the eye's own ``optics.delta_rho`` (its measured
    values, :func:`measured_delta_rho`; Snyder's model; or a multiple of
    Δφ), ``fixed_deg`` for an eye that names none; "fixed" gives every
    receptor ``fixed_deg``; "snyder" takes Δρ from the facet diameter at
    ``wavelength_nm`` (:func:`snyder_delta_rho`). The defaults are the
    config schema's (``eye.delta_rho``), as the workflow and the command
    line have them.
    """

    model: str = _DEFAULT["model"]
    fixed_deg: float = _DEFAULT["fixed_deg"]
    wavelength_nm: float = _DEFAULT["wavelength_nm"]

    @classmethod
    def from_config(cls, delta_rho):
        """The model a config's ``eye.delta_rho`` section describes."""
        return cls(**delta_rho)


def angular_sensitivity(theta, delta_rho):
    """Snyder's Gaussian angular sensitivity A(θ), 1 on the axis.

    Parameters
    ----------
    theta, delta_rho : array_like
        Angle from the axis and full width at half maximum, same units.
    """
    return np.exp(-FOUR_LN2 * (np.asarray(theta) / delta_rho) ** 2)


def snyder_delta_rho(facet_diameter_um, wavelength_nm=SNYDER_WAVELENGTH_NM,
                     rhabdom_deg=RHABDOM_ACCEPTANCE_DEG):
    """Acceptance angle in degrees from Δρ² = (λ/D)² + (d/f)² (Snyder 1977)."""
    diffraction = np.degrees(wavelength_nm * 1e-3 / np.asarray(facet_diameter_um, float))
    return np.sqrt(diffraction**2 + rhabdom_deg**2)


def measured_delta_rho(axes_head, anchors, power=2.0):
    """Δρ measured in named regions, spread over the receptors by Shepard's weighting of angles, degrees.

    Parameters
    ----------
    axes_head : ndarray (n, 3)
        The right eye's receptor axes, head frame.
    anchors : sequence of dict
        Each with ``azimuth_deg``, ``elevation_deg`` (the right eye's
        convention) and ``delta_rho_deg``.
    """
    directions = eye_direction([a["azimuth_deg"] for a in anchors], [a["elevation_deg"] for a in anchors])
    values = np.array([a["delta_rho_deg"] for a in anchors], float)
    angle = np.arccos(np.clip(np.asarray(axes_head) @ directions.T, -1.0, 1.0))
    with np.errstate(divide="ignore"):
        weight = angle ** -power
    exact = np.isinf(weight)
    weight[exact.any(1)] = exact[exact.any(1)]
    return (weight * values).sum(1) / weight.sum(1)


def acceptance_angles(facet_diameter_um, model=AcceptanceModel(), rhabdom_deg=RHABDOM_ACCEPTANCE_DEG,
                      axes_head=None, anchors=(), own=None, delta_phi_deg=None):
    """Per-receptor acceptance angle Δρ, degrees, by an :class:`AcceptanceModel`.

    For the "species" model, ``own`` is the eye's ``optics.delta_rho``
    (``{"model": "measured" | "snyder" | "delta_phi", "ratio": …}``, or None):
    ``axes_head`` and ``anchors`` (the eye's measured Δρ) serve "measured",
    ``delta_phi_deg`` (each receptor's) "delta_phi".
    """
    for name, value in (("fixed_deg", model.fixed_deg), ("wavelength_nm", model.wavelength_nm),
                        ("rhabdom_deg", rhabdom_deg)):
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"delta_rho: {name} must be positive, not {value!r}")
    kind = model.model if model.model != "species" else (own or {}).get("model", "fixed")
    if kind == "fixed":
        return np.full(np.shape(facet_diameter_um), float(model.fixed_deg))
    if kind == "snyder":
        return snyder_delta_rho(facet_diameter_um, model.wavelength_nm, rhabdom_deg)
    if kind == "measured":
        return measured_delta_rho(axes_head, anchors)
    if kind == "delta_phi":
        return own["ratio"] * np.asarray(delta_phi_deg, float)
    raise ValueError(f"unknown acceptance model {kind!r}; use 'species', 'fixed' or 'snyder'")


def acceptance_solid_angle(delta_rho_deg):
    """∫ A dΩ of Snyder's Gaussian acceptance function, sr (small-angle)."""
    return np.pi * np.radians(np.asarray(delta_rho_deg, float)) ** 2 / FOUR_LN2


def nyquist_limit_cpd(delta_phi_deg):
    """The highest spatial frequency a lattice of interommatidial angle Δφ samples, 1/(2Δφ), cycles per degree."""
    return 1.0 / (2.0 * np.asarray(delta_phi_deg, float))


def rayleigh_limit_deg(wavelength_nm, facet_diameter_um):
    """The Rayleigh limit 1.22 λ/D of a facet lens, degrees."""
    return np.degrees(RAYLEIGH_FACTOR * wavelength_nm * 1e-9 / (np.asarray(facet_diameter_um, float) * 1e-6))
