"""The emitters: the sky, the sun's disc and glowing materials, as light spectra.

Light reaching a path is always a flat weight times one of a few spectra:
the sky's basis spectra (:mod:`beeoptics.sky.dome`), the sun's radiance
(:mod:`beeoptics.sky.sun`) and the emission of each material. They are
numbered in one table, so that a contribution names its spectrum by an
integer and the integrator weighs each spectrum once.

The sun is seen directly when a path's first segment points into its disc,
and is sampled uniformly over the disc's solid angle (:func:`sample_sun`)
by next-event estimation from every surface a path meets and, in a
receptor's cone, against the cone's own samples (Veach 1997; see
:mod:`beeoptics.light.integrator`).

The sky is sampled from every surface too, from the table of
:mod:`beeoptics.sky.sampling` (MIS compensation: what the sky holds above
its smooth part), weighed against the surface's own scattering by
multiple importance sampling (:mod:`beeoptics.light.integrator`). The sun's
disc is not in the sky's radiance: it has its own next-event estimation
(:func:`sample_sun`).

References
----------
Veach E (1997) Robust Monte Carlo methods for light transport simulation.
PhD thesis, Stanford University.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.jit import kernel
from beeoptics.light.sampler import around


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
        The sky's shape model (:func:`beeoptics.sky.hosekwilkie.shape_radiance`), one row of ``sky_shape``
        per basis spectrum; its rows are the lights' first.
    sky_neutral, sky_max_degree : ndarray (2,), float
        The sky's polarisation (:func:`beeoptics.sky.skypolarisation.polarisation`, ``degree``).
    sky_depolarisation : ndarray (basis spectra,)
        Its depolarisation at each basis spectrum's wavelength.
    sky_nee : bool
        Whether the sky is sampled from every surface, from its table:
    sky_rows, sky_cols, sky_table : ndarray
        :func:`beeoptics.sky.sampling.sky_table`'s cumulative rows and cells and density, sr⁻¹.
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
