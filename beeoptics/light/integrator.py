"""The integrator: spectral path tracing with Open3D's RaycastingScene (Embree).

Every ray, primary, shadow or bounce, is cast through Open3D's
``RaycastingScene``: ``cast_rays`` for the paths, ``test_occlusions`` for
the shadow rays of next-event estimation towards the sun.

Light transport. A path starts along a sampled direction of a sensor
(:mod:`beeoptics.light.sensors`): a receptor's acceptance cone or a pixel. Where it leaves
the scene it sees the sky (and, on its first segment only, the sun's
disc). Where it meets a surface it collects the surface's emission, the
sun's light by next-event estimation, with a shadow ray
(:mod:`beeoptics.light.emitters`), and then scatters
(:mod:`beeoptics.light.scattering`). ``depth`` bounds the number of
scattering events: depth 1 is direct light only (sun, sky and emitters
seen from the first surface). After the second scattering, Russian
roulette ends paths in proportion to their throughput.

The sun in a receptor's cone. The sun's disc (0.27° across) is rarely hit
by a cone's samples: with 256 samples a 2.6° receptor 2–4.5° off the sun
expects 0.18 hits, so it would see the sky alone or a flash tens of times
too bright. For receptors' cones (``cones``) the disc is therefore also
sampled directly, once per cone sample, uniformly over its solid angle and
with a shadow ray, and the two strategies are combined by the balance
heuristic of multiple importance sampling (Veach 1997, ch. 9): a sample of
either kind counts with weight A(θ)/(2πσ² (p_cone + p_sun)), in the units
of the cone's samples, with A the Gaussian acceptance, p_cone the cone's
sampling density (:func:`beeoptics.light.sensors.cone_density`) and p_sun
one over the disc's solid angle. The estimate stays unbiased, and its noise
small wherever the sun falls in the cone.

Spectra. Diffuse scattering multiplies a path's spectral throughput by
the material's reflectance; glossy scattering, emission geometry and
sampling weights are spectrally flat. A path's throughput is therefore
exactly a scalar weight times the product of the reflectance spectra of
the materials it scattered from, in order: the path carries that scalar
and the sequence (as an integer key, numbered in order of appearance), and
the products are formed once per distinct sequence, on the full spectral
grid, when the contributions are summed. Light likewise is a flat weight
times one of a few spectra (the sky's basis, the sun's radiance, a
material's emission). The result is the full spectrum, with no RGB or
band-limited shortcut, at the cost of scalar arithmetic per ray.

Compiled shading. Between two casts, everything runs in compiled kernels
(numba; :mod:`beeoptics.jit`), one path at a time and serially within a
batch: what each ray met (:func:`_arrive`, a loop over the paths through
its stages, after pbrt-v4's wavefront integrator and Mitsuba 3's path
integrator: the sky and the sun's disc seen, emission, next-event
estimation of the sun and of the sky, scattering and roulette), the sun and
the sky through the unblocked shadow rays (:func:`_through`), and each
bundle's spectral sum (:func:`_sum_contributions`). The kernels take the
paths' state, their hits, the surfaces, the lights and the cones as named
tuples of arrays (:class:`Paths`, :class:`Hits`,
:class:`beeoptics.light.scattering.SurfaceArrays`,
:class:`beeoptics.light.emitters.LightArrays`,
:class:`beeoptics.light.sensors.Cones`; the last three made once per
trace). Only Embree's calls and the material lookup of the hits are
outside them.

Randomness. Each random number is a hash (see :mod:`beeoptics.light.sampler`)
of the seed, the receptor's index, the sample's index and the dimension,
so a receptor's result does not depend on which others are traced with it:
a run split into chunks gives bit-identical results.

References
----------
Kajiya JT (1986) The rendering equation. Proc SIGGRAPH 86:143–150.
Veach E (1997) Robust Monte Carlo methods for light transport simulation.
PhD thesis, Stanford University (next-event estimation, Russian roulette,
multiple importance sampling).
Lafortune EP, Willems YD (1994) Using the modified Phong reflectance model
for physically based rendering. Report CW197, KU Leuven.
Steele GL, Lea D, Flood CH (2014) Fast splittable pseudorandom number
generators. Proc OOPSLA 2014:453–472.
Pharr M, Jakob W, Humphreys G (2023) Physically Based Rendering, 4th ed.
MIT Press, ch. 15 (wavefront rendering).
Jakob W, Speierer S, Roussel N, Nimier-David M, Vicini D, Zeltner T,
Nicolet B, Crespo M, Leroy V, Zhang Z (2022) Mitsuba 3 renderer, version
3.0.1. https://mitsuba-renderer.org (its ``path`` integrator).
"""

import threading
from typing import NamedTuple

import numpy as np

from beeoptics.jit import NumbaModule, kernel, stage
from beeoptics.light.emitters import LightArrays, Lights, sample_sun
from beeoptics.light.mueller import depolarise, double_angle, plane_normal, reflect, reflect_column
from beeoptics.light.sampler import STREAMS, shifted_halton, tangent_frames, uniform1
from beeoptics.light.scattering import SurfaceArrays, Surfaces, glossy_share, lobes, scatter
from beeoptics.light.scene import raycasting_scene
from beeoptics.light.sensors import Cones, cone_density
from beeoptics.raycasting import first_hits, occluded
from beeoptics.sky.hosekwilkie import shape_radiance
from beeoptics.sky.sampling import sample_sky, sky_density, sky_table
from beeoptics.sky.skypolarisation import degree, polarisation

#: Ray origins leave a surface by this fraction of the scene's size.
OFFSET = 1e-7
#: Russian roulette starts after this many scattering events.
ROULETTE_AFTER = 2
#: Random dimensions drawn per scattering event: the sun's sample (2), the scattering (3), roulette,
#: the sky's sample (2).
DIMENSIONS_PER_EVENT = 8
#: How the sky is sampled (:func:`trace_paths`), the default first.
SKY_SAMPLING = ("nee", "escape")
#: A sun sample in a receptor's cone is not cast where the cone's acceptance there is below this: 7.4 σ
#: off the axis, its weight is 10⁻¹² of the axis's, below what the radiance, kept in single precision,
#: resolves; and it spares the shadow rays of the many receptors that look away from the sun.
NEGLIGIBLE_ACCEPTANCE = 1e-12
#: Random dimensions of the sun's samples in a receptor's cone, apart from the events' and the cones'.
SUN_DIMENSIONS = (254, 255)
#: numba's typed containers and types, for the kernels that number sequences of materials.
typed, types = NumbaModule("numba.typed"), NumbaModule("numba.types")


class Paths(NamedTuple):
    """The paths' state as the compiled kernels take it (numba takes named tuples of arrays), updated in place.

    One row per path (a sensor's sample), but ``rays``, one per live path.

    Attributes
    ----------
    rays : ndarray (m, 6) float32
        The live paths' rays as Embree casts them, origin then direction, in the order of the live paths.
    w : ndarray (N,)
        The throughput's flat weight (the spectra of its materials are its ``key``'s).
    key : ndarray of int (N,)
        The number of its sequence of materials (:func:`_arrive`).
    bound : ndarray (N,)
        An upper bound of the throughput's spectral maximum, for Russian roulette.
    mueller : ndarray (N, 3, 3), or (0, 3, 3) without polarisation
        The chain of Mueller matrices from the path's bundle to its ray.
    frame : ndarray (N, 3), or (0, 3) without polarisation
        Its ray's reference direction for polarisation.
    last_pdf : ndarray (N,)
        The density, sr⁻¹, with which its last scattering drew its ray (the lobe's probability times the
        lobe's density), 0 for a sensor's ray.
    bundle, stream, sample : ndarray of int (N,)
        Its bundle (a receptor or a pixel), that bundle's random stream, and its sample's index there.
    """

    rays: np.ndarray
    w: np.ndarray
    key: np.ndarray
    bound: np.ndarray
    mueller: np.ndarray
    frame: np.ndarray
    last_pdf: np.ndarray
    bundle: np.ndarray
    stream: np.ndarray
    sample: np.ndarray


class Hits(NamedTuple):
    """What the live paths' rays met, one row per ray: the distance ``t_hit`` (m,) float32, scene units; the
    surface's normal ``normals`` (m, 3); its ``material`` (m,), −1 where the ray left the scene."""

    t_hit: np.ndarray
    normals: np.ndarray
    material: np.ndarray


class ShadowRays(NamedTuple):
    """Shadow rays towards a light's samples, and the light each brings where it is not blocked.

    Attributes
    ----------
    rays : ndarray (k, 6) float32
        Origin and direction.
    row : ndarray of int (k,)
        The row among the live paths of the path each leaves.
    lit : ndarray (k, 2, lights, 1 or 3)
        Its Lambertian and its glossy lobe's weight (or Stokes vector) of each of the light's spectra: the
        sun's one, or the sky's basis spectra.
    key : ndarray of int (k, 2)
        The two lobes' keys (the diffuse lobe's adds the material to the path's sequence).
    """

    rays: np.ndarray
    row: np.ndarray
    lit: np.ndarray
    key: np.ndarray


class Vertices(NamedTuple):
    """Where the live paths meet surfaces, one row per live path, for :func:`_arrive`'s stages.

    Attributes
    ----------
    du : ndarray (m, 3), or (0, 3) without polarisation
        The ray's direction at full precision and unit length: the polarisation's frames and angles are taken
        from it, not from Embree's single precision.
    normal, mirror, back : ndarray (m, 3)
        The surface's normal, facing the ray; the mirror direction; back along the ray (the view).
    p_glossy : ndarray (m,)
        The probability of sampling the glossy lobe there (:func:`beeoptics.light.scattering.glossy_share`).
    rho_key : ndarray of int (m,)
        The number of the path's sequence of materials with this one added: its key after a diffuse scattering.
    """

    du: np.ndarray
    normal: np.ndarray
    mirror: np.ndarray
    back: np.ndarray
    p_glossy: np.ndarray
    rho_key: np.ndarray


@kernel
def _put(out, scale, mueller, i):
    """A contribution's weight ``out`` (1 or 3,): ``scale`` alone (intensity only), or times the Stokes vector
    that unpolarised light arriving in path ``i``'s frame makes at its bundle (the first column of its Mueller
    chain)."""
    if len(out) == 1:
        out[0] = scale
    else:
        for k in range(3):
            out[k] = scale * mueller[i, k, 0]


@kernel
def _arrive(event, depth, live, paths, hits, surfaces, lights, cones, sequences, numbers, seed, eps):
    """What the live paths (indices ``live``) meet along their rays: light where they leave the scene or meet a
    glowing surface (as contributions), and, at a surface, the shadow rays towards the sun and the sky and
    the scattered ray.

    Updates ``paths`` (:class:`Paths`) in place: the scattered rays, and the paths' weight, key, bound,
    last density and, with polarisation, their Mueller chains and frames. A path's key is the number of its
    sequence of materials in ``sequences`` (a list of the sequences' integers, added to here, with
    ``numbers`` its inverse), so that the contributions' columns are small, dense numbers. With
    polarisation, every contribution is a Stokes vector at the bundle (I, Q, U). The sky's degree of
    polarisation is taken at each basis spectrum's wavelength, so its light stays one contribution per basis
    spectrum. ``hits`` (:class:`Hits`) is what the rays met; ``surfaces``, ``lights`` and ``cones`` are
    :class:`beeoptics.light.scattering.SurfaceArrays`, :class:`beeoptics.light.emitters.LightArrays` and
    :class:`beeoptics.light.sensors.Cones`; ``eps``, scene units, how far a ray's origin leaves a surface.

    The stages run in turn, each over its queue of live rows, those that left the scene (``escaped``) or
    those that met a surface (``met``), as pbrt-v4's wavefront integrator does: the sky and the sun's disc
    seen, emission, then, unless this is the last event, where the paths meet the surfaces, the sun's and the
    sky's next-event estimation, and scattering. A stage takes the records' arrays out once, not once per
    path: numba counts the references to an array taken out of a record, which per path made the tracer
    twice as slow. A path's state is only its own stages', so the result is what one path after another
    through all of them would give; each light's contributions keep the paths' order, and with it every
    sum's.

    Returns
    -------
    contributions : (bundle, combo, weights (k, 1 or 3)) arrays
    sun, sky : ShadowRays
        Towards the sun's samples, and towards the sky's (with ``lights.sky_nee``).
    scattered : ndarray of bool (m,)
        The live paths that go on.
    """
    m = len(live)
    n_stokes = 3 if len(paths.mueller) else 1
    n_sky = lights.sky_shape.shape[0] if lights.has_sky else 0
    m_sky = m if lights.sky_nee else 0
    found = (np.empty(m * (n_sky + 1), np.int64), np.empty(m * (n_sky + 1), np.int64),
             np.empty((m * (n_sky + 1), n_stokes)))
    sun = ShadowRays(np.empty((m, 6), np.float32), np.empty(m, np.int64), np.empty((m, 2, 1, n_stokes)),
                     np.empty((m, 2), np.int64))
    sky = ShadowRays(np.empty((m_sky, 6), np.float32), np.empty(m_sky, np.int64),
                     np.empty((m_sky, 2, max(n_sky, 1), n_stokes)), np.empty((m_sky, 2), np.int64))
    at = Vertices(np.empty((m if n_stokes == 3 else 0, 3)), np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3)),
                  np.empty(m), np.empty(m, np.int64))
    scattered = np.zeros(m, np.bool_)
    # The queues of the live rows that left the scene and that met a surface, each in the paths' order.
    escaped, met = np.flatnonzero(hits.material < 0), np.flatnonzero(hits.material >= 0)
    dim = event * DIMENSIONS_PER_EVENT
    _incoming(paths.rays, at.du)
    nc = ns = nk = 0
    if n_sky:
        nc = _sky_seen(escaped, live, paths, lights, at, found, nc)
    if event == 0 and lights.sun_row >= 0:
        # The sun's disc on first sight only: after a surface, next-event estimation has counted it.
        nc = _sun_seen(escaped, live, paths, lights, cones, found, nc)
    nc = _emission(met, live, paths, hits, surfaces, lights, found, nc)
    if event < depth:
        _meet(met, live, paths, hits, surfaces, sequences, numbers, eps, at)
        if lights.sun_row >= 0:
            ns = _sun_nee(dim, met, live, paths, hits, surfaces, lights, seed, at, sun)
        if n_sky and lights.sky_nee:
            nk = _sky_nee(dim, met, live, paths, hits, surfaces, lights, seed, at, sky)
        _scatter(event, dim, met, live, paths, hits, surfaces, lights.sky_nee, seed, at, scattered)
    return ((found[0][:nc], found[1][:nc], found[2][:nc]), _first(sun, ns), _first(sky, nk), scattered)


@stage
def _first(shadows, n):
    """The first ``n`` of ``shadows``."""
    return ShadowRays(shadows.rays[:n], shadows.row[:n], shadows.lit[:n], shadows.key[:n])


@stage
def _incoming(rays, du):
    """The rays' directions at full precision and unit length into ``du`` (m, 3; (0, 3), and nothing to do,
    without polarisation)."""
    for r in range(len(du)):
        x, y, z = np.float64(rays[r, 3]), np.float64(rays[r, 4]), np.float64(rays[r, 5])
        norm = np.sqrt(x * x + y * y + z * z)
        du[r, 0], du[r, 1], du[r, 2] = x / norm, y / norm, z / norm


@stage
def _sky_seen(escaped, live, paths, lights, at, found, nc):
    """The sky's light where the paths leave the scene, per basis spectrum, appended to the contributions
    ``found`` from row ``nc``: weighed, where a ray was scattered and the sky is sampled too, against the sky
    table's sample of the same direction. Returns the contributions' new count."""
    rays, du = paths.rays, at.du
    w, key, bundle, mueller, frame, last_pdf = paths.w, paths.key, paths.bundle, paths.mueller, paths.frame, paths.last_pdf
    sky_sun, shape, floor, offset, hemisphere = (lights.sky_sun, lights.sky_shape, lights.sky_floor,
                                                 lights.sky_offset, lights.sky_hemisphere)
    neutral, max_degree, depolarisation = lights.sky_neutral, lights.sky_max_degree, lights.sky_depolarisation
    table, sky_nee, n_lights = lights.sky_table, lights.sky_nee, lights.n_lights
    c_bundle, c_combo, c_weight = found
    sky, d, e_vector = np.empty(len(shape)), np.empty(3), np.empty(3)
    for r in escaped:
        i = live[r]
        for k in range(3):
            d[k] = rays[r, 3 + k]
        shape_radiance(d[0], d[1], d[2], sky_sun, shape, floor, offset, hemisphere, sky)
        if sky_nee and last_pdf[i] > 0.0:
            norm = np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            p_table = sky_density(table, d[0] / norm, d[1] / norm, d[2] / norm)
            mis = last_pdf[i] / (last_pdf[i] + p_table)
            for k in range(len(sky)):
                sky[k] *= mis
        size = c2 = s2 = 0.0
        if len(mueller):
            size = polarisation(du[r, 0], du[r, 1], du[r, 2], sky_sun, neutral, e_vector)
            c2, s2 = double_angle(e_vector[0], e_vector[1], e_vector[2], frame[i], du[r])
        for k in range(len(sky)):
            if sky[k] != 0.0:
                c_bundle[nc], c_combo[nc] = bundle[i], key[i] * n_lights + k
                if not len(mueller):
                    c_weight[nc, 0] = w[i] * sky[k]
                else:
                    # The degree at the basis spectrum's wavelength.
                    p = degree(size, max_degree, depolarisation[k])
                    q_sky, u_sky = p * c2, p * s2
                    for q in range(3):
                        c_weight[nc, q] = w[i] * sky[k] * (mueller[i, q, 0] + mueller[i, q, 1] * q_sky
                                                           + mueller[i, q, 2] * u_sky)
                nc += 1
    return nc


@stage
def _sun_seen(escaped, live, paths, lights, cones, found, nc):
    """The sun's light where the paths' first rays leave the scene within its disc, appended to the
    contributions ``found`` from row ``nc``; in a receptor's cone, weighed against the sun's own samples
    (:func:`_sun_in_cones`) by the balance heuristic. Returns the contributions' new count."""
    rays, w, key, bundle, mueller = paths.rays, paths.w, paths.key, paths.bundle, paths.mueller
    sun_dir, sun_cos, p_sun, column = lights.sun_dir, lights.sun_cos, 1.0 / lights.sun_solid_angle, lights.sun_row
    axis, sigma = cones.axis, cones.sigma
    c_bundle, c_combo, c_weight = found
    for r in escaped:
        x, y, z = np.float64(rays[r, 3]), np.float64(rays[r, 4]), np.float64(rays[r, 5])
        if not x * sun_dir[0] + y * sun_dir[1] + z * sun_dir[2] >= sun_cos:
            continue
        i = live[r]
        b = bundle[i]
        weight = w[i]
        if sigma[b] > 0.0:
            cos_a = axis[b, 0] * x + axis[b, 1] * y + axis[b, 2] * z
            q = cone_density(np.arccos(min(max(cos_a, -1.0), 1.0)), sigma[b])
            weight *= q / (q + p_sun)
        c_bundle[nc], c_combo[nc] = b, key[i] * lights.n_lights + column
        _put(c_weight[nc], weight, mueller, i)
        nc += 1
    return nc


@stage
def _emission(met, live, paths, hits, surfaces, lights, found, nc):
    """The light of the glowing materials the paths meet, appended to the contributions ``found`` from row
    ``nc``. Returns their new count."""
    material, w, key, bundle, mueller, glows = hits.material, paths.w, paths.key, paths.bundle, paths.mueller, surfaces.glows
    row, n_lights = surfaces.emission_row, lights.n_lights
    c_bundle, c_combo, c_weight = found
    for r in met:
        mat = material[r]
        if not glows[mat]:
            continue
        i = live[r]
        c_bundle[nc], c_combo[nc] = bundle[i], key[i] * n_lights + row + mat
        _put(c_weight[nc], w[i], mueller, i)
        nc += 1
    return nc


@stage
def _meet(met, live, paths, hits, surfaces, sequences, numbers, eps, at):
    """Where the live rays meet surfaces: the normal facing each ray, the mirror direction, the view, the
    glossy lobe's probability and the key after a diffuse scattering into ``at``; each ray's origin moved to
    the point just off the surface."""
    rays, key, material, normals, t_hit = paths.rays, paths.key, hits.material, hits.normals, hits.t_hit
    normal, mirror, back, p_glossy, rho_key = at.normal, at.mirror, at.back, at.p_glossy, at.rho_key
    specular, mean_rho, roughness, coat_table = (surfaces.specular, surfaces.mean_rho, surfaces.roughness,
                                                 surfaces.coat_table)
    radix = surfaces.radix
    for r in met:
        mat = material[r]
        cos_o = 0.0
        for k in range(3):
            normal[r, k] = normals[r, k]
            cos_o -= normal[r, k] * np.float64(rays[r, 3 + k])
        if cos_o < 0.0:
            for k in range(3):
                normal[r, k] = -normal[r, k]
            cos_o = -cos_o
        for k in range(3):
            d = np.float64(rays[r, 3 + k])
            mirror[r, k] = 2.0 * cos_o * normal[r, k] + d
            back[r, k] = -d
            rays[r, k] = np.float64(rays[r, k]) + np.float64(t_hit[r]) * d + eps * normal[r, k]
        p_glossy[r] = glossy_share(cos_o, specular[mat], mean_rho[mat], roughness[mat], coat_table[mat])
        rho_key[r] = _number(sequences, numbers, sequences[key[live[r]]] * radix + (mat + 1))


@kernel
def _vertex(r, normals, mirrors, backs, dus, normal, mirror, back, du):
    """Row ``r`` of :class:`Vertices`' ``normals``, ``mirrors``, ``backs`` and, with polarisation, ``dus`` into
    the (3,) arrays ``normal``, ``mirror``, ``back`` and ``du`` that the scattering functions take."""
    for k in range(3):
        normal[k], mirror[k], back[k] = normals[r, k], mirrors[r, k], backs[r, k]
    if len(dus):
        for k in range(3):
            du[k] = dus[r, k]


@stage
def _sun_nee(dim, met, live, paths, hits, surfaces, lights, seed, at, sun):
    """Next-event estimation towards the sun's disc, sampled uniformly, from where the paths meet surfaces:
    the shadow rays and the light each brings, into ``sun``, from each point the sample is above. Returns
    their count."""
    rays, material, w, key, mueller, frame = paths.rays, hits.material, paths.w, paths.key, paths.mueller, paths.frame
    stream, sample = paths.stream, paths.sample
    specular, exponent, roughness, eta, coat_table = (surfaces.specular, surfaces.exponent, surfaces.roughness,
                                                      surfaces.refractive_index, surfaces.coat_table)
    sun_dir, sun_cos, solid_angle = lights.sun_dir, lights.sun_cos, lights.sun_solid_angle
    shadow, shadow_row, lit, lit_key, p_glossy, rho_key = sun.rays, sun.row, sun.lit, sun.key, at.p_glossy, at.rho_key
    normals, mirrors, backs, dus = at.normal, at.mirror, at.back, at.du
    normal, mirror, back, du, s_plane = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    ns = 0
    for r in met:
        mat, i = material[r], live[r]
        _vertex(r, normals, mirrors, backs, dus, normal, mirror, back, du)
        lx, ly, lz = sample_sun(sun_dir, sun_cos, uniform1(seed, stream[i], sample[i], dim),
                                uniform1(seed, stream[i], sample[i], dim + 1))
        cos_l = normal[0] * lx + normal[1] * ly + normal[2] * lz
        if not cos_l > 0.0:
            continue
        _shadow_ray(shadow, shadow_row, lit_key, ns, rays, r, lx, ly, lz, rho_key[r], key[i])
        base = w[i] * cos_l * solid_angle
        diffuse, f, _, _ = lobes(normal, mirror, back, lx, ly, lz, specular[mat], exponent[mat], roughness[mat],
                                 eta[mat], coat_table[mat], p_glossy[r])
        glint = base * f
        _put(lit[ns, 0, 0], base / np.pi * diffuse, mueller, i)
        _put(lit[ns, 1, 0], glint, mueller, i)
        if len(mueller) and glint != 0.0:
            # The sun's unpolarised light, polarised by the glossy reflection.
            plane_normal(du, lx, ly, lz, s_plane)
            c2, s2 = double_angle(s_plane[0], s_plane[1], s_plane[2], frame[i], du)
            lit[ns, 1, 0, 0], lit[ns, 1, 0, 1], lit[ns, 1, 0, 2] = reflect_column(
                mueller[i], c2, s2, _half_cosine(du, lx, ly, lz), eta[mat])
            for q in range(3):
                lit[ns, 1, 0, q] *= glint
        ns += 1
    return ns


@kernel
def _shadow_ray(shadow, row, keys, n, rays, r, x, y, z, diffuse_key, glossy_key):
    """Shadow ray ``n``: from live ray ``r``'s origin towards (x, y, z), with its two lobes' keys."""
    shadow[n, 0], shadow[n, 1], shadow[n, 2] = rays[r, 0], rays[r, 1], rays[r, 2]
    shadow[n, 3], shadow[n, 4], shadow[n, 5] = x, y, z
    keys[n, 0], keys[n, 1], row[n] = diffuse_key, glossy_key, r


@stage
def _sky_nee(dim, met, live, paths, hits, surfaces, lights, seed, at, sky):
    """Next-event estimation towards the sky, drawn from its table, from where the paths meet surfaces that
    reflect: each lobe's sample weighed against the surface's own sampling of that lobe by the balance
    heuristic. The shadow rays and the light each brings per basis spectrum, into ``sky``, from each point
    the sample is above. Returns their count."""
    rays, material, w, key, mueller, frame = paths.rays, hits.material, paths.w, paths.key, paths.mueller, paths.frame
    stream, sample = paths.stream, paths.sample
    specular, exponent, roughness, eta, coat_table, mean_rho = (
        surfaces.specular, surfaces.exponent, surfaces.roughness, surfaces.refractive_index, surfaces.coat_table,
        surfaces.mean_rho)
    sky_sun, shape, floor, offset, hemisphere = (lights.sky_sun, lights.sky_shape, lights.sky_floor,
                                                 lights.sky_offset, lights.sky_hemisphere)
    neutral, max_degree, depolarisation = lights.sky_neutral, lights.sky_max_degree, lights.sky_depolarisation
    row_cdf, col_cdf, table = lights.sky_rows, lights.sky_cols, lights.sky_table
    shadow, shadow_row, lit, lit_key, p_glossy, rho_key = sky.rays, sky.row, sky.lit, sky.key, at.p_glossy, at.rho_key
    normals, mirrors, backs, dus = at.normal, at.mirror, at.back, at.du
    normal, mirror, back, du, s_plane = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    e_vector, dl, chain, radiance = np.empty(3), np.empty(3), np.empty((3, 3)), np.empty(len(shape))
    nk = 0
    for r in met:
        mat, i = material[r], live[r]
        if not (roughness[mat] > 0.0 or mean_rho[mat] + specular[mat] > 0.0):
            continue
        _vertex(r, normals, mirrors, backs, dus, normal, mirror, back, du)
        lx, ly, lz, p_table = sample_sky(row_cdf, col_cdf, table, uniform1(seed, stream[i], sample[i], dim + 6),
                                         uniform1(seed, stream[i], sample[i], dim + 7))
        cos_l = normal[0] * lx + normal[1] * ly + normal[2] * lz
        if not (cos_l > 0.0 and p_table > 0.0):
            continue
        shape_radiance(lx, ly, lz, sky_sun, shape, floor, offset, hemisphere, radiance)
        # Both lobes, and the densities with which each lobe's own sampling would have drawn this direction.
        coupled, f, p_diffuse, p_lobe = lobes(normal, mirror, back, lx, ly, lz, specular[mat], exponent[mat],
                                              roughness[mat], eta[mat], coat_table[mat], p_glossy[r])
        base = w[i] * cos_l / p_table
        diffuse = base / np.pi * coupled * p_table / (p_table + p_diffuse)
        glint = base * f * p_table / (p_table + p_lobe)
        size = c2 = s2 = 0.0
        if len(mueller):
            size = polarisation(lx, ly, lz, sky_sun, neutral, e_vector)
            # The chain as the glossy lobe's reflection towards the sample would leave it.
            plane_normal(du, lx, ly, lz, s_plane)
            chain[:] = mueller[i]
            c2, s2 = double_angle(s_plane[0], s_plane[1], s_plane[2], frame[i], du)
            reflect(chain, c2, s2, _half_cosine(du, lx, ly, lz), eta[mat])
            dl[0], dl[1], dl[2] = lx, ly, lz
            c2, s2 = double_angle(e_vector[0], e_vector[1], e_vector[2], s_plane, dl)
        for k in range(len(radiance)):
            if not len(mueller):
                lit[nk, 0, k, 0] = diffuse * radiance[k]
                lit[nk, 1, k, 0] = glint * radiance[k]
            else:
                # The Lambertian lobe depolarises; the glossy one reflects the sky's polarisation.
                p = degree(size, max_degree, depolarisation[k])
                for q in range(3):
                    lit[nk, 0, k, q] = diffuse * radiance[k] * mueller[i, q, 0]
                    lit[nk, 1, k, q] = glint * radiance[k] * (chain[q, 0] + chain[q, 1] * p * c2
                                                              + chain[q, 2] * p * s2)
        _shadow_ray(shadow, shadow_row, lit_key, nk, rays, r, lx, ly, lz, rho_key[r], key[i])
        nk += 1
    return nk


@stage
def _scatter(event, dim, met, live, paths, hits, surfaces, sky_nee, seed, at, scattered):
    """The paths that met surfaces, scattered: each one's next direction drawn from the BSDF into its ray; its
    weight, key, bound and (with ``sky_nee``) last density, and its polarisation, updated; after
    :data:`ROULETTE_AFTER` events, Russian roulette. Marks in ``scattered`` the paths that go on."""
    rays, material, w, key, bound, mueller, frame = (paths.rays, hits.material, paths.w, paths.key, paths.bound,
                                                     paths.mueller, paths.frame)
    stream, sample, last_pdf, rho_key = paths.stream, paths.sample, paths.last_pdf, at.rho_key
    specular, exponent, roughness, eta, coat_table, mean_rho, max_rho = (
        surfaces.specular, surfaces.exponent, surfaces.roughness, surfaces.refractive_index, surfaces.coat_table,
        surfaces.mean_rho, surfaces.max_rho)
    normals, mirrors, backs, dus = at.normal, at.mirror, at.back, at.du
    normal, mirror, back, du, s_plane = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for r in met:
        mat, i = material[r], live[r]
        _vertex(r, normals, mirrors, backs, dus, normal, mirror, back, du)
        x, y, z, factor, glossy, density = scatter(normal, mirror, back, specular[mat], exponent[mat], mean_rho[mat],
                                                   roughness[mat], eta[mat], coat_table[mat],
                                                   uniform1(seed, stream[i], sample[i], dim + 2),
                                                   uniform1(seed, stream[i], sample[i], dim + 3),
                                                   uniform1(seed, stream[i], sample[i], dim + 4))
        w[i] *= factor
        if sky_nee:
            last_pdf[i] = density
        if len(mueller):
            plane_normal(du, x, y, z, s_plane)
            if glossy:
                c2, s2 = double_angle(s_plane[0], s_plane[1], s_plane[2], frame[i], du)
                reflect(mueller[i], c2, s2, _half_cosine(du, x, y, z), eta[mat])
            else:
                depolarise(mueller[i])
            frame[i] = s_plane
        if not glossy:
            key[i] = rho_key[r]
            bound[i] *= max_rho[mat]
        if event + 1 >= ROULETTE_AFTER:
            q = min(max(w[i] * bound[i], 0.0), 1.0)
            w[i] = w[i] / max(q, 1e-300) if uniform1(seed, stream[i], sample[i], dim + 5) < q else 0.0
        rays[r, 3], rays[r, 4], rays[r, 5] = x, y, z
        scattered[r] = w[i] > 0.0


@kernel
def _half_cosine(d, x, y, z):
    """The cosine of incidence on the microfacet that reflects (x, y, z) into the ray ``d``: at their half vector."""
    hx, hy, hz = x - d[0], y - d[1], z - d[2]
    norm = np.sqrt(hx * hx + hy * hy + hz * hz)
    return (hx * x + hy * y + hz * z) / norm if norm > 0.0 else 1.0

@kernel
def _no_sequences():
    """The list of sequences of materials with only the empty one (0), and its inverse: numba's typed
    containers, which the kernels extend. Made in compiled code, which numba caches: made from Python, they
    would compile numba's own helpers, which it does not cache, in every process (about a second)."""
    sequences = typed.List.empty_list(types.int64)
    sequences.append(0)
    numbers = typed.Dict.empty(types.int64, types.int64)
    numbers[0] = 0
    return sequences, numbers


@kernel
def _number(sequences, numbers, sequence):
    """The number of a sequence of materials in ``sequences`` (and ``numbers``, its inverse), adding it if new."""
    k = numbers.get(sequence, -1)
    if k < 0:
        k = len(sequences)
        numbers[sequence] = k
        sequences.append(sequence)
    return k


@kernel
def _through(live, shadows, blocked, bundle, first_light, n_lights):
    """Light through the unblocked ``shadows`` (:class:`ShadowRays` of the live paths ``live``): per path, its
    Lambertian then its glossy weight (or Stokes vector) of each light, the lights numbered from
    ``first_light``: the sun's one, or the sky's basis spectra."""
    lit = shadows.lit
    k, _, n_each, n_stokes = lit.shape
    c_bundle = np.empty(2 * k * n_each, np.int64)
    c_combo = np.empty(2 * k * n_each, np.int64)
    c_weight = np.empty((2 * k * n_each, n_stokes))
    nc = 0
    for s in range(k):
        if blocked[s]:
            continue
        b = bundle[live[shadows.row[s]]]
        for lobe in range(2):
            for j in range(n_each):
                if lit[s, lobe, j, 0] != 0.0:
                    c_bundle[nc], c_combo[nc] = b, shadows.key[s, lobe] * n_lights + first_light + j
                    c_weight[nc] = lit[s, lobe, j]
                    nc += 1
    return c_bundle[:nc], c_combo[:nc], c_weight[:nc]


@kernel
def _sun_in_cones(origins, bundle, u, lights, cones):
    """One sample of the sun's disc per cone sample, weighed against the cone's own (balance heuristic).

    ``u`` (n·s, 2) places them on the disc: a stratified set, since the
    acceptance varies across the disc by up to e^±1 in a cone's flank.

    Returns the shadow rays from the receptors towards them, and each
    one's weight in the units of the cone's samples (sin θ/θ): the
    acceptance A(θ) over 2πσ² and the sum of the two densities.
    """
    n = len(bundle)
    rays, weight = np.empty((n, 6), np.float32), np.empty(n)
    rows = np.empty(n, np.int64)
    ns = 0
    p_sun = 1.0 / lights.sun_solid_angle
    axis = cones.axis
    for i in range(n):
        b = bundle[i]
        sigma = cones.sigma[b]
        if sigma <= 0.0:
            continue
        x, y, z = sample_sun(lights.sun_dir, lights.sun_cos, u[i, 0], u[i, 1])
        theta = np.arccos(min(max(axis[b, 0] * x + axis[b, 1] * y + axis[b, 2] * z, -1.0), 1.0))
        acceptance = np.exp(-0.5 * (theta / sigma) ** 2)
        if acceptance < NEGLIGIBLE_ACCEPTANCE:
            continue
        weight[ns] = acceptance / (2.0 * np.pi * sigma * sigma) / (cone_density(theta, sigma) + p_sun)
        rays[ns, 0], rays[ns, 1], rays[ns, 2] = origins[b, 0], origins[b, 1], origins[b, 2]
        rays[ns, 3], rays[ns, 4], rays[ns, 5] = x, y, z
        rows[ns] = i
        ns += 1
    return rays[:ns], rows[:ns], weight[:ns]


@kernel
def _sum_contributions(bundle, column, weight, n, lights, reflectance, radix, depth, sequences, total):
    """Each bundle's spectral sum of its paths' contributions over its sum of weights ``total`` (n,): its
    mean, (n, n_stokes, n_wavelengths).

    ``weight`` (k, n_stokes) holds each contribution's intensity, or Stokes
    vector (I, Q, U). A contribution's column is a sequence's number (its index in the list
    ``sequences``) times the lights plus its light. A bundle's weights in one column are summed
    in the order the paths emitted them, and the columns' spectra weighed in
    increasing order of their sequence's integer, then light: neither order
    depends on the other bundles of the batch, so a bundle's sum is the same
    to the last bit however the run is batched.
    """
    n_lights, n_wl = lights.shape
    n_columns = len(sequences) * n_lights
    n_stokes = weight.shape[1]
    out = np.zeros((n, n_stokes, n_wl))
    # The contributions, stably ordered by bundle (a counting sort).
    start = np.zeros(n + 1, np.int64)
    for j in range(len(bundle)):
        start[bundle[j] + 1] += 1
    start = np.cumsum(start)
    order, fill = np.empty(len(bundle), np.int64), start[:-1].copy()
    for j in range(len(bundle)):
        order[fill[bundle[j]]] = j
        fill[bundle[j]] += 1
    rank = np.empty(n_columns, np.int64)
    spectra = np.empty((n_columns, n_wl))
    made = np.zeros(n_columns, np.bool_)
    value = np.empty(n_columns, np.int64)
    for c in range(n_columns):
        value[c] = sequences[c // n_lights] * n_lights + c % n_lights
    by_value = np.argsort(value)
    rank[by_value] = np.arange(n_columns)
    cell = np.zeros((n_columns, n_stokes))
    seen = np.zeros(n_columns, np.bool_)
    touched = np.empty(n_columns, np.int64)
    for b in range(n):
        nt = 0
        for j in order[start[b]:start[b + 1]]:
            c = column[j]
            if not seen[c]:
                seen[c] = True
                touched[nt] = rank[c]
                nt += 1
            for q in range(n_stokes):
                cell[c, q] += weight[j, q]
        # Its few columns in increasing rank, sorted in place (insertion), not a new array per bundle.
        for a in range(1, nt):
            t, j = touched[a], a - 1
            while j >= 0 and touched[j] > t:
                touched[j + 1] = touched[j]
                j -= 1
            touched[j + 1] = t
        for r in touched[:nt]:
            c = by_value[r]
            if not made[c]:
                # The product of the reflectance spectra that the sequence's digits name, times the light.
                spectra[c] = 1.0
                k = sequences[c // n_lights]
                for _ in range(depth + 1):
                    digit = k % radix
                    if digit > 0:
                        for x in range(n_wl):
                            spectra[c, x] *= reflectance[digit - 1, x]
                    k //= radix
                for x in range(n_wl):
                    spectra[c, x] *= lights[c % n_lights, x]
                made[c] = True
            for q in range(n_stokes):
                for x in range(n_wl):
                    out[b, q, x] += cell[c, q] * spectra[c, x]
                cell[c, q] = 0.0
            seen[c] = False
        for q in range(n_stokes):
            for x in range(n_wl):
                out[b, q, x] /= total[b]
    return out


def trace_paths(scene, origins, directions, weights, *, depth, seed, streams=None, first_samples=None,
                rs=None, counts=None, cones=None, frames=None, target=None, sky_sampling=SKY_SAMPLING[0]):
    """Spectral radiance arriving along bundles of rays, averaged per bundle; with ``frames``, its Stokes vector.

    Parameters
    ----------
    scene : Scene
    origins : ndarray, shape (n, 3)
        One origin per bundle (a receptor or a pixel), scene units.
    directions : ndarray, shape (n, s, 3)
        Sampled unit directions per bundle.
    weights : ndarray, shape (n, s)
        Sampling weights; each bundle's result is the weighted mean.
    depth : int
        Scattering events per path, at least 1.
    seed : int
    streams : ndarray of int, shape (n,), optional
        Each bundle's index among all bundles of the run (0 … n−1 by
        default), for the random numbers: results do not depend on how a run
        is chunked.
    first_samples : ndarray of int, shape (n,), optional
        The index of each bundle's first sample (0 by default), for a bundle
        traced in blocks of its samples.
    rs : open3d.t.geometry.RaycastingScene, optional
        Built from ``scene`` if not given.
    counts : dict, optional
        Incremented with the rays cast ("cast", "shadow").
    cones : pair of ndarray, optional
        Each bundle's cone axis (n, 3) and Gaussian σ (n,), radians, when
        the bundles are receptors' cones drawn by
        :func:`beeoptics.light.sensors.cone_samples`: the sun is then also
        sampled in each cone and weighed against the cone's samples by
        multiple importance sampling.
    frames : ndarray, shape (n, 3), optional
        Each bundle's reference direction for polarisation: a sample's
        Stokes vector is in the frame whose e is this direction made
        perpendicular to the sample's direction d, and f = d × e
        (:mod:`beeoptics.light.mueller`). With it, polarisation is carried
        from the sky through reflections (the sky's, the sun's and surfaces'
        as they are, a Lambertian surface depolarising).
    target : (ndarray (3,) or (n, 3), float or ndarray (n,)), optional
        A target's centre and radius, scene units, or one per bundle: each
        bundle's share of its weight whose first hit lies within that
        sphere is returned too (what share of a receptor's acceptance a
        flower fills, as its samples met it, leaves and petals in front of
        it included).

    sky_sampling : {"nee", "escape"}
        ``nee`` (the default): the sky is also sampled from every surface,
        by next-event estimation from its table of its light above its mean
        (:func:`beeoptics.sky.sampling.sky_table`; none for a uniform sky),
        weighed against the surface's own sampling by multiple importance
        sampling; ``escape``: a path sees the sky only where it escapes the scene.

    Returns
    -------
    ndarray, shape (n, n_wavelengths), or (n, 3, n_wavelengths) with ``frames``
        Spectral radiance, W m⁻² sr⁻¹ nm⁻¹; with ``frames``, the spectral
        Stokes vector (I, Q, U) in those units.
    ndarray, shape (n,)
        With ``target`` only: each bundle's share that met it first.
    """
    if depth < 1:
        raise ValueError("depth must be at least 1")
    rs = rs if rs is not None else raycasting_scene(scene)
    polarised = frames is not None
    surfaces, lights = Surfaces(scene), Lights(scene)
    radix = len(scene.material_names) + 1
    if (depth + 1) * np.log2(radix) + np.log2(len(lights.spectra)) > 62:
        raise ValueError(f"depth {depth} is too deep for {radix - 1} materials")
    counts = counts if counts is not None else {}
    counts.setdefault("cast", 0)
    counts.setdefault("shadow", 0)
    n, s = weights.shape
    eps = OFFSET * max(scene.extent, 1.0)
    if sky_sampling not in SKY_SAMPLING:
        raise ValueError(f"sky_sampling must be one of {', '.join(SKY_SAMPLING)}, not {sky_sampling!r}")
    light = _light_arrays(scene, lights, sky_sampling == "nee")
    shading = SurfaceArrays(surfaces.specular, surfaces.exponent, surfaces.roughness, surfaces.refractive_index,
                            surfaces.coat_table, surfaces.mean_rho, surfaces.max_rho, lights.glows, lights.emission,
                            radix)
    sensor = Cones(np.zeros((n, 3)), np.zeros(n)) if cones is None else Cones(
        np.ascontiguousarray(cones[0], float), np.broadcast_to(np.asarray(cones[1], float), (n,)).copy())

    if streams is not None and len(streams) and not 0 <= np.min(streams) <= np.max(streams) < STREAMS:
        raise ValueError(f"streams must lie in 0 … {STREAMS - 1}, where each draws random numbers of its own")
    bundle = np.repeat(np.arange(n), s)
    stream = bundle if streams is None else np.repeat(streams, s)
    sample = np.tile(np.arange(s), n)
    if first_samples is not None:
        sample += np.repeat(first_samples, s)
    # Each ray as Embree takes it: origin and direction in single precision.
    rays = np.empty((n * s, 6), np.float32)
    rays[:, :3] = np.repeat(origins, s, axis=0)
    rays[:, 3:] = directions.reshape(-1, 3)
    sequences, numbers = _no_sequences()
    contributions = []  # (bundle, combo, weights (k, n_stokes))
    n_stokes = 3 if polarised else 1
    mueller, frame = np.zeros((0, 3, 3)), np.zeros((0, 3))
    if polarised:
        mueller = np.zeros((n * s, 3, 3))
        mueller[:, [0, 1, 2], [0, 1, 2]] = 1.0
        frame = _frames(np.repeat(np.asarray(frames, float), s, axis=0), directions.reshape(-1, 3))
    paths = Paths(rays, weights.reshape(-1).astype(np.float64), np.zeros(n * s, np.int64), np.ones(n * s), mueller,
                  frame, np.zeros(n * s), bundle, stream, sample)

    if cones is not None and scene.sun is not None:
        u = shifted_halton(s, seed, np.arange(n) if streams is None else streams, SUN_DIMENSIONS, first_samples)
        shadow, rows, weight = _sun_in_cones(np.asarray(origins, float), bundle, u.reshape(-1, 2), light, sensor)
        if len(rows):
            seen = ~occluded(rs, shadow)
            counts["shadow"] += len(rows)
            sunlight = np.zeros((seen.sum(), n_stokes))
            sunlight[:, 0] = weight[seen]
            contributions.append((bundle[rows[seen]], np.full(seen.sum(), lights.sun, np.int64), sunlight))

    live = np.arange(n * s)
    cover = None
    for event in range(depth + 1):
        counts["cast"] += len(live)
        if event == depth and not lights.glows.any():
            # The last rays only see the sky where they leave the scene (no surface they meet glows, and none
            # scatters them again): whether each meets a surface is all they ask of Embree, which answers it
            # without finding the nearest.
            material = np.where(occluded(rs, paths.rays), 0, -1)
            hits = Hits(np.zeros(len(live), np.float32), np.zeros((len(live), 3), np.float32), material)
        else:
            out = first_hits(rs, paths.rays)
            hit = np.isfinite(out["t_hit"])
            if event == 0 and target is not None:
                cover = _target_share(paths.rays, out["t_hit"], hit, paths.w, bundle, n, *target)
            material = np.full(len(live), -1, np.int64)
            material[hit] = surfaces.material(out["geometry_ids"][hit].astype(np.int64),
                                              out["primitive_ids"][hit].astype(np.int64), out["primitive_uvs"][hit])
            hits = Hits(out["t_hit"], out["primitive_normals"], material)
        found, sun_shadows, sky_shadows, scattered = _arrive(event, depth, live, paths, hits, shading, light, sensor,
                                                             sequences, numbers, seed, eps)
        contributions.append(found)
        for shadows, first_light in ((sun_shadows, lights.sun), (sky_shadows, 0)):
            if len(shadows.row):
                blocked = occluded(rs, shadows.rays)
                counts["shadow"] += len(shadows.row)
                contributions.append(_through(live, shadows, blocked, bundle, first_light, len(lights.spectra)))
        if event == depth or not scattered.any():
            break
        live, paths = live[scattered], paths._replace(rays=paths.rays[scattered])

    b, combo, weight = (np.concatenate(c) for c in zip(*contributions))
    total = weights.sum(axis=1)
    out = _sum_contributions(b, combo, weight, n, lights.spectra, scene.reflectance, radix, depth, sequences, total)
    out = out if polarised else out[:, 0]
    return out if target is None else (out, cover / total)


def _target_share(rays, t_hit, hit, w, bundle, n, centre, radius):
    """Each bundle's weight of first hits within ``radius`` of ``centre`` (unnormalised), (n,)."""
    rows = np.flatnonzero(hit)
    point = rays[rows, :3].astype(np.float64) + t_hit[rows, None].astype(np.float64) * rays[rows, 3:]
    centre = np.broadcast_to(np.asarray(centre, float), (n, 3))[bundle[rows]]
    radius = np.broadcast_to(np.asarray(radius, float), (n,))[bundle[rows]]
    inside = np.linalg.norm(point - centre, axis=1) <= radius
    return np.bincount(bundle[rows[inside]], weights=w[rows[inside]], minlength=n)


def _light_arrays(scene, lights, nee):
    """The lights of ``scene`` as the kernels take them (:class:`beeoptics.light.emitters.LightArrays`), the sky
    sampled from every surface if ``nee`` and the scene has one."""
    sky, sun = scene.sky, scene.sun
    sun_fields = ((-1, np.zeros(3), 1.0, 1.0) if sun is None else
                  (lights.sun, sun.direction.astype(float), float(sun.cos_radius), float(sun.solid_angle)))
    sky_fields = ((False, np.zeros(3), np.zeros((0, 10)), 0.0, 0.0, False, np.zeros(2), 0.0, np.zeros(1))
                  if sky is None else
                  (True, sky.sun, sky.shape, sky.cos_floor, sky.cos_offset, sky.hemisphere, sky.neutral_rad,
                   sky.max_degree, np.broadcast_to(sky.depolarisation, len(sky.shape)).astype(float)))
    table = _sky_table(sky, lights.spectra[:0 if sky is None else len(sky.basis)])
    # A sky nowhere above its mean (a uniform one) has an empty table: the surfaces' own sampling carries it
    # alone, and no shadow ray is cast towards it.
    return LightArrays(len(lights.spectra), *sun_fields, *sky_fields, nee and sky is not None and table[2].any(),
                       *table)


def _sky_table(sky, spectra):
    """The sky's sampling table (:func:`beeoptics.sky.sampling.sky_table`), made once per sky."""
    if sky is None:
        return np.zeros(2), np.zeros((1, 2)), np.zeros((1, 1))
    key = (sky.sun.tobytes(), sky.shape.tobytes(), float(sky.cos_floor), float(sky.cos_offset), bool(sky.hemisphere),
           np.asarray(spectra).tobytes())
    # Batches are traced on several threads at once: the table is made under a lock, once.
    with _SKY_LOCK:
        if key not in _SKY_TABLES:
            _SKY_TABLES.clear()  # one sky at a time is traced: keep the last
            _SKY_TABLES[key] = sky_table(sky, spectra)
        return _SKY_TABLES[key]


_SKY_TABLES, _SKY_LOCK = {}, threading.Lock()


def _frames(reference, directions):
    """Unit vectors perpendicular to ``directions`` (k, 3), nearest each ``reference`` (k, 3), or to
    any perpendicular where a reference is parallel to its direction."""
    e = reference - (reference * directions).sum(1, keepdims=True) * directions
    norm = np.linalg.norm(e, axis=1)
    parallel = norm < 1e-9
    e[parallel] = tangent_frames(directions[parallel])[:, 0]
    norm[parallel] = 1.0
    return e / norm[:, None]
