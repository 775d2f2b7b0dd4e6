"""Photon catches of the receptors: Collins eq. 1–3 in photon units.

Photoreceptors count photons, so the quantum catch of class i is
Q_i = Σ_λ S_i(λ) E_p(λ) Δλ, E_p = E λ/(hc), with S_i summing to one on the
grid as pavo's do (Maia et al. 2019); Q is then a weighted photon
irradiance, photons m⁻² s⁻¹, when E is a receptor's spectral irradiance
(its radiance times its acceptance solid angle,
:func:`beeoptics.eye.optics.acceptance_solid_angle`).

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
    """Quantum catch of each receptor class, (n, k), from spectral irradiance (n, n_wl), W m⁻² nm⁻¹."""
    step = float(wavelengths_nm[1] - wavelengths_nm[0])
    return photon_flux(irradiance, wavelengths_nm) @ sensitivities * step
