"""The ground of a generated meadow: a random rough surface, flat at its border.

The height is a Gaussian random field with a Gaussian autocorrelation
function, of root-mean-square height ``rms_height_m`` and correlation
length ``correlation_length_m`` — the usual description of a natural
soil surface (Ulaby, Moore & Fung 1986, ch. 12) — made by filtering
seeded white noise in the Fourier domain. It is tapered to zero height
over the outer tenth of the patch, where it meets the flat ground beyond.

References
----------
Ulaby FT, Moore RK, Fung AK (1986) Microwave remote sensing: active and
passive, vol. III. Artech House.
"""

import numpy as np

from beeoptics.world.plants import Mesh

#: The fraction of the patch, at each side, over which the ground falls to the level beyond (a drawing
#: choice: it only joins the patch to the flat ground).
BORDER = 0.1


def height_field(extent_m, spacing_m, rms_height_m, correlation_length_m, rng):
    """Grid coordinates x (nx,), y (ny,) and heights (nx, ny), metres.

    The spectrum of a Gaussian autocorrelation exp(−r²/ℓ²) is Gaussian,
    exp(−k²ℓ²/4); white noise filtered by its square root and scaled to the
    RMS height has that autocorrelation.
    """
    nx, ny = (int(np.ceil(e / spacing_m)) + 1 for e in extent_m)
    x = np.linspace(-extent_m[0] / 2.0, extent_m[0] / 2.0, nx)
    y = np.linspace(-extent_m[1] / 2.0, extent_m[1] / 2.0, ny)
    if rms_height_m == 0.0:
        return x, y, np.zeros((nx, ny))
    kx = 2.0 * np.pi * np.fft.fftfreq(nx, x[1] - x[0])
    ky = 2.0 * np.pi * np.fft.fftfreq(ny, y[1] - y[0])
    k2 = kx[:, None] ** 2 + ky[None, :] ** 2
    noise = np.fft.fft2(rng.standard_normal((nx, ny)))
    h = np.real(np.fft.ifft2(noise * np.exp(-k2 * correlation_length_m**2 / 8.0)))
    h *= rms_height_m / h.std()
    return x, y, h * _taper(x, extent_m[0])[:, None] * _taper(y, extent_m[1])[None, :]


def _taper(u, extent):
    """1 inside, falling as cos² to 0 over the outer :data:`BORDER` of the extent."""
    edge = extent / 2.0
    d = np.clip((edge - np.abs(u)) / (BORDER * extent), 0.0, 1.0)
    return np.sin(0.5 * np.pi * d) ** 2


def level_round(x, y, centres, radii):
    """A factor (nx, ny) that levels the ground to zero height within each circle, rising as cos² over as much again."""
    gx, gy = np.meshgrid(x, y, indexing="ij")
    factor = np.ones_like(gx)
    for (cx, cy), r in zip(centres, radii):
        d = np.hypot(gx - cx, gy - cy)
        factor *= np.sin(0.5 * np.pi * np.clip(d / max(r, 1e-9) - 1.0, 0.0, 1.0)) ** 2
    return factor


def ground_mesh(x, y, h, part="soil"):
    """The height field as triangles, two per grid cell."""
    nx, ny = h.shape
    gx, gy = np.meshgrid(x, y, indexing="ij")
    vertices = np.column_stack([gx.ravel(), gy.ravel(), h.ravel()])
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="ij")
    a = (i * ny + j).ravel()
    b, c, d = a + ny, a + ny + 1, a + 1
    faces = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return Mesh(vertices, faces, np.full(len(faces), part, dtype=object))


def ground_height(x, y, h, points):
    """Heights (n,) of the ground under points (n, 2), bilinear in the grid."""
    # Imported where used: the stages that import the meadow's module and build no ground would pay 0.4 s.
    from scipy.interpolate import RegularGridInterpolator

    return RegularGridInterpolator((x, y), h, bounds_error=False, fill_value=0.0)(points)
