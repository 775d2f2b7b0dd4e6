"""Surface scattering: which material a ray meets, and its BSDF, evaluated and sampled.

The BSDF is Lambertian with the material's spectral reflectance ρ(λ), plus,
for a glossy material, a normalised Phong lobe (Lafortune & Willems 1994)
of spectrally flat albedo k_s about the mirror direction. Sampling picks the
diffuse or the glossy lobe in proportion to their albedos (the diffuse
albedo taken as ρ's mean over the grid), then a cosine-weighted direction or
one from the Phong lobe's cos^n distribution.

The diffuse lobe's spectrum is not multiplied in here: a path carries the
materials it scattered from as a key (see :mod:`beeoptics.light.integrator`),
so its diffuse factors are the flat 1/π and, once sampled, 1 over the
lobe's probability. The lobes are evaluated and sampled one path at a time
in compiled code, called from the integrator's kernels.

References
----------
Lafortune EP, Willems YD (1994) Using the modified Phong reflectance model
for physically based rendering. Report CW197, KU Leuven.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.jit import kernel
from beeoptics.light.coating import ALBEDO_NODES, albedo_table, coupling, through
from beeoptics.light.coating import sample as sample_coating
from beeoptics.light.coating import specular as coating_lobe
from beeoptics.light.sampler import around


class Surfaces:
    """The material of every face (or texel) of a scene, and each material's scattering parameters.

    Attributes
    ----------
    specular, exponent : ndarray (materials,)
        The Phong lobe's albedo k_s and exponent n.
    roughness : ndarray (materials,)
        The coating's GGX roughness α, 0 for a material without one.
    refractive_index : ndarray (materials,)
        The coating's η, or how the Phong lobe polarises (:mod:`beeoptics.light.mueller`).
    coat_table : ndarray (materials, ALBEDO_NODES + 1)
        Each coating's directional albedo and its mean
        (:func:`beeoptics.light.coating.albedo_table`), zeros without one.
    mean_rho, max_rho : ndarray (materials,)
        The diffuse reflectance's mean and maximum over the grid.
    """

    def __init__(self, scene):
        sizes = [len(o.faces) for o in scene.objects]
        self._offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self._face_material = np.concatenate(
            [o.face_material if o.face_material is not None else np.full(len(o.faces), -1, np.int32)
             for o in scene.objects] + [np.zeros(0, np.int32)])
        self._textured = [i for i, o in enumerate(scene.objects) if o.texture is not None]
        self._objects = scene.objects
        self.specular = scene.specular
        self.exponent = scene.exponent
        self.roughness = scene.roughness
        self.refractive_index = scene.refractive_index
        self.coat_table = np.zeros((len(scene.roughness), ALBEDO_NODES + 1))
        for k in np.flatnonzero(scene.roughness > 0.0):
            self.coat_table[k] = albedo_table(scene.roughness[k], scene.refractive_index[k])
        self.mean_rho = scene.reflectance.mean(axis=1)
        self.max_rho = scene.reflectance.max(axis=1)

    def material(self, geometry, primitive, bary):
        """Material index of each hit: its face's, or its texel's on a textured object."""
        m = self._face_material[self._offset[geometry] + primitive].astype(np.int64)
        for i in self._textured:
            hit = np.flatnonzero(geometry == i)
            if hit.size == 0:
                continue
            o = self._objects[i]
            uv = o.uv[primitive[hit]]
            b = bary[hit]
            st = (1.0 - b[:, :1] - b[:, 1:]) * uv[:, 0] + b[:, :1] * uv[:, 1] + b[:, 1:] * uv[:, 2]
            h, w = o.texture.shape
            col = np.floor(st[:, 0] * w).astype(np.int64) % w
            row = np.floor((1.0 - st[:, 1]) * h).astype(np.int64) % h
            m[hit] = o.texture[row, col]
        return m


class SurfaceArrays(NamedTuple):
    """Each material's scattering and emission as the compiled integrator takes them: numba takes named tuples
    of arrays. Made once per trace (:func:`beeoptics.light.integrator.trace_paths`).

    Attributes
    ----------
    specular, exponent, roughness, refractive_index, coat_table, mean_rho, max_rho : ndarray
        :class:`Surfaces`' own.
    glows : ndarray of bool (materials,)
        Whether each material emits.
    emission_row : int
        The row of the first material's emission among the lights
        (:class:`beeoptics.light.emitters.Lights`); material m's is ``emission_row + m``.
    radix : int
        The materials plus one: the base of the integer that numbers a path's sequence of materials.
    """

    specular: np.ndarray
    exponent: np.ndarray
    roughness: np.ndarray
    refractive_index: np.ndarray
    coat_table: np.ndarray
    mean_rho: np.ndarray
    max_rho: np.ndarray
    glows: np.ndarray
    emission_row: int
    radix: int


@kernel
def phong(specular, exponent, mirror, x, y, z):
    """The normalised Phong lobe towards (x, y, z), k_s (n + 2)/(2π) cos^n α, α off the ``mirror`` direction (3,)."""
    cos_a = max(mirror[0] * x + mirror[1] * y + mirror[2] * z, 0.0)
    return specular * (exponent + 2.0) / (2.0 * np.pi) * cos_a**exponent


@kernel
def glossy_share(cos_v, specular, mean_rho, alpha, table):
    """The probability of sampling the surface reflection rather than the base, seen at cos θ = ``cos_v``: in
    proportion to their albedos (the base's taken at its mean reflectance)."""
    if alpha > 0.0:
        e = 1.0 - through(cos_v, table)
        albedo, glossy = e + mean_rho * (1.0 - e), e
    else:
        albedo, glossy = mean_rho + specular, specular
    return glossy / albedo if albedo > 0.0 else 0.0


@kernel
def lobes(normal, mirror, view, x, y, z, specular, exponent, alpha, eta, table, p_glossy):
    """Both lobes towards (x, y, z), seen from ``view`` (3, towards the viewer).

    Returns
    -------
    diffuse : float
        The base's factor on ρ/π: 1 for the bare Lambertian base, the
        coating's coupling (:func:`beeoptics.light.coating.coupling`) under a coating.
    glossy : float
        The surface reflection's BRDF, per steradian (Phong's lobe or the coating's).
    p_diffuse, p_glossy : float
        The densities (per steradian) with which :func:`scatter` draws the direction by each lobe,
        times the lobe's probability.
    """
    cos_i = normal[0] * view[0] + normal[1] * view[1] + normal[2] * view[2]
    cos_o = normal[0] * x + normal[1] * y + normal[2] * z
    p_diffuse = (1.0 - p_glossy) * max(cos_o, 0.0) / np.pi
    if alpha > 0.0:
        f, p = coating_lobe(normal, view, x, y, z, alpha, eta)
        return coupling(cos_i, cos_o, table), f, p_diffuse, p_glossy * p
    cos_a = max(mirror[0] * x + mirror[1] * y + mirror[2] * z, 0.0)
    return (1.0, phong(specular, exponent, mirror, x, y, z), p_diffuse,
            p_glossy * (exponent + 1.0) / (2.0 * np.pi) * cos_a**exponent)


@kernel
def scatter(normal, mirror, view, specular, exponent, mean_rho, alpha, eta, table, u_lobe, u_cos, u_phi):
    """Sample a path's next direction from its BSDF.

    Parameters
    ----------
    normal, mirror, view : ndarray (3,)
        The shading normal, facing the incoming ray, the mirror direction, and the direction back along
        the incoming ray.
    specular, exponent, mean_rho : float
        The material's Phong albedo and exponent, and mean diffuse reflectance.
    alpha, eta, table : float, float, ndarray
        The coating's roughness (0: none), refractive index and albedo table.
    u_lobe, u_cos, u_phi : float
        Uniform random numbers.

    Returns
    -------
    x, y, z : float
        The direction.
    factor : float
        The flat part of BSDF × cosine / probability; zero for a black
        material or a direction below the surface.
    glossy : bool
        Whether the surface reflection was sampled (else the base, whose
        reflectance the path's key records; its flat 1/π cancels the cosine
        lobe's probability).
    density : float
        The density of the direction by the lobe sampled, times its probability (for MIS).
    """
    cos_i = normal[0] * view[0] + normal[1] * view[1] + normal[2] * view[2]
    p_glossy = glossy_share(cos_i, specular, mean_rho, alpha, table)
    glossy = u_lobe < p_glossy
    if glossy and alpha > 0.0:
        x, y, z = sample_coating(normal, view, alpha, u_cos, u_phi)
    else:
        axis = mirror if glossy else normal
        cos_t = u_cos ** (1.0 / (exponent + 1.0)) if glossy else np.sqrt(1.0 - u_cos)
        x, y, z = around(axis[0], axis[1], axis[2], cos_t, 2.0 * np.pi * u_phi)
    cos_n = normal[0] * x + normal[1] * y + normal[2] * z
    if (alpha <= 0.0 and mean_rho + specular <= 0.0) or cos_n <= 0.0:
        return x, y, z, 0.0, glossy, 0.0
    diffuse, f, p_diffuse, p_lobe = lobes(normal, mirror, view, x, y, z, specular, exponent, alpha, eta, table,
                                          p_glossy)
    if glossy:
        return x, y, z, f * cos_n / max(p_lobe, 1e-300), glossy, p_lobe
    return x, y, z, diffuse / max(1.0 - p_glossy, 1e-300), glossy, p_diffuse
