"""Receptor sets: a species' photoreceptor classes, their curves, noise, colour spaces and display.

What differs between species in colour vision is data, not code: each eye
names its receptor set in its ``eye.yaml`` (``receptors: apis_mellifera``),
one the package ships in ``vision/data/receptor_sets/`` or a file of the
user's own beside the eye, checked against
``beeoptics/io/schemas/receptorset.schema.yaml``. A set gives

- its classes, shortest peak first where known, each with its λmax;
- its curves: a measured table (pavo's layout, a column per class) or,
  where none was measured, the A1 template at the measured λmax
  (:mod:`beeoptics.vision.sensitivity`);
- the class of achromatic contrast (the honey bee's green receptor,
  Giurfa et al. 1996);
- the classes colour vision compares, their relative numbers and noise for
  the receptor-noise-limited model (Vorobyev & Osorio 1998), where
  published (the gap stays visible: no RNL distance without them), and the
  bee colour spaces that apply (the triangle and hexagon to trichromats,
  Backhaus's COC to the honey bee for which it was fitted);
- map3's display: which class shows as red, green and blue (Collins §4.4);
  a channel may list several classes, of which an ommatidium has one;
- optionally a mosaic: ommatidial types, each with its own classes, spread
  at random in their published shares (a fly's pale and yellow ommatidia;
  :func:`ommatidium_types`); a receptor's catches of the classes its type
  lacks are NaN;
- optionally the light-adapted overall sensitivity (von Helversen 1972, the
  honey bee) and the class whose microvilli analyse polarisation in the
  dorsal rim;
- optionally the rule by which the species detects a target (the smallest
  visual angles and the contrasts they need; :mod:`beeoptics.vision.detection`).

A config's ``colour.sensitivities`` chooses between each set's own curves
(``species``), the template at each set's λmax (``template``) or one CSV
of curves for every eye (a path): :func:`curves`.

References
----------
Giurfa M, Vorobyev M, Kevan P, Menzel R (1996) Detection of coloured
stimuli by honeybees: minimum visual angles and receptor specific
contrasts. J Comp Physiol A 178:699–709.
Vorobyev M, Osorio D (1998) Receptor noise as a determinant of colour
thresholds. Proc R Soc B 265:351–358.
"""

from pathlib import Path
from typing import NamedTuple

import numpy as np

from beeoptics.io.errors import InputError
from beeoptics.io.validation import config_default, load_yaml, validate
from beeoptics.vision.sensitivity import (measured_sensitivities, overall_sensitivity, overall_weights,
                                          receptor_sensitivities)

#: The receptor sets the package ships, by name.
SETS_DIR = Path(__file__).parent / "data" / "receptor_sets"
#: The set of eyes that name none: every eye of the package's first release was a honey bee's.
DEFAULT_SET = "apis_mellifera"
#: ``colour.sensitivities``: each set's own curves, or the A1 template at each set's λmax.
SPECIES, TEMPLATE = "species", "template"
#: The receptor curves of every door that is not told otherwise: the config schema's ``colour.sensitivities``.
DEFAULT_CURVES = config_default("colour.sensitivities")
#: The display channels of map3, in RGB order.
DISPLAY = ("red", "green", "blue")
#: The seed of a mosaic's draw: a fixed one, so that an eye's ommatidia keep their types in every
#: scene and run, as an animal's do (the config's seed draws the rays, not the animal).
MOSAIC_SEED = 20060309
#: How far a mosaic's shares may sum from one (they are published as rounded percentages).
SHARE_TOLERANCE = 1e-6


class ReceptorSet(NamedTuple):
    """A species' receptor classes (see the module notes); arrays are per class unless stated.

    ``curves_file`` is None where the set's curves are the template;
    ``chromatic`` (indices into ``classes``) are the classes colour vision
    compares, with their relative numbers ``densities`` and noise ``weber``
    (Weber fractions, None where not published); ``display`` the indices
    shown in each of red, green and blue (one or, with a mosaic, several
    each); ``overall`` None or (peaks_nm, ratio); ``mosaic`` None or a tuple
    of (type name, class indices, share); ``detection`` None or the checked
    ``detection`` section, each criterion with its ``regions`` (:class:`Regions`).
    """

    name: str
    species: str
    path: Path
    classes: tuple
    lambda_max_nm: np.ndarray
    curves_file: Path | None
    curves_source: str
    achromatic: int
    chromatic: np.ndarray
    densities: np.ndarray | None
    weber: np.ndarray | None
    spaces: tuple
    display: tuple
    overall: tuple | None
    polarisation: int | None
    mosaic: tuple | None
    detection: dict | None
    document: dict

    @property
    def trichromat(self):
        return len(self.chromatic) == 3


class Regions(NamedTuple):
    """A detection criterion's smallest visual angle by eye region, arrays per region from ventral to dorsal:
    ``upper_deg`` each region's highest elevation of the target in the head frame (a band includes its
    upper bound), ``angle_deg`` its smallest visual angle and ``se_deg`` that angle's standard error
    (0 where none is published), ``names``. A criterion with one angle has one region, "all"."""

    upper_deg: np.ndarray
    angle_deg: np.ndarray
    se_deg: np.ndarray
    names: tuple


def set_file(spec, base=None):
    """The file of a receptor set named in an eye.yaml: a shipped set's name, or a path relative to ``base``."""
    if (SETS_DIR / f"{spec}.yaml").is_file():
        return SETS_DIR / f"{spec}.yaml"
    return (Path(base) / spec) if base is not None else Path(spec)


def load_receptor_set(spec=DEFAULT_SET, base=None, source=None, field="receptors"):
    """Read and check a receptor set.

    Parameters
    ----------
    spec : str
        A shipped set's name (a file of :data:`SETS_DIR`) or the path of a set file.
    base : path, optional
        Where a relative path is taken from (the eye's folder).
    source : path, optional
        The file that names the set, for the error if it does not exist.

    Raises
    ------
    InputError
        If the set does not exist, breaks its schema, names a class it does
        not have, or its curves file is missing.
    """
    path = set_file(spec, base)
    if not path.is_file():
        shipped = sorted(p.stem for p in SETS_DIR.glob("*.yaml"))
        raise InputError(source or path, field, f"no receptor set {spec!r}: not one the package ships "
                         f"({', '.join(shipped)}) and no file {path}")
    doc = validate(load_yaml(path), "receptorset", path)
    classes = tuple(c["name"] for c in doc["classes"])

    def index(name, field):
        if name not in classes:
            raise InputError(path, field, f"names class {name!r}; the set's classes are {', '.join(classes)}")
        return classes.index(name)

    colour = doc["colour"]
    chromatic = np.array([index(c, f"colour.classes.{i}") for i, c in enumerate(colour["classes"])])
    noise = colour.get("noise")
    weber = densities = None
    if noise is not None:
        if "densities" in noise:
            densities = np.asarray(noise["densities"], float)
        if "weber" in noise:
            weber = np.asarray(noise["weber"], float)
        else:
            # One Weber fraction measured for a reference class, pooled by the classes' numbers.
            ref = list(colour["classes"]).index(noise["reference"]) if noise["reference"] in colour["classes"] else None
            if ref is None:
                raise InputError(path, "colour.noise.reference", f"{noise['reference']!r} is not one of "
                                 f"colour.classes ({', '.join(colour['classes'])})")
            weber = noise["weber_fraction"] * np.sqrt(densities[ref] / densities)
        for name, values in (("weber", weber), ("densities", densities)):
            if values is not None and len(values) != len(chromatic):
                raise InputError(path, f"colour.noise.{name}", f"gives {len(values)} values for "
                                 f"{len(chromatic)} classes ({', '.join(colour['classes'])})")
    spaces = tuple(colour["spaces"])
    if spaces and len(chromatic) != 3:
        raise InputError(path, "colour.spaces", "the triangle, hexagon and COC are spaces of trichromats; "
                         f"this set's colour vision has {len(chromatic)} classes")
    lam = np.array([c.get("lambda_max_nm", np.nan) for c in doc["classes"]], float)
    # Two classes at one peak are one class twice: their templates are the same curve (to the 1 nm λmax is given to).
    same = np.abs(lam[:, None] - lam[None, :]) < 1.0
    twice = np.argwhere(np.triu(same, 1))
    if len(twice):
        i, j = twice[0]
        raise InputError(path, f"classes.{j}.lambda_max_nm", f"{classes[j]} peaks at {lam[j]:g} nm, as "
                         f"{classes[i]} does: two classes need two peaks")
    curves = doc["curves"]
    curves_file = None
    if curves.get("file"):
        curves_file = (SETS_DIR.parent if path.parent == SETS_DIR else path.parent) / curves["file"]
        if not curves_file.is_file():
            raise InputError(path, "curves.file", f"no file {curves_file}")
    elif np.isnan(lam).any():
        raise InputError(path, "classes", "without a curves file every class needs its lambda_max_nm (the A1 "
                         "template is drawn at it)")
    overall = doc.get("overall_sensitivity")
    display = []
    for c in DISPLAY:
        names = doc["display"][c] if isinstance(doc["display"][c], list) else [doc["display"][c]]
        display.append(tuple(index(n, f"display.{c}") for n in names))
    return ReceptorSet(
        name=doc["name"], species=doc["species"], path=path, classes=classes, lambda_max_nm=lam,
        curves_file=curves_file, curves_source=curves["source"],
        achromatic=index(doc["achromatic"]["class"], "achromatic.class"), chromatic=chromatic,
        densities=densities, weber=weber, spaces=spaces,
        display=tuple(display),
        overall=None if overall is None else (tuple(overall["peaks_nm"]), tuple(overall["ratio"])),
        polarisation=None if "polarisation" not in doc else index(doc["polarisation"]["class"], "polarisation.class"),
        mosaic=_mosaic(doc.get("mosaic"), index, path),
        detection=_detection(doc.get("detection"), weber, spaces, doc["achromatic"]["class"], colour["classes"], path),
        document=doc,
    )


def _detection(spec, weber, spaces, achromatic, colour_classes, path):
    """A set's detection rule, checked: each criterion's contrast must be one the set can measure, and its
    smallest visual angle given once or by regions that cover every elevation. Each criterion comes back
    with its angles as a region table (:func:`_regions`), one region for an angle given once."""
    if spec is None:
        return None
    rule = dict(spec)
    for criterion in ("achromatic", "chromatic"):
        rule[criterion] = {**spec[criterion], "regions": _regions(spec[criterion], f"detection.{criterion}", path)}
        measure = spec[criterion]["contrast"]["measure"]
        field = f"detection.{criterion}.contrast.measure"
        if measure in ("rnl", "achromatic_rnl") and weber is None:
            raise InputError(path, field, f"{measure} needs the receptors' noise (colour.noise), which this set "
                             "does not give")
        if measure == "achromatic_rnl" and achromatic not in colour_classes:
            raise InputError(path, field, f"achromatic_rnl needs the achromatic class {achromatic!r} among "
                             "colour.classes, whose noise it takes")
        if measure == "hexagon" and "hexagon" not in spaces:
            raise InputError(path, field, "hexagon needs the hexagon among colour.spaces")
    return rule


def _regions(criterion, field, path):
    """A criterion's smallest visual angles as :class:`Regions`, ordered from ventral to dorsal."""
    if ("regions" in criterion) == ("min_visual_angle_deg" in criterion):
        raise InputError(path, field, "give the smallest visual angle once (min_visual_angle_deg) or by "
                         "regions, one of the two")
    if "regions" not in criterion:
        return Regions(np.array([90.0]), np.array([criterion["min_visual_angle_deg"]]),
                       np.array([criterion.get("min_visual_angle_se_deg", 0.0)]), ("all",))
    rows = sorted(criterion["regions"], key=lambda r: r["elevation_deg"][0])
    bounds = np.array([r["elevation_deg"] for r in rows], float)
    # The bands must run from -90 to 90, each starting where the one below it ends.
    if bounds[0, 0] != -90.0 or bounds[-1, 1] != 90.0 or (bounds[1:, 0] != bounds[:-1, 1]).any() or \
            (bounds[:, 1] <= bounds[:, 0]).any():
        raise InputError(path, f"{field}.regions", "the regions' elevation_deg bands must cover -90 to 90, "
                         "each starting where the one below it ends")
    return Regions(bounds[:, 1], np.array([r["min_visual_angle_deg"] for r in rows], float),
                   np.array([r["min_visual_angle_se_deg"] for r in rows], float), tuple(r["name"] for r in rows))


def _mosaic(spec, index, path):
    if spec is None:
        return None
    types = tuple((t["name"], tuple(index(c, f"mosaic.types.{i}.classes") for c in t["classes"]), t["share"])
                  for i, t in enumerate(spec["types"]))
    total = sum(share for *_, share in types)
    if abs(total - 1.0) > SHARE_TOLERANCE:
        raise InputError(path, "mosaic.types", f"the types' shares sum to {total:g}, not 1")
    named = [k for _, classes, _ in types for k in classes]
    if len(named) != len(set(named)):
        raise InputError(path, "mosaic.types", "a class belongs to two types; each class is of one type, "
                         "or of every ommatidium (left out of the types)")
    return types


def ommatidium_types(receptor_set, count):
    """Each of ``count`` receptors' ommatidial type (indices into ``receptor_set.mosaic``), or None without a mosaic.

    Drawn independently for each receptor in its share, as the fly's pale and
    yellow ommatidia are spread at random (Wernet et al. 2006), from
    :data:`MOSAIC_SEED`, so that receptor ``k`` of a table has the same type in
    every run.
    """
    if receptor_set.mosaic is None:
        return None
    shares = np.cumsum([share for *_, share in receptor_set.mosaic])
    draw = np.random.default_rng(MOSAIC_SEED).random(count)
    return np.minimum(np.searchsorted(shares / shares[-1], draw, side="right"), len(shares) - 1)


def ommatidium_names(receptor_set, types):
    """The name of each receptor's ommatidial type (``types`` from :func:`ommatidium_types`), as the tables write it."""
    return np.array([name for name, *_ in receptor_set.mosaic])[types]


def lacking(receptor_set, types):
    """(receptors, classes) mask of the classes each receptor's ommatidium lacks (none without a mosaic)."""
    mask = np.zeros((0 if types is None else len(types), len(receptor_set.classes)), bool)
    if types is None:
        return mask
    for k, (_, classes, _) in enumerate(receptor_set.mosaic):
        others = [c for j, (_, cs, _) in enumerate(receptor_set.mosaic) if j != k for c in cs]
        mask[np.ix_(types == k, others)] = True
    return mask


def receptor_set_of(eye_yaml):
    """The receptor set an eye's ``eye.yaml`` names (its ``receptors``), the file checked against its schema."""
    path = Path(eye_yaml)
    doc = validate(load_yaml(path), "eye", path)
    return load_receptor_set(doc["receptors"], base=path.parent, source=path)


def curves(receptor_set, wavelengths, setting=DEFAULT_CURVES):
    """The set's receptor curves on a grid, (n_wavelengths, classes), each of area 1 nm (pavo's on its 1-nm grid).

    ``setting`` is :data:`SPECIES` (the set's measured curves, or the
    template where it has none), :data:`TEMPLATE` (the A1 template at the
    set's λmax) or the path of a CSV in pavo's layout with a column per class.
    """
    lam = None if np.isnan(receptor_set.lambda_max_nm).any() else receptor_set.lambda_max_nm
    if setting == TEMPLATE or (setting == SPECIES and receptor_set.curves_file is None):
        if lam is None:
            raise InputError(receptor_set.path, "classes", "the template needs every class's lambda_max_nm; "
                             "this set has measured curves only")
        return receptor_sensitivities(wavelengths, lam)
    path = receptor_set.curves_file if setting == SPECIES else setting
    return measured_sensitivities(path, wavelengths, receptor_set.classes, lam)


def peaks_nm(receptor_set):
    """Each class's peak wavelength, nm: its λmax, or where none is given the peak of its measured curve."""
    lam = receptor_set.lambda_max_nm
    if np.isnan(lam).any():
        # The curves' 1-nm grid (pavo's), over the range every measured set here covers.
        grid = np.arange(300.0, 701.0)
        measured = measured_sensitivities(receptor_set.curves_file, grid, receptor_set.classes)
        lam = np.where(np.isnan(lam), grid[np.argmax(measured, axis=0)], lam)
    return lam


def describe(receptor_set, setting=DEFAULT_CURVES):
    """A receptor-curve setting in words, for figures."""
    if setting == TEMPLATE or (setting == SPECIES and receptor_set.curves_file is None):
        peaks = "/".join(f"{v:g}" for v in receptor_set.lambda_max_nm)
        return f"{receptor_set.species}: Govardovskii A1 template, λmax {peaks} nm"
    if setting == SPECIES:
        return f"{receptor_set.species}: measured, {receptor_set.curves_source}"
    return f"{receptor_set.species}: measured, {Path(setting).name}"


def overall(receptor_set, wavelengths, sensitivities):
    """The set's overall spectral sensitivity on the grid (largest value one), or None if it has none."""
    if receptor_set.overall is None:
        return None
    return overall_sensitivity(wavelengths, sensitivities, *receptor_set.overall)


def brightness_weights(receptor_set, wavelengths, sensitivities):
    """The weights (classes,) of the receptors' catches in the brightness, summing to one, or None if the set
    has no overall sensitivity (:func:`beeoptics.vision.sensitivity.overall_weights`)."""
    if receptor_set.overall is None:
        return None
    return overall_weights(wavelengths, sensitivities, *receptor_set.overall)
