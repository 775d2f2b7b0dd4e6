"""Quantum catches are integrals over wavelength: the same on any grid, pavo's on pavo's 1-nm grid."""

import numpy as np
import pytest
from scipy.constants import c, h, k

from beeoptics.spectra import grid
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.colourspace import reflectance_catches
from beeoptics.vision.receptorset import SPECIES, TEMPLATE, brightness_weights, curves, load_receptor_set

APIS = load_receptor_set("apis_mellifera")
#: The Sun's effective temperature, K (IAU 2015 Resolution B3: 5772 K): a smooth daylight-like spectrum.
SUN_K = 5772.0
#: Four emission lines (centre nm, relative height), each 20 nm wide at half maximum, as narrow-band LEDs
#: are: a spiky spectrum whose lines span two grid steps at 10 nm.
LINES = ((365.0, 1.0), (450.0, 0.6), (530.0, 0.8), (610.0, 0.5))
LINE_FWHM_NM = 20.0


def planck(wl):
    """Black-body spectral radiance at :data:`SUN_K`, W m⁻² sr⁻¹ nm⁻¹."""
    m = wl * 1e-9
    return 2.0 * h * c**2 / m**5 / np.expm1(h * c / (m * k * SUN_K)) * 1e-9


def lines(wl):
    sigma = LINE_FWHM_NM / (2.0 * np.sqrt(2.0 * np.log(2.0)))
    return 1e-3 * sum(a * np.exp(-0.5 * ((wl - m) / sigma) ** 2) for m, a in LINES)


def catches(spectrum, step_nm, setting):
    """Each class's catch and the brightness (the overall sensitivity's) of ``spectrum`` sampled on a grid."""
    wl = grid(300.0, 700.0, step_nm)
    sens = curves(APIS, wl, setting)
    q = quantum_catches(spectrum(wl)[None], sens, wl)[0]
    return np.append(q, q @ brightness_weights(APIS, wl, sens))


# The rectangle rule's error on these spectra, against a 0.1-nm grid: at most 1.8 % (daylight, the
# template's UV curve, 10 nm) and 4.6 % (the lines), shrinking with the step.
@pytest.mark.parametrize("spectrum, tolerance", [(planck, 0.02), (lines, 0.05)], ids=["daylight", "lines"])
@pytest.mark.parametrize("setting", [SPECIES, TEMPLATE])
def test_catches_do_not_depend_on_the_grid_step(spectrum, tolerance, setting):
    exact = catches(spectrum, 0.1, setting)
    for step in (1.0, 2.0, 5.0, 10.0):
        np.testing.assert_allclose(catches(spectrum, step, setting), exact, rtol=tolerance, err_msg=f"{step} nm")


def test_a_flat_spectrum_is_caught_as_its_value_on_any_grid():
    # Curves of area 1 nm: a flat photon spectrum of 1 photon m⁻² s⁻¹ nm⁻¹ gives 1 photon m⁻² s⁻¹.
    for step in (1.0, 2.0, 5.0, 10.0):
        wl = grid(300.0, 700.0, step)
        flat = np.full(len(wl), h * c / (wl * 1e-9))
        np.testing.assert_allclose(quantum_catches(flat[None], curves(APIS, wl), wl), 1.0, rtol=1e-12)


def test_catches_on_a_1_nm_grid_are_pavos(shared_data):
    # pavo's vismodel(qcatch = "Qi", vonkries = FALSE): colSums(y * S * illum), S summing to one on 300:700.
    wl = grid(300.0, 700.0, 1.0)
    raw = np.loadtxt(shared_data / "apis_sensitivity_peitsch1992.csv", delimiter=",", skiprows=1)[:, 1:]
    sens = raw / raw.sum(0)
    light = planck(wl)
    np.testing.assert_allclose(reflectance_catches(np.ones(len(wl)), light, curves(APIS, wl), wl),
                               light @ sens, rtol=1e-12)
