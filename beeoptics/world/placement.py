"""Where plants grow: a clustered point process of given density.

Plants of one species are placed by a Thomas process (Thomas 1949;
Illian et al. 2008, section 6.3.2), the standard model of clumped plant
populations: clump centres fall at random (Poisson) with density
``density / per_clump``; each clump has a Poisson number of plants of
mean ``per_clump``, scattered round its centre with a Gaussian of standard
deviation ``spread_m``. The mean density is ``density`` per square metre
whatever the clumping; ``per_clump`` = 1 with any spread is the Poisson
(unclumped) case. The patch wraps round at its edges, so that clumps
near a border do not thin the plants there.

References
----------
Thomas M (1949) A generalization of Poisson's binomial limit for use in
ecology. Biometrika 36:18–25.
Illian J, Penttinen A, Stoyan H, Stoyan D (2008) Statistical analysis
and modelling of spatial point patterns. Wiley.
"""

import numpy as np


def thomas(extent_m, density, per_clump, spread_m, rng):
    """Positions (n, 2), metres, in a patch of ``extent_m`` (2,) centred on the origin."""
    extent = np.asarray(extent_m, float)
    area = float(np.prod(extent))
    if density <= 0.0:
        return np.zeros((0, 2))
    clumps = rng.poisson(density / per_clump * area)
    centres = (rng.random((clumps, 2)) - 0.5) * extent
    counts = rng.poisson(per_clump, clumps) if per_clump > 1.0 else np.ones(clumps, int)
    points = np.repeat(centres, counts, axis=0) + spread_m * rng.standard_normal((counts.sum(), 2)) * (per_clump > 1.0)
    return (points + extent / 2.0) % extent - extent / 2.0


def clear_of(points, centres, radii):
    """Which points (n, 2) lie outside every circle of ``centres`` (k, 2) and ``radii`` (k,)."""
    if len(centres) == 0:
        return np.ones(len(points), bool)
    d = np.linalg.norm(points[:, None, :] - np.asarray(centres)[None, :, :2], axis=2)
    return (d > np.asarray(radii)[None, :]).all(1)
