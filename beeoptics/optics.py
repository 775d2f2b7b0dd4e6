"""Receptor optics: the angular acceptance of one ommatidium, and sampling it.

Each receptor accepts light from around its axis with the Gaussian angular
sensitivity of Snyder (1977),

    A(θ) = exp(−4 ln 2 · θ² / Δρ²) ≈ exp(−2.77 θ² / Δρ²),

θ being the angle from the axis and Δρ the full width at half maximum,
A(Δρ/2) = ½. Collins prints Δρ where Snyder has Δρ²; Eheim & Wehner's
(1972) fit, exp(−0.41 θ²) with θ in degrees for Δρ = 2.57°, confirms the
square. Δρ is either fixed, 2.6° (Laughlin & Horridge 1971; Rigosi et al.
2017 give the same mean for dark-adapted workers), or follows the facet
diameter D through Snyder's

    Δρ² = (λ/D)² + (d/f)²,

with the rhabdom's angular width d/f = 1.7° for workers (Somanathan et al.
2009, Table 1, after Greiner et al. 2004) and λ = 500 nm (the wavelength
Land 1990 and Collins use for the bee's diffraction limit).

Directions are drawn from the two-dimensional Gaussian: in the tangent
plane at the axis the angle off-axis has a Rayleigh distribution, and a
weight sin θ/θ makes the density exact on the sphere. Drawing a
one-dimensional normal angle with a uniform azimuth instead puts too many
samples near the axis and narrows the cone.

References
----------
Snyder AW (1977) Acuity of compound eyes: physical limitations and design.
J Comp Physiol 116:161–182.
Eheim WP, Wehner R (1972) Die Sehfelder der zentralen Ommatidien in den
Appositionsaugen von Apis mellifica und Cataglyphis bicolor. Kybernetik
10:168–179.
Laughlin SB, Horridge GA (1971) Angular sensitivity of the retinula cells
of dark-adapted worker bee. Z Vergl Physiol 74:329–335.
Somanathan H, Warrant EJ, Borges RM, Wallén R, Kelber A (2009) Resolution
and sensitivity of the eyes of the Asian honeybees Apis florea, Apis cerana
and Apis dorsata. J Exp Biol 212:2448–2453.
Land MF (1990) The design of compound eyes. In Blakemore C (ed) Vision:
coding and efficiency. Cambridge University Press, 55–64.
"""

import numpy as np
from scipy.stats import qmc

from beeoptics.randomness import uniform

#: 4 ln 2, the "2.77" of Snyder's Gaussian.
FOUR_LN2 = 4.0 * np.log(2.0)
#: Acceptance angle of worker photoreceptors, degrees (Laughlin & Horridge 1971).
DELTA_RHO_WORKER_DEG = 2.6
#: Rhabdom angular width d/f of workers, degrees (Somanathan et al. 2009, Table 1).
RHABDOM_ACCEPTANCE_DEG = 1.7
#: Wavelength for the diffraction term, nm (Land 1990).
SNYDER_WAVELENGTH_NM = 500.0
#: Random dimensions of a receptor's cone shift, apart from those its paths use.
CONE_DIMENSIONS = (250, 251)


def acceptance(theta, delta_rho):
    """Snyder's Gaussian angular sensitivity, 1 on the axis.

    Parameters
    ----------
    theta, delta_rho : array_like
        Angle from the axis and full width at half maximum, same units.
    """
    return np.exp(-FOUR_LN2 * (np.asarray(theta) / delta_rho) ** 2)


def snyder_delta_rho(facet_diameter_um, wavelength_nm=SNYDER_WAVELENGTH_NM,
                     rhabdom_deg=RHABDOM_ACCEPTANCE_DEG):
    """Acceptance angle in degrees from Δρ² = (λ/D)² + (d/f)² (Snyder 1977)."""
    diffraction = np.degrees(wavelength_nm * 1e-3 / np.asarray(facet_diameter_um, float))
    return np.sqrt(diffraction**2 + rhabdom_deg**2)


def delta_rho(facet_diameter_um, model, fixed_deg=DELTA_RHO_WORKER_DEG,
              wavelength_nm=SNYDER_WAVELENGTH_NM, rhabdom_deg=RHABDOM_ACCEPTANCE_DEG):
    """Per-receptor acceptance angle, degrees, by ``model`` "fixed" or "snyder"."""
    for name, value in (("fixed_deg", fixed_deg), ("wavelength_nm", wavelength_nm), ("rhabdom_deg", rhabdom_deg)):
        if not np.isfinite(value) or value <= 0:
            raise ValueError(f"delta_rho: {name} must be positive, not {value!r}")
    if model == "fixed":
        return np.full(np.shape(facet_diameter_um), float(fixed_deg))
    if model == "snyder":
        return snyder_delta_rho(facet_diameter_um, wavelength_nm, rhabdom_deg)
    raise ValueError(f"unknown acceptance model {model!r}; use 'fixed' or 'snyder'")


def tangent_frames(axes):
    """Two unit vectors perpendicular to each unit axis and to each other, shape (n, 2, 3).

    The branchless basis of Duff et al. (2017): no cross products or
    square roots, and continuous everywhere but across the plane z = 0.

    References
    ----------
    Duff T, Burgess J, Christensen P, Hery C, Kensler A, Liani M, Villemin R
    (2017) Building an orthonormal basis, revisited. J Comput Graph Tech 6:1–8.
    """
    x, y, z = np.asarray(axes, float).T
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    frames = np.empty((len(x), 2, 3))
    frames[:, 0, 0] = 1.0 + sign * x * x * a
    frames[:, 0, 1] = sign * b
    frames[:, 0, 2] = -sign * x
    frames[:, 1, 0] = b
    frames[:, 1, 1] = sign + y * y * a
    frames[:, 1, 2] = -y
    return frames


def cone_samples(axes, delta_rho_deg, samples, seed, first=0):
    """Directions importance-sampled from each receptor's Gaussian acceptance cone.

    One scrambled Halton set of ``samples`` points in the unit square is
    shared by all receptors, each shifting it by its own random offset
    (Cranley–Patterson rotation), so that every receptor's directions are
    stratified and the whole set is reproducible from ``seed``.

    Parameters
    ----------
    axes : ndarray, shape (n, 3)
        Unit receptor axes.
    delta_rho_deg : array_like, shape (n,) or scalar
        Acceptance angles (full width at half maximum), degrees.
    samples : int
        Directions per receptor.
    seed : int
    first : int
        Index of the first of these receptors in the whole eye, so that a
        receptor draws the same directions however the eye is split up.

    Returns
    -------
    directions : ndarray, shape (n, samples, 3)
    weights : ndarray, shape (n, samples)
        sin θ/θ, which turns the tangent-plane density into the density on
        the sphere; a receptor's response is the weighted mean radiance.
    """
    if int(samples) != samples or samples < 1:
        raise ValueError(f"cone_samples: samples must be a positive whole number, not {samples!r}")
    axes = np.asarray(axes, float)
    n = len(axes)
    base = qmc.Halton(2, scramble=True, seed=np.random.default_rng(seed)).random(samples)
    ids = np.arange(first, first + n)
    shift = np.stack([uniform(seed, ids, np.zeros(n, np.int64), d) for d in CONE_DIMENSIONS], -1)
    u = (base[None] + shift[:, None, :]) % 1.0
    sigma = np.radians(np.broadcast_to(delta_rho_deg, (n,))) / np.sqrt(2.0 * FOUR_LN2)
    theta = sigma[:, None] * np.sqrt(-2.0 * np.log1p(-u[..., 0]))
    phi = 2.0 * np.pi * u[..., 1]
    frame = tangent_frames(axes)
    sin_t = np.sin(theta)
    directions = (
        np.cos(theta)[..., None] * axes[:, None]
        + (sin_t * np.cos(phi))[..., None] * frame[:, None, 0]
        + (sin_t * np.sin(phi))[..., None] * frame[:, None, 1]
    )
    weights = np.where(theta > 0, sin_t / np.where(theta > 0, theta, 1.0), 1.0)
    return directions, weights
