"""The sampler: random numbers, stratified sample sets, and directions about an axis.

Random numbers are counter-based: the same number for the same (seed,
stream, sample, dimension). A stream is a receptor (or pixel), a sample one
of its rays, a dimension one random choice along that ray's path. Because
each number is a hash of those four integers (SplitMix64's finaliser,
Steele et al. 2014), a receptor's samples do not depend on which other
receptors are traced with it, or in what order: chunked runs are
bit-identical to whole ones.

A bundle of rays (a receptor's cone, a pixel) is stratified by one
scrambled Halton set (Owen 2017) shared by all bundles, each shifting it by
its own random offset (Cranley & Patterson 1976).

A bundle may be traced as several independent replicates (randomised
quasi-Monte Carlo: L'Ecuyer & Lemieux 2002): replicate j draws the same
Halton points 0, 1, … under its own random shift, and its paths' numbers
from sample indices j·2²⁴ + i, so that no two replicates share a number and
their spread is an honest error. In :func:`uniform1`'s key a sample index
takes bits 0–31 (replicate 0–255 in bits 24–31, a replicate's sample
0–2²⁴−1 below), the stream bits 32–55 (streams below 2²⁴) and the
dimension bits 56–63 (dimensions below 256).

References
----------
Steele GL, Lea D, Flood CH (2014) Fast splittable pseudorandom number
generators. Proc OOPSLA 2014:453–472.
Cranley R, Patterson TNL (1976) Randomization of number theoretic methods
for multiple integration. SIAM J Numer Anal 13:904–914.
Owen AB (2017) A randomized Halton algorithm in R. arXiv:1706.02808.
L'Ecuyer P, Lemieux C (2002) Recent advances in randomized quasi-Monte Carlo
methods. In: Dror M et al. (eds) Modeling Uncertainty. Kluwer, pp 419–474.
Duff T, Burgess J, Christensen P, Hery C, Kensler A, Liani M, Villemin R
(2017) Building an orthonormal basis, revisited. J Comput Graph Tech 6:1–8.
"""

import copy
import functools

import numpy as np

from beeoptics.jit import kernel

#: Bits of a sample index below its replicate's index: a replicate holds at most 2²⁴ samples.
REPLICATE_SHIFT = 24
#: Streams a run may number: :func:`uniform1`'s key holds a stream in bits 32–55, and a larger one would
#: share bits with the dimension's, so that two streams could draw the same numbers.
STREAMS = 1 << 24

_GOLDEN, _MIX1, _MIX2 = np.uint64(0x9E3779B97F4A7C15), np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)


@kernel
def _splitmix(x):
    x = x + _GOLDEN
    x = (x ^ (x >> np.uint64(30))) * _MIX1
    x = (x ^ (x >> np.uint64(27))) * _MIX2
    return x ^ (x >> np.uint64(31))


@kernel
def uniform1(seed, stream, sample, dimension):
    """One counter-based uniform number in [0, 1) for (seed, stream, sample, dimension), compiled."""
    key = _splitmix(np.uint64(seed) ^ _splitmix((np.uint64(stream) << np.uint64(32)) ^ np.uint64(sample)
                                                ^ (np.uint64(dimension) << np.uint64(56))))
    return np.float64(key >> np.uint64(11)) * (1.0 / 2.0**53)


@kernel
def _uniform_many(seed, stream, sample, dimension):
    out = np.empty(len(stream))
    for i in range(len(stream)):
        out[i] = uniform1(seed, stream[i], sample[i], dimension)
    return out


def uniform(seed, stream, sample, dimension):
    """Counter-based uniform numbers in [0, 1): one per (stream, sample) pair, for one dimension."""
    return _uniform_many(int(seed), np.asarray(stream, np.int64), np.asarray(sample, np.int64), int(dimension))


def shifted_halton(samples, seed, streams, dimensions, first_samples=None):
    """Points in the unit square: one scrambled Halton sequence, shifted per stream and replicate.

    Parameters
    ----------
    samples : int
        Points per stream.
    seed : int
    streams : ndarray of int, shape (n,)
        The bundles' indices among all bundles of the run.
    dimensions : pair of int
        The random dimensions of the two shifts.
    first_samples : ndarray of int, shape (n,), optional
        Each stream's first sample index (0 by default): its replicate
        (``first >> REPLICATE_SHIFT``) chooses the shift, the rest where in
        the sequence the points start, so that a bundle's samples can be
        drawn in blocks.

    Returns
    -------
    ndarray, shape (n, samples, 2)
    """
    n = len(streams)
    first_samples = np.zeros(n, np.int64) if first_samples is None else np.asarray(first_samples, np.int64)
    offset = first_samples & ((1 << REPLICATE_SHIFT) - 1)
    base = np.empty((n, samples, 2))
    # A copy of the seed's sequence (sharing its scrambling), so that threads drawing from it at once do not
    # move each other's position.
    halton = copy.copy(_scrambled_halton(seed))
    for start in np.unique(offset):
        # The Halton sequence is computed from a point's index: start there. (scipy's
        # fast_forward would draw and discard the points before it, a cost that grows with it.)
        halton.num_generated = int(start)
        base[offset == start] = halton.random(samples)
    # A replicate's shift is keyed by its first sample index, which no path's number of another replicate uses.
    shift = np.stack([uniform(seed, streams, first_samples - offset, d) for d in dimensions], -1)
    return (base + shift[:, None, :]) % 1.0


@functools.lru_cache(maxsize=8)
def _scrambled_halton(seed):
    """The seed's scrambled Halton sequence in two dimensions. Made once: drawing its digit permutations took
    a quarter of a small trace call's time besides its rays (0.6 ms, twice a call)."""
    from scipy.stats import qmc  # imported where used: scipy.stats takes half a second, which only tracing needs

    return qmc.Halton(2, scramble=True, seed=np.random.default_rng(seed))


@kernel
def tangent_frame(x, y, z):
    """Two unit vectors perpendicular to the unit axis (x, y, z) and to each other, as six numbers.

    The branchless basis of Duff et al. (2017): no cross products or
    square roots, and continuous everywhere but across the plane z = 0.
    """
    sign = 1.0 if z >= 0.0 else -1.0
    a = -1.0 / (sign + z)
    b = x * y * a
    return 1.0 + sign * x * x * a, sign * b, -sign * x, b, sign + y * y * a, -y


@kernel
def around(x, y, z, cos_t, phi):
    """The unit direction at polar cosine ``cos_t`` and azimuth ``phi`` about the unit axis (x, y, z)."""
    t0, t1, t2, b0, b1, b2 = tangent_frame(x, y, z)
    sin_t = np.sqrt(max(0.0, 1.0 - cos_t * cos_t))
    c, s = sin_t * np.cos(phi), sin_t * np.sin(phi)
    return cos_t * x + c * t0 + s * b0, cos_t * y + c * t1 + s * b1, cos_t * z + c * t2 + s * b2


@kernel
def tangent_frames(axes):
    """:func:`tangent_frame` of each unit axis (n, 3): shape (n, 2, 3)."""
    frames = np.empty((len(axes), 2, 3))
    for i in range(len(axes)):
        f = tangent_frame(axes[i, 0], axes[i, 1], axes[i, 2])
        for k in range(6):
            frames[i, k // 3, k % 3] = f[k]
    return frames
