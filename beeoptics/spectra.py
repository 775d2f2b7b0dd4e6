"""Spectra: the wavelength grid, resampling onto it, and pavo's CSV layout.

Every spectrum in the tracer lives on one uniform grid, 300–700 nm by
default (the range of the bee's receptors, Collins eq. 1–3, and of pavo),
at the step the config sets. Collins used 8 samples; the default here is
5 nm. Spectra from files or data sets are resampled onto the grid by
linear interpolation, which cannot overshoot into negative reflectance as
a spline can near a sharp absorption edge: numpy's ``interp``, which is
what colour-science's linear interpolator computes (the same values to the
last bit), without colour-science's import (two seconds, with matplotlib
and pandas) in every stage that reads a spectrum.

pavo's layout (Maia et al. 2019) is a CSV whose first column is the
wavelength in nm and whose other columns are one spectrum each; values
above 1 anywhere mean percent, as in pavo's ``vismodel``.

References
----------
Maia R, Gruson H, Endler JA, White TE (2019) pavo 2: new tools for the
spectral and spatial analysis of colour in R. Methods Ecol Evol 10:1097–1107.
"""

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.io.table import read_table, write_table
from beeoptics.io.validation import config_default

#: How far beyond its last measured wavelength a spectrum may be held
#: constant, nm: FReD's spectra stop at 699 nm, one short of the grid.
EDGE_TOLERANCE_NM = 2.0


#: The config schema's grid (``spectral``), the default of every door.
_GRID = {key: float(value) for key, value in config_default("spectral").items()}


def grid(start_nm=_GRID["start_nm"], end_nm=_GRID["end_nm"], step_nm=_GRID["step_nm"]):
    """The uniform wavelength grid, nm, both ends included."""
    n = int(round((end_nm - start_nm) / step_nm)) + 1
    return start_nm + step_nm * np.arange(n)


def resample(wavelengths, values, onto, source="spectrum", field=""):
    """Resample spectra onto a grid, linearly; ends within :data:`EDGE_TOLERANCE_NM` held at their last value.

    Parameters
    ----------
    wavelengths : array_like, shape (k,)
        nm, increasing.
    values : array_like, shape (k,) or (k, m)
        One spectrum per column.
    onto : ndarray
        The target grid, nm.
    source, field : str
        Named in the error if the spectra do not cover the grid.

    Returns
    -------
    ndarray, shape (len(onto),) or (len(onto), m)

    Raises
    ------
    InputError
        If the data stop short of either end of the grid by more than
        :data:`EDGE_TOLERANCE_NM`, or hold NaN.
    """
    wl = np.asarray(wavelengths, float)
    v = np.asarray(values, float)
    if wl[0] - onto[0] > EDGE_TOLERANCE_NM or onto[-1] - wl[-1] > EDGE_TOLERANCE_NM:
        raise InputError(
            source, field,
            f"covers {wl[0]:g}–{wl[-1]:g} nm; spectra must cover {onto[0]:g}–{onto[-1]:g} nm",
        )
    if np.isnan(v).any():
        raise InputError(source, field, "holds NaN")
    # Measured spectra often come on uneven grids (ASTM G173: 0.5 nm, then 1 and 5 nm): linear
    # interpolation takes them as they are; beyond the data, np.interp holds the last value.
    columns = v.reshape(len(wl), -1)
    out = np.stack([np.interp(onto, wl, c) for c in columns.T], axis=-1)
    return out.reshape((len(onto),) + v.shape[1:])


def read_pavo_csv(path, onto=None):
    """Read spectra in pavo's layout: a wavelength column, then one column per sample.

    Percent is detected as in pavo (any value above 1) and turned into a
    fraction. Negative values, as spectrometer noise makes near zero, are
    refused rather than clipped, since they are as often a sign of a wrong
    file.

    Returns
    -------
    names : list of str
    wavelengths : ndarray, nm (``onto`` if given)
    values : ndarray, shape (n_wavelengths, n_samples), fraction
    """
    table = read_table(path)
    names = list(table)
    table = read_table(path, numeric=names)
    if len(names) < 2:
        raise InputError(path, "", "expected a wavelength column and at least one spectrum")
    wl_name, samples = names[0], names[1:]
    wl = table[wl_name].astype(float)
    if len(wl) < 2:
        raise InputError(path, wl_name, f"{len(wl)} wavelength(s); a spectrum needs at least two")
    if (np.diff(wl) == 0).any():
        raise InputError(path, wl_name, f"duplicate {wl[1:][np.diff(wl) == 0][0]:g} nm")
    if not np.isfinite(wl).all() or np.any(np.diff(wl) <= 0):
        raise InputError(path, wl_name, "the first column must hold increasing wavelengths in nm")
    values = np.column_stack([table[s].astype(float) for s in samples])
    for j, s in enumerate(samples):
        if np.isnan(values[:, j]).any():
            raise InputError(path, s, f"holds a value that is not a number, empty or NaN, at "
                             f"{wl[np.isnan(values[:, j])][0]:g} nm")
        if np.isinf(values[:, j]).any():
            raise InputError(path, s, f"holds infinity at {wl[np.isinf(values[:, j])][0]:g} nm")
        if (values[:, j] < 0).any():
            k = np.argmin(values[:, j])
            raise InputError(path, s, f"holds negative values (down to {values[k, j]:g} at {wl[k]:g} nm)")
    if values.max() > 1.0:
        values = values / 100.0
    if onto is not None:
        values = resample(wl, values, onto, path, samples[0])
        wl = onto
    return samples, wl, values


def write_pavo_csv(path, wavelengths, spectra):
    """Write spectra in pavo's layout; ``spectra`` maps names to arrays on ``wavelengths``."""
    write_table(path, {"wl": np.asarray(wavelengths, float), **{k: np.asarray(v, float) for k, v in spectra.items()}})

