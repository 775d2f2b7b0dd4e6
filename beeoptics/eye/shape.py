"""Hand-made eye surfaces shaped from measurements: the outline the measured field implies, and a curved cornea.

An eye whose axes follow the field model (:mod:`beeoptics.eye.axismodel`)
keeps its measured interommatidial angles only where its lines of facets
hold as many facets as the model's lines hold ommatidia. The outline is
therefore drawn from the model itself: its rows of ommatidia
(:mod:`beeoptics.eye.fieldmodel`), laid out as a hexagonal lattice of
facets of the eye's mean diameter D, the frontal meridian (azimuth 0) on
one line, and scaled to the eye's published facet count. A lattice in rows
(the eye's ``lattice.lines``) takes each of the model's rows as a row of
facets, rows √3/2·D apart and each as long as its ommatidia side by side;
a lattice in columns takes each column of the model, its ommatidia Δφ_v
apart, as a column of adjacent facets, so that the model's rows, Δφ_v/2
apart, lie D/2 apart and an ommatidium of a row takes √3·D of it (two
columns √3/2·D apart). Its length, width and area then follow from the
facet count and diameters, and are compared with the published ones in
``quality.json``.

The cornea is a paraboloid over that outline, bulging along the eye's
local +z, whose vertical radius of curvature is 2.5 times its horizontal
one (del Portillo 1936, measured on worker eyes) and whose normals span
the solid angle given (the corneal normals of micro-CT honey-bee eyes span
about 3 sr); it is then scaled so that its area is the facets' area,
count × (√3/2)·D² for hexagonal facets of mean diameter D (flat to flat).

References
----------
del Portillo J (1936) Beziehungen zwischen den Öffnungswinkeln der
Ommatidien, Krümmung und Gestalt der Insekten-Augen und ihrer
funktionellen Aufgabe. Z vergl Physiol 23:100–145.
"""

import numpy as np
from matplotlib.path import Path as Polygon
from scipy.ndimage import gaussian_filter1d
from scipy.optimize import brentq
from scipy.spatial import Delaunay

from beeoptics.eye import fieldmodel

#: Vertical over horizontal radius of curvature of the worker's cornea (del Portillo 1936: "annähernd 2,5:1").
CURVATURE_RATIO = 2.5
#: The rim is smoothed with a Gaussian of this many facet diameters.
RIM_SMOOTHING_FACETS = 2.0
#: Hexagonal facets of diameter D (flat to flat) each cover √3/2·D².
HEXAGON_AREA = np.sqrt(3.0) / 2.0
#: Where the model's rows of ommatidia lie in a hexagonal lattice of facets of diameter 1, by how its
#: lenses line up: the step from one row to the next, and the length each ommatidium takes of its row.
#: In rows, a row of adjacent facets per row; in columns, rows half a facet apart and each ommatidium
#: two columns' width of its row.
ROW_LAYOUT = {"rows": (np.sqrt(3.0) / 2.0, 1.0), "columns": (0.5, np.sqrt(3.0))}


def field_outline(count, facet_diameter_mm, lines="rows", samples=200):
    """The outline of an eye whose lines of facets hold the field model's ommatidia, (k, 2) in (anterior, dorsal), mm.

    Lengths are along the cornea. The polygon runs up the anterior edge and
    back down the posterior one.

    Parameters
    ----------
    count : int
        Facets of the eye.
    facet_diameter_mm : float
        Their mean diameter, flat to flat, mm.
    lines : {"rows", "columns"}
        How the lenses line up (the eye's ``lattice.lines``).
    samples : int
        Elevations the border is read at.
    """
    # From pole to pole: the field's band and the caps beyond, where its rows close round.
    elevation = np.linspace(-90.0, 90.0, samples)
    scale = np.sqrt(count / fieldmodel.ommatidia_count())
    rows = np.concatenate([[0.0], np.cumsum(np.diff(elevation) * 0.5 * (
        fieldmodel.rows_per_degree(elevation[1:]) + fieldmodel.rows_per_degree(elevation[:-1])))])
    row_step, along_row = ROW_LAYOUT[lines]
    dorsal = rows * row_step * facet_diameter_mm * scale
    medial = fieldmodel.ommatidia_medial_of(0.0, elevation)
    anterior = medial * along_row * facet_diameter_mm * scale
    posterior = (medial - fieldmodel.row_count(elevation)) * along_row * facet_diameter_mm * scale
    outline = np.vstack([np.column_stack([anterior, dorsal]), np.column_stack([posterior, dorsal])[::-1]])
    # Resampled evenly and smoothed over a few facets, so that no corner of the rim is narrower
    # than the lattice can fill (the border's ends, where it closes round the pole, are abrupt).
    closed = np.vstack([outline, outline[:1]])
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))])
    step = facet_diameter_mm * scale / 4.0
    t = np.arange(0.0, along[-1], step)
    even = np.column_stack([np.interp(t, along, closed[:, 0]), np.interp(t, along, closed[:, 1])])
    smooth = gaussian_filter1d(even, RIM_SMOOTHING_FACETS * 4.0, axis=0, mode="wrap")
    return smooth - smooth.mean(0)


def _normal_solid_angle(xy, r_h, r_v):
    """Solid angle swept by the normals of z = −x²/2r_h − y²/2r_v over sample points (their area weights)."""
    points, weight = xy
    p, q = points[:, 0] / r_h, points[:, 1] / r_v
    # Gauss image: ∫ K dA, with K dA = (1 + p² + q²)^(−3/2) / (r_h r_v) dx dy on a height field.
    return float(((1.0 + p**2 + q**2) ** -1.5 / (r_h * r_v) * weight).sum())


def _plane_from_arc(arc, radius):
    """Where along the plane a length ``arc`` along the parabola z = −x²/2r, from its apex, ends."""
    def length(x):
        t = x / radius
        return 0.5 * radius * (t * np.sqrt(1.0 + t * t) + np.arcsinh(t))

    grid = np.linspace(0.0, np.abs(arc).max() * 1.0001, 4001)
    return np.sign(arc) * np.interp(np.abs(arc), length(grid), grid)


def _area(xy, r_h, r_v):
    points, weight = xy
    return float((np.sqrt(1.0 + (points[:, 0] / r_h) ** 2 + (points[:, 1] / r_v) ** 2) * weight).sum())


def _samples(outline, n=400):
    """Points filling the outline on a fine grid, each with the area it stands for."""
    lo, hi = outline.min(0), outline.max(0)
    step = (hi - lo).max() / n
    grid = np.stack(np.meshgrid(np.arange(lo[0], hi[0], step) + step / 2,
                                np.arange(lo[1], hi[1], step) + step / 2), -1).reshape(-1, 2)
    inside = grid[Polygon(outline).contains_points(grid)]
    return inside, np.full(len(inside), step * step)


def cornea(outline, area_mm2, normals_sr, spacing_mm):
    """A triangulated paraboloid cap over ``outline`` with the given area and normal spread.

    Parameters
    ----------
    outline : ndarray (k, 2)
        The rim in the eye's local xy-plane (x anterior, y dorsal), mm.
    area_mm2 : float
        The cornea's area.
    normals_sr : float
        The solid angle its normals span.
    spacing_mm : float
        Spacing of the mesh's vertices.

    Returns
    -------
    vertices : ndarray (n, 3)
        Local frame, +z outward; the apex at the origin.
    faces : ndarray (m, 3)
        Wound counter-clockwise seen from +z.
    """
    arcs = np.asarray(outline, float)
    shape, r_h = arcs, np.inf
    for _ in range(50):
        samples = _samples(shape)
        r_h = brentq(lambda r: _normal_solid_angle(samples, r, CURVATURE_RATIO * r) - normals_sr, 1e-3, 1e3)
        stretch = np.sqrt(area_mm2 / _area(samples, r_h, CURVATURE_RATIO * r_h))
        arcs = arcs * stretch
        # The outline's lengths are along the cornea: laid on the plane so that, once lifted, its
        # arcs along the two principal directions keep them.
        shape = np.column_stack([_plane_from_arc(arcs[:, 0], r_h), _plane_from_arc(arcs[:, 1], CURVATURE_RATIO * r_h)])
        if abs(stretch - 1.0) < 1e-7:
            break
    lo, hi = shape.min(0), shape.max(0)
    inner = np.stack(np.meshgrid(np.arange(lo[0], hi[0], spacing_mm), np.arange(lo[1], hi[1], spacing_mm)),
                     -1).reshape(-1, 2)
    rim = Polygon(shape)
    inner = inner[rim.contains_points(inner, radius=-spacing_mm)]
    perimeter = np.linalg.norm(np.diff(np.vstack([shape, shape[:1]]), axis=0), axis=1)
    along = np.concatenate([[0.0], np.cumsum(perimeter)])
    t = np.arange(0.0, along[-1], spacing_mm)
    closed = np.vstack([shape, shape[:1]])
    edge = np.column_stack([np.interp(t, along, closed[:, 0]), np.interp(t, along, closed[:, 1])])
    xy = np.vstack([edge, inner])
    faces = Delaunay(xy).simplices
    keep = rim.contains_points(xy[faces].mean(1))
    faces = faces[keep]
    z = -(xy[:, 0] ** 2 / (2.0 * r_h) + xy[:, 1] ** 2 / (2.0 * CURVATURE_RATIO * r_h))
    vertices = np.column_stack([xy, z])
    d = xy[faces]
    e1, e2 = d[:, 1] - d[:, 0], d[:, 2] - d[:, 0]
    flip = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
    faces[flip] = faces[flip][:, ::-1]
    used = np.unique(faces)
    remap = np.full(len(vertices), -1)
    remap[used] = np.arange(len(used))
    return vertices[used], remap[faces]
