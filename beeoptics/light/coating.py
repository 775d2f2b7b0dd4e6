"""A rough dielectric coating over a Lambertian base: a GGX microfacet interface, Fresnel in strength and polarisation.

The coating's reflection is a microfacet BRDF (Walter et al. 2007) with
the GGX (Trowbridge–Reitz) distribution of normals of roughness α, the
Smith shadowing–masking function (separable, G2 = G1(i) G1(o)), and
Fresnel's reflectance of a dielectric of refractive index η at each
microfacet:

    f_s(i, o) = F(i·h) D(h) G1(i) G1(o) / (4 |n·i| |n·o|),

its strength Fresnel's mean reflectance (R_s + R_p)/2 and its
polarisation Fresnel's Mueller matrix (:mod:`beeoptics.light.mueller`)
at the same microfacet, so both follow from one set of equations.

The light the coating does not reflect reaches the Lambertian base, which
returns ρ of it; the coating lets some of that out and reflects the rest
back to the base (from inside, wholly beyond the critical angle), where it
is absorbed or returned again, as Saunderson (1942) sums a pigmented
plastic's internal reflections. The base's share is Kelemen &
Szirmay-Kalos's (2001) coupling of a microfacet layer to a matte one, with
the base's albedo as it is returned through those reflections:

    f_d(i, o) = ρ'/π · (1 − E(μ_i)) (1 − E(μ_o)) / (1 − Ē),
    ρ' = ρ (1 − F_dr) / (1 − ρ F_dr),

E(μ) the coating's directional albedo (∫ f_s cos θ_o dω_o at incidence
cos θ = μ, tabulated per material), Ē = 2∫ E(μ) μ dμ its hemispherical
mean, and F_dr the same mean of the coating's albedo seen from inside
(η → 1/η): how much of the base's diffuse light it sends back. ρ'
(:func:`base_albedo`) is a spectrum per material and the coupling
(:func:`coupling`) spectrally flat, as the tracer carries them. The pair
is reciprocal, and with ρ = 1 (ρ' = 1) it reflects everything:
E(μ) + (1 − E(μ)) = 1 for any α and η (the white furnace).

The exact answer of this layered model, a random walk between interface
and base as pbrt-v4's coated diffuse computes it
(:mod:`beeoptics.light.layered`), is Mitsuba 3's ``roughplastic`` with
``nonlinear`` internal scattering, ρ/π T(μ_i) T(μ_o) / (η² (1 − ρ F_dr)),
T the interface's transmittance: the walk, once at the base, forgets its
direction. It depends on ρ as ρ' does; where it differs from this
coupling is in the light a microfacet interface that scatters once loses
(its reflections and refractions into the surface, which a real surface
scatters on: a white base under α 0.3, η 1.5, returns 66 % of a uniform
sky). This coupling gives that light to the base, so that a white base
returns the sky (``benchmarks/layered.py`` compares the two, and
Kelemen's with ρ in place of ρ', this module's until then: 44–151 % too
bright, median over angles and albedos at α 0.05–0.6). Only the specular
lobe is Mitsuba's ``roughplastic`` (and, polarised, ``pplastic``) lobe.
Light passed through the coating is taken as unpolarised, as the
Lambertian base leaves it. The specular lobe is sampled by the
distribution of visible normals (Heitz 2018), whose density is
G1(i) D(h) / (4 |n·i|) per reflected direction.

References
----------
Walter B, Marschner SR, Li H, Torrance KE (2007) Microfacet models for
refraction through rough surfaces. Proc. Eurographics Symposium on
Rendering, 195–206.
Trowbridge TS, Reitz KP (1975) Average irregularity representation of a
rough surface for ray reflection. J Opt Soc Am 65:531–536.
Heitz E (2018) Sampling the GGX distribution of visible normals. Journal
of Computer Graphics Techniques 7(4):1–13.
Kelemen C, Szirmay-Kalos L (2001) A microfacet based coupled specular-matte
BRDF model with importance sampling. Eurographics 2001 Short Presentations.
Saunderson JL (1942) Calculation of the color of pigmented plastics. J Opt
Soc Am 32:727–736.
Born M, Wolf E (1999) Principles of Optics, 7th ed. (§1.5: Fresnel).
"""

import functools

import numpy as np

from beeoptics.jit import kernel
from beeoptics.light.mueller import fresnel
from beeoptics.light.sampler import tangent_frame

#: Nodes of each material's tabulated directional albedo E(μ), at μ = (k + ½)/N, and of the quadrature
#: (per dimension, midpoints over the visible normals) that computes it.
ALBEDO_NODES, QUADRATURE_NODES = 64, 96


@kernel
def ggx(cos_h, alpha):
    """The GGX distribution of microfacet normals D(h), per steradian, at cos θ_h (Walter et al. 2007, eq. 33)."""
    if cos_h <= 0.0:
        return 0.0
    a2 = alpha * alpha
    t = cos_h * cos_h * (a2 - 1.0) + 1.0
    return a2 / (np.pi * t * t)


@kernel
def smith_g1(cos_v, alpha):
    """Smith's masking G1 of GGX for a direction at cos θ_v to the normal (Walter et al. 2007, eq. 34)."""
    if cos_v <= 0.0:
        return 0.0
    c2 = cos_v * cos_v
    return 2.0 / (1.0 + np.sqrt(1.0 + alpha * alpha * (1.0 - c2) / c2))


@kernel
def half_vector(normal, wi, x, y, z):
    """cos θ_h (to the normal) and cos(i·h) of the half vector of ``wi`` (3,) and (x, y, z)."""
    hx, hy, hz = wi[0] + x, wi[1] + y, wi[2] + z
    norm = np.sqrt(hx * hx + hy * hy + hz * hz)
    if norm <= 0.0:
        return 0.0, 0.0
    return ((normal[0] * hx + normal[1] * hy + normal[2] * hz) / norm,
            (wi[0] * hx + wi[1] * hy + wi[2] * hz) / norm)


@kernel
def specular(normal, wi, x, y, z, alpha, eta):
    """The coating's BRDF f_s towards (x, y, z) from the viewer's direction ``wi`` (3,), per steradian, and its
    density when sampled by :func:`sample` (per steradian of the reflected direction)."""
    cos_i = normal[0] * wi[0] + normal[1] * wi[1] + normal[2] * wi[2]
    cos_o = normal[0] * x + normal[1] * y + normal[2] * z
    if cos_i <= 0.0 or cos_o <= 0.0:
        return 0.0, 0.0
    cos_h, cos_ih = half_vector(normal, wi, x, y, z)
    d = ggx(cos_h, alpha)
    g1 = smith_g1(cos_i, alpha)
    rs2, rp2, _ = fresnel(cos_ih, eta)
    f = 0.5 * (rs2 + rp2) * d * g1 * smith_g1(cos_o, alpha) / (4.0 * cos_i * cos_o)
    return f, g1 * d / (4.0 * cos_i)


@kernel
def sample(normal, wi, alpha, u1, u2):
    """A reflected direction drawn from the visible normals of the GGX surface seen from ``wi`` (3,)
    (Heitz 2018, listing 1), as (x, y, z); below the surface for a grazing few."""
    t0, t1, t2, b0, b1, b2 = tangent_frame(normal[0], normal[1], normal[2])
    # The view in the local frame (tangent, bitangent, normal), stretched to the hemisphere configuration.
    vx = alpha * (wi[0] * t0 + wi[1] * t1 + wi[2] * t2)
    vy = alpha * (wi[0] * b0 + wi[1] * b1 + wi[2] * b2)
    vz = wi[0] * normal[0] + wi[1] * normal[1] + wi[2] * normal[2]
    norm = np.sqrt(vx * vx + vy * vy + vz * vz)
    vx, vy, vz = vx / norm, vy / norm, vz / norm
    len2 = vx * vx + vy * vy
    if len2 > 0.0:
        inv = 1.0 / np.sqrt(len2)
        ax, ay = -vy * inv, vx * inv
    else:
        ax, ay = 1.0, 0.0
    bx, by, bz = -vz * ay, vz * ax, vx * ay - vy * ax  # the view × (ax, ay, 0)
    r = np.sqrt(u1)
    phi = 2.0 * np.pi * u2
    p1, p2 = r * np.cos(phi), r * np.sin(phi)
    s = 0.5 * (1.0 + vz)
    p2 = (1.0 - s) * np.sqrt(max(1.0 - p1 * p1, 0.0)) + s * p2
    p3 = np.sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0))
    nx, ny, nz = p1 * ax + p2 * bx + p3 * vx, p1 * ay + p2 * by + p3 * vy, p2 * bz + p3 * vz
    # Unstretched: the microfacet normal, in world coordinates.
    mx, my, mz = alpha * nx, alpha * ny, max(nz, 0.0)
    norm = np.sqrt(mx * mx + my * my + mz * mz)
    mx, my, mz = mx / norm, my / norm, mz / norm
    hx = mx * t0 + my * b0 + mz * normal[0]
    hy = mx * t1 + my * b1 + mz * normal[1]
    hz = mx * t2 + my * b2 + mz * normal[2]
    c = wi[0] * hx + wi[1] * hy + wi[2] * hz
    return 2.0 * c * hx - wi[0], 2.0 * c * hy - wi[1], 2.0 * c * hz - wi[2]


@kernel
def through(cos_v, table):
    """1 − E(μ) at μ = ``cos_v``, linear in the table ``table`` (ALBEDO_NODES + 1,) of :func:`albedo_table`."""
    n = len(table) - 1
    x = min(max(cos_v * n - 0.5, 0.0), n - 1.0)
    k = min(int(x), n - 2)
    t = x - k
    return 1.0 - ((1.0 - t) * table[k] + t * table[k + 1])


@kernel
def coupling(cos_i, cos_o, table):
    """The base's factor through the coating, (1 − E(μ_i)) (1 − E(μ_o)) / (1 − Ē): f_d = ρ'/π times it,
    ρ' the base's :func:`base_albedo`."""
    mean = table[len(table) - 1]
    return through(cos_i, table) * through(cos_o, table) / max(1.0 - mean, 1e-12)


def base_albedo(rho, alpha, eta):
    """The base's albedo as the coupling takes it, ρ' = ρ (1 − F_dr)/(1 − ρ F_dr): what it returns through the
    coating's internal reflections (see the module's notes).

    Parameters
    ----------
    rho : ndarray
        The base's albedo ρ, in [0, 1] (per wavelength).
    alpha, eta : float
        The coating's roughness α (GGX) and refractive index η.

    Returns
    -------
    ndarray
        ρ', in [0, ρ]; 1 where ρ is 1.
    """
    internal = albedo_table(alpha, 1.0 / eta)[-1]  # F_dr: the coating's hemispherical albedo from inside
    return rho * (1.0 - internal) / (1.0 - rho * internal)


@kernel
def _albedo(alpha, eta, mu, n):
    """E(μ): the coating's f_s cos θ_o integrated over the visible normals at midpoints of an n × n grid."""
    normal = np.array([0.0, 0.0, 1.0])
    wi = np.array([np.sqrt(max(1.0 - mu * mu, 0.0)), 0.0, mu])
    total = 0.0
    for a in range(n):
        for b in range(n):
            x, y, z = sample(normal, wi, alpha, (a + 0.5) / n, (b + 0.5) / n)
            if z <= 0.0:
                continue
            f, p = specular(normal, wi, x, y, z, alpha, eta)
            if p > 0.0:
                total += f * z / p
    return total / (n * n)


@functools.cache
def albedo_table(alpha, eta, nodes=ALBEDO_NODES, quadrature=QUADRATURE_NODES):
    """A coating's directional albedo E(μ) at μ = (k + ½)/nodes, and its hemispherical mean Ē last, made once
    per coating (a trace asks for it in every batch), read-only.

    Parameters
    ----------
    alpha, eta : float
        Roughness α (GGX) and refractive index η.

    Returns
    -------
    ndarray (nodes + 1,)
        E at each node, then Ē = 2∫ E(μ) μ dμ (midpoint rule over the same nodes).
    """
    mu = (np.arange(nodes) + 0.5) / nodes
    e = np.array([_albedo(float(alpha), float(eta), m, quadrature) for m in mu])
    table = np.append(e, 2.0 * np.sum(e * mu) / nodes)
    table.flags.writeable = False
    return table
