"""Materials: spectral reflectance, an optional glossy lobe, an optional emission.

A spectrum in a scene file is one of:

``0.5`` or ``{constant: 0.5}``
    Flat.
``{csv: {file: spectra.csv, column: name}}``
    A column of a CSV in pavo's layout (see :mod:`beeoptics.spectra`).
``{fred: {data_id: 1234}}`` or ``{fred: {genus: …, species: …, part: …}}``
    A measured flower or leaf spectrum from FReD (:mod:`beeoptics.light.fred`);
    with ``median: true``, the median of every spectrum the fields match
    (``{fred: {part: leaf upper side, median: true}}``: FReD's typical leaf).
``{sigmoid: {low: …, high: …, edge_nm: …, width_nm: …}}``
    A logistic step from ``low`` to ``high`` centred on ``edge_nm``: the
    shape of most flower spectra, which Chittka & Menzel (1992) describe by
    the wavelength of their steep rise (their "marker points").
``{gaussian: {base: …, peak: …, centre_nm: …, width_nm: …}}``
    A band of reflectance (or emission) on a flat base, width the
    standard deviation.
``{cie_d: 6504}``
    The CIE D-series illuminant of that correlated colour temperature,
    1 at 560 nm (for emitters and skies).
``{ground: loam}``
    The measured albedo of a kind of ground, from 290 nm (Feister & Grewe
    1995; the package's ``light/data/ground_albedo_feister_grewe1995.csv``):
    loam, sand, grass, lawn, stubble, beet, oat, rye, concrete_dry,
    concrete_wet or snow.

``{measured_daylight: {granada: 1234}}`` or ``{measured_daylight: {spitschan: 42}}``
    The radiance of a uniform sky over the upper hemisphere that gives one
    measured record's global irradiance (E/π): for ``light: {sky: uniform,
    hemisphere: true, radiance: …}`` (:mod:`beeoptics.sky.daylightrecords`;
    Spitschan et al.'s records start at 360 nm, so the grid must too).

A material is ``{reflectance: <spectrum>, coating: {roughness: α,
refractive_index: η}, emission: <spectrum>}`` or, in place of ``coating``,
``gloss: {specular: ks, exponent: n, refractive_index: η}``; only
``reflectance`` is required. The BRDF is Lambertian with the spectral
reflectance, plus one of two surface reflections:

- ``coating``: a rough dielectric interface over the Lambertian base
  (:mod:`beeoptics.light.coating`; its specular lobe Mitsuba 3's
  ``roughplastic``): GGX microfacets of roughness α (0 < α ≤ 1), whose
  reflection follows Fresnel's equations for η in strength and in
  polarisation, the light it does not reflect passed to the base and back
  (checked against pbrt-v4's coated diffuse, the layered model's random
  walk). What
  water, a waxy cuticle or a glossy petal is. A spectrum measured from
  the whole surface (a spectrometer's reflectance of a leaf holds its
  cuticle's reflection) says so, ``in_reflectance: true``: the base's
  albedo through the coating is then what the coating leaves of it at
  normal incidence, ρ' = (ρ − E(1)) / (1 − E(1)), E the coating's
  directional albedo (the coupling's albedo at incidence μ,
  E(μ) + ρ' (1 − E(μ)), inverted), so that the coated surface reflects
  the measured spectrum there and its reflection is not counted twice.
  Otherwise ρ is the base's own, and ρ' what it returns through the
  coating's internal reflections
  (:func:`beeoptics.light.coating.base_albedo`).
- ``gloss``: a normalised Phong lobe (Lafortune & Willems 1994) of
  spectrally flat albedo ``ks``, whatever the angle: an empirical sheen,
  kept for the scenes that use it. η sets only how it polarises (Fresnel's
  matrix divided by its first element; see :mod:`beeoptics.light.mueller`),
  not how strong it is.

η is :data:`CUTICLE_REFRACTIVE_INDEX` unless given.

References
----------
Chittka L, Menzel R (1992) The evolutionary adaptation of flower colours
and the insect pollinators' colour vision. J Comp Physiol A 171:171–181.
Lafortune EP, Willems YD (1994) Using the modified Phong reflectance model
for physically based rendering. Report CW197, KU Leuven.
Féret J-B, François C, Asner GP, et al. (2008) PROSPECT-4 and 5: advances in
the leaf optical properties model separating photosynthetic pigments.
Remote Sens Environ 112:3030–3043.
Daimon M, Masumura A (2007) Measurement of the refractive index of
distilled water from the near-infrared region to the ultraviolet region.
Appl Opt 46:3811–3820.
Feister U, Grewe R (1995) Spectral albedo measurements in the UV and
visible region over different types of surfaces. Photochem Photobiol
62:736–744.
"""

import difflib
from pathlib import Path

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.light import fred
from beeoptics.light.coating import albedo_table, base_albedo, through
from beeoptics.sky import daylightrecords
from beeoptics.sky.dome import cie_daylight
from beeoptics.spectra import read_pavo_csv

#: A glossy surface's refractive index unless its material gives one: a leaf's surface at 550 nm in
#: PROSPECT (Féret et al. 2008; 1.4739 in its table of optical constants, 1.51–1.44 over 400–700 nm).
#: Water's is 1.3334 at 587.6 nm (Daimon & Masumura 2007).
CUTICLE_REFRACTIVE_INDEX = 1.4739
#: Measured ground albedos (Feister & Grewe 1995), in pavo's layout; source in the folder's README.
GROUND_ALBEDO_FILE = Path(__file__).parent / "data" / "ground_albedo_feister_grewe1995.csv"


def ground_albedo(name, wavelengths, source, field):
    """The albedo Feister & Grewe (1995) measured for ground ``name`` (loam, sand, grass, ...), on the grid."""
    names, _, values = read_pavo_csv(GROUND_ALBEDO_FILE, wavelengths)
    if name not in names:
        close = difflib.get_close_matches(str(name), names, n=1)
        raise InputError(source, field, f"no measured ground {name!r}; "
                         + (f"did you mean {close[0]!r}?" if close else f"there are {', '.join(names)}"))
    return values[:, names.index(name)]


def spectrum(spec, wavelengths, base_dir, source, field):
    """A spectrum spec (see the module docstring) evaluated on the grid."""
    wl = np.asarray(wavelengths, float)
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        return np.full(len(wl), float(spec))
    if not isinstance(spec, dict) or len(spec) != 1:
        raise InputError(source, field, f"a spectrum is a number or a mapping with one key, not {spec!r}")
    (kind, args), = spec.items()
    where = f"{field}.{kind}"
    try:
        if kind == "constant":
            return np.full(len(wl), float(args))
        if kind == "csv":
            names, _, values = read_pavo_csv(Path(base_dir) / args["file"], wl)
            if args["column"] not in names:
                raise InputError(Path(base_dir) / args["file"], args["column"], "no such column")
            return values[:, names.index(args["column"])]
        if kind == "fred":
            # median says how to combine the records the fields match (the schema fills in false); not a field.
            query = {k: v for k, v in args.items() if k != "median"}
            if args.get("median"):
                return fred.median_reflectance(wl, source, where, **query)
            data_id = query["data_id"] if "data_id" in query else fred.find(source, where, **query)
            return fred.reflectance(int(data_id), wl, source, where)
        if kind == "sigmoid":
            return args["low"] + (args["high"] - args["low"]) / (
                1.0 + np.exp(-(wl - args["edge_nm"]) / args["width_nm"]))
        if kind == "gaussian":
            return args["base"] + (args["peak"] - args["base"]) * np.exp(
                -0.5 * ((wl - args["centre_nm"]) / args["width_nm"]) ** 2)
        if kind == "cie_d":
            return cie_daylight(wl, float(args))
        if kind == "ground":
            return ground_albedo(args, wl, source, where)
        if kind == "measured_daylight":
            (dataset, index), = args.items()
            # The radiance of a uniform sky over the upper hemisphere that gives the record's irradiance.
            return daylightrecords.record(dataset, int(index), wl, source, where) / np.pi
    except (KeyError, TypeError) as e:
        raise InputError(source, where, f"missing or malformed parameter {e}") from None
    raise InputError(source, field, f"unknown spectrum kind {kind!r}; use constant, csv, fred, sigmoid, gaussian, "
                     "cie_d, ground or measured_daylight")


def material(spec, wavelengths, base_dir, source, name):
    """A material's reflectance, emission and surface reflection, checked.

    Returns
    -------
    dict
        ``reflectance`` and ``emission`` on the grid, ``specular`` (albedo
        of the Phong lobe), ``exponent`` (its Phong exponent),
        ``roughness`` (the coating's α; 0 without a coating) and
        ``refractive_index`` (the coating's or the lobe's η;
        :data:`CUTICLE_REFRACTIVE_INDEX` unless given).
    """
    field = f"materials.{name}"
    if not isinstance(spec, dict) or "reflectance" not in spec:
        raise InputError(source, field, "a material needs a reflectance")
    unknown = set(spec) - {"reflectance", "gloss", "coating", "emission"}
    if unknown:
        raise InputError(source, f"{field}.{sorted(unknown)[0]}", "unknown material property")
    if "gloss" in spec and "coating" in spec:
        raise InputError(source, f"{field}.coating", "a material has a coating or a gloss, not both")
    rho = spectrum(spec["reflectance"], wavelengths, base_dir, source, f"{field}.reflectance")
    gloss = spec.get("gloss", {"specular": 0.0, "exponent": 1.0})
    ks = float(gloss.get("specular", 0.0))
    if np.isnan(rho).any() or rho.min() < 0.0 or rho.max() + ks > 1.0:
        raise InputError(source, f"{field}.reflectance",
                         "reflectance plus specular albedo must lie in [0, 1] at every wavelength")
    emission = spectrum(spec.get("emission", 0.0), wavelengths, base_dir, source, f"{field}.emission")
    if np.isnan(emission).any() or emission.min() < 0.0:
        raise InputError(source, f"{field}.emission", "emission must be non-negative")
    surface = "coating" if "coating" in spec else "gloss"
    coat = spec.get("coating", {})
    if not isinstance(coat, dict) or set(coat) - {"roughness", "refractive_index", "in_reflectance"}:
        raise InputError(source, f"{field}.coating", "a coating is {roughness: α, refractive_index: η, "
                         "in_reflectance: true or false}")
    alpha = coat.get("roughness", 0.0) if "coating" in spec else 0.0
    if "coating" in spec and (not isinstance(alpha, (int, float)) or not 0.0 < alpha <= 1.0):
        raise InputError(source, f"{field}.coating.roughness", "a coating's roughness α must be a number in (0, 1]")
    n = (coat if "coating" in spec else gloss).get("refractive_index", CUTICLE_REFRACTIVE_INDEX)
    if not isinstance(n, (int, float)) or not 1.0 <= n <= 4.0:
        raise InputError(source, f"{field}.{surface}.refractive_index", "a refractive index must be a number in [1, 4]")
    if coat.get("in_reflectance", False):
        # What the coating reflects at normal incidence, taken out of the measured reflectance: the rest is ρ'.
        reflected = 1.0 - through(1.0, albedo_table(alpha, n))
        rho = np.maximum(rho - reflected, 0.0) / (1.0 - reflected)
    elif "coating" in spec:
        rho = base_albedo(rho, alpha, n)
    return {"reflectance": rho, "emission": emission, "specular": ks,
            "exponent": float(gloss.get("exponent", 1.0)), "roughness": float(alpha), "refractive_index": float(n)}
