"""Photon catches of the receptors: Collins eq. 1–3 in photon units.

Photoreceptors count photons, so the quantum catch of class i is
Q_i = ∫ S_i(λ) E_p(λ) dλ ≈ Σ_λ S_i(λ) E_p(λ) Δλ, E_p = E λ/(hc), with S_i
dimensionless and of area 1 nm (:func:`beeoptics.vision.sensitivity.unit_area`):
pavo's curves, which sum to one on its 1-nm grid (Maia et al. 2019). Q is
then a weighted photon irradiance, photons m⁻² s⁻¹ (the photons of a band
1 nm wide, weighted by the curve), when E is a receptor's spectral
irradiance (its radiance times its acceptance solid angle,
:func:`beeoptics.eye.optics.acceptance_solid_angle`); it does not depend on
the grid's step beyond the integration error, and on a 1-nm grid it is
pavo's ``vismodel`` catch.

References
----------
Maia R, Gruson H, Endler JA, White TE (2019) pavo 2. Methods Ecol Evol
10:1097–1107.
"""

import numpy as np
from scipy.constants import c, h


def photon_flux(energy, wavelengths_nm):
    """Spectral energy (… nm⁻¹) to spectral photon flux (photons s⁻¹ … nm⁻¹)."""
    return np.asarray(energy) * (np.asarray(wavelengths_nm) * 1e-9) / (h * c)


def quantum_catches(irradiance, sensitivities, wavelengths_nm):
    """Quantum catch of each receptor class, (n, k), from spectral irradiance (n, n_wl), W m⁻² nm⁻¹.

    ``sensitivities`` (n_wl, k) of area 1 nm each give photons m⁻² s⁻¹; the
    rectangle rule over the uniform grid ``wavelengths_nm`` (nm).
    """
    step = float(wavelengths_nm[1] - wavelengths_nm[0])
    return photon_flux(irradiance, wavelengths_nm) @ sensitivities * step
