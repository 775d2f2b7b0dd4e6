"""The tracer's entry points, under the Python API (:mod:`beeoptics.api`): acceptance cones traced
to their mean spectral radiance with its replicates, that radiance turned into every receptor's
catches and colour coordinates, and a pinhole camera's image.

The stages, the command line and the benchmarks reach these through the API, not directly.
"""

import logging
import threading
import time

import numpy as np

from beeoptics.eye.optics import acceptance_solid_angle
from beeoptics.io.errors import InputError
from beeoptics.io.validation import check_background, config_default
from beeoptics.light.batching import trace_bundles
from beeoptics.light.integrator import trace_paths
from beeoptics.light.precision import adaptive_samples, neighbourhoods, replicate_samples
from beeoptics.light.scene import back_faces_met, raycasting_scene, receptors_in_world
from beeoptics.light.sensors import cone_samples, cone_sigma, pinhole_rays
from beeoptics.replicates import standard_error
from beeoptics.sky.dome import white_radiance
from beeoptics.vision.adaptation import background_catches
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.human import srgb, tristimulus
from beeoptics.vision.receptorset import (DEFAULT_CURVES, brightness_weights, curves, lacking, ommatidium_names,
                                          ommatidium_types)
from beeoptics.vision.uncertainty import colour_columns

log = logging.getLogger("beeoptics")

#: The share of receptors meeting back faces that says an eye is enclosed: below a ground or inside a
#: closed mesh every one does; among two-sided blades and petals about half do (58 % of the worker's in
#: the generated meadow), so a bare majority would warn of every meadow.
BACK_FACES_ENCLOSED = 0.9
#: Percentile of the human view's luminance shown as white.
HUMAN_WHITE_PERCENTILE = 99.0


def trace_receptors(scene, table, first, last, settings, n_wavelengths, progress=None, rs=None, polarised=False,
                    target=None, sensitivities=None, errors=None, enclosure=True, deferred=False):
    """The mean spectral radiance (last − first, n_wavelengths) of receptors ``first``..``last`` of a table,
    and the ray counts, wall and CPU seconds (as :func:`trace_part`); ``rs``, the scene's Embree scene if already built.

    ``polarised``: the spectral Stokes vectors instead, (last − first, 3, n_wavelengths), each in
    the frame of the head's dorsal direction about the receptor's samples
    (:func:`beeoptics.light.integrator.trace_paths`). ``target``, a sphere
    (centre, radius; scene units): also the share of each receptor's
    acceptance whose samples met it first, (last − first,), a third result.
    ``sensitivities``, ``errors`` and ``deferred``: as :func:`trace_cones` takes them. ``enclosure``: warn
    where the eye seems enclosed (its receptors' axes meeting back faces, a ray each); a closed loop asks it
    of its first look only, its steps stopping at surfaces."""
    origins, axes = receptors_in_world(scene, table.position, table.axis)
    rs = raycasting_scene(scene) if rs is None else rs
    met, back = back_faces_met(rs, origins[first:last], axes[first:last]) if enclosure else (0, 0)
    if back > BACK_FACES_ENCLOSED * met:
        log.warning("%.0f%% of the receptors whose axis meets a surface meet its back face (%d of %d): the eye "
                    "may sit below the ground or inside a closed mesh; the scene's eye.position_m places it",
                    100.0 * back / met, back, met)
    each = (f"{settings.samples} samples each" if settings.precision is None else
            f"samples to the precision asked, after a pilot of {settings.precision.min_samples}")
    log.info("tracing receptors %d to %d: %s, depth %d, on %d threads", first, last, each, settings.depth,
             settings.threads)
    # Each receptor draws the random numbers of its id, so that it is traced alike in any table that holds it.
    out = trace_cones(scene, origins, axes, table.delta_rho_deg, np.asarray(table.id, np.int64), first, last,
                      settings, n_wavelengths, progress, rs, scene.eye_rotation[:, 2] if polarised else None, target,
                      sensitivities, errors, deferred)
    counts = out[1]
    log.info("traced receptors %d to %d: %d rays and %d shadow rays in %.1f s", first, last, counts["cast"],
             counts["shadow"], counts["seconds"])
    return out


def trace_cones(scene, origins, axes, delta_rho_deg, streams, first, last, settings, n_wavelengths, progress=None,
                rs=None, dorsal=None, target=None, sensitivities=None, errors=None, deferred=False):
    """The mean spectral radiance of acceptance cones ``first``..``last`` at ``origins`` (m) along ``axes``,
    and the ray counts, wall and CPU seconds, as :func:`trace_receptors` gives them.

    Each cone is traced as independent replicates (:func:`beeoptics.light.precision.replicate_samples`),
    its radiance their mean (:mod:`beeoptics.light.precision`): of ``settings.samples`` samples in all,
    or, with ``settings.precision``, as many as the pilots of its neighbourhood (it and the cones nearest
    it in axis and origin among all the ``origins``, :func:`beeoptics.light.precision.neighbourhoods`, so
    that a share ``first``..``last`` takes the samples the whole would) say it needs for the precision
    asked of its catches (of ``sensitivities``' classes, or without them of the radiance summed over the
    grid).

    Parameters
    ----------
    delta_rho_deg : ndarray (n,)
        Each cone's acceptance angle.
    streams : ndarray of int (n,)
        Each cone's random-number stream: a cone of the same stream, origin
        and axis is traced the same in any call.
    dorsal : ndarray (3,) or (n, 3), optional
        The head's dorsal direction, or one per cone: with it, Stokes vectors in its frame
        (:func:`trace_receptors`' ``polarised``).
    target : (ndarray, float or ndarray), optional
        A sphere (centre, radius), or one per cone ((n, 3), (n,)): also each
        cone's share that met it first, a third result.
    sensitivities : (ndarray, ndarray), optional
        The spectral grid (nm) and the receptor classes' sensitivities on it
        (n_wavelengths, k), as :func:`respond` makes them: the catches of each
        replicate (of the Stokes vector's intensity where polarised).
    errors : dict, optional
        Filled with each cone's ``radiance_se`` (the radiance's standard
        error, the radiance's shape), ``samples`` (the samples of its
        estimate, (n,); an adaptive trace's pilot of ``min_samples`` is
        not among them) and, with ``sensitivities``, ``catches``: each replicate's catches
        (n, replicates, k) over the acceptance solid angle, as
        :func:`respond` computes them from the mean.
    deferred : bool
        Fill ``errors`` with the ``replicates`` themselves (n, replicates, columns) in place of
        ``radiance_se`` and ``catches``, which :func:`replicate_errors` makes of them when asked (a
        closed loop observes its catches alone, and the errors are most of the work after the trace).
    """
    sigma = cone_sigma(delta_rho_deg)
    rs = raycasting_scene(scene) if rs is None else rs
    counts, counting = {"cast": 0, "shadow": 0}, threading.Lock()
    start, cpu = time.perf_counter(), time.process_time()
    centres = radii = None
    if target is not None:
        centres = np.broadcast_to(np.asarray(target[0], float), (len(origins), 3))
        radii = np.broadcast_to(np.asarray(target[1], float), (len(origins),))

    def trace(blocks):
        b = blocks.bundle
        dirs, weights = cone_samples(axes[b], delta_rho_deg[b], blocks.samples, settings.seed,
                                     streams=streams[b], first_samples=blocks.first_sample)
        cast = {}
        radiance = trace_paths(scene, origins[b], dirs, weights, depth=settings.depth, seed=settings.seed,
                               streams=streams[b], first_samples=blocks.first_sample, rs=rs, counts=cast,
                               cones=(axes[b], sigma[b]),
                               frames=None if dorsal is None else np.broadcast_to(dorsal, (len(origins), 3))[b],
                               target=None if target is None else (centres[b], radii[b]),
                               sky_sampling=settings.sky_sampling)
        with counting:
            for k, v in cast.items():
                counts[k] += v
        if target is not None:
            # The share rides along as one more column, averaged over sample blocks as the radiance is.
            radiance = np.column_stack([radiance[0].reshape(len(b), -1), radiance[1]])
        return radiance.reshape(len(b), -1), weights.sum(axis=1)

    stokes = 1 if dorsal is None else 3
    columns = stokes * n_wavelengths + (target is not None)
    omega = acceptance_solid_angle(np.broadcast_to(delta_rho_deg, (len(origins),)))

    precision = settings.precision
    if precision is None:
        k, m = replicate_samples(settings.samples)
        samples = np.full(last - first, m)
        replicates = trace_bundles(trace, first, last, settings, columns, samples, range(k), progress)
    else:
        # Stein's two stages (beeoptics.light.precision): the pilots of each cone's neighbourhood fix its
        # samples, fresh replicates of them make its estimate. Of a Stokes vector, the intensity's catches decide.
        k, m = replicate_samples(precision.min_samples)
        # The pilot of every cone in the share's neighbourhoods, whichever share holds it: a cone's pilot
        # draws the random numbers of its own stream, so a share sees the pilots any other share would.
        near = neighbourhoods(origins, axes)[first:last]
        cones, rows = np.unique(near, return_inverse=True)

        def trace_pilot(blocks):
            return trace(blocks._replace(bundle=cones[blocks.bundle]))

        # The pilot's own K replicates (fewer than eight where min_samples is below eight), and no progress
        # of its own: the bar follows the estimate's trace.
        pilot = trace_bundles(trace_pilot, 0, len(cones), settings, columns, np.full(len(cones), m), range(k))
        white = cone_catches(np.broadcast_to(white_radiance(scene.sky, scene.sun, n_wavelengths),
                                             (len(cones), n_wavelengths)), omega[cones], sensitivities)
        samples = adaptive_samples(cone_catches(pilot[..., :n_wavelengths], omega[cones], sensitivities), white,
                                   precision, rows.reshape(near.shape))
        replicates = trace_bundles(trace, first, last, settings, columns, samples, range(k, 2 * k), progress)
        if len(samples):
            log.info("adaptive sampling: %d to %d samples a cone, %.0f on average, after a pilot of %d",
                     k * samples.min(), k * samples.max(), k * samples.mean(), k * m)
    radiance = replicates.mean(axis=1)
    cover = None
    if target is not None:
        radiance, cover, replicates = radiance[:, :-1], radiance[:, -1], replicates[..., :-1]
    if errors is not None:
        errors["samples"] = k * samples
        if deferred:
            errors["replicates"] = replicates
        else:
            errors.update(replicate_errors(replicates, omega[first:last], sensitivities, n_wavelengths))
    if dorsal is not None:
        radiance = radiance.reshape(-1, stokes, n_wavelengths)
    counts["seconds"], counts["cpu_seconds"] = time.perf_counter() - start, time.process_time() - cpu
    return (radiance, counts) if target is None else (radiance, counts, cover)


def cone_catches(spectra, omega, sensitivities):
    """Catches over the acceptance of radiance spectra (n, ..., n_wavelengths) of cones of acceptance solid
    angles ``omega`` (n,), sr: of ``sensitivities`` (the grid, nm, and the curves on it, (n_wavelengths,
    k)), photons m⁻² s⁻¹, or without them a flat receptor's (the radiance summed over the grid): (n, ..., k)."""
    irradiance = spectra * omega.reshape(-1, *[1] * (spectra.ndim - 1))
    if sensitivities is None:
        return irradiance.sum(axis=-1, keepdims=True)
    return quantum_catches(irradiance, sensitivities[1], sensitivities[0])


def replicate_errors(replicates, omega, sensitivities, n_wavelengths):
    """What cones' replicates (n, K, n_wavelengths or 3 × n_wavelengths, a Stokes vector's) say of their
    errors: ``radiance_se``, the mean radiance's standard error (n, n_wavelengths), or (n, 3, n_wavelengths)
    of a Stokes vector, and with ``sensitivities`` (as :func:`cone_catches` takes them) ``catches``, each
    replicate's catches (n, K, k) over the acceptance solid angles ``omega`` (n,), sr, of the intensity."""
    se = standard_error(replicates)
    out = {"radiance_se": se if se.shape[1] == n_wavelengths else se.reshape(len(se), -1, n_wavelengths)}
    if sensitivities is not None:
        # Of the intensity, where the radiance is a Stokes vector: its first n_wavelengths columns.
        out["catches"] = cone_catches(replicates[..., :n_wavelengths], omega, sensitivities)
    return out


def class_catches(table, radiance, wl, receptor_set, sensitivities, replicate_catches=None):
    """Every receptor's catch of each class (photons m⁻² s⁻¹, :func:`respond`'s), NaN for a class its
    ommatidium lacks, and the catches' standard errors over the trace's replicates: what a look's catches
    table holds, without the colour that :func:`respond` adds.

    Parameters
    ----------
    radiance : ndarray (n, wavelengths)
        Each receptor's mean spectral radiance, W m⁻² sr⁻¹ nm⁻¹.
    sensitivities : ndarray (wavelengths, classes)
        The set's curves on ``wl`` (:func:`beeoptics.vision.receptorset.curves`).
    replicate_catches : ndarray (n, K, classes), optional
        The trace's replicate catches (:func:`trace_cones`).

    Returns
    -------
    catches : ndarray (n, classes)
    se : ndarray (n, classes) or None
        None without replicates.
    replicates : ndarray (n, K, classes) or None
        ``replicate_catches`` with the lacking classes NaN, as the colour's errors take them.
    """
    omega = acceptance_solid_angle(table.delta_rho_deg)
    catches = quantum_catches(radiance * omega[:, None], sensitivities, wl)
    catches[lacking(receptor_set, ommatidium_types(receptor_set, len(table.id)))] = np.nan
    if replicate_catches is None:
        return catches, None, None
    replicate_catches = np.where(np.isnan(catches)[:, None, :], np.nan, replicate_catches)
    return catches, standard_error(replicate_catches), replicate_catches


def respond(table, radiance, scene, wl, scene_file, *, receptor_set, background=config_default("colour.background"),
            receptor_curves=DEFAULT_CURVES, replicate_catches=None):
    """Every receptor's catches and colour coordinates from its spectral radiance (n, wavelengths) on the grid ``wl``.

    Returns the responses table's columns (id, side, its acceptance solid
    angle ``acceptance_sr``, a catch per class of ``receptor_set`` named as
    the set names it (UV, B, G for a bee), the brightness where the set has
    an overall sensitivity, colour-space coordinates) and the arrays of the
    irradiance file:
    ``radiance``, ``irradiance`` (float32), ``background_q`` (the adapting
    catches), ``white_radiance`` (a white Lambertian surface under the
    scene's sky and sun) and ``white_q`` (each receptor's catch of it,
    map3's unity). See :func:`gather_responses` for ``background``.

    Every column of colour is computed from the table's own columns: a
    receptor adapts through its own acceptance, so that its Δρ moves none of
    its colour coordinates. Its catch over ``acceptance_sr`` (a radiance
    catch) is divided by the background's: for ``"scene"`` the mean of
    that over the table's receptors that have the class, for a material
    the radiance catch of that surface (``background_q``).

    ``replicate_catches`` (n, K, classes), the trace's K independent
    replicate estimates of each receptor's catches (:func:`trace_cones`):
    with them, each catch and each colour column has its standard error
    beside it, ``se_<column>`` (:func:`beeoptics.vision.uncertainty.colour_columns`;
    empty where one replicate gives none, or the receptor lacks the class).
    """
    sens = curves(receptor_set, wl, receptor_curves)
    catches, se, replicate_catches = class_catches(table, radiance, wl, receptor_set, sens, replicate_catches)
    omega = acceptance_solid_angle(table.delta_rho_deg)
    irradiance = radiance * omega[:, None]
    types = ommatidium_types(receptor_set, len(table.id))
    seen = catches / omega[:, None]
    # A white Lambertian surface under the scene's sky and sun: what a named
    # background reflects, and the photon flux of the spectral locus's lights.
    white = white_radiance(scene.sky, scene.sun, len(wl))
    surface = None
    if background != "scene":
        check_background(scene_file, background, scene_file, "materials")
        surface = scene.reflectance[scene.material_names.index(background)] * white
    reference = background_catches(seen, sens, wl, surface)
    if not (reference > 0.0).all():
        raise InputError(scene_file, "colour.background",
                         f"the background {background!r} gives no catch in some receptor class; "
                         "von Kries adaptation needs a background every class sees")
    columns = {"id": table.id, "side": table.side}
    if types is not None:
        columns["ommatidium"] = ommatidium_names(receptor_set, types)
    columns["acceptance_sr"] = omega
    for k, r in enumerate(receptor_set.classes):
        columns[r] = catches[:, k]
        if se is not None:
            columns[f"se_{r}"] = se[:, k]
    weights = brightness_weights(receptor_set, wl, sens)
    if weights is not None:
        columns["brightness"] = catches @ weights
    columns.update(colour_columns(seen, reference, receptor_set,
                                  None if replicate_catches is None else replicate_catches / omega[:, None, None]))
    # What each receptor would catch of the white surface: map3's unity.
    white_q = quantum_catches(white[None] * omega[:, None], sens, wl)
    return columns, {"radiance": radiance.astype(np.float32), "irradiance": irradiance.astype(np.float32),
                     "background_q": reference, "white_radiance": white, "white_q": white_q}


def render_human(scene, camera, settings, wavelengths, rs=None):
    """The CIE 1931 XYZ image (height, width, 3) of ``scene`` through a pinhole ``camera`` (a scene's
    ``camera`` section), ``settings.samples`` rays a pixel; ``rs``, the scene's Embree scene if built."""
    origin, dirs = pinhole_rays(camera, settings.samples, settings.seed)
    rs = raycasting_scene(scene) if rs is None else rs

    def trace(blocks):
        ones = np.ones((len(blocks.bundle), blocks.samples))
        return trace_paths(scene, np.broadcast_to(origin, (len(blocks.bundle), 3)),
                           dirs[blocks.bundle[:, None], blocks.first_sample[:, None] + np.arange(blocks.samples)], ones,
                           depth=settings.depth, seed=settings.seed, streams=blocks.bundle,
                           first_samples=blocks.first_sample, rs=rs), ones.sum(axis=1)

    # A pixel is one replicate of all its samples: an image carries no errors, and its rays were drawn at once.
    radiance = trace_bundles(trace, 0, len(dirs), settings, len(wavelengths), np.full(len(dirs), settings.samples),
                             range(1))[:, 0]
    xyz = tristimulus(wavelengths, radiance)
    return xyz.reshape(camera["height_px"], camera["width_px"], 3)


def human_srgb(xyz):
    """A human view's display sRGB in [0, 1]: the :data:`HUMAN_WHITE_PERCENTILE` of luminance as white."""
    return srgb(xyz, np.percentile(xyz[..., 1], HUMAN_WHITE_PERCENTILE))
