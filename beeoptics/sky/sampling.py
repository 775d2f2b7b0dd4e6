"""The sky's sampling: a table of where the sky holds more light than its smooth part, for the tracer's
next-event estimation.

The sky is sampled from every surface too, in proportion to what it holds
above its smooth part (:func:`sky_table`, :func:`sample_sky`): a
piecewise-constant distribution over :data:`SKY_ROWS` × :data:`SKY_COLUMNS`
cells of equal solid angle (rows even in the world's z, columns in
azimuth), each cell's weight its radiance above the sky's mean, max(0, L −
L̄), the radiance taken at a few points in the cell, its basis spectra
summed by their mean over the grid, and L̄ the mean over the directions the
sky shines from (the sphere, or a hemisphere sky's upper half). This is MIS
compensation (Karlík et al. 2019): the surface's own scattering, which
multiple importance sampling weighs against the table's
(:mod:`beeoptics.light.integrator`), already samples a smooth sky well (a
Lambertian surface's cosine sampling of a uniform sky is exact), so the
table need only carry the sky's peaks, the circumsolar aureole and the
horizon's brightening. And it is drawn from only as often as it holds the
sky's light (its share, ∫max(0, L − L̄)/∫L, about a fifth of a clear
sky's): at a surface a sample falls in it with that probability, and none
is taken, nor its shadow ray cast, otherwise, so the table's density
integrates to its share, the density multiple importance sampling weighs
(Veach 1997, ch. 9, with an expected sample count below one), and a sky
whose peaks hold little light costs few shadow rays. A uniform sky's
table is empty and it is not sampled at all. Directions the table gives no
weight are still reached by the surface's scattering, whose sample then
counts alone (its weight 1), so the estimate stays unbiased whatever the
table holds. The sun's disc is not in the sky's radiance: it has its own
next-event estimation (:func:`beeoptics.light.emitters.sample_sun`).

References
----------
Karlík O, Šik M, Vévoda P, Skřivan T, Křivánek J (2019) MIS compensation:
optimizing sampling techniques in multiple importance sampling. ACM Trans
Graph 38(6):151.
Veach E (1997) Robust Monte Carlo methods for light transport simulation.
PhD thesis, Stanford University.
"""

import math

import numpy as np

from beeoptics.jit import kernel
from beeoptics.sky.hosekwilkie import shape_radiances

#: Rows (even in z, from −1 to 1) and columns (even in azimuth) of the sky's sampling table: cells of
#: 4π/2048 sr, about 2.5° across, finer than the sky's gradients away from the sun's aureole. Powers of
#: two, and the rows even, so that the upper hemisphere is whole rows and a mean over cells is exact.
SKY_ROWS, SKY_COLUMNS = 32, 64
#: Points per cell, along each of its sides, at which the sky is evaluated for its weight.
SKY_SUPERSAMPLE = 3


def sky_table(sky, spectra):
    """The sky's sampling distribution: each row's cumulative weight (rows + 1,), from 0 to the table's
    share, each row's cells' (rows, columns + 1), from 0 to 1, and each cell's density per steradian
    (rows, columns), in proportion to the cell's radiance above the sky's mean (MIS compensation,
    Karlík et al. 2019) and integrating to the share: the part of the sky's light above its mean. All zero
    for a sky that is nowhere above its mean.

    Parameters
    ----------
    sky : Sky or None
    spectra : ndarray (k, n_wavelengths)
        The sky's basis spectra; each basis weight counts by its spectrum's mean.
    """
    rows, cols, m = SKY_ROWS, SKY_COLUMNS, SKY_SUPERSAMPLE
    density = np.zeros((rows, cols))
    share = 0.0
    if sky is not None:
        z = -1.0 + 2.0 * (np.arange(rows * m) + 0.5) / (rows * m)
        phi = 2.0 * np.pi * (np.arange(cols * m) + 0.5) / (cols * m)
        zz, pp = np.meshgrid(z, phi, indexing="ij")
        s = np.sqrt(1.0 - zz**2)
        d = np.column_stack([(s * np.cos(pp)).ravel(), (s * np.sin(pp)).ravel(), zz.ravel()])
        value = shape_radiances(d, sky.sun, sky.shape, sky.cos_floor, sky.cos_offset, sky.hemisphere)
        value = (value @ np.asarray(spectra, float).mean(axis=1)).reshape(rows, m, cols, m).mean(axis=(1, 3))
        # The mean over the sky's own directions (cells of equal solid angle; the upper rows are z > 0), and
        # what rises above it: Karlík et al.'s compensated density for a technique combined with another
        # (here the surface's) that knows nothing of the sky. Cells at or below it are left to the surface's
        # sampling. The sums are exactly rounded and the cells a power of two, so that a uniform sky's equal
        # cells are not above their mean by a rounding.
        domain = value[rows // 2:] if sky.hemisphere else value
        whole = math.fsum(domain.ravel())
        value = np.maximum(value - whole / domain.size, 0.0)
        total = math.fsum(value.ravel())
        if total > 0.0:
            # The table is drawn from as often as it holds the sky's light (a sample from it is skipped
            # otherwise): a smooth sky's few peaks are not worth a shadow ray at every surface.
            share = total / whole
            density = value * share / (total * 4.0 * np.pi / (rows * cols))
    weight = density.sum(axis=1)
    row_cdf = np.concatenate([[0.0], np.cumsum(weight)])
    row_cdf = share * row_cdf / row_cdf[-1] if share > 0.0 else row_cdf
    cells = np.concatenate([np.zeros((rows, 1)), np.cumsum(density, axis=1)], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        col_cdf = np.where(cells[:, -1:] > 0, cells / cells[:, -1:], np.linspace(0.0, 1.0, cols + 1)[None])
    return row_cdf, col_cdf, density


@kernel
def sample_sky(row_cdf, col_cdf, density, u_row, u_col):
    """A direction from the sky's table (:func:`sky_table`) and its density per steradian; density 0 (and no
    direction) where ``u_row`` falls past the table's share.

    Continuous inversion of the piecewise-constant distribution: the
    fraction of ``u`` past a cell's start places the direction uniformly in
    the cell's z and azimuth, so uniformly over its solid angle.
    """
    rows, cols = density.shape
    if u_row >= row_cdf[-1]:
        return 0.0, 0.0, 0.0, 0.0
    r = min(max(np.searchsorted(row_cdf, u_row, side="right") - 1, 0), rows - 1)
    width = row_cdf[r + 1] - row_cdf[r]
    t = (u_row - row_cdf[r]) / width if width > 0.0 else 0.5
    c = min(max(np.searchsorted(col_cdf[r], u_col, side="right") - 1, 0), cols - 1)
    width = col_cdf[r, c + 1] - col_cdf[r, c]
    v = (u_col - col_cdf[r, c]) / width if width > 0.0 else 0.5
    z = -1.0 + 2.0 * (r + min(max(t, 0.0), 1.0)) / rows
    phi = 2.0 * np.pi * (c + min(max(v, 0.0), 1.0)) / cols
    s = np.sqrt(max(1.0 - z * z, 0.0))
    return s * np.cos(phi), s * np.sin(phi), z, density[r, c]


@kernel
def sky_density(density, x, y, z):
    """The density per steradian with which :func:`sample_sky` draws the unit direction (x, y, z)."""
    rows, cols = density.shape
    r = min(max(int((z + 1.0) * 0.5 * rows), 0), rows - 1)
    phi = np.arctan2(y, x)
    if phi < 0.0:
        phi += 2.0 * np.pi
    c = min(max(int(phi / (2.0 * np.pi) * cols), 0), cols - 1)
    return density[r, c]
