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
- optionally the light-adapted overall sensitivity (von Helversen 1972, the
  honey bee) and the class whose microvilli analyse polarisation in the
  dorsal rim.

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
from beeoptics.io.validation import load_yaml, validate
from beeoptics.vision.sensitivity import measured_sensitivities, overall_sensitivity, receptor_sensitivities

#: The receptor sets the package ships, by name.
SETS_DIR = Path(__file__).parent / "data" / "receptor_sets"
#: The set of eyes that name none: every eye of the package's first release was a honey bee's.
DEFAULT_SET = "apis_mellifera"
#: ``colour.sensitivities``: each set's own curves, or the A1 template at each set's λmax.
SPECIES, TEMPLATE = "species", "template"
#: The display channels of map3, in RGB order.
DISPLAY = ("red", "green", "blue")


class ReceptorSet(NamedTuple):
    """A species' receptor classes (see the module notes); arrays are per class unless stated.

    ``curves_file`` is None where the set's curves are the template;
    ``chromatic`` (indices into ``classes``) are the classes colour vision
    compares, with their relative numbers ``densities`` and noise ``weber``
    (Weber fractions, None where not published); ``display`` the indices
    shown as red, green and blue; ``overall`` None or (peaks_nm, ratio).
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
    display: np.ndarray
    overall: tuple | None
    polarisation: int | None
    document: dict

    @property
    def trichromat(self):
        return len(self.chromatic) == 3


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
    return ReceptorSet(
        name=doc["name"], species=doc["species"], path=path, classes=classes, lambda_max_nm=lam,
        curves_file=curves_file, curves_source=curves["source"],
        achromatic=index(doc["achromatic"]["class"], "achromatic.class"), chromatic=chromatic,
        densities=densities, weber=weber, spaces=spaces,
        display=np.array([index(doc["display"][c], f"display.{c}") for c in DISPLAY]),
        overall=None if overall is None else (tuple(overall["peaks_nm"]), tuple(overall["ratio"])),
        polarisation=None if "polarisation" not in doc else index(doc["polarisation"]["class"], "polarisation.class"),
        document=doc,
    )


def receptor_set_of(eye_yaml):
    """The receptor set an eye's ``eye.yaml`` names (its ``receptors``), the file checked against its schema."""
    path = Path(eye_yaml)
    doc = validate(load_yaml(path), "eye", path)
    return load_receptor_set(doc["receptors"], base=path.parent, source=path)


def curves(receptor_set, wavelengths, setting=SPECIES):
    """The set's receptor curves on a grid, (n_wavelengths, classes), each summing to one.

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


def describe(receptor_set, setting=SPECIES):
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
