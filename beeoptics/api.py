"""The library in your hands: an eye, a scene, and a look at the scene through the eye, from Python.

The same stages as the workflow's and the command line's, called with the
configuration's defaults (``beeoptics/io/schemas/config.schema.yaml``), so that
a look gives the numbers ``beeoptics render`` writes for the same eye, scene,
samples, depth and seed. The scene and its Embree scene stay in memory between
looks; an eye described by an ``eye.yaml`` is built once and kept in the cache
(``$BEEOPTICS_CACHE``, as the scene cache is, :mod:`beeoptics.light.scenecache`).

>>> import beeoptics
>>> eye = beeoptics.load_eye("tests/data/eyes/tiny/eye.yaml")          # doctest: +SKIP
>>> scene = beeoptics.load_scene("tests/data/scenes/flower/scene.yaml")  # doctest: +SKIP
>>> view = beeoptics.look(eye, scene, samples=16, depth=1)              # doctest: +SKIP
>>> view.catches.head()                                                 # doctest: +SKIP

A view's colour coordinates are those of :mod:`beeoptics.vision.colourspace`,
whose references cite each model in full: the colour hexagon (Chittka 1992),
the colour-opponent coding space (Backhaus 1991) and the receptor-noise-limited
distance (Vorobyev & Osorio 1998), against a von Kries-adapted background, as
pavo computes them (Maia et al. 2019); its images are Collins's map3 and map2
(§4.4), and its errors those of independent replicates (Owen 1997;
:mod:`beeoptics.light.precision`).

References
----------
Collins S. Reconstructing the visual field of compound eyes. §4.4.
Maia R, Gruson H, Endler JA, White TE (2019) pavo 2: new tools for the
spectral and spatial analysis of colour in R. Methods Ecol Evol 10:1097–1107.
Owen AB (1997) Monte Carlo variance of scrambled net quadrature. SIAM J
Numer Anal 34:1884–1910.
"""

import functools
import hashlib
import inspect
import logging
import numbers
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from beeoptics import __version__
from beeoptics.eye.optics import acceptance_solid_angle
from beeoptics.eye.receptors import read_receptor_file
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import read_receptors, rows_of
from beeoptics.io.validation import (CONFIG_SCHEMA, check_background, config_default, load_yaml, validate,
                                     validate_config)
from beeoptics.images.display import bee_colours
from beeoptics.images.fieldmaps import field_images
from beeoptics.images.retina import retinal_images
from beeoptics.light import scene as scenes
from beeoptics.light.batching import TraceSettings
from beeoptics.light.scenecache import cache_root, code_digest, file_digest
from beeoptics.light.sensors import cone_samples
from beeoptics.pipeline.outputs import channel, retinal_images as retinal_outputs
from beeoptics.raycasting import first_hits
from beeoptics.sky.dome import white_radiance
from beeoptics.spectra import grid
from beeoptics.tracing import (class_catches, cone_catches, human_srgb, render_human, replicate_errors, respond,
                               trace_cones, trace_receptors)
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.receptorset import (DEFAULT_CURVES, DEFAULT_SET, ReceptorSet, curves, lacking, load_receptor_set,
                                          ommatidium_names, ommatidium_types, receptor_set_of)
from beeoptics.vision.uncertainty import noise_forms

log = logging.getLogger("beeoptics")

__all__ = ["Eye", "Scene", "View", "load_eye", "load_scene", "look", "looks", "human_view", "human_srgb", "look_cones",
           "Cones", "catches", "cone_rays"]

#: The package's code that builds an eye: its files are part of a built eye's cache key, so that a change to
#: any builds the eye afresh.
EYE_CODE = ("eye", "io", "pipeline/eyes.py")


def _frame(*args, **kwargs):
    """A pandas DataFrame, pandas imported here: the workflow's jobs import this module and return no
    table, and pandas would add half a second to each of them."""
    import pandas as pd

    return pd.DataFrame(*args, **kwargs)


class Eye:
    """An eye pair: its receptor table and its receptor set.

    Attributes
    ----------
    path : Path
        The file it was read from (an ``eye.yaml``, a receptor table, ``.eye``, ``.ply`` or OCES file).
    table : ReceptorTable
        The receptors (:class:`beeoptics.io.receptortable.ReceptorTable`): positions in mm in the head frame.
    receptor_set : ReceptorSet
        Its receptor classes (UV, B, G for a bee; :mod:`beeoptics.vision.receptorset`).
    eye_file : Path or None
        Its ``eye.yaml``, where it has one (placing it on the head for the retinal images).
    """

    def __init__(self, path, table, receptor_set, eye_file=None):
        self.path, self.table, self.receptor_set, self.eye_file = Path(path), table, receptor_set, eye_file

    @property
    def receptors(self):
        """The receptors as a table, one row each (pandas DataFrame).

        Columns: ``id``, ``side``; ``x``, ``y``, ``z`` (mm) and ``ax``, ``ay``, ``az``
        (a unit vector), the facet's position and optical axis in the head frame
        (x anterior, y left, z dorsal); ``facet_diameter_um`` (µm), ``delta_phi_deg``
        (Δφ, the interommatidial angle, degrees) and ``delta_rho_deg`` (Δρ, the
        acceptance angle's full width at half maximum, degrees); ``dorsal_rim`` and
        ``microvilli_deg`` where the eye has a dorsal rim area; ``ommatidium``, each
        receptor's ommatidial type, where the receptor set has a mosaic; ``classes``,
        the receptor classes of its ommatidium (its set's names, space-separated:
        "UV B G" for a bee's every ommatidium, a fly's pale one "R1_6 R7p R8p").
        """
        columns = self.table.columns()
        types = ommatidium_types(self.receptor_set, len(self.table.id))
        if types is not None:
            columns["ommatidium"] = ommatidium_names(self.receptor_set, types)
        classes = np.array(self.receptor_set.classes)
        if types is None:
            columns["classes"] = np.full(len(self.table.id), " ".join(classes))
        else:
            kinds = np.arange(len(self.receptor_set.mosaic))
            columns["classes"] = np.array([" ".join(classes[~lacks]) for lacks in lacking(self.receptor_set,
                                                                                          kinds)])[types]
        return _frame(columns)

    def __repr__(self):
        return (f"Eye({str(self.path)!r}: {len(self.table.id)} receptors, "
                f"classes {', '.join(self.receptor_set.classes)})")


def load_eye(path, *, receptor_set=None, **options):
    """Load an eye: built from its ``eye.yaml``, or read from receptors in any format ``convert`` reads.

    An ``eye.yaml`` is built as the workflow builds it with the default
    configuration (remeshed, its facets placed and relaxed: some seconds to
    minutes, :func:`beeoptics.pipeline.eyes.build_facets`) the first time,
    and then read from the cache, keyed by the contents of the eye's folder
    and of the code that builds eyes.

    Parameters
    ----------
    path : str or Path
        An ``eye.yaml``, a receptor table (``.csv``), a CompoundRay ``.eye``,
        a ``.ply`` or an OCES glTF (``.gltf``, ``.glb``).
    receptor_set : str or ReceptorSet, optional
        A shipped receptor set's name, a set file or a loaded set; by default the eye's own
        (its ``eye.yaml``'s ``receptors``), or the honey bee's for receptors
        without one.
    **options
        ``convert``'s options for a ``.eye`` file, by their long names with
        underscores (``units="mm"``, ``side="auto"``, ``frame=…``): see
        ``beeoptics convert --help``.

    Returns
    -------
    Eye

    Raises
    ------
    InputError
        Naming the file and the field of bad input.
    """
    path = Path(path)
    eye_file = path if path.suffix.lower() in (".yaml", ".yml") else None
    if eye_file is not None:
        table = read_receptors(_built(eye_file) / "receptors.csv")
    else:
        unknown = set(options) - set(list(inspect.signature(read_receptor_file).parameters)[1:])
        if unknown:
            raise InputError("load_eye", sorted(unknown)[0], "no such option of convert")
        table = read_receptor_file(path, **options)
    if isinstance(receptor_set, ReceptorSet):
        rset = receptor_set
    elif receptor_set is not None:
        rset = load_receptor_set(receptor_set, source="load_eye", field="receptor_set")
    else:
        rset = receptor_set_of(eye_file) if eye_file is not None else load_receptor_set(DEFAULT_SET)
    return Eye(path, table, rset, eye_file)


def _built(eye_yaml):
    """The folder of the cache holding the eye's build (remeshed.ply, receptors.csv, quality.json), built if absent."""
    from beeoptics.eye.optics import AcceptanceModel
    from beeoptics.pipeline.eyes import build_facets, remesh_eye
    from beeoptics.pipeline.outputs import FACET_OUTPUTS

    if not eye_yaml.is_file():
        raise InputError(eye_yaml, "", "no such file")
    # Every file of the eye's folder: its mesh, anchors, ommatidia or cornea, whatever its eye.yaml names.
    eye_files = "".join(f"{p.name} {file_digest(p)}\n" for p in sorted(eye_yaml.parent.iterdir()) if p.is_file())
    h = hashlib.sha256(f"beeoptics {__version__} {eye_yaml.name} code {code_digest(names=EYE_CODE)}\n{eye_files}"
                       .encode())
    folder = cache_root() / "eyes" / h.hexdigest()
    if (folder / "receptors.csv").is_file():
        return folder
    eye = config_default("eye")
    folder.parent.mkdir(parents=True, exist_ok=True)
    log.info("building %s once, into %s", eye_yaml, folder)
    # Built beside its place and renamed into it: a reader never meets half an eye.
    tmp = Path(tempfile.mkdtemp(prefix=".partial-", dir=folder.parent))
    try:
        outputs = {"remeshed": tmp / "remeshed.ply", **{k: tmp / name for k, name in FACET_OUTPUTS.items()}}
        remesh_eye(eye_yaml, outputs, edge_fraction=eye["edge_fraction"])
        build_facets(eye_yaml, outputs["remeshed"], outputs, tolerance_um=eye["tolerance_um"],
                     acceptance=AcceptanceModel.from_config(eye["delta_rho"]))
        try:
            os.rename(tmp, folder)
        except OSError:
            if not (folder / "receptors.csv").is_file():  # not another process's identical build
                raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return folder


class Scene:
    """A scene loaded once: its geometry, materials and light on a spectral grid, and its Embree scene.

    Attributes
    ----------
    path : Path
        Its ``scene.yaml``.
    wavelengths_nm : ndarray (n_wavelengths,)
        The spectral grid, nm.
    scene : beeoptics.light.scene.Scene
        The loaded scene (objects, materials' spectra, sky, sun, the bee's pose).
    light : dict
        The overrides of the scene file's ``light`` section it is lit by (the whole section,
        defaults included: :attr:`lighting`).
    """

    def __init__(self, path, wavelengths_nm, scene, light, rs=None):
        self.path, self.wavelengths_nm, self.scene, self.light = Path(path), wavelengths_nm, scene, light
        self._rs = rs

    def __deepcopy__(self, memo):
        # A scene is never changed in place (with_light makes another) and its Embree scene cannot be copied:
        # a deep copy (gymnasium.make copies an environment's arguments) is the scene itself, as a tuple's is.
        return self

    @functools.cached_property
    def head(self):
        """The scene file's ``eye`` section, checked: the head's own pose, which a look's pose completes. Read
        once, not at every look (a scene file's reading and checking took a fifth of a look of a few samples)."""
        return validate(load_yaml(self.path), "scene", self.path)["eye"]

    @property
    def raycasting(self):
        """Open3D's Embree scene of its objects, built on first use and kept."""
        if self._rs is None:
            self._rs = scenes.raycasting_scene(self.scene)
        return self._rs

    @property
    def materials(self):
        """The materials' names and spectral reflectance (pandas DataFrame: a row per material, a column per
        wavelength, nm; their surfaces' other properties in :attr:`surfaces`)."""
        return _frame(self.scene.reflectance, index=self.scene.material_names, columns=self.wavelengths_nm)

    @property
    def surfaces(self):
        """How each material's surface scatters and emits (pandas DataFrame, a row per material): ``kind``,
        "lambertian", "gloss" (a Phong lobe over the Lambertian base) or "coating" (a rough dielectric over
        it, :mod:`beeoptics.light.coating`); the gloss's ``specular`` (its reflectance) and ``exponent``;
        the coating's ``roughness`` (its GGX α); ``refractive_index`` (η, of the coating or the gloss);
        ``emission_peak`` (the largest of its spectral radiance, W m⁻² sr⁻¹ nm⁻¹; 0 for a surface that
        does not glow). NaN where the kind has no such property (``beeoptics/io/schemas/scene.schema.yaml``,
        ``materials``)."""
        scene = self.scene
        coating, gloss = scene.roughness > 0.0, scene.specular > 0.0
        return _frame({"kind": np.select([coating, gloss], ["coating", "gloss"], "lambertian"),
                       "specular": np.where(gloss, scene.specular, np.nan),
                       "exponent": np.where(gloss, scene.exponent, np.nan),
                       "roughness": np.where(coating, scene.roughness, np.nan),
                       "refractive_index": np.where(coating | gloss, scene.refractive_index, np.nan),
                       "emission_peak": scene.emission.max(axis=1)}, index=scene.material_names)

    @property
    def objects(self):
        """The objects: ``name``, ``vertices``, ``faces`` and ``materials``, the names of the materials its
        faces (or its texture's texels) are of, space-separated (pandas DataFrame, a row per object)."""
        names = np.array(self.scene.material_names)
        objects = self.scene.objects
        return _frame({"name": [o.name for o in objects], "vertices": [len(o.vertices) for o in objects],
                       "faces": [len(o.faces) for o in objects],
                       "materials": [" ".join(names[np.unique(o.texture if o.face_material is None
                                                             else o.face_material)]) for o in objects]})

    @property
    def lighting(self):
        """The light the scene is lit by: its file's ``light`` section with the overrides of :meth:`with_light`
        applied and the schema's defaults filled in (a dict: ``sky``, ``sun``, ``sun_elevation_deg``,
        ``sun_azimuth_deg``, ``turbidity``, …; ``beeoptics/io/schemas/scene.schema.yaml``)."""
        return scenes.lit_by(self.path, self.light)["light"]

    def with_light(self, **light):
        """The same scene under other light, its geometry and Embree scene shared, not loaded again.

        Parameters
        ----------
        **light
            Overrides of the scene file's ``light`` section, as sweeps give
            them: ``sun_elevation_deg`` (degrees), ``sun_azimuth_deg``
            (degrees, from +x towards +y), ``turbidity`` (Linke, 1.7–10),
            ``day_of_year``, ``sky``, ``sun``, … (``beeoptics/io/schemas/scene.schema.yaml``).
        """
        light = {**self.light, **light}
        return Scene(self.path, self.wavelengths_nm, scenes.relit(self.scene, self.wavelengths_nm, light), light,
                     self.raycasting)

    def without_objects(self):
        """The same light over nothing: the open sky and the sun, no ground or object to hide or scatter them."""
        return Scene(self.path, self.wavelengths_nm, self.scene._replace(objects=[]), self.light)

    def __repr__(self):
        return (f"Scene({str(self.path)!r}: {len(self.scene.objects)} objects, materials "
                f"{', '.join(self.scene.material_names)}; {self.wavelengths_nm[0]:g}–{self.wavelengths_nm[-1]:g} nm)")


def load_scene(path, *, start_nm=None, end_nm=None, step_nm=None, geometry=True, cache=True, **light):
    """Load a scene once (from the scene cache where it is there), for any number of looks.

    A scene of a generated meadow whose mesh is not there yet (a fresh
    clone's) has it generated first, once, as the workflow's meadow rule does.

    Parameters
    ----------
    path : str or Path
        A ``scene.yaml``.
    start_nm, end_nm, step_nm : float, optional
        The spectral grid, nm; the configuration's (``spectral``) by default.
    geometry : bool
        Read its objects; without them (for what needs only its light and materials) it has none.
    cache : bool
        Take its objects and materials from the scene cache (or put them there); False reads and checks
        them from its files, as a scene loader's benchmark times it.
    **light
        Overrides of its ``light`` section (:meth:`Scene.with_light`).

    Returns
    -------
    Scene
    """
    from beeoptics.pipeline.world import missing_meadow

    spectral = validate_config({"spectral": {k: v for k, v in (("start_nm", start_nm), ("end_nm", end_nm),
                                                             ("step_nm", step_nm)) if v is not None}},
                               CONFIG_SCHEMA, source="load_scene", folders=False)["spectral"]
    wl = grid(**spectral)
    missing_meadow(path, starting=lambda mesh: log.warning("generating %s from the meadow file beside it, once", mesh))
    return Scene(path, wl, scenes.load_scene(path, wl, light or None, geometry=geometry, cache=cache), light)


class View:
    """What an eye sees of a scene from one pose: its receptors' radiance, catches and colour.

    Made by :func:`look` and :func:`looks`, or from radiance traced before (the workflow's gathered
    shares). Its tables are computed on first use.

    Parameters
    ----------
    eye : Eye
        The receptors looked with.
    scene : Scene
    radiance : ndarray (receptors, wavelengths)
        Each receptor's mean spectral radiance over its acceptance, W m⁻² sr⁻¹ nm⁻¹.
    placed : beeoptics.light.scene.Scene, optional
        The scene with the head at the view's pose (``scene.scene`` by default).
    replicate_catches : ndarray (receptors, replicates, classes), optional
        The trace's independent replicate estimates of each catch: with them, every catch and colour
        coordinate has its standard error.
    samples : ndarray (receptors,), optional
        The samples of each receptor's estimate.
    radiance_se : ndarray, optional
        The radiance's standard error, as ``radiance``.
    replicates : ndarray (receptors, replicates, wavelengths), optional
        The trace's replicate estimates of the radiance (of a Stokes vector's, (receptors, replicates,
        3 × wavelengths)), from which ``radiance_se`` and ``replicate_catches`` are made on first use
        where not given (:func:`beeoptics.tracing.replicate_errors`).
    background : str
        The von Kries adapting background: ``"scene"``, or a material of the scene.
    sensitivities : str
        The receptor curves: ``"species"``, ``"template"`` or a CSV in pavo's layout.

    Attributes
    ----------
    radiance : ndarray (receptors, wavelengths)
    wavelengths_nm : ndarray (wavelengths,)
    stokes : ndarray (receptors, 3, wavelengths) or None
        With ``polarised``, each receptor's spectral Stokes vector (I, Q, U), W m⁻² sr⁻¹ nm⁻¹, in the
        frame of the head's dorsal direction (:func:`beeoptics.light.integrator.trace_paths`).
    cover : ndarray (receptors,) or None
        With a ``target``, the share of each receptor's acceptance whose samples met it first.
    counts : dict
        The rays traced (``cast``, ``shadow``) and the tracing's wall and CPU seconds (``seconds``,
        ``cpu_seconds``): of the call that traced it (:func:`looks` traces several views in one).
    """

    def __init__(self, eye, scene, radiance, *, placed=None, replicate_catches=None, samples=None, radiance_se=None,
                 replicates=None, background=config_default("colour.background"), sensitivities=DEFAULT_CURVES,
                 stokes=None, cover=None, counts=None, relative=None):
        self.eye, self.scene, self.radiance, self.wavelengths_nm = eye, scene, radiance, scene.wavelengths_nm
        self.placed = scene.scene if placed is None else placed
        self._replicate_catches, self.samples, self._radiance_se = replicate_catches, samples, radiance_se
        self._replicates, self.background, self.sensitivities = replicates, background, sensitivities
        self.stokes, self.cover, self.counts = stokes, cover, counts or {}
        self._relative, self._responses, self._catches = relative, None, None

    def __repr__(self):
        return (f"View({len(self.eye.table.id)} receptors of {str(self.eye.path)!r} in {str(self.scene.path)!r}, "
                f"classes {', '.join(self.eye.receptor_set.classes)}; {self.wavelengths_nm[0]:g}–"
                f"{self.wavelengths_nm[-1]:g} nm)")

    def _errors(self):
        """The radiance's standard error and the replicates' catches, made of the replicates kept for them."""
        if self._replicates is not None:
            rset, wl = self.eye.receptor_set, self.wavelengths_nm
            made = replicate_errors(self._replicates, acceptance_solid_angle(self.eye.table.delta_rho_deg),
                                    (wl, curves(rset, wl, self.sensitivities)), len(wl))
            self._radiance_se, self._replicate_catches, self._replicates = made["radiance_se"], made["catches"], None

    @property
    def radiance_se(self):
        """The radiance's standard error over the trace's replicates, as ``radiance`` (None without them)."""
        self._errors()
        return self._radiance_se

    @property
    def spectral_radiance(self):
        """:attr:`radiance` labelled: a row per receptor, indexed by its ``id``, a column per wavelength of
        the scene's grid, ``wavelength_nm`` (pandas DataFrame, W m⁻² sr⁻¹ nm⁻¹)."""
        return self._by_wavelength(self.radiance)

    @property
    def spectral_radiance_se(self):
        """:attr:`radiance_se` labelled as :attr:`spectral_radiance` (None without the trace's replicates)."""
        return None if self.radiance_se is None else self._by_wavelength(self.radiance_se)

    def _by_wavelength(self, values):
        return _frame(values, index=self.eye.table.id, columns=self.wavelengths_nm).rename_axis(
            index="id", columns="wavelength_nm")

    @property
    def replicate_catches(self):
        """Each replicate's catch of each class, (receptors, replicates, classes) (None without them)."""
        self._errors()
        return self._replicate_catches

    def _respond(self):
        if self._responses is None:
            columns, arrays = respond(self.eye.table, self.radiance, self.placed, self.wavelengths_nm, self.scene.path,
                                      receptor_set=self.eye.receptor_set, background=self.background,
                                      receptor_curves=self.sensitivities, replicate_catches=self.replicate_catches)
            if self.samples is not None:
                columns["samples"] = self.samples
            self._responses = columns, arrays
        return self._responses

    @property
    def columns(self):
        """The columns of ``responses.csv`` exactly, in its order (a dict of arrays; see the README)."""
        return self._respond()[0]

    @property
    def spectra(self):
        """The arrays of ``irradiance.npz``: ``radiance``, ``irradiance`` (float32), ``background_q`` (the
        adapting catches), ``white_radiance`` (a white Lambertian surface under the scene's light) and ``white_q``
        (each receptor's catch of it) (:func:`beeoptics.tracing.respond`)."""
        return self._respond()[1]

    def table(self):
        """The columns of ``responses.csv`` exactly, in its order (pandas DataFrame)."""
        return _frame(self.columns)

    @property
    def directions(self):
        """Each receptor's optical axis in the world (pandas DataFrame): ``azimuth_deg`` from +x towards +y and
        ``elevation_deg`` above the horizontal, degrees."""
        _, axes = scenes.receptors_in_world(self.placed, self.eye.table.position, self.eye.table.axis)
        return _frame({"azimuth_deg": np.degrees(np.arctan2(axes[:, 1], axes[:, 0])),
                             "elevation_deg": np.degrees(np.arcsin(np.clip(axes[:, 2], -1.0, 1.0)))})

    @property
    def distance_m(self):
        """Each receptor's distance along its optical axis to the first surface it meets, m; infinite where it
        meets the sky: (receptors,)."""
        origins, axes = scenes.receptors_in_world(self.placed, self.eye.table.position, self.eye.table.axis)
        hits = first_hits(self.scene.raycasting, np.column_stack([origins, axes]).astype(np.float32))
        return hits["t_hit"].astype(np.float64)

    def class_catches(self, errors=True):
        """Each receptor's quantum catch of each class of the eye's receptor set (photons m⁻² s⁻¹, as
        ``responses.csv``; NaN for a class its ommatidium lacks) and their standard errors (None without the
        trace's replicates, or where ``errors`` is false): ndarrays (receptors, classes), without the colour
        the tables add (what a closed loop observes, :class:`beeoptics.loop.BeeView`)."""
        if self._catches is None or (errors and self._catches[1] is None):
            rset = self.eye.receptor_set
            self._catches = class_catches(self.eye.table, self.radiance, self.wavelengths_nm, rset,
                                          curves(rset, self.wavelengths_nm, self.sensitivities),
                                          self.replicate_catches if errors else None)[:2]
        return self._catches

    @property
    def catches(self):
        """A row per receptor: ``id``, ``side``, ``azimuth_deg``, ``elevation_deg`` (:attr:`directions`), the
        quantum catch of each receptor class (photons m⁻² s⁻¹, as ``responses.csv``) and each one's standard
        error (``se_<class>``, over the trace's replicates) (pandas DataFrame)."""
        catches, se = self.class_catches()
        table = {"id": self.eye.table.id, "side": self.eye.table.side, **self.directions}
        for k, r in enumerate(self.eye.receptor_set.classes):
            table[r] = catches[:, k]
            if se is not None:
                table[f"se_{r}"] = se[:, k]
        return _frame(table)

    @property
    def colour(self):
        """``id``, ``side`` and the colour-space coordinates against the background (colour hexagon,
        colour-opponent coding, receptor-noise limited distance), each with its ``se_*`` (pandas DataFrame)."""
        columns = self.columns
        described = {"id", "side", "ommatidium", "acceptance_sr", "brightness", "se_brightness", "samples",
                     *(c for k in self.eye.receptor_set.classes for c in (k, f"se_{k}"))}
        return _frame({"id": columns["id"], "side": columns["side"],
                             **{c: v for c, v in columns.items() if c not in described}})

    @property
    def relative(self):
        """Each class's catch of each receptor's radiance over a white Lambertian surface's under the scene's
        light (map3's unit, Collins §4.4), NaN for a class the receptor's ommatidium lacks: (receptors, classes)."""
        if self._relative is None:
            self._relative = _relative(self.eye, self.placed, self.radiance, self.wavelengths_nm,
                                       self.sensitivities)[0]
        return self._relative

    def _colours(self):
        """Each receptor's catches over white's, map3 colour and map2 colour (:func:`bee_colours`)."""
        catches = np.column_stack([self.columns[r] for r in self.eye.receptor_set.classes])
        return bee_colours(catches, self.spectra["white_q"], self.wavelengths_nm, self.radiance,
                           self.eye.receptor_set.display)

    def images(self, *, width_px=None, field_width_px=None, retina=True):
        """The view's images as arrays, as the workflow draws them (``beeoptics/images/``).

        Parameters
        ----------
        width_px : int, optional
            Each eye's panel in the retinal images, pixels (``images.width_px``).
        field_width_px : int, optional
            The visual-field maps' width, pixels (``images.visual_field_width_px``); their height is half.
        retina : bool
            The retinal images too (where the eye has its ``eye.yaml``); without them, the visual field's alone.

        Returns
        -------
        dict of str to ndarray
            ``field_map3`` and ``field_map2``, the visual field of both eyes, equirectangular (h, w, 3),
            azimuth from +180° (the bee's left) to −180° left to right, elevation +90° to −90° top to
            bottom; ``field_eyes`` (h, w), the bits of the eyes that see each direction (1 right,
            2 left); and where the eye has its ``eye.yaml`` (placing it on the head), its retinal images,
            left eye on the left, (h, 2w, 3): ``voronoi_map3``, ``voronoi_map2``, ``density_map3``,
            ``density_map3_normalised``, and each class's catch over white's, (h, 2w), as ``channel_uv``, …
            Display values in [0, 1] (map3: each class's catch over white's, sRGB-encoded; map2: the
            light's human colour), NaN where no receptor sees.
        """
        field, maps = self._field(field_width_px)
        out = {**{f"field_{k}": v for k, v in maps.items()}, "field_eyes": field.eyes}
        if retina and self.eye.eye_file is not None:
            drawn = self._retina(width_px)
            out.update({**drawn.images, **{channel(k): v for k, v in drawn.channels.items()}})
        return out

    def _field(self, width_px):
        """The visual field's geometry (:func:`beeoptics.eye.fieldofview.visual_field`) and its maps."""
        from beeoptics.eye.fieldofview import visual_field

        t = self.eye.table
        field = visual_field(t.axis, t.side, t.delta_rho_deg, t.delta_phi_deg,
                             width_px or config_default("images.visual_field_width_px"))
        _, colours, srgb = self._colours()
        return field, field_images(field.receptor, colours, srgb)

    def _retina(self, width_px):
        """The retinal images (:func:`beeoptics.images.retina.retinal_images`)."""
        from beeoptics.eye.description import load_eye as describe_eye

        relative, colours, srgb = self._colours()
        return retinal_images(describe_eye(self.eye.eye_file), self.eye.table, relative, colours, srgb,
                              self.eye.receptor_set.classes, width_px or config_default("images.width_px"))

    def plot(self, kind="field", *, title="", width_px=None, field_width_px=None):
        """A figure of the view, for a notebook: the visual field's maps, or one retinal image.

        Parameters
        ----------
        kind : str
            ``"field"``: map3 and map2 over both eyes' visual field, the binocular overlap outlined;
            or a retinal image of :meth:`images` (``"voronoi_map3"``, ``"channel_uv"``, …).
        title : str
        width_px, field_width_px : int, optional
            As :meth:`images`.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from beeoptics.images import figures

        if kind == "field":
            field, maps = self._field(field_width_px)
            panels = {"bee colours (map3, white = 1)": maps["map3"],
                      "human colours on the bee's geometry (map2)": maps["map2"]}
            return figures.visual_field_figure(panels, field.eyes, field.azimuth_deg, field.elevation_deg, None,
                                               title, 5.2)[0]
        kinds = [] if self.eye.eye_file is None else [k for k in retinal_outputs(self.eye.receptor_set) if k != "exr"]
        if kind not in kinds:
            raise InputError("plot", "kind", f"{kind!r} is none of {', '.join(['field', *kinds])}")
        retina = self._retina(width_px)
        image = {**retina.images, **{channel(k): v for k, v in retina.channels.items()}}[kind]
        return figures.retina_figure(image, retina.extents, retina.anterior, retina.dorsal, title, "",
                                     "catch ÷ white's catch" if image.ndim == 2 else None)[0]


def _relative(eye, placed, radiance, wl, sensitivities):
    """Catches of radiance (n, wavelengths) over a white surface's under ``placed``'s light, NaN where lacking."""
    rset = eye.receptor_set
    sens = curves(rset, wl, sensitivities)
    white = quantum_catches(white_radiance(placed.sky, placed.sun, len(wl))[None], sens, wl)[0]
    q = quantum_catches(radiance, sens, wl) / white
    n = len(eye.table.id)
    q = q.reshape(-1, n, q.shape[-1])
    types = ommatidium_types(rset, n)
    if types is not None:
        q[:, lacking(rset, types)] = np.nan
    return q


def _config(scene, samples, depth, seed, precision, background, sensitivities, trace, source):
    """The config's ``trace`` and ``colour`` sections these give, checked against its schema (whose keys an
    error names: trace.samples_per_receptor, …)."""
    given = {"trace": {**(trace or {}), **{k: v for k, v in (("samples_per_receptor", samples), ("depth", depth),
                                                             ("seed", seed)) if v is not None}},
             "colour": {k: v for k, v in (("background", background), ("sensitivities", sensitivities))
                        if v is not None}}
    if precision is not None:
        given["trace"]["precision"] = {**given["trace"].get("precision", {}), "target": precision}
    config = validate_config(given, CONFIG_SCHEMA, source=source, folders=False)
    # Refused now rather than after the trace.
    check_background(scene.path, config["colour"]["background"], source, "background")
    return config


def _settings(config, threads, receptor_set, classes=None):
    """How a config's checked ``trace`` section traces receptors of ``receptor_set`` (of its ``classes``, all
    where None; without a set, a flat receptor's catch) on ``threads`` threads (all cores where None):
    :class:`beeoptics.light.batching.TraceSettings`."""
    if receptor_set is None:
        return TraceSettings.from_config(config["trace"], threads or os.cpu_count(), classes=1)
    kept = [receptor_set.classes.index(c) for c in (receptor_set.classes if classes is None else classes)]
    noise = noise_forms(receptor_set)
    return TraceSettings.from_config(config["trace"], threads or os.cpu_count(), classes=len(kept),
                                     noise=None if noise is None else noise[:, kept][:, :, kept])


def _placed(scene, pose):
    """The scene with the head at ``pose`` (a mapping: ``position_m`` and either ``rotation``, 3 × 3, its
    columns the head's axes in the world, or ``heading_deg``, ``pitch_deg``, ``roll_deg``); a part of it not
    given keeps the scene's own."""
    placed = scene.scene
    for field, shape in (("position_m", (3,)), ("rotation", (3, 3))):
        if pose.get(field) is None:
            continue
        try:
            value = np.asarray(pose[field], float)
        except (TypeError, ValueError):
            value = np.zeros(0)
        if value.shape != shape or not np.isfinite(value).all():
            raise InputError("pose", field, f"expected {' × '.join(map(str, shape))} finite numbers")
    if pose.get("rotation") is not None:
        if pose.get("position_m") is None:
            raise InputError("pose", "position_m", "a pose with a rotation needs its position")
        return placed._replace(eye_position=np.asarray(pose["position_m"], float),
                               eye_rotation=np.asarray(pose["rotation"], float))
    if not any(pose.get(k) is not None for k in ("position_m", "heading_deg", "pitch_deg", "roll_deg")):
        return placed
    own = scene.head
    return scenes.posed(placed, {"position_m": placed.eye_position if pose.get("position_m") is None else
                                 pose["position_m"],
                                 **{k: own[k] if pose.get(k) is None else pose[k]
                                    for k in ("heading_deg", "pitch_deg", "roll_deg")}})


def look(eye, scene, *, position_m=None, heading_deg=None, pitch_deg=None, roll_deg=None, rotation=None,
         samples=None, depth=None, seed=None, precision=None, background=None, sensitivities=None, trace=None,
         threads=None, part=0, parts=1, polarised=False, target=None, progress=None):
    """Place the eye at a pose in the scene and trace its receptors: the view.

    The defaults are the configuration's; the numbers are those of
    ``beeoptics render`` for the same eye, scene and settings, for any
    ``threads`` and any ``parts``.

    Parameters
    ----------
    eye : Eye
    scene : Scene
    position_m : array_like (3,), optional
        The head's position in the world, m; the scene's own ``eye`` by default.
    heading_deg, pitch_deg, roll_deg : float, optional
        The head's heading (from +x towards +y), pitch (nose up) and roll,
        degrees; the scene's own by default.
    rotation : array_like (3, 3), optional
        Instead of the angles, the head's rotation: its columns the head's axes in the world.
    samples : int, optional
        Rays per receptor (``trace.samples_per_receptor``).
    depth : int, optional
        Scattering events per path; 1 is direct light only.
    seed : int, optional
        The random seed: the same seed and settings give the same view.
    precision : float or "auto", optional
        The relative standard error asked of every catch (0.03: 3 %) or
        ``"auto"``, a quarter of a just-noticeable difference in the receptor
        set's colour and achromatic distances
        (:func:`beeoptics.vision.uncertainty.noise_forms`), the samples then
        chosen per receptor (*Every number with its error*); None: ``samples`` each.
    background : str, optional
        The von Kries adapting background: ``"scene"``, or a material of the scene.
    sensitivities : str, optional
        The receptor curves: ``"species"``, ``"template"`` or a CSV in pavo's layout.
    trace : dict, optional
        A config's whole ``trace`` section (``beeoptics/io/schemas/config.schema.yaml``), which the
        keywords above override.
    threads : int, optional
        Threads tracing; all cores by default.
    part, parts : int
        Trace only share ``part`` of ``parts`` contiguous shares of the receptors (the view is of those):
        each receptor is traced the same in any share.
    polarised : bool
        Trace Stokes vectors (:attr:`View.stokes`); the radiance is their intensity.
    target : (array_like (3,), float), optional
        A sphere (centre, m; radius, m): each receptor's share of its acceptance that met it first
        (:attr:`View.cover`).
    progress : callable, optional
        Called with (receptors done, receptors to trace).

    Returns
    -------
    View
    """
    config = _config(scene, samples, depth, seed, precision, background, sensitivities, trace, "look")
    placed = _placed(scene, {"position_m": position_m, "heading_deg": heading_deg, "pitch_deg": pitch_deg,
                             "roll_deg": roll_deg, **({} if rotation is None else {"rotation": rotation})})
    settings = _settings(config, threads, eye.receptor_set)
    if not (isinstance(parts, numbers.Integral) and isinstance(part, numbers.Integral) and 0 <= part < parts):
        raise InputError("look", "part", f"share {part!r} of {parts!r}: parts is a whole number from 1, part one "
                         "from 0 below it")
    bounds = np.linspace(0, len(eye.table.id), parts + 1).round().astype(int)
    # The errors are made when the view is first asked for them: a flight's frames keep the radiance alone.
    return _traced_view(eye, scene, placed, settings, config["colour"], bounds[part], bounds[part + 1],
                        progress=progress, polarised=polarised, target=target, deferred=True)


def _traced_view(eye, scene, placed, settings, colour, first, last, *, progress=None, polarised=False, target=None,
                 enclosure=True, deferred=False):
    """The view of the eye's receptors ``first``..``last`` in ``placed`` (the scene with the head at its pose),
    traced with ``settings`` (TraceSettings) and coloured by ``colour`` (a config's checked ``colour``
    section): :func:`look` once its arguments are checked, which a closed loop checks once for all its looks
    (:class:`beeoptics.loop.BeeView`). ``enclosure`` and ``deferred``: as
    :func:`beeoptics.tracing.trace_receptors` takes them, the errors then made on first use."""
    rset, wl, table = eye.receptor_set, scene.wavelengths_nm, eye.table
    curve = colour["sensitivities"]
    errors = {}
    traced = trace_receptors(placed, table, first, last, settings, len(wl), progress, rs=scene.raycasting,
                             polarised=polarised, target=target, sensitivities=(wl, curves(rset, wl, curve)),
                             errors=errors, enclosure=enclosure, deferred=deferred)
    radiance = traced[0][:, 0] if polarised else traced[0]
    if last - first < len(table.id):
        eye = Eye(eye.path, rows_of(table, slice(first, last)), rset, eye.eye_file)
    return View(eye, scene, radiance, placed=placed, replicate_catches=errors.get("catches"),
                samples=errors["samples"], radiance_se=errors.get("radiance_se"), replicates=errors.get("replicates"),
                background=colour["background"], sensitivities=curve, stokes=traced[0] if polarised else None,
                cover=traced[2] if target is not None else None, counts=traced[1])


#: Frames :func:`looks` traces at once: their receptors' cones in one call, so that Embree's batches
#: stay full however few receptors an eye has.
FRAMES_AT_ONCE = 8


def looks(eye, scene, poses, *, samples=None, depth=None, seed=None, precision=None, background=None,
          sensitivities=None, trace=None, threads=None, progress=None, counts=None):
    """The views from a sequence of poses, the eye and the scene held in memory: frame after frame.

    :data:`FRAMES_AT_ONCE` poses are traced in one call. Each frame draws
    random numbers of its own (a receptor's stream offset by the frame's
    place in ``poses``), so that a sequence traces the same on any number
    of threads; its first frame is the :func:`look` from its pose. A view's
    :attr:`View.relative` catches are computed for the frames of a call at
    once; its tables on first use.

    Parameters
    ----------
    eye : Eye
    scene : Scene
    poses : iterable of mapping
        Each: ``position_m`` (m) and either ``heading_deg``, ``pitch_deg``, ``roll_deg`` (degrees, the
        scene's own where not given) or ``rotation`` (3 × 3, its columns the head's axes in the world).
    samples, depth, seed, precision, background, sensitivities, trace, threads
        As :func:`look`'s.
    progress : callable, optional
        Called with (frames done, frames) where ``poses`` has a length.
    counts : dict, optional
        Filled with the rays of every frame traced so far (``cast``, ``shadow``) and the tracing's wall
        and CPU seconds (``seconds``, ``cpu_seconds``).

    Yields
    ------
    View
    """
    config = _config(scene, samples, depth, seed, precision, background, sensitivities, trace, "looks")
    rset, wl, table = eye.receptor_set, scene.wavelengths_nm, eye.table
    curve = config["colour"]["sensitivities"]
    settings = _settings(config, threads, rset)
    sens = (wl, curves(rset, wl, curve))
    n, width = len(table.id), int(table.id.max()) + 1
    total = len(poses) if hasattr(poses, "__len__") else None
    poses, done = iter(poses), 0
    while chunk := [_placed(scene, p) for _, p in zip(range(FRAMES_AT_ONCE), poses)]:
        origins, axes = map(np.vstack, zip(*(scenes.receptors_in_world(p, table.position, table.axis)
                                             for p in chunk)))
        # Each frame draws random numbers of its own: a receptor's id offset by the frame's.
        streams = np.concatenate([(done + k) * width + table.id for k in range(len(chunk))]).astype(np.int64)
        errors = {}
        radiance, traced = trace_cones(scene.scene, origins, axes, np.tile(table.delta_rho_deg, len(chunk)), streams,
                                       0, len(origins), settings, len(wl), rs=scene.raycasting, sensitivities=sens,
                                       errors=errors)
        relative = _relative(eye, chunk[0], radiance, wl, curve)
        if counts is not None:
            for key, value in traced.items():
                counts[key] = counts.get(key, 0) + value
        for k, placed in enumerate(chunk):
            rows = slice(k * n, (k + 1) * n)
            yield View(eye, scene, radiance[rows], placed=placed, replicate_catches=errors["catches"][rows],
                       samples=errors["samples"][rows], radiance_se=errors["radiance_se"][rows],
                       background=config["colour"]["background"], sensitivities=curve, counts=traced,
                       relative=relative[k])
        done += len(chunk)
        if progress is not None:
            progress(done, total)


def human_view(scene, *, camera=None, position_m=None, heading_deg=None, pitch_deg=None, roll_deg=None,
               rotation=None, size_px=None, samples=None, depth=None, seed=None, trace=None, threads=None):
    """What a person sees of the scene through a pinhole camera: its CIE 1931 XYZ image (height, width, 3).

    Traced as the receptors are (the config's ``trace`` section, the keywords
    overriding it); :func:`human_srgb` makes it displayable.

    Parameters
    ----------
    scene : Scene
    camera : dict, optional
        A scene's ``camera`` section (``position_m``, ``look_at_m``, ``vertical_fov_deg``, ``width_px``,
        ``height_px``); the scene's own by default, or with a pose, the bee's view from the head.
    position_m, heading_deg, pitch_deg, roll_deg, rotation
        The head's pose, as :func:`look` takes it: the camera then looks where the head faces
        (:func:`beeoptics.light.scene.bee_camera`), ``size_px`` (width, height) pixels.
    samples : int, optional
        Rays per pixel.
    depth, seed, trace, threads
        As :func:`look`'s.
    """
    config = validate_config({"trace": {**(trace or {}), **{k: v for k, v in (("depth", depth), ("seed", seed))
                                                           if v is not None}}},
                             CONFIG_SCHEMA, source="human_view", folders=False)
    placed = _placed(scene, {"position_m": position_m, "heading_deg": heading_deg, "pitch_deg": pitch_deg,
                             "roll_deg": roll_deg, **({} if rotation is None else {"rotation": rotation})})
    if camera is None:
        camera = placed.camera if placed is scene.scene else scenes.bee_camera(placed.eye_position,
                                                                                placed.eye_rotation, *size_px)
    settings = TraceSettings.from_config(config["trace"], threads or os.cpu_count(), samples=samples)
    return render_human(placed, camera, settings, scene.wavelengths_nm, scene.raycasting)


def _curves(receptor_set, wavelengths_nm, sensitivities, classes, source):
    """The receptor set's curves on the grid (n_wavelengths, classes): of ``classes`` only, in their order,
    where given."""
    unknown = [c for c in classes or () if c not in receptor_set.classes]
    if unknown:
        raise InputError(source, "classes", f"{unknown[0]!r} is none of {', '.join(receptor_set.classes)}")
    sens = curves(receptor_set, wavelengths_nm, sensitivities or DEFAULT_CURVES)
    return sens if classes is None else sens[:, [receptor_set.classes.index(c) for c in classes]]


def catches(radiance, wavelengths_nm, receptor_set, *, sensitivities=None, classes=None, delta_rho_deg=None):
    """Each receptor class's quantum catch of spectral radiance: pavo's ``vismodel`` catch (``qcatch = "Qi"``).

    The rectangle rule over the grid in photon units (Collins eq. 1–3,
    :mod:`beeoptics.vision.catches`), the curves of area 1 nm as pavo's.

    Parameters
    ----------
    radiance : array_like (n, ..., n_wavelengths)
        Spectral radiance, W m⁻² sr⁻¹ nm⁻¹: a receptor's mean over its acceptance (:attr:`View.radiance`,
        :attr:`Cones.radiance`), or its Stokes vector's components (n, 3, n_wavelengths) alike.
    wavelengths_nm : ndarray (n_wavelengths,)
        The uniform spectral grid, nm.
    receptor_set : ReceptorSet
        The receptor classes (:attr:`Eye.receptor_set`).
    sensitivities : str, optional
        The receptor curves: ``"species"`` (by default), ``"template"`` or a CSV in pavo's layout.
    classes : sequence of str, optional
        Only these classes, in this order (``["UV"]``); every class by default.
    delta_rho_deg : array_like (n,), optional
        Each receptor's acceptance angle, degrees: the catch over its acceptance solid angle, photons
        m⁻² s⁻¹, as :attr:`View.catches` gives it. Without it, the catch of the radiance itself, photons
        m⁻² s⁻¹ sr⁻¹, which receptors of unequal Δρ share for the same light.

    Returns
    -------
    ndarray (n, ..., classes)
    """
    radiance = np.asarray(radiance)
    sens = _curves(receptor_set, wavelengths_nm, sensitivities, classes, "catches")
    if delta_rho_deg is not None:
        return cone_catches(radiance, acceptance_solid_angle(delta_rho_deg), (wavelengths_nm, sens))
    return quantum_catches(radiance, sens, wavelengths_nm)


class Cones:
    """Acceptance cones traced through a scene (:func:`look_cones`).

    Attributes
    ----------
    radiance : ndarray (n, n_wavelengths), or (n, 3, n_wavelengths) polarised
        Each cone's mean spectral radiance over its acceptance, W m⁻² sr⁻¹ nm⁻¹; polarised, its spectral
        Stokes vector (I, Q, U) in the frame of its ``dorsal`` direction.
    radiance_se : ndarray, as ``radiance``
        Its standard error over the trace's replicates.
    samples : ndarray (n,)
        The samples of each cone's estimate.
    replicate_catches : ndarray (n, replicates, classes) or None
        With a receptor set, each replicate's catch of each class over the cone's acceptance solid
        angle, photons m⁻² s⁻¹ (of the intensity where polarised): their spread is each catch's error.
    cover : ndarray (n,) or None
        With a ``target``, the share of each cone's acceptance whose samples met it first.
    counts : dict
        The rays traced (``cast``, ``shadow``) and the tracing's wall and CPU seconds (``seconds``,
        ``cpu_seconds``).

    ``radiance_se`` and ``replicate_catches`` are made of the trace's replicates when first asked for (a
    compass reads the radiance alone, a detection the replicates' catches alone), as a look's are.
    """

    def __init__(self, radiance, samples, cover, counts, replicates, omega, sensitivities):
        self.radiance, self.samples, self.cover, self.counts = radiance, samples, cover, counts
        self._replicates, self._omega, self._sensitivities = replicates, omega, sensitivities
        self._errors = None

    def _made(self):
        if self._errors is None:
            n_wavelengths = self.radiance.shape[-1]
            self._errors = replicate_errors(self._replicates, self._omega, self._sensitivities, n_wavelengths)
            self._replicates = None
        return self._errors

    @property
    def radiance_se(self):
        """The radiance's standard error over the trace's replicates, as ``radiance``."""
        return self._made()["radiance_se"]

    @property
    def replicate_catches(self):
        """Each replicate's catch of each class, (cones, replicates, classes); None without a receptor set."""
        return self._made().get("catches")


def look_cones(scene, origins_m, axes, delta_rho_deg, *, streams=None, receptor_set=None, classes=None,
               sensitivities=None, samples=None, depth=None, seed=None, precision=None, trace=None, threads=None,
               dorsal=None, target=None, progress=None):
    """Trace any acceptance cones through a scene: a few receptors at many poses, or cones pointing anywhere.

    Each cone is traced as a receptor of :func:`look` is, with the same
    settings (the configuration's where not given): a cone of the same
    stream, origin, axis and Δρ gives the same numbers in any call, on any
    number of threads.

    Parameters
    ----------
    scene : Scene
    origins_m : array_like (n, 3)
        The cones' apices in the world, m.
    axes : array_like (n, 3)
        Their axes in the world, unit vectors.
    delta_rho_deg : array_like (n,) or float
        Their acceptance angles (the Gaussian's full width at half maximum), degrees.
    streams : array_like of int (n,), optional
        Each cone's random-number stream (0 … n − 1 by default): cones of their own streams are
        independent; :func:`look` gives a receptor its id, :func:`looks` a frame's receptors
        their ids offset by the frame's.
    receptor_set : ReceptorSet, optional
        The classes whose catches the replicates give (:attr:`Cones.replicate_catches`) and a
        ``precision`` is asked of; without it, the precision is asked of the radiance summed over the grid.
    classes : sequence of str, optional
        Of the set's classes, only these (``["UV"]``).
    sensitivities : str, optional
        The receptor curves: ``"species"``, ``"template"`` or a CSV in pavo's layout.
    samples, depth, seed, precision, trace, threads
        As :func:`look`'s.
    dorsal : array_like (3,) or (n, 3), optional
        A direction in the world, or one per cone (the head's dorsal direction): with it, polarised,
        each cone's Stokes vector in the frame of that direction about its samples
        (:func:`beeoptics.light.integrator.trace_paths`).
    target : (array_like, float or array_like), optional
        A sphere, centre (3,) and radius, m, or one per cone ((n, 3), (n,)): each cone's share of its
        acceptance that met it first (:attr:`Cones.cover`).
    progress : callable, optional
        Called with (cones done, cones).

    Returns
    -------
    Cones
    """
    config = _config(scene, samples, depth, seed, precision, None, sensitivities, trace, "look_cones")
    origins_m, axes = (np.asarray(v, float) for v in (origins_m, axes))
    n = len(origins_m) if origins_m.ndim else 0
    drho = np.asarray(delta_rho_deg, float)
    drho = np.full(n, drho) if drho.ndim == 0 else drho
    streams = np.arange(n, dtype=np.int64) if streams is None else np.asarray(streams, np.int64)
    for field, value, shape in (("origins_m", origins_m, (n, 3)), ("axes", axes, (n, 3)),
                                ("delta_rho_deg", drho, (n,)), ("streams", streams, (n,))):
        if value.shape != shape or not np.isfinite(value).all():
            raise InputError("look_cones", field, f"expected {' × '.join(map(str, shape))} finite numbers, "
                             f"one per cone, not {' × '.join(map(str, value.shape))}")
    if not (drho > 0.0).all():
        raise InputError("look_cones", "delta_rho_deg", "acceptance angles are positive")
    wl = scene.wavelengths_nm
    sens = None if receptor_set is None else (wl, _curves(receptor_set, wl, config["colour"]["sensitivities"],
                                                          classes, "look_cones"))
    settings = _settings(config, threads, receptor_set, classes)
    errors = {}
    traced = trace_cones(scene.scene, origins_m, axes, drho, streams, 0, n, settings, len(wl), progress,
                         scene.raycasting, dorsal, target, sens, errors, deferred=True)
    return Cones(traced[0], errors["samples"], traced[2] if target is not None else None, traced[1],
                 errors["replicates"], acceptance_solid_angle(drho), sens)


def cone_rays(eye, scene, samples, *, seed=1, receptors=slice(None)):
    """The rays a look casts first: ``samples`` directions drawn from each receptor's acceptance cone, at the
    scene's own pose of the head, as Open3D's ``RaycastingScene.cast_rays`` takes them (a benchmark's
    yardstick: bare Embree on the rays the tracer casts).

    Parameters
    ----------
    eye : Eye
    scene : Scene
    samples : int
        Directions a receptor.
    seed : int
        The random seed.
    receptors : slice or array_like of int
        Which rows of the eye's receptor table.

    Returns
    -------
    ndarray (receptors × samples, 6)
        Each ray's origin (m) and unit direction in the world, a receptor's rays together.
    """
    table = eye.table
    origins, axes = scenes.receptors_in_world(scene.scene, table.position[receptors], table.axis[receptors])
    dirs, _ = cone_samples(axes, table.delta_rho_deg[receptors], samples, seed)
    return np.hstack([np.repeat(origins, samples, axis=0), dirs.reshape(-1, 3)])
