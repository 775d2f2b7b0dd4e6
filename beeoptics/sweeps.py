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


def trace_settings(trace, chosen):
    """The config's ``trace`` section with a variant's sample count."""
    return {**trace, **{k: v for k, v in chosen.items() if k == "samples_per_receptor"}}


def light(chosen):
    """Overrides of a scene's ``light`` section for a variant."""
    return {k: v for k, v in chosen.items() if k == "sun_elevation_deg"}
