"""Counter-based random numbers: the same number for the same (seed, stream, sample, dimension).

A stream is a receptor (or pixel), a sample one of its rays, a dimension
one random choice along that ray's path. Because each number is a hash of
those four integers (SplitMix64's finaliser, Steele et al. 2014), a
receptor's samples do not depend on which other receptors are traced with
it, or in what order: chunked runs are bit-identical to whole ones.

References
----------
Steele GL, Lea D, Flood CH (2014) Fast splittable pseudorandom number
generators. Proc OOPSLA 2014:453–472.
"""

import numpy as np


def _splitmix(x):
    x = x + np.uint64(0x9E3779B97F4A7C15)
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


def uniform(seed, stream, sample, dimension):
    """Counter-based uniform numbers in [0, 1): one per (stream, sample) pair, for one dimension."""
    with np.errstate(over="ignore"):
        key = _splitmix(np.uint64(seed) ^ _splitmix(
            (stream.astype(np.uint64) << np.uint64(32)) ^ sample.astype(np.uint64)
            ^ (np.uint64(dimension) << np.uint64(56))))
    return (key >> np.uint64(11)).astype(np.float64) * (1.0 / 2.0**53)
