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
"""

import hashlib
import inspect
import logging
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

from beeoptics import __version__
from beeoptics.eye.receptors import read_receptor_file
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.validation import (CONFIG_SCHEMA, check_background, config_default, load_yaml, validate,
                                     validate_config)
from beeoptics.light import scene as scenes
from beeoptics.light.batching import TraceSettings
from beeoptics.light.scenecache import cache_root, code_digest, file_digest
from beeoptics.spectra import grid
from beeoptics.vision.receptorset import DEFAULT_SET, curves, load_receptor_set, ommatidium_names, ommatidium_types
from beeoptics.vision.receptorset import receptor_set_of

log = logging.getLogger("beeoptics")

#: The package's code that builds an eye: its files are part of a built eye's cache key, so that a change to
#: any builds the eye afresh.
EYE_CODE = ("eye", "io", "pipeline/eyes.py")


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
        receptor's ommatidial type, where the receptor set has a mosaic.
        """
        columns = self.table.columns()
        types = ommatidium_types(self.receptor_set, len(self.table.id))
        if types is not None:
            columns["ommatidium"] = ommatidium_names(self.receptor_set, types)
        return pd.DataFrame(columns)

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
    receptor_set : str, optional
        A shipped receptor set's name or a set file; by default the eye's own
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
    if receptor_set is not None:
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
        The overrides of the scene file's ``light`` section it is lit by.
    """

    def __init__(self, path, wavelengths_nm, scene, light, rs=None):
        self.path, self.wavelengths_nm, self.scene, self.light = Path(path), wavelengths_nm, scene, light
        self._rs = rs

    @property
    def raycasting(self):
        """Open3D's Embree scene of its objects, built on first use and kept."""
        if self._rs is None:
            self._rs = scenes.raycasting_scene(self.scene)
        return self._rs

    @property
    def materials(self):
        """The materials' names and spectral reflectance (pandas DataFrame: a row per material, a column per
        wavelength, nm)."""
        return pd.DataFrame(self.scene.reflectance, index=self.scene.material_names, columns=self.wavelengths_nm)

    @property
    def objects(self):
        """The objects: name, vertices and faces (pandas DataFrame, a row per object)."""
        return pd.DataFrame({"name": [o.name for o in self.scene.objects],
                             "vertices": [len(o.vertices) for o in self.scene.objects],
                             "faces": [len(o.faces) for o in self.scene.objects]})

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

    def __repr__(self):
        return (f"Scene({str(self.path)!r}: {len(self.scene.objects)} objects, materials "
                f"{', '.join(self.scene.material_names)}; {self.wavelengths_nm[0]:g}–{self.wavelengths_nm[-1]:g} nm)")


def load_scene(path, *, start_nm=None, end_nm=None, step_nm=None, **light):
    """Load a scene once (from the scene cache where it is there), for any number of looks.

    A scene of a generated meadow whose mesh is not there yet (a fresh
    clone's) has it generated first, once, as the workflow's meadow rule does.

    Parameters
    ----------
    path : str or Path
        A ``scene.yaml``.
    start_nm, end_nm, step_nm : float, optional
        The spectral grid, nm; the configuration's (``spectral``) by default.
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
    return Scene(path, wl, scenes.load_scene(path, wl, light or None), light)


class View:
    """What an eye sees of a scene from one pose: its receptors' catches, radiance and colour.

    Attributes
    ----------
    catches : pandas.DataFrame
        A row per receptor: ``id``, ``side``, ``azimuth_deg`` and ``elevation_deg``
        (its optical axis in the world: azimuth from +x towards +y, elevation above
        the horizontal, degrees), the quantum catch of each receptor class over the
        acceptance solid angle (photons s⁻¹ m⁻²-equivalent, as ``responses.csv``)
        and each one's standard error (``se_<class>``, over the trace's replicates).
    radiance : ndarray (receptors, wavelengths)
        Each receptor's mean spectral radiance over its acceptance, W m⁻² sr⁻¹ nm⁻¹,
        on the grid :attr:`wavelengths_nm`.
    wavelengths_nm : ndarray (wavelengths,)
    colour : pandas.DataFrame
        ``id``, ``side`` and the colour-space coordinates against the chosen
        background (colour hexagon, colour-opponent coding, receptor-noise
        limited distance), each with its ``se_*``.
    """

    def __init__(self, columns, radiance, wavelengths_nm, directions, classes):
        self._columns, self.radiance, self.wavelengths_nm = columns, radiance, wavelengths_nm
        catch = [c for k in classes for c in (k, f"se_{k}") if c in columns]
        self.catches = pd.DataFrame({"id": columns["id"], "side": columns["side"], **directions,
                                     **{c: columns[c] for c in catch}})
        described = {"id", "side", "ommatidium", "acceptance_sr", "brightness", "se_brightness", "samples", *catch}
        self.colour = pd.DataFrame({"id": columns["id"], "side": columns["side"],
                                    **{c: v for c, v in columns.items() if c not in described}})

    def table(self):
        """The columns of ``responses.csv`` exactly, in its order (pandas DataFrame)."""
        return pd.DataFrame(self._columns)


def look(eye, scene, *, position_m=None, heading_deg=None, pitch_deg=None, roll_deg=None, samples=None,
         depth=None, seed=None, precision=None, background=None, sensitivities=None, threads=None):
    """Place the eye at a pose in the scene and trace its receptors: the view.

    The defaults are the configuration's; the numbers are those of
    ``beeoptics render`` for the same eye, scene and settings, for any
    ``threads``.

    Parameters
    ----------
    eye : Eye
    scene : Scene
    position_m : array_like (3,), optional
        The head's position in the world, m; the scene's own ``eye`` by default.
    heading_deg, pitch_deg, roll_deg : float, optional
        The head's heading (from +x towards +y), pitch (nose up) and roll,
        degrees; the scene's own by default.
    samples : int, optional
        Rays per receptor (``trace.samples_per_receptor``).
    depth : int, optional
        Scattering events per path; 1 is direct light only.
    seed : int, optional
        The random seed: the same seed and settings give the same view.
    precision : float or "auto", optional
        The relative standard error asked of every catch (0.03: 3 %), the
        samples then chosen per receptor (*Every number with its error*);
        None: ``samples`` each.
    background : str, optional
        The von Kries adapting background: ``"scene"``, or a material of the scene.
    sensitivities : str, optional
        The receptor curves: ``"species"``, ``"template"`` or a CSV in pavo's layout.
    threads : int, optional
        Threads tracing; all cores by default.

    Returns
    -------
    View
    """
    from beeoptics.pipeline.trace import respond, trace_receptors

    # Checked against the config's schema, whose keys the error names (trace.samples_per_receptor, …).
    given = {"trace": {k: v for k, v in (("samples_per_receptor", samples), ("depth", depth), ("seed", seed))
                       if v is not None},
             "colour": {k: v for k, v in (("background", background), ("sensitivities", sensitivities))
                        if v is not None}}
    if precision is not None:
        given["trace"]["precision"] = {"target": precision}
    config = validate_config(given, CONFIG_SCHEMA, source="look", folders=False)
    # Refused now rather than after the trace.
    check_background(scene.path, config["colour"]["background"], "look", "background")
    placed = scene.scene
    if any(v is not None for v in (position_m, heading_deg, pitch_deg, roll_deg)):
        pose = {"position_m": placed.eye_position if position_m is None else position_m}
        # A part of the pose not given keeps the scene's: heading, pitch and roll from its file.
        own = validate(load_yaml(scene.path), "scene", scene.path)["eye"]
        pose.update({k: own[k] if v is None else v for k, v in
                     (("heading_deg", heading_deg), ("pitch_deg", pitch_deg), ("roll_deg", roll_deg))})
        placed = scenes.posed(placed, pose)
    rset, wl, table = eye.receptor_set, scene.wavelengths_nm, eye.table
    curve = config["colour"]["sensitivities"]
    settings = TraceSettings.from_config(config["trace"], threads or os.cpu_count(), receptor_set=rset)
    errors = {}
    radiance, _ = trace_receptors(placed, table, 0, len(table.id), settings, len(wl), rs=scene.raycasting,
                                  sensitivities=(wl, curves(rset, wl, curve)), errors=errors)
    columns, _ = respond(table, radiance, placed, wl, scene.path, receptor_set=rset,
                         background=config["colour"]["background"], receptor_curves=curve,
                         replicate_catches=errors["catches"])
    columns["samples"] = errors["samples"]
    _, axes = scenes.receptors_in_world(placed, table.position, table.axis)
    directions = {"azimuth_deg": np.degrees(np.arctan2(axes[:, 1], axes[:, 0])),
                  "elevation_deg": np.degrees(np.arcsin(np.clip(axes[:, 2], -1.0, 1.0)))}
    return View(columns, radiance, wl, directions, rset.classes)
