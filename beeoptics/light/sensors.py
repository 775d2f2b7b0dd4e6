"""The sensors: receptor acceptance cones and the pinhole camera of the human view.

A sensor turns into bundles of rays, one bundle per receptor or pixel,
each stratified by the sampler's shifted Halton set, which the integrator
traces (:func:`beeoptics.light.integrator.trace_paths`) and averages.

Receptor cones. Each receptor accepts light from around its axis with
Snyder's Gaussian angular sensitivity A(θ) (:mod:`beeoptics.eye.optics`).
Directions are drawn from the two-dimensional Gaussian: in the tangent
plane at the axis the angle off-axis has a Rayleigh distribution, and a
weight sin θ/θ makes the density exact on the sphere. Drawing a
one-dimensional normal angle with a uniform azimuth instead puts too many
samples near the axis and narrows the cone.

The pinhole camera jitters its rays over each pixel; the human and the bee
images of a scene then differ only in the eye.
"""

from typing import NamedTuple

import numpy as np

from beeoptics.eye.optics import FOUR_LN2
from beeoptics.jit import kernel
from beeoptics.light.sampler import shifted_halton, tangent_frame

#: Random dimensions of a receptor's cone shift, apart from those its paths use.
CONE_DIMENSIONS = (250, 251)
#: Random dimensions of a pixel's sub-pixel shift, apart from those of receptor cones.
PIXEL_DIMENSIONS = (252, 253)


class Cones(NamedTuple):
    """Receptors' acceptance cones as the compiled integrator takes them (numba takes named tuples of arrays).

    Attributes
    ----------
    axis : ndarray (n, 3)
        Each bundle's unit axis.
    sigma : ndarray (n,)
        Its Gaussian σ, radians (:func:`cone_sigma`); 0 for a bundle that is not a cone (a pixel).
    """

    axis: np.ndarray
    sigma: np.ndarray


def cone_samples(axes, delta_rho_deg, samples, seed, streams=None, first_samples=None):
    """Directions importance-sampled from each receptor's Gaussian acceptance cone.

    Parameters
    ----------
    axes : ndarray, shape (n, 3)
        Unit receptor axes.
    delta_rho_deg : array_like, shape (n,) or scalar
        Acceptance angles (full width at half maximum), degrees.
    samples : int
        Directions per receptor.
    seed : int
    streams : ndarray of int, shape (n,), optional
        Each receptor's index in the whole eye (0 … n−1 by default), so that
        a receptor draws the same directions however the eye is split up.
    first_samples : ndarray of int, shape (n,), optional
        The index of each receptor's first sample, for drawing its samples
        in blocks (0 by default).

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
    streams = np.arange(n) if streams is None else np.asarray(streams)
    u = shifted_halton(samples, seed, streams, CONE_DIMENSIONS, first_samples)
    return _cone_directions(axes, cone_sigma(np.broadcast_to(delta_rho_deg, (n,))), u)


def cone_sigma(delta_rho_deg):
    """The Gaussian's σ, radians, of acceptance angles Δρ (full width at half maximum, degrees)."""
    return np.radians(np.asarray(delta_rho_deg, float)) / np.sqrt(2.0 * FOUR_LN2)


@kernel
def cone_density(theta, sigma):
    """The density, sr⁻¹, of :func:`cone_samples`' directions θ off the axis of a cone of σ (radians).

    The tangent plane's Gaussian, 1/(2πσ²) e^{−θ²/2σ²}, over the sphere's
    area element: times θ/sin θ.
    """
    stretch = theta / np.sin(theta) if theta > 0.0 else 1.0
    return np.exp(-0.5 * (theta / sigma) ** 2) / (2.0 * np.pi * sigma * sigma) * stretch


@kernel
def _cone_directions(axes, sigma, u):
    n, s = u.shape[0], u.shape[1]
    directions, weights = np.empty((n, s, 3)), np.empty((n, s))
    for i in range(n):
        t0, t1, t2, b0, b1, b2 = tangent_frame(axes[i, 0], axes[i, 1], axes[i, 2])
        for j in range(s):
            theta = sigma[i] * np.sqrt(-2.0 * np.log1p(-u[i, j, 0]))
            phi = 2.0 * np.pi * u[i, j, 1]
            sin_t = np.sin(theta)
            c, t = sin_t * np.cos(phi), sin_t * np.sin(phi)
            cos_t = np.cos(theta)
            directions[i, j, 0] = cos_t * axes[i, 0] + c * t0 + t * b0
            directions[i, j, 1] = cos_t * axes[i, 1] + c * t1 + t * b1
            directions[i, j, 2] = cos_t * axes[i, 2] + c * t2 + t * b2
            weights[i, j] = sin_t / theta if theta > 0.0 else 1.0
    return directions, weights


def pinhole_rays(camera, samples, seed):
    """Jittered rays through every pixel of a pinhole camera.

    Parameters
    ----------
    camera : dict
        ``position_m``, ``look_at_m``, ``vertical_fov_deg``, ``width_px``,
        ``height_px``; world +z is up.
    samples : int
        Rays per pixel.
    seed : int

    Returns
    -------
    origin : ndarray, shape (3,)
    directions : ndarray, shape (h·w, samples, 3)
        Unit directions, pixels in row-major order from the top left.
    """
    w, h = camera["width_px"], camera["height_px"]
    eye = np.asarray(camera["position_m"], float)
    forward = np.asarray(camera["look_at_m"], float) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half_h = np.tan(np.radians(camera["vertical_fov_deg"]) / 2.0)
    half_w = half_h * w / h
    ids = np.arange(w * h)
    u = shifted_halton(samples, seed, ids, PIXEL_DIMENSIONS)
    col = (ids % w)[:, None] + u[..., 0]
    row = (ids // w)[:, None] + u[..., 1]
    sx = (2.0 * col / w - 1.0) * half_w
    sy = (1.0 - 2.0 * row / h) * half_h
    d = forward + sx[..., None] * right + sy[..., None] * up
    return eye, d / np.linalg.norm(d, axis=-1, keepdims=True)
