"""The light stages: trace the receptors through a scene in shares, gather their responses, render the human view.

Each stage reads its inputs, calls the library and writes ``outputs``, a
mapping of output names to paths, atomically.
"""

import numpy as np

from beeoptics.api import View, human_srgb, human_view as photograph, load_eye, load_scene, look
from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.imagefile import write_exr, write_png
from beeoptics.io.table import write_table
from beeoptics.io.validation import config_default
from beeoptics.vision.receptorset import DEFAULT_CURVES


def trace_part(receptors_csv, scene_file, outputs, *, spectral, trace, threads, receptor_set, part=0, parts=1,
               light=None, progress=None, receptor_curves=DEFAULT_CURVES):
    """Trace the acceptance cones of one share of the receptors through a scene: ``outputs["radiance"]``.

    Receptors are split into ``parts`` contiguous shares, for running on
    several machines; every receptor draws the same random numbers in any
    share, so the gathered result is bit-identical to a single part's.
    Writes the share's receptor ids (``id``), mean spectral radiance
    (``radiance``) and its standard error (``radiance_se``), each
    replicate's catches (``catches``, receptors × replicates × classes,
    float64) and the samples each receptor took (``samples``) (npz); returns
    the ray counts ("cast", "shadow") and the tracing's wall and CPU seconds
    ("seconds", "cpu_seconds").

    Parameters
    ----------
    spectral : dict
        The config's ``spectral`` section (the grid, nm).
    trace : dict
        The config's ``trace`` section.
    threads : int
        Threads tracing.
    receptor_set : ReceptorSet
        The eye's receptor classes, whose catches each replicate gives.
    receptor_curves : str
        The receptor sensitivities (:func:`beeoptics.vision.receptorset.curves`).
    light : dict, optional
        Overrides of the scene's light section (sweeps).
    progress : callable, optional
        Called with (receptors done, receptors in the share).
    """
    scene = load_scene(scene_file, **spectral, **(light or {}))  # a scene without light refused before the eye is read
    view = look(load_eye(receptors_csv, receptor_set=receptor_set), scene, trace=trace, threads=threads,
                sensitivities=receptor_curves, part=part, parts=parts, progress=progress)
    with atomic_path(outputs["radiance"]) as tmp:
        # Uncompressed: zlib shrinks these spectra by 6 % and took a sixth of the stage's time.
        np.savez(tmp, id=view.eye.table.id, radiance=view.radiance, radiance_se=view.radiance_se,
                 catches=view.replicate_catches, samples=view.samples)
    return view.counts


def gather_responses(receptors_csv, scene_file, part_npzs, outputs, *, spectral, receptor_set,
                     background=config_default("colour.background"), light=None, receptor_curves=DEFAULT_CURVES):
    """Catches and colour-space coordinates of every receptor: ``outputs["responses"]`` and ``["irradiance"]``.

    Parameters
    ----------
    part_npzs : list of path
        The shares written by :func:`trace_part`, in order.
    spectral : dict
        The config's ``spectral`` section.
    background : str
        The adapting background of von Kries adaptation: ``"scene"``, the
        mean radiance catch of the receptors of both eyes, or the name of one
        of the scene's materials, as a Lambertian surface under the scene's
        sky and sun (:func:`beeoptics.tracing.respond`).
    receptor_set : ReceptorSet
        The eye's receptor classes (:mod:`beeoptics.vision.receptorset`).
    light : dict, optional
        Overrides of the scene's light section, as the trace had them.
    receptor_curves : str
        The receptor sensitivities: the species' own, the template, or a CSV of measured curves
        (:func:`beeoptics.vision.receptorset.curves`).
    """
    eye = load_eye(receptors_csv, receptor_set=receptor_set)
    parts = [np.load(p) for p in part_npzs]
    ids = np.concatenate([p["id"] for p in parts])
    if not np.array_equal(ids, eye.table.id):
        raise InputError(part_npzs[0], "id", "the traced shares do not cover the receptor table in order")
    for key in ("radiance_se", "catches", "samples"):
        if key not in parts[0]:
            raise InputError(part_npzs[0], key, "missing: the share was traced by an earlier version; trace it again")
    replicate_catches = np.concatenate([p["catches"] for p in parts])
    if replicate_catches.shape[2] != len(receptor_set.classes):
        raise InputError(part_npzs[0], "catches", f"{replicate_catches.shape[2]} receptor classes where the receptor "
                         f"set has {len(receptor_set.classes)}: the share was traced for another eye")
    # Of the samples traced for the estimate; an adaptive trace's pilot is not among them (trace.precision).
    view = View(eye, load_scene(scene_file, **spectral, geometry=False, **(light or {})),
                np.concatenate([p["radiance"] for p in parts]), replicate_catches=replicate_catches,
                samples=np.concatenate([p["samples"] for p in parts]), background=background,
                sensitivities=receptor_curves)
    write_table(outputs["responses"], view.columns)
    with atomic_path(outputs["irradiance"]) as tmp:
        np.savez(tmp, id=eye.table.id, wavelength_nm=view.wavelengths_nm,
                 radiance_se=np.concatenate([p["radiance_se"] for p in parts]), **view.spectra)


def human_view(scene_file, outputs, *, spectral, trace, threads, samples):
    """What a person sees of a scene through its pinhole camera: ``outputs["png"]`` and ``["exr"]``.

    Traced like the receptors (``samples`` rays per pixel, the config's
    ``trace`` section otherwise), then mapped through the CIE 1931 observer
    to sRGB (PNG, the 99th percentile of luminance as white) and written as
    linear XYZ (EXR, channels ``X``, ``Y``, ``Z``).
    """
    xyz = photograph(load_scene(scene_file, **spectral), samples=samples, trace=trace, threads=threads)
    write_png(outputs["png"], human_srgb(xyz))
    write_exr(outputs["exr"], xyz, ("X", "Y", "Z"))
