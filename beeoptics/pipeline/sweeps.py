"""Parameter sweeps declared in the workflow's config.

A sweep names the eyes and scenes it covers and, for any of the swept
parameters, the values to try; every combination is one variant, traced for
every eye in every scene. Variants are named after their values, so that a
variant's folder says what it holds, e.g. ``drho-2.6_spp-64_sun-20``.

Swept parameters:

``delta_rho_deg``
    Every receptor's acceptance angle Δρ (degrees), replacing the eye's own.
``samples_per_receptor``
    Directions traced per receptor.
``sun_elevation_deg``
    The sun's elevation in the scene's ``light`` section (degrees).
"""

import itertools

import numpy as np

from beeoptics.io.receptortable import read_receptors, write_receptors
from beeoptics.io.table import read_table, write_table

#: Swept parameters and the short names that label variants.
PARAMETERS = {"delta_rho_deg": "drho", "samples_per_receptor": "spp", "sun_elevation_deg": "sun"}


def variants(sweep):
    """Every combination of a sweep's values, by variant name.

    Parameters
    ----------
    sweep : dict
        One entry of the config's ``sweeps``: parameter names to lists of values.

    Returns
    -------
    dict of str to dict
        Variant name to its parameter values; a sweep with no parameters has
        one variant, ``default``.
    """
    swept = [p for p in PARAMETERS if p in sweep]
    out = {}
    for values in itertools.product(*(sweep[p] for p in swept)):
        chosen = dict(zip(swept, values))
        name = "_".join(f"{PARAMETERS[p]}-{v:g}" for p, v in chosen.items()) or "default"
        out[name] = chosen
    return out


def variant_trace(chosen):
    """Overrides of the config's ``trace`` section for a variant: samples it names are traced, fixed."""
    if "samples_per_receptor" not in chosen:
        return {}
    return {"samples_per_receptor": chosen["samples_per_receptor"], "precision": {"target": None}}


def variant_light(chosen):
    """Overrides of a scene's ``light`` section for a variant."""
    return {k: v for k, v in chosen.items() if k == "sun_elevation_deg"}


def with_delta_rho(receptors_csv, outputs, *, delta_rho_deg=None):
    """``outputs["receptors"]``: the receptor table, every receptor's Δρ set to ``delta_rho_deg`` (a copy if None)."""
    table = read_receptors(receptors_csv)
    if delta_rho_deg is not None:
        table = table._replace(delta_rho_deg=np.full(len(table.id), float(delta_rho_deg)))
    write_receptors(outputs["receptors"], table)


#: Columns of responses.csv summarised per sweep variant, eye and scene, besides each receptor class's catch,
#: where the eye's receptor set has them.
SUMMARISED = ("brightness", "hex_r", "rnl_dS")


def sweep_summary(runs, outputs):
    """``outputs["summary"]``: one row per sweep variant, eye and scene, its parameters and responses.

    Parameters
    ----------
    runs : list of dict
        ``variant``, ``eye``, ``scene``, ``responses`` (path), ``classes``
        (the eye's receptor classes) and the variant's parameter values, in
        the order the rows are written.

    The responses are summarised by their mean and their 5th, 50th and 95th
    percentiles over both eyes' receptors; a column an eye's species lacks
    (another species' receptor class, an RNL distance without published
    noise) is empty in its rows.
    """
    rows = []
    for run in runs:
        resp = read_table(run["responses"], numeric=list(run["classes"]), text=["side"])
        row = {k: v for k, v in run.items() if k not in ("responses", "classes")}
        for name in [*run["classes"], *(c for c in SUMMARISED if c in resp)]:
            row[f"{name}_mean"] = np.mean(resp[name])
            row.update({f"{name}_p{p}": np.percentile(resp[name], p) for p in (5, 50, 95)})
        rows.append(row)
    text = ("variant", "eye", "scene")
    keys = list(dict.fromkeys(k for r in rows for k in r))
    write_table(outputs["summary"], {k: [r[k] for r in rows] if k in text else
                                     np.array([r.get(k, np.nan) for r in rows], float) for k in keys})
