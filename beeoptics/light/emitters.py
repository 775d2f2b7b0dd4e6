"""The emitters: the sky, the sun's disc and glowing materials, as light spectra.

Light reaching a path is always a flat weight times one of a few spectra:
the sky's basis spectra (:mod:`beeoptics.light.sky`), the sun's radiance
(:mod:`beeoptics.light.sun`) and the emission of each material. They are
numbered in one table, so that a contribution names its spectrum by an
integer and the integrator weighs each spectrum once.

The sun is seen directly when a path's first segment points into its disc,
and is sampled uniformly over the disc's solid angle (:func:`sample_sun`)
by next-event estimation from every surface a path meets and, in a
receptor's cone, against the cone's own samples (Veach 1997; see
:mod:`beeoptics.light.integrator`).

The sky is sampled from every surface too, in proportion to its radiance
(:func:`sky_table`, :func:`sample_sky`): a piecewise-constant
distribution over :data:`SKY_ROWS` × :data:`SKY_COLUMNS` cells of equal
solid angle (rows even in the world's z, columns in azimuth), each cell's
weight the sky's radiance at a few points in it, its basis spectra
summed by their mean over the grid. Directions the table gives no weight
(a hemisphere sky's below the horizon) are still reached by the surface's
own scattering, which multiple importance sampling weighs against the
table's (:mod:`beeoptics.light.integrator`), so the estimate stays unbiased
whatever the table's resolution.

References
----------
Veach E (1997) Robust Monte Carlo methods for light transport simulation.
PhD thesis, Stanford University.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.jit import kernel
from beeoptics.light.hosekwilkie import shape_radiances
from beeoptics.light.sampler import around

#: Rows (even in z, from −1 to 1) and columns (even in azimuth) of the sky's sampling table: cells of
#: 4π/2048 sr, about 2.5° across, finer than the sky's gradients away from the sun's aureole.
SKY_ROWS, SKY_COLUMNS = 32, 64
#: Points per cell, along each of its sides, at which the sky is evaluated for its weight.
SKY_SUPERSAMPLE = 3


class Lights:
    """The light spectra of a scene, one table: the sky's basis, the sun, each material's emission.

    Attributes
    ----------
    spectra : ndarray, shape (k, n_wavelengths)
    sun : int
        Row of the sun's radiance (zero where the scene has no sun).
    emission : int
        Row of the first material's emission; material m glows in row ``emission + m``.
    glows : ndarray of bool
        Per material, whether it emits.
    """

    def __init__(self, scene):
        n_sky = 0 if scene.sky is None else len(scene.sky.basis)
        parts = [scene.sky.basis] if scene.sky is not None else []
        parts.append(scene.sun.radiance[None] if scene.sun is not None else np.zeros((1, scene.reflectance.shape[1])))
        parts.append(scene.emission)
        self.spectra = np.vstack(parts)
        self.sun = n_sky
        self.emission = n_sky + 1
        self.glows = scene.emission.max(axis=1) > 0.0


class LightArrays(NamedTuple):
    """The lights as the compiled integrator takes them: numba takes named tuples of arrays. Made once per
    trace (:func:`beeoptics.light.integrator.trace_paths`); without a sun or a sky, their fields are
    placeholders that ``sun_row`` < 0 or ``has_sky`` false leave unread.

    Attributes
    ----------
    n_lights : int
        Rows of :attr:`Lights.spectra`.
    sun_row : int
        The sun's row there, −1 without a sun.
    sun_dir : ndarray (3,)
        The unit direction towards the sun's centre.
    sun_cos, sun_solid_angle : float
        The cosine of the disc's angular radius, and its solid angle, sr.
    has_sky : bool
    sky_sun, sky_shape, sky_floor, sky_offset, sky_hemisphere
        The sky's shape model (:func:`beeoptics.light.hosekwilkie.shape_radiance`), one row of ``sky_shape``
        per basis spectrum; its rows are the lights' first.
    sky_neutral, sky_max_degree : ndarray (2,), float
        The sky's polarisation (:func:`beeoptics.light.skypolarisation.polarisation`, ``degree``).
    sky_depolarisation : ndarray (basis spectra,)
        Its depolarisation at each basis spectrum's wavelength.
    sky_nee : bool
        Whether the sky is sampled from every surface, from its table:
    sky_rows, sky_cols, sky_table : ndarray
        :func:`sky_table`'s cumulative rows and cells and density, sr⁻¹.
    """

    n_lights: int
    sun_row: int
    sun_dir: np.ndarray
    sun_cos: float
    sun_solid_angle: float
    has_sky: bool
    sky_sun: np.ndarray
    sky_shape: np.ndarray
    sky_floor: float
    sky_offset: float
    sky_hemisphere: bool
    sky_neutral: np.ndarray
    sky_max_degree: float
    sky_depolarisation: np.ndarray
    sky_nee: bool
    sky_rows: np.ndarray
    sky_cols: np.ndarray
    sky_table: np.ndarray


@kernel
def sample_sun(direction, cos_radius, u_cos, u_phi):
    """A direction towards the sun's disc (``direction``, ``cos_radius``), uniform over its solid angle."""
    cos_a = 1.0 - u_cos * (1.0 - cos_radius)
    return around(direction[0], direction[1], direction[2], cos_a, 2.0 * np.pi * u_phi)


def sky_table(sky, spectra):
    """The sky's sampling distribution: each row's cumulative weight (rows + 1,), each row's cells'
    (rows, columns + 1), both from 0 to 1, and each cell's density per steradian (rows, columns).

    Parameters
    ----------
    sky : Sky or None
    spectra : ndarray (k, n_wavelengths)
        The sky's basis spectra; each basis weight counts by its spectrum's mean.
    """
    rows, cols, m = SKY_ROWS, SKY_COLUMNS, SKY_SUPERSAMPLE
    density = np.zeros((rows, cols))
    if sky is not None:
        z = -1.0 + 2.0 * (np.arange(rows * m) + 0.5) / (rows * m)
        phi = 2.0 * np.pi * (np.arange(cols * m) + 0.5) / (cols * m)
        zz, pp = np.meshgrid(z, phi, indexing="ij")
        s = np.sqrt(1.0 - zz**2)
        d = np.column_stack([(s * np.cos(pp)).ravel(), (s * np.sin(pp)).ravel(), zz.ravel()])
        value = shape_radiances(d, sky.sun, sky.shape, sky.cos_floor, sky.cos_offset, sky.hemisphere)
        value = (value @ np.asarray(spectra, float).mean(axis=1)).reshape(rows, m, cols, m).mean(axis=(1, 3))
        total = value.sum()
        if total > 0.0:
            density = value / (total * 4.0 * np.pi / (rows * cols))
    weight = density.sum(axis=1)
    row_cdf = np.concatenate([[0.0], np.cumsum(weight)])
    row_cdf = row_cdf / row_cdf[-1] if row_cdf[-1] > 0 else np.linspace(0.0, 1.0, rows + 1)
    cells = np.concatenate([np.zeros((rows, 1)), np.cumsum(density, axis=1)], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        col_cdf = np.where(cells[:, -1:] > 0, cells / cells[:, -1:], np.linspace(0.0, 1.0, cols + 1)[None])
    return row_cdf, col_cdf, density


@kernel
def sample_sky(row_cdf, col_cdf, density, u_row, u_col):
    """A direction from the sky's table (:func:`sky_table`) and its density per steradian.

    Continuous inversion of the piecewise-constant distribution: the
    fraction of ``u`` past a cell's start places the direction uniformly in
    the cell's z and azimuth, so uniformly over its solid angle.
    """
    rows, cols = density.shape
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
