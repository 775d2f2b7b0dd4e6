"""Reconstructing the visual field in the retinal plane (Collins §4.3).

Receptors are projected parallel to their eye's z-axis onto its xy-plane,
the retinal plane. The left eye is mirrored into the right eye's frame, so
both panels share one geometry; they are laid side by side, left eye on the
left, each with its anterior edge towards the middle, dorsal up, as the
bee's two visual hemifields would sit.

The Voronoi image gives each pixel the value of its nearest receptor
(found with a KD-tree, scipy's), masked by the convex hull of the eye. The
density image spreads each receptor's value with a Gaussian kernel, as in
Collins' Colour Plate 2, whose brightness then follows the density of
receptors; dividing it by the kernel-spread receptor count (Nadaraya 1964;
Watson 1964) removes that artefact.

References
----------
Collins S. Reconstructing the visual field of compound eyes. §4.3.
Nadaraya EA (1964) On estimating regression. Theory Probab Appl 9:141–142.
Watson GS (1964) Smooth regression analysis. Sankhyā A 26:359–372.
"""

from typing import NamedTuple

import numpy as np
from scipy.ndimage import gaussian_filter
from scipy.spatial import ConvexHull, cKDTree

from beeoptics.headframe import LEFT, RIGHT, in_eye_plane, mirror
from beeoptics.images.display import EXPOSURE_PERCENTILE, encode
from beeoptics.images.fieldmaps import paint

#: Blank margin around each eye, as a fraction of its extent.
MARGIN = 0.03
#: How far beyond a hull's edge a pixel still counts as within it, mm: far below a pixel (micrometres) and far above
#: the rounding of millimetre coordinates in double precision (10⁻¹⁶ mm), so that a pixel on an edge is within.
HULL_TOLERANCE_MM = 1e-9


def retinal_plane(eye, positions, sides):
    """Receptor positions (head frame, mm) projected into the right eye's local xy-plane."""
    p = np.array(positions, float)
    left = np.asarray(sides) == LEFT
    p[left] = mirror(p[left])
    return ((p - eye.origin) @ eye.rotation.T)[:, :2]


class Canvas(NamedTuple):
    """Pixel grid of the two panels: for each pixel its side and retinal-plane point."""

    side: np.ndarray  # (h, w) "left", "right" or ""
    xy: np.ndarray  # (h, w, 2), mm
    pixel_mm: float


def canvas(xy, width_px):
    """Two panels, each ``width_px`` wide, covering the retinal-plane points ``xy``."""
    lo, hi = xy.min(0), xy.max(0)
    pad = MARGIN * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    pixel = (hi[0] - lo[0]) / width_px
    height = int(np.ceil((hi[1] - lo[1]) / pixel))
    u = (np.arange(width_px) + 0.5) * pixel
    y = hi[1] - (np.arange(height) + 0.5) * pixel
    left_x, right_x = lo[0] + u, hi[0] - u
    xs = np.concatenate([left_x, right_x])
    grid = np.stack(np.broadcast_arrays(xs[None, :], y[:, None]), -1)
    side = np.broadcast_to(np.repeat(np.array([LEFT, RIGHT]), width_px)[None, :], (height, 2 * width_px))
    return Canvas(np.array(side), grid, pixel)


def panel_extents(can):
    """Each panel's (x0, x1, y_bottom, y_top) in the retinal plane, mm, left eye first.

    The right eye's panel is mirrored, so its x runs from larger to smaller.
    """
    w = can.side.shape[1] // 2
    half = 0.5 * can.pixel_mm
    ys = can.xy[:, 0, 1]
    extents = []
    for xs in (can.xy[0, :w, 0], can.xy[0, w:, 0]):
        edge = half * np.sign(xs[-1] - xs[0])
        extents.append((xs[0] - edge, xs[-1] + edge, ys[-1] - half, ys[0] + half))
    return extents


def within_hull(points, queries):
    """Whether each of ``queries`` (m, 2) lies within the convex hull of ``points`` (n, 2), its edges included.

    Tested against the hull's edges (Qhull's, as unit normals and offsets), not by finding each pixel's
    triangle: a pixel outside the hull sends the triangulation's walk to a search of every triangle (half a
    minute for a worker's canvas, against half a second).
    """
    inside = np.ones(len(queries), bool)
    for nx, ny, offset in ConvexHull(points).equations:
        inside &= queries[:, 0] * nx + queries[:, 1] * ny + offset <= HULL_TOLERANCE_MM
    return inside


def within_eyes(can, xy, sides):
    """Whether each pixel (h, 2w) lies within the convex hull of its panel's eye (:func:`within_hull`)."""
    inside = np.zeros(can.side.shape, bool)
    for s in (LEFT, RIGHT):
        where = can.side == s
        inside[where] = within_hull(xy[np.asarray(sides) == s], can.xy[where])
    return inside


def nearest_receptor(can, xy, sides, inside=None):
    """Index of the receptor each pixel shows (−1 outside its eye's convex hull): the Voronoi diagram of the
    receptors in the retinal plane (Collins §4.3), to paint with :func:`beeoptics.images.fieldmaps.paint`.
    ``inside``: :func:`within_eyes`, computed here if not given."""
    inside = within_eyes(can, xy, sides) if inside is None else inside
    out = np.full(can.side.shape, -1)
    for s in (LEFT, RIGHT):
        mine = np.flatnonzero(np.asarray(sides) == s)
        shown = (can.side == s) & inside
        out[shown] = mine[cKDTree(xy[mine]).query(can.xy[shown])[1]]
    return out


def density(can, xy, sides, values, inside=None):
    """Kernel estimates of receptor values, (h, w, c) each, NaN outside the eyes: the kernel's sums, and the
    sums divided by the receptor density (the kernel-spread receptor count).

    The kernel's standard deviation is the median distance between
    neighbouring receptors of one eye in the retinal plane (the two eyes
    share that plane, mirrored, so they are measured apart). ``inside``:
    :func:`within_eyes`, computed here if not given.
    """
    inside = within_eyes(can, xy, sides) if inside is None else inside
    values = np.asarray(values, float).reshape(len(xy), -1)
    h, w = can.side.shape
    raw, normalised = np.full((h, w, values.shape[1]), np.nan), np.full((h, w, values.shape[1]), np.nan)
    for s in (LEFT, RIGHT):
        mine = np.flatnonzero(np.asarray(sides) == s)
        sigma = np.median(cKDTree(xy[mine]).query(xy[mine], k=2)[0][:, 1]) / can.pixel_mm
        cols = np.flatnonzero(can.side[0] == s)
        x0, x1 = can.xy[0, cols[0], 0], can.xy[0, cols[-1], 0]
        step = (x1 - x0) / (len(cols) - 1)
        col = np.rint((xy[mine, 0] - x0) / step).astype(int)
        row = np.rint((can.xy[0, 0, 1] - xy[mine, 1]) / can.pixel_mm).astype(int)
        flat = row * len(cols) + col
        count = gaussian_filter(np.bincount(flat, minlength=h * len(cols)).reshape(h, -1).astype(float), sigma)
        for k in range(values.shape[1]):
            sums = gaussian_filter(np.bincount(flat, values[mine, k], h * len(cols)).reshape(h, -1), sigma)
            raw[:, cols, k] = np.where(inside[:, cols], sums, np.nan)
            normalised[:, cols, k] = np.where(inside[:, cols], np.divide(sums, count, out=np.full_like(sums, np.nan),
                                                                         where=count > 0), np.nan)
    return raw, normalised


class Retina(NamedTuple):
    """The retinal images of an eye pair in a view (:func:`retinal_images`)."""

    images: dict  # voronoi_map3, voronoi_map2, density_map3, density_map3_normalised: (h, 2w, 3) in [0, 1], NaN outside
    channels: dict  # each receptor class's catch over white's, (h, 2w) clipped to [0, 1]
    nearest: np.ndarray  # (h, 2w): each pixel's nearest receptor, -1 outside the eyes
    extents: tuple  # each half's extent in the retinal plane, mm (panel_extents)
    anterior: np.ndarray  # (2,): the head's anterior direction in the retinal plane
    dorsal: np.ndarray  # (2,): its dorsal direction


def retinal_images(eye, table, relative, colours, srgb, classes, width_px):
    """Both eyes' retinal images of a view: Voronoi and density images of map3, map2 and each class's channel.

    Parameters
    ----------
    eye : beeoptics.eye.description.Eye
        The eye's description, placing it on the head.
    table : ReceptorTable
    relative, colours, srgb : ndarray (n, classes), (n, 3), (n, 3)
        Each receptor's catches over white's, its map3 colour and its map2 colour
        (:func:`beeoptics.images.display.bee_colours`).
    classes : sequence of str
        The receptor classes, ``relative``'s columns.
    width_px : int
        Each eye's panel width, pixels.
    """
    xy = retinal_plane(eye, table.position, table.side)
    can = canvas(xy, width_px)
    inside = within_eyes(can, xy, table.side)
    dens, normalised = density(can, xy, table.side, colours, inside)
    shows = nearest_receptor(can, xy, table.side, inside)
    images = {
        "voronoi_map3": encode(paint(shows, colours)),
        # Nearest-receptor images copy values, so encoding before the Voronoi step is exact.
        "voronoi_map2": paint(shows, srgb),
        "density_map3": encode(dens, np.nanpercentile(dens, EXPOSURE_PERCENTILE)),
        "density_map3_normalised": encode(normalised),
    }
    channels = {name: np.clip(paint(shows, relative[:, k])[..., 0], 0.0, 1.0) for k, name in enumerate(classes)}
    return Retina(images, channels, shows, panel_extents(can), *in_eye_plane(eye.rotation))
