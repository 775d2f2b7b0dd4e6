"""Polarised light along rays: Stokes vectors, their reference frames, and the Mueller matrix of a reflection.

A ray's linear polarisation is the Stokes vector (I, Q, U) in a reference
frame that the ray carries: a unit vector e perpendicular to its direction
d, and f = d × e. The angle of polarisation ψ (of the electric vector's line)
is measured from e towards f, Q = I p cos 2ψ and U = I p sin 2ψ. A line
perpendicular to a ray is the same line whichever way the ray runs, so the
tracer measures angles about its own (backward) rays and compares them with
receptors' microvilli in the same frame. Circular polarisation (V) is left
out: skylight's is below 1 % (Horváth & Varjú 2004, ch. 3) and no insect
photoreceptor is known to analyse it except in stomatopods, not bees; the
reflections carried here (dielectrics below the critical angle) make none
from linearly polarised light.

Where a ray's frame must change (to the plane of incidence of a reflection),
the Stokes vector rotates by twice the angle between the frames. A smooth
dielectric's reflection is, in frames whose e is the normal to the plane of
incidence (the s direction) on both rays, the Mueller matrix
1/2 [[R_s + R_p, R_s − R_p, 0], [R_s − R_p, R_s + R_p, 0], [0, 0, 2 r_s r_p]]
with Fresnel's amplitude coefficients r_s and r_p (Born & Wolf 1999,
§1.5.2, with r_p's sign such that r_s = −r_p at normal incidence, where a
mirror keeps the electric vector's line; then in these frames, where f
turns over with the ray, U changes sign). The tracer keeps its glossy
lobe's intensity and takes from Fresnel only how a reflection polarises:
the matrix divided by its first element.

References
----------
Born M, Wolf E (1999) Principles of Optics, 7th ed. Cambridge University
Press (§1.5: the Fresnel formulae).
Chandrasekhar S (1950) Radiative Transfer. Oxford: Clarendon (Stokes
parameters and their rotation).
Horváth G, Varjú D (2004) Polarized Light in Animal Vision. Springer.
Collett E (2005) Field Guide to Polarization. SPIE (Mueller matrices of
Fresnel reflection).
"""

import numpy as np

from beeoptics.jit import kernel
from beeoptics.light.sampler import tangent_frame


@kernel
def fresnel(cos_i, n):
    """R_s, R_p and r_s r_p of light reflected from a dielectric of refractive index ``n`` (from air) at
    incidence cos_i."""
    cos_i = min(max(cos_i, 0.0), 1.0)
    cos_t = np.sqrt(max(1.0 - (1.0 - cos_i * cos_i) / (n * n), 0.0))
    rs = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    rp = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    return rs * rs, rp * rp, rs * rp


@kernel
def double_angle(x, y, z, e, d):
    """cos 2ψ and sin 2ψ of the line (x, y, z) about the ray ``d`` (3,), from its frame ``e`` (3,) towards d × e."""
    f0, f1, f2 = d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0]
    c = x * e[0] + y * e[1] + z * e[2]
    s = x * f0 + y * f1 + z * f2
    norm = c * c + s * s
    if norm <= 0.0:
        return 1.0, 0.0
    return (c * c - s * s) / norm, 2.0 * c * s / norm


@kernel
def plane_normal(d, x, y, z, out):
    """The unit normal to the plane of ``d`` (3,) and (x, y, z), into ``out``; any normal to (x, y, z) if they
    are parallel."""
    out[0], out[1], out[2] = d[1] * z - d[2] * y, d[2] * x - d[0] * z, d[0] * y - d[1] * x
    norm = np.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2])
    if norm < 1e-12:
        out[0], out[1], out[2] = tangent_frame(x, y, z)[:3]
    else:
        out[0], out[1], out[2] = out[0] / norm, out[1] / norm, out[2] / norm


@kernel
def reflect_column(m, c2, s2, cos_i, n):
    """The first column of ``m`` (3, 3) · R(2α) · F: unpolarised light reflected into polarised light, seen
    through ``m``.

    ``c2``, ``s2``: cos 2α and sin 2α of the plane of incidence's normal in
    the frame of ``m``; F the normalised Fresnel matrix at incidence cos_i.
    """
    rs2, rp2, _ = fresnel(cos_i, n)
    b = (rs2 - rp2) / (rs2 + rp2)
    return (m[0, 0] + b * (m[0, 1] * c2 + m[0, 2] * s2), m[1, 0] + b * (m[1, 1] * c2 + m[1, 2] * s2),
            m[2, 0] + b * (m[2, 1] * c2 + m[2, 2] * s2))


@kernel
def reflect(m, c2, s2, cos_i, n):
    """``m`` (3, 3) ← m · R(2α) · F, in place: a reflection at the end of the chain of Mueller matrices ``m``.

    R(2α) turns Stokes vectors from the plane of incidence's frame into that
    of ``m`` (``c2``, ``s2`` as :func:`reflect_column`); F is the Fresnel
    matrix at incidence cos_i divided by its first element.
    """
    rs2, rp2, rsrp = fresnel(cos_i, n)
    a = 0.5 * (rs2 + rp2)
    b, c = 0.5 * (rs2 - rp2) / a, rsrp / a
    for r in range(3):
        q = m[r, 1] * c2 + m[r, 2] * s2
        u = -m[r, 1] * s2 + m[r, 2] * c2
        m[r, 0], m[r, 1], m[r, 2] = m[r, 0] + b * q, b * m[r, 0] + q, c * u


@kernel
def depolarise(m):
    """``m`` (3, 3) ← m · D, in place, D the Mueller matrix of a Lambertian surface (its intensity element 1)."""
    for r in range(3):
        m[r, 1] = m[r, 2] = 0.0
