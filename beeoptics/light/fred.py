"""The Floral Reflectance Database (FReD), as shipped in the ``dreye`` package.

FReD (Arnold et al. 2010) holds some 2,200 reflectance spectra of flowers
and leaves measured from 300 nm, mostly by Chittka and colleagues. The
``dreye`` package (MIT licence) ships it as a Feather file; it is read
here directly, without importing ``dreye``, whose own imports are heavy.
Reflectance is a fraction of a white standard. As in dreye, the database's
duplicate rows are dropped and missing values read as zero; values are
clipped to [0, 1], since a few raw readings fall just outside it.

References
----------
Arnold SEJ, Faruq S, Savolainen V, McOwan PW, Chittka L (2010) FReD: the
floral reflectance database — a web portal for analyses of flower colour.
PLoS ONE 5:e14287.
"""

import importlib.util
from functools import cache
from pathlib import Path

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.spectra import resample

#: Metadata columns of the database, and the names this package gives them.
FIELDS = {"data_id": "data_id", "genus": "flower_genus", "species": "flower_species",
          "family": "flower_family", "part": "part_of_flower", "human_colour": "human_color",
          "bee_colour": "bee_color", "country": "country"}


def database_path():
    """Path of FReD's Feather file inside the installed ``dreye`` package."""
    spec = importlib.util.find_spec("dreye")
    if spec is None or not spec.submodule_search_locations:
        raise InputError("dreye", "", "the dreye package is not installed (pip install --no-deps dreye)")
    return Path(spec.submodule_search_locations[0]) / "datasets" / "flowers.feather"


SPECTRUM = ["data_id", "wavelengths", "reflectance"]


@cache
def _spectra():
    """The spectral columns of every row: data_id, wavelength (nm), reflectance."""
    import pandas as pd  # imported where used: only scenes with FReD's spectra read the database

    return pd.read_feather(database_path(), columns=SPECTRUM)


@cache
def _metadata():
    import pandas as pd  # as in _spectra
    import pyarrow as pa

    # Only the metadata columns: the whole file, spectra included, takes a second to read.
    names = pa.ipc.open_file(database_path()).schema.names
    return pd.read_feather(database_path(), columns=[c for c in names if c not in SPECTRUM[1:]]).drop_duplicates(
        "data_id")


def catalogue():
    """One row of metadata per spectrum (a pandas DataFrame)."""
    return _metadata().copy()


def matching(source="FReD", field="fred", **query):
    """The ``data_id`` of every spectrum matching ``query`` (keys of :data:`FIELDS`, case ignored)."""
    rows = _metadata()
    for key, value in query.items():
        if key not in FIELDS:
            raise InputError(source, f"{field}.{key}", f"unknown FReD field; use one of {sorted(FIELDS)}")
        rows = rows[rows[FIELDS[key]].astype(str).str.lower() == str(value).lower()]
    return [int(i) for i in rows["data_id"]]


def find(source="FReD", field="fred", **query):
    """The ``data_id`` of the one spectrum matching ``query`` (keys of :data:`FIELDS`).

    Raises
    ------
    InputError
        If no spectrum or more than one matches.
    """
    ids = matching(source, field, **query)
    if len(ids) != 1:
        raise InputError(source, field, f"{len(ids)} FReD spectra match {query}; give data_id (e.g. {ids[:10]})")
    return ids[0]


def median_reflectance(wavelengths, source="FReD", field="fred", **query):
    """The median, wavelength by wavelength, of every spectrum matching ``query`` that covers the grid.

    FReD's leaves (``part: leaf upper side``: 477 of its 478 cover 300–700 nm) give a
    typical leaf this way, as the meadow's foliage.

    Raises
    ------
    InputError
        If no spectrum that covers the grid matches.
    """
    # Spectra measured on the same wavelengths are resampled together, one call per grid.
    grids = {}
    for data_id in matching(source, field, **query):
        wl, values = _by_id()[data_id]
        grids.setdefault(wl.tobytes(), (wl, []))[1].append(values)
    spectra = []
    for wl, columns in grids.values():
        try:
            spectra.append(resample(wl, np.column_stack(columns), wavelengths, source, field).T)
        except InputError:
            continue
    if not spectra:
        raise InputError(source, field, f"no FReD spectrum matching {query} covers "
                         f"{wavelengths[0]:g}–{wavelengths[-1]:g} nm")
    return np.median(np.clip(np.vstack(spectra), 0.0, 1.0), axis=0)


def reflectance(data_id, wavelengths, source="FReD", field="fred"):
    """One FReD spectrum on the grid, as a fraction in [0, 1]."""
    if data_id not in _by_id():
        raise InputError(source, field, f"no FReD spectrum with data_id {data_id}")
    wl, values = _by_id()[data_id]
    return np.clip(resample(wl, values, wavelengths, source, f"{field} (FReD data_id {data_id})"), 0.0, 1.0)


@cache
def _by_id():
    """Each spectrum's wavelengths and reflectance (missing values 0), by data_id, duplicate rows dropped."""
    df = _spectra().drop_duplicates().sort_values(["data_id", "wavelengths"], kind="stable")
    ids = df["data_id"].to_numpy()
    wl = df["wavelengths"].to_numpy(float)
    values = df["reflectance"].fillna(0.0).to_numpy(float)
    bounds = np.flatnonzero(np.r_[True, ids[1:] != ids[:-1], True])
    return {int(ids[a]): (wl[a:b], values[a:b]) for a, b in zip(bounds[:-1], bounds[1:])}
