"""Measured daylight, to hold the clear-sky model against: Granada and Spitschan et al.'s records.

Both ship in the ``dreye`` package (MIT licence), read here directly:
Hernández-Andrés et al. (2001) measured 2,600 spectra of global daylight
in Granada, Spain, 300–1100 nm at 5 nm, over two years (dreye's copy holds
no time or sun elevation); Spitschan et al. (2016) 6,391 spectra in rural
and city Pennsylvania, 280–840 nm at 1 nm, each with the sun's elevation,
of which the instrument's range is taken from 360 nm. Both are spectral
irradiance on a horizontal surface, W m⁻² nm⁻¹, clouds included: a clear
sky is compared with the records that are about as bright at 550 nm
(:func:`clear_like`) and, for Spitschan's, taken with the sun at about the
same elevation.

The two figures compared are the ratio of UV (up to 400 nm) to visible
(400–700 nm) photons and the ratio of the bee's UV to green receptor's
quantum catch, the two a UV-rich or UV-poor daylight moves most.

References
----------
Hernández-Andrés J, Romero J, Nieves JL, Lee RL (2001) Color and spectral
analysis of daylight in southern Europe. J Opt Soc Am A 18:1325–1335.
Spitschan M, Aguirre GK, Brainard DH, Sweeney AM (2016) Variation of
outdoor illumination as a function of solar elevation and light
pollution. Sci Rep 6:26756.
"""

import importlib.util
from functools import cache
from pathlib import Path

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.spectra import resample

#: Where Spitschan et al.'s instrument is trusted from, nm (its data below are noise).
SPITSCHAN_FROM_NM = 360.0


def _datasets():
    spec = importlib.util.find_spec("dreye")
    if spec is None or not spec.submodule_search_locations:
        raise InputError("dreye", "", "the dreye package is not installed (pip install --no-deps dreye)")
    return Path(spec.submodule_search_locations[0]) / "datasets"


def _on_grid(wavelengths, records, onto, source="daylight", field="measured_daylight"):
    """Records (n, k) on their grid, resampled onto ``onto`` (n, len(onto)); gaps and negative noise read as zero."""
    v = np.nan_to_num(np.atleast_2d(np.asarray(records, float)))
    return np.maximum(resample(wavelengths, v.T, np.asarray(onto, float), source, field).T, 0.0)


@cache
def _granada():
    from scipy.io import loadmat  # imported where used: only the daylight comparison reads these records

    return np.linspace(300.0, 1100.0, 161), loadmat(_datasets() / "granada_daylight.mat")["final"].T


def granada(wavelengths):
    """Hernández-Andrés et al.'s (2001) Granada records on the grid: (2600, n) W m⁻² nm⁻¹."""
    return _on_grid(*_granada(), np.asarray(wavelengths, float))


@cache
def _spitschan():
    import pandas as pd  # as in _granada

    df = pd.read_feather(_datasets() / "spitschan2016" / "spitschan2016.feather",
                         columns=["data_id", "solar_elevation", "wavelengths", "spectralirradiance"])
    wide = df.pivot_table("spectralirradiance", "data_id", "wavelengths", dropna=False)
    elevation = df.drop_duplicates("data_id").set_index("data_id")["solar_elevation"].loc[wide.index]
    return wide.columns.to_numpy(float), wide.to_numpy(), elevation.to_numpy()


def spitschan(wavelengths):
    """Spitschan et al.'s (2016) records on the grid (from 360 nm), and the sun's elevation at each, degrees."""
    wl = np.asarray(wavelengths, float)
    if wl[0] < SPITSCHAN_FROM_NM:
        raise ValueError(f"Spitschan et al.'s spectra are compared from {SPITSCHAN_FROM_NM:g} nm")
    grid, records, elevation = _spitschan()
    return _on_grid(grid, records, wl), elevation


def clear_like(records, wavelengths, reference, tolerance):
    """Which records (n, k) are within ``tolerance`` (a fraction) of ``reference``'s irradiance at 550 nm."""
    wl = np.asarray(wavelengths, float)
    k = int(np.clip(np.searchsorted(wl, 550.0) - 1, 0, len(wl) - 2))
    u = (550.0 - wl[k]) / (wl[k + 1] - wl[k])
    measured = (1.0 - u) * np.atleast_2d(records)[:, k] + u * np.atleast_2d(records)[:, k + 1]
    return np.abs(measured / np.interp(550.0, wl, reference) - 1.0) <= tolerance


def uv_ratios(wavelengths, irradiance, sensitivities):
    """UV/VIS photon ratio and UV/G quantum-catch ratio of spectra (n, k) on a uniform grid.

    Photons are counted as irradiance × wavelength; UV is the grid below
    400 nm, visible 400–700 nm. ``sensitivities`` (k, 3) are the UV, blue
    and green receptors' on the grid. Returns two arrays of shape (n,).
    """
    wl = np.asarray(wavelengths, float)
    photons = np.atleast_2d(irradiance) * wl
    uv = photons[:, wl < 400.0].sum(1)
    vis = photons[:, (wl >= 400.0) & (wl <= 700.0)].sum(1)
    catch = photons @ sensitivities
    return uv / vis, catch[:, 0] / catch[:, 2]


#: How near a record's 550 nm irradiance must be to the clear sky's (Granada), and
#: its sun's elevation, degrees, to the sky's (Spitschan, whose clear-like records are fewer).
GRANADA_TOLERANCE, SPITSCHAN_TOLERANCE, SPITSCHAN_ELEVATION_DEG = 0.10, 0.20, 5.0


def measured_ranges(wavelengths, reference, elevation_deg, sensitivities, percentiles=(10, 50, 90)):
    """The measured records like ``reference`` (a clear sky's global irradiance), and their ratios' percentiles.

    Granada's records are taken within :data:`GRANADA_TOLERANCE` of the
    reference's irradiance at 550 nm; Spitschan's also with the sun within
    :data:`SPITSCHAN_ELEVATION_DEG` of ``elevation_deg``, on the grid from
    360 nm. ``sensitivities`` (k, 3) are on ``wavelengths``.

    Returns
    -------
    dict
        ``{"granada": {...}, "spitschan": {...}}``, each with ``n`` records and
        ``uv_vis``, ``uv_g`` percentiles (array of len(percentiles)), and the
        reference's own ``model_uv_vis``, ``model_uv_g`` on the same grid.
    """
    wl = np.asarray(wavelengths, float)
    out = {}
    records = granada(wl)
    chosen = clear_like(records, wl, reference, GRANADA_TOLERANCE)
    out["granada"] = _summary(wl, records[chosen], reference, sensitivities, percentiles)
    late = wl >= SPITSCHAN_FROM_NM
    records, elevation = spitschan(wl[late])
    chosen = (np.abs(elevation - elevation_deg) <= SPITSCHAN_ELEVATION_DEG) & clear_like(
        records, wl[late], reference[late], SPITSCHAN_TOLERANCE)
    out["spitschan"] = _summary(wl[late], records[chosen], reference[late], sensitivities[late], percentiles)
    return out


def _summary(wl, records, reference, sensitivities, percentiles):
    model = uv_ratios(wl, reference, sensitivities)
    result = {"n": len(records), "model_uv_vis": float(model[0][0]), "model_uv_g": float(model[1][0])}
    if len(records):
        uv_vis, uv_g = uv_ratios(wl, records, sensitivities)
        result.update(uv_vis=np.percentile(uv_vis, percentiles), uv_g=np.percentile(uv_g, percentiles))
    return result


def record(dataset, index, wavelengths, source="daylight", field="measured_daylight"):
    """One measured record's global horizontal irradiance on the grid, W m⁻² nm⁻¹.

    ``dataset`` is ``granada`` (index 0–2599) or ``spitschan`` (0–6390, from
    360 nm, so the grid must start there too).
    """
    if dataset == "granada":
        grid, records = _granada()
    elif dataset == "spitschan":
        grid, records, _ = _spitschan()
        keep = grid >= SPITSCHAN_FROM_NM
        grid, records = grid[keep], records[:, keep]
    else:
        raise InputError(source, field, f"unknown measured daylight {dataset!r}; use granada or spitschan")
    if not 0 <= index < len(records):
        raise InputError(source, f"{field}.{dataset}", f"no record {index}: there are {len(records)}, from 0")
    return _on_grid(grid, records[index], wavelengths, source, f"{field}.{dataset}")[0]
