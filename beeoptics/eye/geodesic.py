"""Geodesic distances on eye meshes, with libigl.

Two kinds are needed. Long-range distances from a few anatomical anchors,
which spread the facet-diameter map over the eye, come from the heat method
(Crane et al. 2013). Short distances between neighbouring facets, which set
the springs of the facet lattice, must be exact to well below a micrometre:
they come from the exact polyhedral geodesics of Mitchell, Mount &
Papadimitriou (MMP; Surazhsky et al. 2005), computed on small patches of
the surface around each pair, a batch of pairs to each libigl call.

References
----------
Crane K, Weischedel C, Wardetzky M (2013) Geodesics in heat. ACM Trans
Graph 32:152.
Surazhsky V, Surazhsky T, Kirsanov D, Gortler SJ, Hoppe H (2005) Fast exact
and approximate geodesics on meshes. ACM Trans Graph 24:553–560.
"""

import igl
import numpy as np
from scipy.spatial import cKDTree

_NO_INDEX = np.array([], dtype=np.int64)
#: A patch geodesic longer than this many chords may have been cut off by its patch.
_DETOUR = 1.01
#: Pairs measured in one MMP run. libigl's MMP spends more per pair the more
#: pairs (disjoint patches) a run holds: 30,000 pairs take 2.5 times as long in
#: runs of 1,000 as in runs of 16, and runs much shorter cost more in calls.
_BATCH = 16


def heat_distances(vertices, faces, sources):
    """Geodesic distance from each source vertex to every vertex, by the heat method.

    Parameters
    ----------
    vertices : ndarray, shape (n, 3)
    faces : ndarray, shape (m, 3)
    sources : sequence of int
        Vertex indices.

    Returns
    -------
    ndarray, shape (len(sources), n)
        Distances, in the units of ``vertices``.
    """
    # libigl's precomputation (the factorisations of its heat and Poisson steps) fails on some meshes at one
    # scale and not at another (a micro-CT bumblebee's remeshed cornea, in mm, on one processor); distances scale
    # with the mesh, so such a mesh is measured in micrometres instead.
    for scale in (1.0, 1e3):
        data = igl.HeatGeodesicsData()
        try:
            igl.heat_geodesics_precompute(np.asarray(vertices, float) * scale, faces, data)
        except RuntimeError:
            if scale != 1.0:
                raise
            continue
        return np.stack([igl.heat_geodesics_solve(data, np.array([s], dtype=np.int64)) for s in sources]) / scale


def pair_distances(vertices, faces, points, point_faces, pairs, margin=None, widen=2):
    """Exact geodesic distance between pairs of nearby points on a mesh.

    Each pair gets its own patch: the faces whose centroids lie within
    ``margin`` of the segment joining the two points, with both points
    inserted as vertices. The patches are disjoint, so one multi-source
    MMP run measures a batch of pairs at once. For points a few facets apart on a
    smooth eye, the geodesic strays from the segment by far less than a
    triangle, so the patch holds it. A pair whose distance comes out much
    longer than its chord, or not reached, is measured again on a patch four
    times as wide: its path may have been cut off by the patch's edge, or it
    may truly bend round a notch in the rim of the mesh.

    Parameters
    ----------
    vertices, faces : ndarray
        The mesh.
    points : ndarray, shape (p, 3)
        Points on the mesh.
    point_faces : ndarray, shape (p,)
        The face holding each point.
    pairs : ndarray, shape (k, 2)
        Indices into ``points``.
    margin : float, optional
        Half-width of each patch; by default the median edge length, which
        holds the faces the segment crosses (their centroids lie within
        about two thirds of a triangle's height of it).
    widen : int
        How many times a pair measured too long, or not at all, is measured
        again on a patch four times as wide.

    Returns
    -------
    ndarray, shape (k,)
    """
    vertices = np.asarray(vertices, float)
    faces = np.asarray(faces, np.int64)
    pairs = np.asarray(pairs, np.int64)
    fa, fb = point_faces[pairs[:, 0]], point_faces[pairs[:, 1]]
    a = _off_edges(vertices, faces, points[pairs[:, 0]], fa)
    b = _off_edges(vertices, faces, points[pairs[:, 1]], fb)
    out = np.linalg.norm(b - a, axis=1)
    if margin is None:
        margin = np.median(np.sqrt(igl.squared_edge_lengths(vertices, faces)))
    # Two points on one flat face are joined by the straight segment.
    todo = np.flatnonzero(fa != fb)
    if todo.size == 0:
        return out
    a, b, fa, fb, length = a[todo], b[todo], fa[todo], fb[todo], out[todo]

    centroids = vertices[faces].mean(axis=1)
    hits = cKDTree(centroids).query_ball_point((a + b) / 2, length / 2 + margin)
    counts = np.fromiter(map(len, hits), np.int64, len(hits))
    pair_of = np.repeat(np.arange(len(todo)), counts)
    face_of = np.concatenate(hits).astype(np.int64)
    # Keep the capsule around the segment, and always the two end faces.
    seg = (b - a)[pair_of]
    t = np.clip(((centroids[face_of] - a[pair_of]) * seg).sum(1) / (seg * seg).sum(1), 0, 1)
    near = np.linalg.norm(centroids[face_of] - a[pair_of] - t[:, None] * seg, axis=1) <= margin
    pair_of = np.concatenate([pair_of[near], np.arange(len(todo)), np.arange(len(todo))])
    face_of = np.concatenate([face_of[near], fa, fb])
    # np.unique hashes when no inverse is asked for, which is many times slower than sorting here.
    key = np.sort(pair_of * len(faces) + face_of)
    key = key[np.concatenate([[True], key[1:] != key[:-1]])]
    out[todo] = _patch_geodesics(vertices, faces, key, a, b, fa, fb)
    # On a smooth surface a geodesic this short exceeds its chord by ~1e-4. One
    # shorter than its chord never reached its end: near a notch in the rim the
    # segment leaves the mesh and cuts the patch in two, and MMP then gives 0.
    short = out[todo] < (1.0 - 1e-6) * length
    lost = todo[short | ~(out[todo] < _DETOUR * length)]
    if lost.size and widen > 0:
        out[lost] = pair_distances(vertices, faces, points, point_faces, pairs[lost], 4.0 * margin, widen - 1)
    elif short.any():
        raise RuntimeError(f"{short.sum()} geodesics could not be measured on patches {margin:.3g} wide")
    return out


def _patch_geodesics(vertices, faces, key, a, b, fa, fb):
    """MMP from ``a`` to ``b`` of each pair over its own patch of the mesh.

    ``key`` (sorted) lists the patches' faces as pair × n_faces + face;
    ``fa`` and ``fb`` are the faces holding ``a`` and ``b``. The patches'
    vertices and faces are laid out pair after pair, so that a batch of
    consecutive pairs is one slice of each.
    """
    n = len(a)
    pair_of, face_of = key // len(faces), key % len(faces)
    # Disjoint copies of the mesh vertices, one set per pair, followed by the pair's two points.
    used, local = np.unique(pair_of[:, None] * len(vertices) + faces[face_of], return_inverse=True)
    owner = used // len(vertices)
    copies = np.bincount(owner, minlength=n)
    first_vertex = np.concatenate([[0], np.cumsum(copies + 2)])
    src = first_vertex[:-1] + copies
    renumber = np.arange(len(used)) + first_vertex[owner] - (np.cumsum(copies) - copies)[owner]
    patch_v = np.empty((first_vertex[-1], 3))
    patch_v[renumber] = vertices[used % len(vertices)]
    patch_v[src], patch_v[src + 1] = a, b
    patch_f = renumber[local.reshape(-1, 3)]

    # Split each end face into three around its point.
    split_rows = np.searchsorted(key, np.tile(np.arange(n), 2) * len(faces) + np.concatenate([fa, fb]))
    centre = np.concatenate([src, src + 1])
    tri = patch_f[split_rows]
    fans = np.concatenate([np.stack([tri[:, 0], tri[:, 1], centre], 1),
                           np.stack([tri[:, 1], tri[:, 2], centre], 1),
                           np.stack([tri[:, 2], tri[:, 0], centre], 1)])
    keep = np.ones(len(patch_f), bool)
    keep[split_rows] = False
    face_pair = np.concatenate([pair_of[keep], np.tile(np.arange(n), 6)])
    order = np.argsort(face_pair, kind="stable")
    patch_f = np.vstack([patch_f[keep], fans])[order]
    bounds = np.arange(0, n + _BATCH, _BATCH).clip(max=n)
    face_bounds = np.searchsorted(face_pair[order], bounds)
    return np.concatenate([
        igl.exact_geodesic(patch_v[first_vertex[lo]:first_vertex[hi]], patch_f[f_lo:f_hi] - first_vertex[lo],
                           src[lo:hi] - first_vertex[lo], _NO_INDEX, src[lo:hi] + 1 - first_vertex[lo], _NO_INDEX)
        for lo, hi, f_lo, f_hi in zip(bounds[:-1], bounds[1:], face_bounds[:-1], face_bounds[1:])
    ])


def _off_edges(vertices, faces, points, point_faces, eps=1e-4):
    """Move points a hair inside their faces (a ten-thousandth of the face), so that splitting
    a face around one never makes the slivers that stall the MMP propagation."""
    tri = vertices[faces[point_faces]]
    bary = igl.barycentric_coordinates(points, tri[:, 0], tri[:, 1], tri[:, 2])
    bary = np.clip(bary, eps, None)
    bary /= bary.sum(1, keepdims=True)
    return np.einsum("ij,ijk->ik", bary, tri)
