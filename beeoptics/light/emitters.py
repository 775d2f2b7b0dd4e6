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

References
----------
Veach E (1997) Robust Monte Carlo methods for light transport simulation.
PhD thesis, Stanford University.
"""

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


@kernel
def sample_sun(direction, cos_radius, u_cos, u_phi):
    """A direction towards the sun's disc (``direction``, ``cos_radius``), uniform over its solid angle."""
    cos_a = 1.0 - u_cos * (1.0 - cos_radius)
    return around(direction[0], direction[1], direction[2], cos_a, 2.0 * np.pi * u_phi)
