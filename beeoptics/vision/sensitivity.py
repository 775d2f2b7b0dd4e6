"""Spectral sensitivities of the honey bee's photoreceptors.

By default the three receptor classes, UV, blue and green, have the curves
Peitsch et al. (1992) measured, as pavo ships them (``sensdata(visual =
"apis")``; the package's ``vision/data/apis_sensitivity_peitsch1992.csv``).
The option ``govardovskii`` models them instead with the A1 visual-pigment
template of Govardovskii et al. (2000), α and β bands, at the peak
wavelengths Peitsch et al. measured: 344, 436 and 544 nm. The template
puts 0.2 % of the UV receptor's sensitivity above 400 nm, the measured
curve 6 %; under daylight, which rises steeply there, that shifts hues. As
in pavo's ``sensmodel`` each curve sums to one over the grid ("integrate").

The overall spectral sensitivity of the light-adapted bee, S(λ), which
Collins (§3.2, Fig. 5a) takes from von Helversen (1972), has peaks near 345,
440 and 550 nm in the ratio 16 : 2.7 : 1. It is modelled here as the
weighted sum of the three receptor curves whose values at those three
wavelengths stand in that ratio: a parametric stand-in for the behavioural
curve, which we have not seen tabulated.

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

from pathlib import Path

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.spectra import read_pavo_csv

#: The receptor classes, shortest first.
RECEPTORS = ("UV", "B", "G")
#: Peak wavelengths of the honey bee's receptors, nm (Peitsch et al. 1992).
LAMBDA_MAX_APIS = (344.0, 436.0, 544.0)
#: Peaks of the light-adapted overall sensitivity, nm, and their relative
#: heights (von Helversen 1972, as given by Collins §3.2).
HELVERSEN_PEAKS_NM = (345.0, 440.0, 550.0)
HELVERSEN_RATIO = (16.0, 2.7, 1.0)


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


def receptor_sensitivities(wavelengths, lambda_max=LAMBDA_MAX_APIS):
    """Receptor curves on a grid, shape (len(wavelengths), 3), each summing to one (pavo's convention)."""
    s = np.column_stack([govardovskii_a1(wavelengths, lm) for lm in lambda_max])
    s /= s.max(axis=0)
    return s / s.sum(axis=0)


#: The config's name for the template curves, as against a CSV of measured ones.
TEMPLATE = "govardovskii"
#: The config's name for the measured curves of Peitsch et al. (1992) the package ships: the default.
PEITSCH_1992 = "peitsch1992"
#: Where those curves are, in pavo's layout (source in the folder's README).
PEITSCH_1992_FILE = Path(__file__).parent / "data" / "apis_sensitivity_peitsch1992.csv"


def sensitivities(wavelengths, source=PEITSCH_1992):
    """The receptor curves a config names: :data:`PEITSCH_1992`, :data:`TEMPLATE`, or the path of a pavo CSV."""
    if source == TEMPLATE:
        return receptor_sensitivities(wavelengths)
    return measured_sensitivities(PEITSCH_1992_FILE if source == PEITSCH_1992 else source, wavelengths)


def describe(source):
    """A receptor-curve setting in words, for figures."""
    if source == TEMPLATE:
        return f"Govardovskii A1 template, λmax {'/'.join(f'{lam:g}' for lam in LAMBDA_MAX_APIS)} nm"
    if source == PEITSCH_1992:
        return "measured, Peitsch et al. (1992), as in pavo"
    return f"measured, {Path(source).name}"


def measured_sensitivities(path, wavelengths):
    """Receptor curves from a CSV in pavo's layout (columns UV, B, G in that order), summing to one.

    Raises
    ------
    InputError
        If the file does not hold three receptor columns, a column is zero
        everywhere, or the columns' peaks are not in the order UV, B, G;
        and as :func:`~beeoptics.spectra.read_pavo_csv` does.
    """
    names, wl, values = read_pavo_csv(path, wavelengths)
    if len(names) != 3:
        raise InputError(path, ", ".join(names), f"expected three receptor columns (UV, B, G), found {len(names)}")
    for j, name in enumerate(names):
        if not values[:, j].max() > 0.0:
            raise InputError(path, name, "is zero everywhere on the grid; a receptor must be sensitive somewhere")
    peaks = wl[np.argmax(values, axis=0)]
    for j in (1, 2):
        if peaks[j] <= peaks[j - 1]:
            raise InputError(
                path, names[j],
                f"peaks at {peaks[j]:g} nm, not beyond {names[j - 1]} ({peaks[j - 1]:g} nm); "
                "the columns must be UV, B, G, shortest peak first",
            )
    return values / values.sum(axis=0)


def overall_sensitivity(wavelengths, receptors=None):
    """The light-adapted overall spectral sensitivity S(λ), its largest value one.

    The weighted sum of the receptor curves whose values at 345, 440 and
    550 nm stand as 16 : 2.7 : 1 (von Helversen 1972).
    """
    wl = np.asarray(wavelengths, float)
    if receptors is None:
        receptors = receptor_sensitivities(wl)
    at_peaks = np.column_stack([np.interp(HELVERSEN_PEAKS_NM, wl, receptors[:, k]) for k in range(3)])
    weights = np.linalg.solve(at_peaks, np.asarray(HELVERSEN_RATIO))
    s = receptors @ weights
    return s / s.max()
