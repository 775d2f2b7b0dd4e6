"""The facet lattice: its first grid, the count rule, and who neighbours whom.

Collins §4.1 step 2: a regular grid is superimposed over the eye, at the
resolution that gives the right number of facets, and projected parallel to
the eye's z-axis onto the surface; the projected points are the initial
particles. The grid here is hexagonal, like the lattice the relaxation
makes of it.

Neighbours are the edges of a Delaunay triangulation made in a conformal
(least-squares conformal map, Lévy et al. 2002) flattening of the eye: a
conformal map keeps angles, so the empty-circle test, and with it the
neighbour count of a hexagonal lattice, survives the flattening. The
neighbours of receptor axes, on the sphere of directions, are the spherical
Delaunay triangulation of the axes: their convex hull (Qhull, via scipy).
Both triangulations also span the gaps beyond the rim of the eye, with
edges longer than :data:`MAX_EDGE` spacings, which are dropped.

References
----------
Collins S. Reconstructing the visual field of compound eyes. §4.1.
Lévy B, Petitjean S, Ray N, Maillot J (2002) Least squares conformal maps
for automatic texture atlas generation. ACM Trans Graph 21:362–371.
"""

import numpy as np
from scipy.spatial import ConvexHull, Delaunay, cKDTree

from beeoptics.raycasting import embree_scene, first_hits

#: Delaunay edges longer than this many spacings bridge the rim, not neighbours.
#: A hexagonal lattice's Delaunay edges are one spacing long and its second ring
#: lies √3 spacings away; eyes whose horizontal and vertical spacings differ by
#: up to 1.5 times (Seidl 1982, as modelled by Stürzl et al. 2010) keep all
#: their neighbours within 1.8.
MAX_EDGE = 1.8
#: Where Δφ is not known: a triangle of receptor axes with an angle wider than this, degrees,
#: joins three facets along the rim, not neighbours. A hexagonal rim turns by 60°, so three
#: consecutive rim facets make an angle of 120° or more, while the Delaunay triangles of our
#: relaxed lattices' axes have their widest angle below 98–103° in 99 % of cases (worker, drone,
#: queen, measured).
MAX_ANGLE_DEG = 110.0


def hex_grid(pitch, lo, hi, offset=(0.0, 0.0), lines="rows"):
    """Points of a hexagonal grid of spacing ``pitch`` covering the box [lo, hi] in xy.

    With ``lines`` "rows", rows run along x, ``pitch`` apart within a row and
    ``pitch·√3/2`` apart between rows, every other row shifted by half a
    pitch; with "columns", the same grid turned a quarter turn, columns of
    adjacent points running along y.
    """
    if lines == "columns":
        return hex_grid(pitch, lo[::-1], hi[::-1], offset[::-1])[:, ::-1]
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    row = pitch * np.sqrt(3.0) / 2.0
    ys = np.arange(lo[1] - row + offset[1] % row, hi[1] + row, row)
    xs = np.arange(lo[0] - pitch + offset[0] % pitch, hi[0] + pitch, pitch)
    gx, gy = np.meshgrid(xs, ys)
    gx = gx + (np.arange(len(ys)) % 2)[:, None] * (pitch / 2.0)
    return np.stack([gx.ravel(), gy.ravel()], 1)


def _raycast_down(scene, xy, top):
    rays = np.zeros((len(xy), 6), np.float32)
    rays[:, :2] = xy
    rays[:, 2] = top
    rays[:, 5] = -1.0
    hit = first_hits(scene, rays)["t_hit"]
    keep = np.isfinite(hit)
    return np.column_stack([xy[keep], top - hit[keep]])


def project_grid(query, count, lines="rows", max_offsets=64):
    """The count rule: a hexagonal grid with exactly ``count`` points on the eye.

    The pitch is found by bisection on the number of grid points whose
    downward ray (along -z of the eye frame) meets the mesh. Where the count
    jumps over the target at every pitch, the grid is shifted by a fixed
    sequence of sub-pitch offsets until it lands on it.

    Parameters
    ----------
    query : MeshQuery
        The eye mesh in its local frame (z outward, a height field over xy).
    count : int
        Facets wanted.
    lines : {"rows", "columns"}
        How the grid's adjacent points line up (:func:`hex_grid`).

    Returns
    -------
    points : ndarray, shape (count, 3)
        On the mesh.
    faces : ndarray, shape (count,)
        The face under each point.
    pitch : float
        The grid spacing, in mesh units.
    """
    import igl  # imported where used: the receptor readers need this module's edges, not libigl (--help stays quick)

    v, f = query.vertices, query.faces
    scene = embree_scene([(v, f)])
    lo, hi = v[:, :2].min(0), v[:, :2].max(0)
    top = v[:, 2].max() + 1.0
    projected_area = 0.5 * igl.doublearea(v * [1.0, 1.0, 0.0], f).sum()
    pitch0 = np.sqrt(projected_area / (np.sqrt(3.0) / 2.0 * count))
    golden = (np.sqrt(5.0) - 1.0) / 2.0
    best = None
    for k in range(max_offsets):
        offset = (pitch0 * ((k * golden) % 1.0), pitch0 * ((k * golden * golden) % 1.0))
        a, b = 0.7 * pitch0, 1.4 * pitch0
        for _ in range(60):
            pitch = 0.5 * (a + b)
            pts = _raycast_down(scene, hex_grid(pitch, lo, hi, offset, lines), top)
            if len(pts) == count:
                points, faces = query.project(pts)
                return points, faces, pitch
            a, b = (pitch, b) if len(pts) > count else (a, pitch)
            if best is None or abs(len(pts) - count) < abs(len(best[0]) - count):
                best = (pts, pitch)
    raise ValueError(
        f"no hexagonal grid gives exactly {count} facets on this mesh "
        f"(closest: {len(best[0])} at pitch {best[1]:.6g})"
    )


def conformal_map(vertices, faces):
    """Least-squares conformal flattening of a disc-shaped mesh, per vertex (n, 2)."""
    import igl  # imported where used, as in project_grid

    loop = igl.boundary_loop(faces)
    b = np.array([loop[0], loop[len(loop) // 2]], dtype=np.int64)
    bc = np.array([[0.0, 0.0], [1.0, 0.0]])
    uv, _ = igl.lscm(vertices, faces, b, bc)
    return uv


def neighbour_edges(uv, points, max_length):
    """Delaunay edges between particles, without the slivers that bridge the rim.

    Parameters
    ----------
    uv : ndarray, shape (n, 2)
        The particles in the conformal flattening.
    points : ndarray, shape (n, 3)
        The particles on the surface.
    max_length : ndarray, shape (n,)
        Per particle, the longest 3-D edge that still counts as a
        neighbour; longer edges only span the concave parts of the rim.

    Returns
    -------
    edges : ndarray, shape (m, 2)
        Unique, with ``edges[:, 0] < edges[:, 1]``.
    boundary : ndarray of bool, shape (n,)
        Particles on the rim of the triangulation, and those left without
        a neighbour (their Δφ is NaN).
    """
    tri = Delaunay(uv).simplices
    corners = np.stack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]], 1)
    length = np.linalg.norm(points[corners[..., 0]] - points[corners[..., 1]], axis=2)
    limit = np.minimum(max_length[corners[..., 0]], max_length[corners[..., 1]])
    tri_edges = np.sort(corners[(length <= limit).all(1)].reshape(-1, 2), axis=1)
    edges, uses = np.unique(tri_edges, axis=0, return_counts=True)
    boundary = np.zeros(len(points), bool)
    boundary[edges[uses == 1].ravel()] = True
    # A particle whose every triangle bridged the rim is on the rim too, with no neighbours.
    boundary[np.bincount(edges.ravel(), minlength=len(points)) == 0] = True
    return edges, boundary


def neighbour_counts(edges, n):
    """Number of neighbours of each of ``n`` particles."""
    return np.bincount(edges.ravel(), minlength=n)


def mean_over_edges(edges, values, n):
    """Per particle, the mean of ``values`` (m,) over its edges (m, 2); NaN where it has none."""
    count = np.bincount(edges.ravel(), minlength=n)
    total = np.bincount(edges[:, 0], values, n) + np.bincount(edges[:, 1], values, n)
    return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def kernel_mean(points, values, sigma):
    """Gaussian-kernel average of per-facet values at each facet (Nadaraya 1964; Watson 1964).

    Parameters
    ----------
    points : ndarray (n, d)
        Facet positions, mm.
    values : ndarray (n,)
    sigma : float
        The kernel's standard deviation, mm; facets beyond 3σ are left out.

    Returns
    -------
    ndarray (n,)
    """
    tree = cKDTree(points)
    pairs = tree.sparse_distance_matrix(tree, 3.0 * sigma, output_type="coo_matrix")
    weight = np.exp(-0.5 * (pairs.data / sigma) ** 2)
    n = len(points)
    # Values that are NaN (a facet without neighbours has no Δφ) weigh nothing.
    values = np.asarray(values, float)
    known = np.isfinite(values)
    values, weight = np.where(known, values, 0.0), weight * known[pairs.col]
    # The zero self-distances are not stored: each facet's own weight, 1 if known, is added back.
    sums = np.bincount(pairs.row, weight * values[pairs.col], n) + values
    return sums / (np.bincount(pairs.row, weight, n) + known)


def edge_angles(axes, edges):
    """Angle between the unit axes at the ends of each edge, radians."""
    return np.arccos(np.clip((axes[edges[:, 0]] * axes[edges[:, 1]]).sum(1), -1.0, 1.0))


def sphere_triangles(axes, delta_phi_deg=None):
    """Spherical Delaunay triangles of unit axes, less those that span gaps rather than join neighbours.

    A triangle is dropped when one of its edges is longer than
    :data:`MAX_EDGE` spacings of its ends: it bridges the rim of the eye, or
    the far side of the sphere. The spacing is the receptors' Δφ where it is
    known (the mean of the two ends'); without it, the larger
    nearest-neighbour angle of the two ends, which is shorter, so that three
    facets along the rim can pass as neighbours: a triangle with an angle
    wider than :data:`MAX_ANGLE_DEG` is then dropped too.

    Parameters
    ----------
    axes : ndarray, shape (n, 3)
        Unit vectors, n ≥ 4, not all in one plane.
    delta_phi_deg : ndarray, shape (n,), optional
        Each axis's interommatidial angle.

    Returns
    -------
    ndarray, shape (t, 3)
        Indices into ``axes``.

    Raises
    ------
    scipy.spatial.QhullError
        If the axes cannot be triangulated.
    """
    tri = ConvexHull(axes).simplices
    corners = np.stack([tri, np.roll(tri, 1, 1)], -1).reshape(-1, 2)
    length = edge_angles(axes, corners).reshape(-1, 3)
    if delta_phi_deg is not None:
        limit = np.radians(MAX_EDGE * 0.5 * (delta_phi_deg[corners[:, 0]] + delta_phi_deg[corners[:, 1]]))
        return tri[(length <= limit.reshape(-1, 3)).all(1)]
    chord = cKDTree(axes).query(axes, k=2)[0][:, 1]
    nearest = 2.0 * np.arcsin(np.clip(chord / 2.0, 0.0, 1.0))
    limit = MAX_EDGE * np.maximum(nearest[corners[:, 0]], nearest[corners[:, 1]]).reshape(-1, 3)
    # The widest angle faces the longest side (law of cosines; the triangles are small).
    a, b, c = np.sort(length, axis=1).T
    widest = np.degrees(np.arccos(np.clip((a * a + b * b - c * c) / np.maximum(2.0 * a * b, 1e-300), -1.0, 1.0)))
    return tri[(length <= limit).all(1) & (widest <= MAX_ANGLE_DEG)]


def triangle_edges(triangles):
    """The unique edges (m, 2) of triangles (t, 3), each with its smaller index first."""
    pairs = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.unique(np.sort(pairs, axis=1), axis=0).reshape(-1, 2)
