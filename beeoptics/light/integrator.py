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
batch: what each ray met (:func:`_arrive`: sky, sun, emission, the sun's
shadow ray, scattering, roulette), the sun and the sky through the unblocked
shadow rays (:func:`_through`), and each bundle's spectral sum
(:func:`_sum_contributions`). Only Embree's calls and the material lookup
of the hits are outside them.

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
"""

import threading

import numpy as np

from beeoptics.jit import NumbaModule, kernel
from beeoptics.light.emitters import Lights, sample_sky, sample_sun, sky_density, sky_table
from beeoptics.light.hosekwilkie import shape_radiance
from beeoptics.light.mueller import depolarise, double_angle, plane_normal, reflect, reflect_column
from beeoptics.light.sampler import shifted_halton, tangent_frames, uniform1
from beeoptics.light.scattering import Surfaces, glossy_share, lobes, scatter
from beeoptics.light.scene import raycasting_scene
from beeoptics.light.skypolarisation import degree, polarisation
from beeoptics.light.sensors import cone_density
from beeoptics.raycasting import first_hits, occluded

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


@kernel
def _put(weights, row, scale, mueller, i, column):
    """Row ``row`` of the contributions' ``weights``: ``scale`` alone (intensity only), or times the Stokes
    vector that unpolarised light arriving in path ``i``'s frame makes at its bundle (column ``column`` of its
    Mueller chain)."""
    if weights.shape[1] == 1:
        weights[row, 0] = scale
    else:
        for k in range(3):
            weights[row, k] = scale * mueller[i, k, column]


@kernel
def _arrive(event, depth, rays, paths, t_hit, normals, material, w, key, bound, sequences, numbers, bundle, stream,
            sample, seed, mueller, frame, last_pdf, has_sky, sky_sun, sky_shape, sky_floor, sky_offset,
            sky_hemisphere, sky_neutral, sky_max_degree, sky_depolarisation, sky_nee, sky_rows, sky_cols, sky_table,
            sun_row, sun_dir, sun_cos, sun_solid_angle, cone_axis, cone_sigma, glows, emission_row, specular,
            exponent, roughness, refractive_index, coat_table, mean_rho, max_rho, radix, n_lights, eps):
    """What the paths ``paths`` meet along ``rays``: light where they leave the scene or meet a glowing
    surface (as contributions), and, at a surface, the sun's shadow ray and the scattered ray.

    Updates the paths' weight ``w``, ``key`` and ``bound`` in place, and writes
    the scattered ray's origin and direction into ``rays``. A path's key is
    the number of its sequence of materials in ``sequences`` (a list of the
    sequences' integers, added to here, with ``numbers`` its inverse), so
    that the contributions' columns are small, dense numbers. With
    polarisation (``mueller`` not empty), each path also carries the chain
    of Mueller matrices from its bundle to its ray (``mueller``, (N, 3, 3))
    and its ray's reference frame (``frame``, (N, 3)), updated in place, and
    every contribution is a Stokes vector at the bundle (I, Q, U). The
    sky's degree of polarisation is taken at each basis spectrum's
    wavelength (``sky_depolarisation``, :mod:`beeoptics.light.skypolarisation`),
    so its light stays one contribution per basis spectrum.

    With ``sky_nee``, the sky is also sampled from every surface from its
    table (``sky_rows``, ``sky_cols``, ``sky_table``:
    :func:`beeoptics.light.emitters.sky_table`), each lobe's sample weighed
    against the surface's own sampling of that lobe by the balance
    heuristic; ``last_pdf`` holds, per path, the density with which its
    last scattering drew its ray (the lobe's probability times the lobe's
    density, 0 for a sensor's ray), so that sky light a scattered ray
    reaches is weighed against the table's density there.

    Returns
    -------
    contributions : (bundle, combo, weights (k, 1 or 3)) arrays
    shadow : ndarray (k, 6) float32, and the rows of ``paths`` each belongs to
    lit : ndarray (k, 2, 1 or 3)
        The Lambertian and glossy weight (or Stokes vector) of each shadow ray's sun.
    lit_key : ndarray (k, 2)
        Their keys.
    scattered : ndarray of bool (m,), the paths that go on
    sky_shadow : ndarray (j, 6) float32, and the rows of ``paths`` each belongs to
        The shadow rays towards the sky's samples.
    sky_lit : ndarray (j, 2, n_sky, 1 or 3)
        Their Lambertian and glossy weight (or Stokes vector) per basis spectrum of the sky.
    sky_key : ndarray (j, 2)
        Their keys.
    """
    m = len(paths)
    n_stokes = 3 if len(mueller) else 1
    n_sky = sky_shape.shape[0] if has_sky else 0
    sky_shadow = np.empty((m if sky_nee else 0, 6), np.float32)
    sky_row = np.empty(m if sky_nee else 0, np.int64)
    sky_lit = np.empty((m if sky_nee else 0, 2, max(n_sky, 1), n_stokes))
    sky_key = np.empty((m if sky_nee else 0, 2), np.int64)
    chain, dl = np.empty((3, 3)), np.empty(3)
    nk = 0
    c_bundle = np.empty(m * (n_sky + 1), np.int64)
    c_combo = np.empty(m * (n_sky + 1), np.int64)
    c_weight = np.empty((m * (n_sky + 1), n_stokes))
    shadow = np.empty((m, 6), np.float32)
    shadow_row = np.empty(m, np.int64)
    lit = np.empty((m, 2, n_stokes))
    lit_key = np.empty((m, 2), np.int64)
    scattered = np.zeros(m, np.bool_)
    sky = np.empty(max(n_sky, 1))
    d, normal, mirror, s_plane, e_vector = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    view = np.empty(3)
    du = np.empty(3)
    nc = ns = 0
    for r in range(m):
        i = paths[r]
        b = bundle[i]
        for k in range(3):
            d[k] = rays[r, 3 + k]
        if n_stokes == 3:
            # Frames and angles from the direction at full precision, not Embree's single one.
            norm = np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            for k in range(3):
                du[k] = d[k] / norm
        if material[r] < 0:
            # Light from the sky, and from the sun's disc on first sight only (after a
            # surface, next-event estimation has counted the sun).
            if n_sky:
                shape_radiance(d[0], d[1], d[2], sky_sun, sky_shape, sky_floor, sky_offset, sky_hemisphere, sky)
                if sky_nee and last_pdf[i] > 0.0:
                    # A scattered ray's sky, weighed against the table's sample of the same direction.
                    norm = np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
                    p_table = sky_density(sky_table, d[0] / norm, d[1] / norm, d[2] / norm)
                    mis = last_pdf[i] / (last_pdf[i] + p_table)
                    for k in range(n_sky):
                        sky[k] *= mis
                size = c2 = s2 = 0.0
                if n_stokes == 3:
                    size = polarisation(du[0], du[1], du[2], sky_sun, sky_neutral, e_vector)
                    c2, s2 = double_angle(e_vector[0], e_vector[1], e_vector[2], frame[i], du)
                for k in range(n_sky):
                    if sky[k] != 0.0:
                        c_bundle[nc], c_combo[nc] = b, key[i] * n_lights + k
                        if n_stokes == 1:
                            c_weight[nc, 0] = w[i] * sky[k]
                        else:
                            # The degree at the basis spectrum's wavelength.
                            p = degree(size, sky_max_degree, sky_depolarisation[k])
                            q_sky, u_sky = p * c2, p * s2
                            for q in range(3):
                                c_weight[nc, q] = w[i] * sky[k] * (mueller[i, q, 0] + mueller[i, q, 1] * q_sky
                                                                   + mueller[i, q, 2] * u_sky)
                        nc += 1
            if event == 0 and sun_row >= 0 and d[0] * sun_dir[0] + d[1] * sun_dir[1] + d[2] * sun_dir[2] >= sun_cos:
                weight = w[i]
                if cone_sigma[b] > 0.0:
                    # The cone's sample, weighed against the sun's own (balance heuristic).
                    cos_a = cone_axis[b, 0] * d[0] + cone_axis[b, 1] * d[1] + cone_axis[b, 2] * d[2]
                    q = cone_density(np.arccos(min(max(cos_a, -1.0), 1.0)), cone_sigma[b])
                    weight *= q / (q + 1.0 / sun_solid_angle)
                c_bundle[nc], c_combo[nc] = b, key[i] * n_lights + sun_row
                _put(c_weight, nc, weight, mueller, i, 0)
                nc += 1
            continue
        mat = material[r]
        if glows[mat]:
            c_bundle[nc], c_combo[nc] = b, key[i] * n_lights + emission_row + mat
            _put(c_weight, nc, w[i], mueller, i, 0)
            nc += 1
        if event == depth:
            continue
        # The normal facing the incoming ray, and the point just off the surface.
        cos_o = 0.0
        for k in range(3):
            normal[k] = normals[r, k]
            cos_o -= normal[k] * d[k]
        if cos_o < 0.0:
            for k in range(3):
                normal[k] = -normal[k]
            cos_o = -cos_o
        for k in range(3):
            mirror[k] = 2.0 * cos_o * normal[k] + d[k]
            view[k] = -d[k]
            rays[r, k] = np.float64(rays[r, k]) + np.float64(t_hit[r]) * d[k] + eps * normal[k]
        alpha, eta, table = roughness[mat], refractive_index[mat], coat_table[mat]
        p_glossy = glossy_share(cos_o, specular[mat], mean_rho[mat], alpha, table)
        dim = event * DIMENSIONS_PER_EVENT
        rho_key = _number(sequences, numbers, sequences[key[i]] * radix + (mat + 1))
        if sun_row >= 0:
            # Next-event estimation towards the sun's disc, sampled uniformly.
            lx, ly, lz = sample_sun(sun_dir, sun_cos, uniform1(seed, stream[i], sample[i], dim),
                                    uniform1(seed, stream[i], sample[i], dim + 1))
            cos_l = normal[0] * lx + normal[1] * ly + normal[2] * lz
            if cos_l > 0.0:
                shadow[ns, 0], shadow[ns, 1], shadow[ns, 2] = rays[r, 0], rays[r, 1], rays[r, 2]
                shadow[ns, 3], shadow[ns, 4], shadow[ns, 5] = lx, ly, lz
                base = w[i] * cos_l * sun_solid_angle
                diffuse, f, _, _ = lobes(normal, mirror, view, lx, ly, lz, specular[mat], exponent[mat], alpha, eta,
                                         table, p_glossy)
                glint = base * f
                _put(lit[ns], 0, base / np.pi * diffuse, mueller, i, 0)
                _put(lit[ns], 1, glint, mueller, i, 0)
                if n_stokes == 3 and glint != 0.0:
                    # The sun's unpolarised light, polarised by the glossy reflection.
                    plane_normal(du, lx, ly, lz, s_plane)
                    c2, s2 = double_angle(s_plane[0], s_plane[1], s_plane[2], frame[i], du)
                    lit[ns, 1, 0], lit[ns, 1, 1], lit[ns, 1, 2] = reflect_column(
                        mueller[i], c2, s2, _half_cosine(du, lx, ly, lz), eta)
                    for q in range(3):
                        lit[ns, 1, q] *= glint
                lit_key[ns, 0], lit_key[ns, 1], shadow_row[ns] = rho_key, key[i], r
                ns += 1
        if sky_nee and n_sky and (alpha > 0.0 or mean_rho[mat] + specular[mat] > 0.0):
            # Next-event estimation towards the sky, drawn from its table.
            lx, ly, lz, p_table = sample_sky(sky_rows, sky_cols, sky_table,
                                             uniform1(seed, stream[i], sample[i], dim + 6),
                                             uniform1(seed, stream[i], sample[i], dim + 7))
            cos_l = normal[0] * lx + normal[1] * ly + normal[2] * lz
            if cos_l > 0.0 and p_table > 0.0:
                shape_radiance(lx, ly, lz, sky_sun, sky_shape, sky_floor, sky_offset, sky_hemisphere, sky)
                # Both lobes, and the densities with which each lobe's own sampling would have drawn this direction.
                coupled, f, p_diffuse, p_lobe = lobes(normal, mirror, view, lx, ly, lz, specular[mat], exponent[mat],
                                                      alpha, eta, table, p_glossy)
                base = w[i] * cos_l / p_table
                diffuse = base / np.pi * coupled * p_table / (p_table + p_diffuse)
                glint = base * f * p_table / (p_table + p_lobe)
                size = c2 = s2 = 0.0
                if n_stokes == 3:
                    size = polarisation(lx, ly, lz, sky_sun, sky_neutral, e_vector)
                    # The chain as the glossy lobe's reflection towards the sample would leave it.
                    plane_normal(du, lx, ly, lz, s_plane)
                    for a in range(3):
                        for b2 in range(3):
                            chain[a, b2] = mueller[i, a, b2]
                    c2, s2 = double_angle(s_plane[0], s_plane[1], s_plane[2], frame[i], du)
                    reflect(chain, c2, s2, _half_cosine(du, lx, ly, lz), eta)
                    dl[0], dl[1], dl[2] = lx, ly, lz
                    c2, s2 = double_angle(e_vector[0], e_vector[1], e_vector[2], s_plane, dl)
                for k in range(n_sky):
                    if n_stokes == 1:
                        sky_lit[nk, 0, k, 0] = diffuse * sky[k]
                        sky_lit[nk, 1, k, 0] = glint * sky[k]
                    else:
                        # The Lambertian lobe depolarises; the glossy one reflects the sky's polarisation.
                        p = degree(size, sky_max_degree, sky_depolarisation[k])
                        for q in range(3):
                            sky_lit[nk, 0, k, q] = diffuse * sky[k] * mueller[i, q, 0]
                            sky_lit[nk, 1, k, q] = glint * sky[k] * (chain[q, 0] + chain[q, 1] * p * c2
                                                                     + chain[q, 2] * p * s2)
                sky_shadow[nk, 0], sky_shadow[nk, 1], sky_shadow[nk, 2] = rays[r, 0], rays[r, 1], rays[r, 2]
                sky_shadow[nk, 3], sky_shadow[nk, 4], sky_shadow[nk, 5] = lx, ly, lz
                sky_key[nk, 0], sky_key[nk, 1], sky_row[nk] = rho_key, key[i], r
                nk += 1
        x, y, z, factor, glossy, density = scatter(normal, mirror, view, specular[mat], exponent[mat], mean_rho[mat],
                                                   alpha, eta, table, uniform1(seed, stream[i], sample[i], dim + 2),
                                                   uniform1(seed, stream[i], sample[i], dim + 3),
                                                   uniform1(seed, stream[i], sample[i], dim + 4))
        w[i] *= factor
        if sky_nee:
            last_pdf[i] = density
        if n_stokes == 3:
            plane_normal(du, x, y, z, s_plane)
            if glossy:
                c2, s2 = double_angle(s_plane[0], s_plane[1], s_plane[2], frame[i], du)
                reflect(mueller[i], c2, s2, _half_cosine(du, x, y, z), eta)
            else:
                depolarise(mueller[i])
            for k in range(3):
                frame[i, k] = s_plane[k]
        if not glossy:
            key[i] = rho_key
            bound[i] *= max_rho[mat]
        if event + 1 >= ROULETTE_AFTER:
            q = min(max(w[i] * bound[i], 0.0), 1.0)
            w[i] = w[i] / max(q, 1e-300) if uniform1(seed, stream[i], sample[i], dim + 5) < q else 0.0
        rays[r, 3], rays[r, 4], rays[r, 5] = x, y, z
        scattered[r] = w[i] > 0.0
    return ((c_bundle[:nc], c_combo[:nc], c_weight[:nc]), shadow[:ns], shadow_row[:ns], lit[:ns], lit_key[:ns],
            scattered, sky_shadow[:nk], sky_row[:nk], sky_lit[:nk], sky_key[:nk])


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
def _through(paths, rows, blocked, lit, keys, bundle, first_light, n_lights):
    """Light through the unblocked shadow rays: per path, its Lambertian then its glossy weight (or Stokes
    vector) of each light ``lit`` (k, 2, lights, 1 or 3) holds, the lights numbered from ``first_light``:
    the sun's one, or the sky's basis spectra."""
    k, _, n_each, n_stokes = lit.shape
    c_bundle = np.empty(2 * k * n_each, np.int64)
    c_combo = np.empty(2 * k * n_each, np.int64)
    c_weight = np.empty((2 * k * n_each, n_stokes))
    nc = 0
    for s in range(k):
        if blocked[s]:
            continue
        b = bundle[paths[rows[s]]]
        for lobe in range(2):
            for j in range(n_each):
                if lit[s, lobe, j, 0] != 0.0:
                    c_bundle[nc], c_combo[nc] = b, keys[s, lobe] * n_lights + first_light + j
                    c_weight[nc] = lit[s, lobe, j]
                    nc += 1
    return c_bundle[:nc], c_combo[:nc], c_weight[:nc]


@kernel
def _sun_in_cones(origins, bundle, u, sun_dir, sun_cos, sun_solid_angle, cone_axis, cone_sigma):
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
    p_sun = 1.0 / sun_solid_angle
    for i in range(n):
        b = bundle[i]
        sigma = cone_sigma[b]
        if sigma <= 0.0:
            continue
        x, y, z = sample_sun(sun_dir, sun_cos, u[i, 0], u[i, 1])
        theta = np.arccos(min(max(cone_axis[b, 0] * x + cone_axis[b, 1] * y + cone_axis[b, 2] * z, -1.0), 1.0))
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
def _sum_contributions(bundle, column, weight, n, lights, reflectance, radix, depth, sequences):
    """Each bundle's spectral sum of its paths' contributions, (n, n_stokes, n_wavelengths).

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
        for r in np.sort(touched[:nt]):
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
        (:func:`beeoptics.light.emitters.sky_table`; none for a uniform sky),
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
    sky, sun = scene.sky, scene.sun
    sky_args = ((False, np.zeros(3), np.zeros((0, 10)), 0.0, 0.0, False, np.zeros(2), 0.0, np.zeros(1))
                if sky is None else
                (True, sky.sun, sky.shape, sky.cos_floor, sky.cos_offset, sky.hemisphere, sky.neutral_rad,
                 sky.max_degree, np.broadcast_to(sky.depolarisation, len(sky.shape)).astype(float)))
    sun_args = ((-1, np.zeros(3), 1.0, 1.0) if sun is None else
                (lights.sun, sun.direction.astype(float), float(sun.cos_radius), float(sun.solid_angle)))
    cone_axis, cone_sigma = (np.zeros((n, 3)), np.zeros(n)) if cones is None else (
        np.ascontiguousarray(cones[0], float), np.broadcast_to(np.asarray(cones[1], float), (n,)).copy())
    material_args = (lights.glows, lights.emission, surfaces.specular, surfaces.exponent, surfaces.roughness,
                     surfaces.refractive_index, surfaces.coat_table, surfaces.mean_rho, surfaces.max_rho, radix,
                     len(lights.spectra), eps)
    if sky_sampling not in SKY_SAMPLING:
        raise ValueError(f"sky_sampling must be one of {', '.join(SKY_SAMPLING)}, not {sky_sampling!r}")
    table = _sky_table(sky, lights.spectra[:0 if sky is None else len(sky.basis)])
    # A sky nowhere above its mean (a uniform one) has an empty table: the surfaces' own sampling carries it
    # alone, and no shadow ray is cast towards it.
    sky_nee_args = (sky_sampling == "nee" and table[2].any(), *table)

    bundle = np.repeat(np.arange(n), s)
    stream = bundle if streams is None else np.repeat(streams, s)
    sample = np.tile(np.arange(s), n)
    if first_samples is not None:
        sample += np.repeat(first_samples, s)
    # Each ray as Embree takes it: origin and direction in single precision.
    rays = np.empty((n * s, 6), np.float32)
    rays[:, :3] = np.repeat(origins, s, axis=0)
    rays[:, 3:] = directions.reshape(-1, 3)
    w = weights.reshape(-1).astype(np.float64)
    key = np.zeros(n * s, np.int64)
    sequences, numbers = _no_sequences()
    bound = np.ones(n * s)  # an upper bound of the throughput's spectral maximum
    contributions = []  # (bundle, combo, weights (k, n_stokes))
    n_stokes = 3 if polarised else 1
    mueller, frame = np.zeros((0, 3, 3)), np.zeros((0, 3))
    if polarised:
        mueller = np.zeros((n * s, 3, 3))
        mueller[:, [0, 1, 2], [0, 1, 2]] = 1.0
        frame = _frames(np.repeat(np.asarray(frames, float), s, axis=0), directions.reshape(-1, 3))

    if cones is not None and sun is not None:
        u = shifted_halton(s, seed, np.arange(n) if streams is None else streams, SUN_DIMENSIONS, first_samples)
        shadow, rows, weight = _sun_in_cones(np.asarray(origins, float), bundle, u.reshape(-1, 2), *sun_args[1:],
                                             cone_axis, cone_sigma)
        if len(rows):
            seen = ~occluded(rs, shadow)
            counts["shadow"] += len(rows)
            sunlight = np.zeros((seen.sum(), n_stokes))
            sunlight[:, 0] = weight[seen]
            contributions.append((bundle[rows[seen]], np.full(seen.sum(), lights.sun, np.int64), sunlight))

    paths = np.arange(n * s)
    last_pdf = np.zeros(n * s)
    cover = None
    for event in range(depth + 1):
        out = first_hits(rs, rays)
        counts["cast"] += len(paths)
        hit = np.isfinite(out["t_hit"])
        if event == 0 and target is not None:
            cover = _target_share(rays, out["t_hit"], hit, w, bundle, n, *target)
        material = np.full(len(paths), -1, np.int64)
        material[hit] = surfaces.material(out["geometry_ids"][hit].astype(np.int64),
                                          out["primitive_ids"][hit].astype(np.int64), out["primitive_uvs"][hit])
        found, shadow, rows, lit, lit_key, scattered, sky_shadow, sky_rows, sky_lit, sky_key = _arrive(
            event, depth, rays, paths, out["t_hit"], out["primitive_normals"], material, w, key, bound, sequences,
            numbers, bundle, stream, sample, seed, mueller, frame, last_pdf, *sky_args, *sky_nee_args, *sun_args,
            cone_axis, cone_sigma, *material_args)
        contributions.append(found)
        if len(rows):
            blocked = occluded(rs, shadow)
            counts["shadow"] += len(rows)
            contributions.append(_through(paths, rows, blocked, lit[:, :, None], lit_key, bundle, lights.sun,
                                          len(lights.spectra)))
        if len(sky_rows):
            blocked = occluded(rs, sky_shadow)
            counts["shadow"] += len(sky_rows)
            contributions.append(_through(paths, sky_rows, blocked, sky_lit, sky_key, bundle, 0, len(lights.spectra)))
        if event == depth or not scattered.any():
            break
        paths, rays = paths[scattered], rays[scattered]

    b, combo, weight = (np.concatenate(c) for c in zip(*contributions))
    total = weights.sum(axis=1)
    out = _sum_contributions(b, combo, weight, n, lights.spectra, scene.reflectance, radix, depth, sequences)
    out /= total[:, None, None]
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


def _sky_table(sky, spectra):
    """The sky's sampling table (:func:`beeoptics.light.emitters.sky_table`), made once per sky."""
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
