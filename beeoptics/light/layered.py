"""The exact answer of the layered model the coating stands for: a random walk between a rough dielectric
interface and a Lambertian base, the reference the coating's coupling is checked against.

A coated surface is a rough dielectric interface of refractive index η
over a Lambertian base of albedo ρ, with nothing between them (no medium,
thickness zero). Light that the interface lets in meets the base, which
returns ρ of it, some of that leaves through the interface and the rest is
reflected back down (below the critical angle partly, beyond it wholly),
and so on. Guo, Hašan & Zhao (2018) estimate such a stack's BSDF by a
random walk between its interfaces, without tracking positions; pbrt-v4's
``CoatedDiffuse`` (``LayeredBxDF``) is that walk, and this follows it for a
thickness and medium albedo of zero:

- the viewer's direction is sampled through the interface, transmission
  only, its weight f cos/pdf (pbrt's ``wos``); the light's direction
  likewise, once per path (``wis``);
- at each meeting with the base, the light's presampled direction is
  connected to it (next-event estimation: the base's ρ/π times the light's
  weight);
- the base then sends the path up, cosine-distributed, weight ρ; at the
  interface from below only reflection is sampled, the transmitted part
  being what the next connection counts (pbrt's exit interface).

pbrt also connects through the direction sampled at the base, weighed by
multiple importance sampling against this one; for a Lambertian base the
connection through the light's direction alone is unbiased and enough.
pbrt stops at ten bounces; this walks until what the paths still carry
is a negligible share (:data:`REMAINDER`). The base forgets the direction light arrives in, so only the
elevation of each direction matters (the interface is isotropic) and the
base's share of the BSDF does not depend on the azimuth between viewer and
light.

The interface is the coating's: GGX microfacets of roughness α, Smith's
separable masking G1(i) G1(o), Fresnel's mean reflectance (R_s + R_p)/2 at
each microfacet (Walter et al. 2007), sampled by the visible normals
(Heitz 2018), on which a sample's weight is F G1(o) when reflected and
(1 − F) G1(o) when transmitted (power, not radiance: the one factor 1/η²
of radiance leaving a medium of index η, pbrt's radiance-mode scaling, is
applied once at the end). It scatters once per meeting (no light among
its microfacets), so a rough interface loses a little light, as pbrt's
and Mitsuba's do. Written in numpy, independently of the coating's
compiled kernels, so that it checks them.

References
----------
Guo Y, Hašan M, Zhao S (2018) Position-free Monte Carlo simulation for
arbitrary layered BSDFs. ACM Trans Graph 37(6).
Pharr M, Jakob W, Humphreys G (2023) Physically Based Rendering, 4th ed.
MIT Press (§14.3: stochastic evaluation of layered BxDFs).
Walter B, Marschner SR, Li H, Torrance KE (2007) Microfacet models for
refraction through rough surfaces. Proc. Eurographics Symposium on
Rendering, 195–206.
Heitz E (2018) Sampling the GGX distribution of visible normals. Journal
of Computer Graphics Techniques 7(4):1–13.
"""

import numpy as np

#: The walk ends when what its paths still carry is below this share of what they have given, for every setting: the
#: rest, a geometric series of ratio ρ F_dr < 1, adds a few times that at most.
REMAINDER = 1.0e-7


def fresnel_mean(cos_i, eta):
    """Fresnel's mean reflectance (R_s + R_p)/2 at incidence cos_i, ``eta`` the index beyond the interface over
    the index before it; 1 beyond the critical angle (Born & Wolf 1999, §1.5)."""
    sin2_t = (1.0 - cos_i**2) / eta**2
    cos_t = np.sqrt(np.clip(1.0 - sin2_t, 0.0, None))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return np.where(sin2_t >= 1.0, 1.0, 0.5 * (rs**2 + rp**2))


def smith_g1(cos_v, alpha):
    """Smith's masking of GGX for a direction at |cos θ| = ``cos_v`` to the normal (Walter et al. 2007, eq. 34)."""
    c2 = np.clip(cos_v, 1e-12, 1.0) ** 2
    return 2.0 / (1.0 + np.sqrt(1.0 + alpha**2 * (1.0 - c2) / c2))


def interface(mu, alpha, eta, u1, u2):
    """One scattering at the rough interface seen at cos θ = ``mu`` (in the plane x–z, normal +z), the visible
    normal drawn by (u1, u2) (Heitz 2018, listing 1).

    Parameters
    ----------
    mu, alpha, eta, u1, u2 : ndarray or float
        Broadcast together: the direction's cosine to the normal on its own side, the roughness, the index
        beyond over the index on the direction's side, and two uniform numbers.

    Returns
    -------
    reflected, transmitted : ndarray
        The sample's weight (f cos/pdf, as power) were it reflected, and were it transmitted; zero where the
        direction leaves on the wrong side.
    """
    s = np.sqrt(np.clip(1.0 - mu**2, 0.0, None))
    # The view stretched to the hemisphere configuration; its azimuth is 0, so the frame's T1 is +y.
    vx, vz = alpha * s, mu
    norm = np.hypot(vx, vz)
    vx, vz = vx / norm, vz / norm
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    t1, t2 = r * np.cos(phi), r * np.sin(phi)
    t2 = (1.0 - 0.5 * (1.0 + vz)) * np.sqrt(np.clip(1.0 - t1**2, 0.0, None)) + 0.5 * (1.0 + vz) * t2
    t3 = np.sqrt(np.clip(1.0 - t1**2 - t2**2, 0.0, None))
    # T1 = (0, 1, 0), T2 = view × T1 = (−vz, 0, vx); unstretched to the microfacet normal m.
    mx, my, mz = alpha * (-vz * t2 + vx * t3), alpha * t1, np.clip(vx * t2 + vz * t3, 0.0, None)
    norm = np.sqrt(mx**2 + my**2 + mz**2)
    mx, mz = mx / norm, mz / norm
    c = s * mx + mu * mz  # cos(view, m) > 0
    f = fresnel_mean(c, eta)
    # Reflected r = 2c m − v; refracted t = −v/η + (c/η − cos θ_t) m.
    r_z = 2.0 * c * mz - mu
    cos_t = np.sqrt(np.clip(1.0 - (1.0 - c**2) / eta**2, 0.0, None))
    t_z = -mu / eta + (c / eta - cos_t) * mz
    reflected = np.where(r_z > 0.0, f * smith_g1(r_z, alpha), 0.0)
    transmitted = np.where(t_z < 0.0, (1.0 - f) * smith_g1(-t_z, alpha), 0.0)
    return reflected, transmitted


def base_reflection(mu_i, mu_o, rho, alpha, eta, paths=4096, seed=0):
    """The base's share of the coated surface's BRDF, per steradian, by the random walk; the coating's own
    reflection (its specular lobe) left out.

    Parameters
    ----------
    mu_i, mu_o : ndarray or float
        cos θ of the light's and the viewer's directions to the normal, in (0, 1].
    rho : ndarray or float
        The base's albedo, in [0, 1].
    alpha, eta : ndarray or float
        The interface's GGX roughness and refractive index (over air's).
    paths : int
        Paths per setting.
    seed : int
        Seed of the random numbers: the same seed, the same answer.

    Returns
    -------
    ndarray
        f_base(i, o), 1/sr, of the broadcast shape of the inputs.
    """
    mu_i, mu_o, rho, alpha, eta = (a[..., None] for a in np.broadcast_arrays(*map(np.asarray, (
        mu_i, mu_o, rho, alpha, eta))))
    shape = mu_i.shape[:-1] + (paths,)
    rng = np.random.default_rng(seed)
    _, light = interface(mu_i, alpha, eta, *rng.random((2,) + shape))
    _, beta = interface(mu_o, alpha, eta, *rng.random((2,) + shape))
    total = np.zeros(shape)
    while (beta.sum(axis=-1) > REMAINDER * total.sum(axis=-1)).any():
        total += beta  # connected to the light at the base: ρ/π × light, applied below
        beta = beta * rho
        up = np.sqrt(rng.random(shape))  # the base's cosine-distributed direction
        reflected, _ = interface(up, alpha, 1.0 / eta, *rng.random((2,) + shape))
        beta = beta * reflected
    return (rho / np.pi * light * total / eta**2).mean(axis=-1)
