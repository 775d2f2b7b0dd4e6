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

Spectra. Diffuse scattering multiplies a path's spectral throughput by
the material's reflectance; glossy scattering, emission geometry and
sampling weights are spectrally flat. A path's throughput is therefore
exactly a scalar weight times the product of the reflectance spectra of
the materials it scattered from, in order: the path carries that scalar
and the sequence (as an integer key), and the products are formed once
per distinct sequence, on the full spectral grid, when the contributions
are summed. Light likewise is a flat weight times one of a few spectra
(the sky's basis, the sun's radiance, a material's emission). The result
is the full spectrum, with no RGB or band-limited shortcut, at the cost of
scalar arithmetic per ray.

Randomness. Each random number is a hash (see :mod:`beeoptics.light.sampler`)
of the seed, the receptor's index, the sample's index and the dimension,
so a receptor's result does not depend on which others are traced with it:
a run split into chunks gives bit-identical results.

References
----------
Kajiya JT (1986) The rendering equation. Proc SIGGRAPH 86:143–150.
Veach E (1997) Robust Monte Carlo methods for light transport simulation.
PhD thesis, Stanford University (next-event estimation, Russian roulette).
Lafortune EP, Willems YD (1994) Using the modified Phong reflectance model
for physically based rendering. Report CW197, KU Leuven.
Steele GL, Lea D, Flood CH (2014) Fast splittable pseudorandom number
generators. Proc OOPSLA 2014:453–472.
"""

import numpy as np
from scipy import sparse

from beeoptics.light.emitters import Lights, sample_sun, sees_sun
from beeoptics.light.sampler import uniform
from beeoptics.light.scattering import Surfaces, lambert, phong, scatter
from beeoptics.light.scene import raycasting_scene
from beeoptics.light.sky import sky_coefficients
from beeoptics.raycasting import first_hits, occluded

#: Ray origins leave a surface by this fraction of the scene's size.
OFFSET = 1e-7
#: Russian roulette starts after this many scattering events.
ROULETTE_AFTER = 2
#: Random dimensions drawn per scattering event.
DIMENSIONS_PER_EVENT = 6


def _cast(rs, rays):
    out = first_hits(rs, rays)
    return (out["t_hit"], out["geometry_ids"].astype(np.int64), out["primitive_ids"].astype(np.int64),
            out["primitive_uvs"], out["primitive_normals"].astype(np.float64))


def _occluded(rs, origins, directions):
    return occluded(rs, np.concatenate([origins, directions], axis=1, dtype=np.float32))


def _product_spectra(keys, reflectance, radix, depth):
    """The product of the reflectance spectra that each key's digits name."""
    out = np.ones((len(keys), reflectance.shape[1]))
    k = keys.copy()
    for _ in range(depth + 1):
        digit = k % radix
        sel = digit > 0
        out[sel] *= reflectance[digit[sel] - 1]
        k //= radix
    return out


def _sum_contributions(contributions, n, lights, reflectance, radix, depth):
    """Each bundle's spectral sum of its paths' contributions, (n, n_wavelengths).

    Sum the weights of equal (bundle, sequence, light) triples, then weigh
    each distinct sequence-and-light spectrum once. The (sequence, light)
    pair is one integer, and so is the (bundle, pair) pair: sorting flat
    integers is many times faster than sorting rows. bincount adds in the
    order paths were emitted, and the product below in the order of the
    pairs, neither of which depends on the other bundles of the batch: a
    bundle's sum is the same to the last bit however the run is batched.
    """
    if not contributions:
        return np.zeros((n, lights.shape[1]))
    b, k, light, weight = (np.concatenate(c) for c in zip(*contributions))
    n_lights = len(lights)
    combos, column = np.unique(k * n_lights + light, return_inverse=True)
    cells, cell = np.unique(b * len(combos) + column, return_inverse=True)
    matrix = sparse.csr_matrix((np.bincount(cell, weights=weight), (cells // len(combos), cells % len(combos))),
                               shape=(n, len(combos)))
    spectra = _product_spectra(combos // n_lights, reflectance, radix, depth) * lights[combos % n_lights]
    return np.asarray(matrix @ spectra)


def trace_paths(scene, origins, directions, weights, *, depth, seed, streams=None, first_samples=None,
                rs=None, counts=None):
    """Spectral radiance arriving along bundles of rays, averaged per bundle.

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

    Returns
    -------
    ndarray, shape (n, n_wavelengths)
        Spectral radiance, W m⁻² sr⁻¹ nm⁻¹.
    """
    if depth < 1:
        raise ValueError("depth must be at least 1")
    rs = rs if rs is not None else raycasting_scene(scene)
    surfaces, lights = Surfaces(scene), Lights(scene)
    radix = len(scene.material_names) + 1
    if (depth + 1) * np.log2(radix) + np.log2(len(lights.spectra)) > 62:
        raise ValueError(f"depth {depth} is too deep for {radix - 1} materials")
    counts = counts if counts is not None else {}
    counts.setdefault("cast", 0)
    counts.setdefault("shadow", 0)
    n, s = weights.shape
    eps = OFFSET * max(scene.extent, 1.0)

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
    bound = np.ones(n * s)  # an upper bound of the throughput's spectral maximum
    contributions = []  # (bundle, key, light, weight)

    def emit(idx, light, weight, keys=None):
        keep = weight != 0.0
        if keep.any():
            contributions.append((bundle[idx][keep], (key[idx] if keys is None else keys)[keep],
                                  np.broadcast_to(light, idx.shape)[keep].astype(np.int64), weight[keep]))

    alive = np.arange(n * s)
    for event in range(depth + 1):
        batch = rays[alive]
        t_hit, geometry, primitive, bary, normal = _cast(rs, batch)
        counts["cast"] += len(alive)
        d = batch[:, 3:].astype(np.float64)
        missed = ~np.isfinite(t_hit)
        # Light from the sky, and from the sun's disc on first sight only (after
        # a surface, next-event estimation has counted the sun).
        out, dir_out = alive[missed], d[missed]
        if scene.sky is not None and out.size:
            c = sky_coefficients(scene.sky, dir_out)
            for k in range(c.shape[1]):
                emit(out, k, w[out] * c[:, k])
        if event == 0 and scene.sun is not None and out.size:
            seen = sees_sun(scene.sun, dir_out)
            emit(out[seen], lights.sun, w[out[seen]])
        hit = ~missed
        alive, t_hit, geometry, primitive, bary, normal, d = (
            alive[hit], t_hit[hit], geometry[hit], primitive[hit], bary[hit], normal[hit], d[hit])
        if alive.size == 0:
            break
        m = surfaces.material(geometry, primitive, bary)
        glowing = lights.glows[m]
        emit(alive[glowing], lights.emission + m[glowing], w[alive[glowing]])
        if event == depth:
            break

        p = batch[hit, :3] + t_hit[:, None] * d
        wi = -d
        normal = np.where(((normal * wi).sum(1) < 0.0)[:, None], -normal, normal)
        start = p + eps * normal
        rnd = [uniform(seed, stream[alive], sample[alive], event * DIMENSIONS_PER_EVENT + j)
               for j in range(DIMENSIONS_PER_EVENT)]
        rho_key = key[alive] * radix + (m + 1)
        ks = surfaces.specular[m]
        expo = surfaces.exponent[m]
        cos_o = (normal * wi).sum(1)
        mirror = 2.0 * cos_o[:, None] * normal - wi

        # Next-event estimation towards the sun's disc, sampled uniformly.
        if scene.sun is not None:
            to_sun = sample_sun(scene.sun, rnd[0], rnd[1])
            cos_l = (normal * to_sun).sum(1)
            facing = np.flatnonzero(cos_l > 0.0)
            if facing.size:
                blocked = _occluded(rs, start[facing], to_sun[facing])
                counts["shadow"] += facing.size
                lit = facing[~blocked]
                idx = alive[lit]
                base = w[idx] * cos_l[lit] * scene.sun.solid_angle
                emit(idx, lights.sun, lambert(base), keys=rho_key[lit])
                emit(idx, lights.sun, phong(base, ks[lit], expo[lit], mirror[lit], to_sun[lit]))

        d_new, factor, glossy = scatter(normal, mirror, ks, expo, surfaces.mean_rho[m], rnd[2], rnd[3], rnd[4])
        w[alive] *= factor
        key[alive] = np.where(glossy, key[alive], rho_key)
        bound[alive] *= np.where(glossy, 1.0, surfaces.max_rho[m])
        if event + 1 >= ROULETTE_AFTER:
            q = np.clip(w[alive] * bound[alive], 0.0, 1.0)
            survive = rnd[5] < q
            w[alive] = np.where(survive, w[alive] / np.maximum(q, 1e-300), 0.0)
        keep = w[alive] > 0.0
        alive = alive[keep]
        rays[alive, :3] = start[keep]
        rays[alive, 3:] = d_new[keep]
        if alive.size == 0:
            break

    total = weights.sum(axis=1)
    return _sum_contributions(contributions, n, lights.spectra, scene.reflectance, radix, depth) / total[:, None]
