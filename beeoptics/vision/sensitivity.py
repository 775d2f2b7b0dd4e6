"""Spectral sensitivities of photoreceptors: the A1 visual-pigment template and measured curves.

A receptor class's curve is either measured (a table in pavo's layout:
a wavelength column, then one column per class) or modelled with the A1
visual-pigment template of Govardovskii et al. (2000), α and β bands, at
the class's measured peak wavelength λmax. Each curve is normalised to an
area of one nanometre, Σ S(λ) Δλ = 1 nm (:func:`unit_area`), so that a
quantum catch Q = ∫ S(λ) E_p(λ) dλ is the same on any grid up to the
integration error, and equal to pavo's on pavo's 1-nm grid, where
``sensmodel(integrate = TRUE)`` makes each curve sum to one ("a total area
under the curve of 1", ``wl <- range[1]:range[2]``, ``peaks / rowSums(peaks)``
in ``R/sensmodel.R``) and ``vismodel`` sums S·E over that grid without a
step (``colSums(y * S[, x] * illum)``). Which classes a species
has, and which curves it uses, is the species' receptor set
(:mod:`beeoptics.vision.receptorset`).

For the honey bee, the template puts 0.2 % of the UV receptor's
sensitivity above 400 nm, Peitsch et al.'s (1992) measured curve 6 %;
under daylight, which rises steeply there, that shifts hues.

The overall spectral sensitivity of the light-adapted honey bee, S(λ),
which Collins (§3.2, Fig. 5a) takes from von Helversen (1972), has peaks
near 345, 440 and 550 nm in the ratio 16 : 2.7 : 1. It is modelled here as
the weighted sum of the receptor curves whose values at those wavelengths
stand in that ratio (:func:`overall_sensitivity`): a parametric stand-in
for the behavioural curve, which we have not seen tabulated.

References
----------
Govardovskii VI, Fyhrquist N, Reuter T, Kuzmin DG, Donner K (2000) In search
of the visual pigment template. Vis Neurosci 17:509–528.
Peitsch D, Fietz A, Hertel H, de Souza J, Ventura DF, Menzel R (1992) The
spectral input systems of hymenopteran insects and their receptor-based
colour vision. J Comp Physiol A 170:23–40.
von Helversen O (1972) Zur spektralen Unterschiedsempfindlichkeit der
Honigbiene. J Comp Physiol 80:439–472.
Maia R, Gruson H, Endler JA, White TE (2019) pavo 2. Methods Ecol Evol
10:1097–1107.
"""

import functools
import os

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.spectra import read_pavo_csv


def govardovskii_a1(wavelengths, lambda_max, beta=True):
    """The A1 visual-pigment template, α band plus optional β band, peak near 1.

    Parameters
    ----------
    wavelengths : array_like
        nm.
    lambda_max : float
        Peak wavelength of the α band, nm.

    Notes
    -----
    α band (Govardovskii et al. 2000, eq. 1–2):
    S = 1 / [exp(A(a−x)) + exp(B(b−x)) + exp(C(c−x)) + D], x = λmax/λ,
    A = 69.7, a = 0.8795 + 0.0459 exp(−(λmax−300)²/11940), B = 28,
    b = 0.922, C = −14.9, c = 1.104, D = 0.674.
    β band (eq. 4–6): 0.26 exp(−((λ − λmβ)/bβ)²), λmβ = 189 + 0.315 λmax,
    bβ = −40.5 + 0.195 λmax.
    """
    wl = np.asarray(wavelengths, float)
    x = lambda_max / wl
    a = 0.8795 + 0.0459 * np.exp(-((lambda_max - 300.0) ** 2) / 11940.0)
    s = 1.0 / (np.exp(69.7 * (a - x)) + np.exp(28.0 * (0.922 - x)) + np.exp(-14.9 * (1.104 - x)) + 0.674)
    if beta:
        s = s + 0.26 * np.exp(-(((wl - (189.0 + 0.315 * lambda_max)) / (-40.5 + 0.195 * lambda_max)) ** 2))
    return s


def unit_area(curves, wavelengths):
    """Curves (n_wavelengths, k) scaled to an area of 1 nm each on the uniform grid ``wavelengths`` (nm).

    The area is the rectangle rule's Σ S Δλ, the rule by which
    :func:`beeoptics.vision.catches.quantum_catches` integrates, so that a
    flat spectrum's catch is its value exactly on every grid. Dimensionless;
    on pavo's 1-nm grid these are pavo's curves, each summing to one.
    """
    curves = np.asarray(curves, float)
    return curves / (curves.sum(axis=0) * float(wavelengths[1] - wavelengths[0]))


def receptor_sensitivities(wavelengths, lambda_max):
    """Template curves at the peaks ``lambda_max`` (nm), shape (len(wavelengths), k), each of area 1 nm."""
    return unit_area(np.column_stack([govardovskii_a1(wavelengths, lm) for lm in lambda_max]), wavelengths)


def measured_sensitivities(path, wavelengths, classes, lambda_max=None):
    """Receptor curves from a CSV in pavo's layout, one column per class in order, each of area 1 nm.

    Parameters
    ----------
    classes : sequence of str
        The receptor classes the columns must be, in order (their names are
        not required to match: pavo names them ``apis.s``, ``apis.m``, ...).
    lambda_max : sequence of float, optional
        The classes' peaks, nm: the columns' peaks must come in the same order.

    Raises
    ------
    InputError
        If the file does not hold a column per class, a column is zero
        everywhere, or the columns' peaks are not in the order of the
        classes' λmax; and as :func:`~beeoptics.spectra.read_pavo_csv` does.
    """
    try:
        stamp = os.stat(path)
        stamp = (stamp.st_ino, stamp.st_mtime_ns, stamp.st_size)
    except OSError:
        stamp = None  # read_pavo_csv names the missing file in one line
    # A loop of looks reads the same curves at every look: a file is read once per version of it.
    return _measured(str(path), stamp, np.asarray(wavelengths, float).tobytes(), tuple(classes),
                     None if lambda_max is None else tuple(lambda_max)).copy()


@functools.lru_cache(maxsize=16)
def _measured(path, stamp, wavelengths, classes, lambda_max):
    """:func:`measured_sensitivities` of a file at one version (``stamp``: its inode, time and size), the grid
    as bytes."""
    names, wl, values = read_pavo_csv(path, np.frombuffer(wavelengths))
    if len(names) != len(classes):
        raise InputError(path, ", ".join(names), f"expected {len(classes)} receptor columns "
                         f"({', '.join(classes)}), found {len(names)}")
    for j, name in enumerate(names):
        if not values[:, j].max() > 0.0:
            raise InputError(path, name, "is zero everywhere on the grid; a receptor must be sensitive somewhere")
    if lambda_max is not None:
        peaks = wl[np.argmax(values, axis=0)]
        order = np.argsort(lambda_max, kind="stable")
        for before, after in zip(order[:-1], order[1:]):
            if peaks[after] <= peaks[before]:
                raise InputError(
                    path, names[after],
                    f"peaks at {peaks[after]:g} nm, not beyond {names[before]} ({peaks[before]:g} nm); the columns "
                    f"must be {', '.join(classes)}, whose peaks lie at {', '.join(f'{v:g}' for v in lambda_max)} nm",
                )
    return unit_area(values, wl)


def overall_weights(wavelengths, receptors, peaks_nm, ratio):
    """The weights (k,), summing to one, of the receptor curves (n, k) in the overall sensitivity.

    Those whose weighted sum's values at the ``peaks_nm`` (k,) stand as
    ``ratio`` (for the honey bee 345, 440 and 550 nm and 16 : 2.7 : 1, von
    Helversen 1972). With curves of area 1 nm (:func:`unit_area`) the sum
    has area 1 nm too, so its catch, the brightness, is the same weighted
    sum of the receptors' catches.
    """
    wl = np.asarray(wavelengths, float)
    at_peaks = np.column_stack([np.interp(peaks_nm, wl, receptors[:, k]) for k in range(receptors.shape[1])])
    weights = np.linalg.solve(at_peaks, np.asarray(ratio, float))
    return weights / weights.sum()


def overall_sensitivity(wavelengths, receptors, peaks_nm, ratio):
    """The light-adapted overall spectral sensitivity S(λ), its largest value one: the receptor curves (n, k)
    weighted by :func:`overall_weights`."""
    s = receptors @ overall_weights(wavelengths, receptors, peaks_nm, ratio)
    return s / s.max()
