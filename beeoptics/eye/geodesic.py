"""Geodesic distances on eye meshes, with libigl.

Two kinds are needed. Long-range distances from a few anatomical anchors,
which spread the facet-diameter map over the eye, come from the heat method
(Crane et al. 2013). Short distances between neighbouring facets, which set
the springs of the facet lattice, must be exact to well below a micrometre:
they come from the exact polyhedral geodesics of Mitchell, Mount &
Papadimitriou (MMP; Surazhsky et al. 2005), computed on small patches of
the surface around each pair, all in one libigl call.

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
    data = igl.HeatGeodesicsData()
    igl.heat_geodesics_precompute(vertices, faces, data)
    return np.stack(
        [igl.heat_geodesics_solve(data, np.array([s], dtype=np.int64)) for s in sources]
    )


def pair_distances(vertices, faces, points, point_faces, pairs, margin=None, widen=2):
    """Exact geodesic distance between pairs of nearby points on a mesh.

    Each pair gets its own patch: the faces whose centroids lie within
    ``margin`` of the segment joining the two points, with both points
    inserted as vertices. The patches are disjoint, so one multi-source
    MMP run measures every pair at once. For points a few facets apart on a
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
    key = np.unique(pair_of * len(faces) + face_of)
    pair_of, face_of = key // len(faces), key % len(faces)

    # Disjoint copies of the mesh vertices, one set per pair.
    corner = pair_of[:, None] * len(vertices) + faces[face_of]
    used, local = np.unique(corner, return_inverse=True)
    patch_v = vertices[used % len(vertices)]
    patch_f = local.reshape(-1, 3)

    # Split each end face into three around its point.
    n0 = len(patch_v)
    src = n0 + np.arange(len(todo))
    dst = n0 + len(todo) + np.arange(len(todo))
    patch_v = np.vstack([patch_v, a, b])
    split_rows = np.concatenate(
        [
            np.searchsorted(key, np.arange(len(todo)) * len(faces) + fa),
            np.searchsorted(key, np.arange(len(todo)) * len(faces) + fb),
        ]
    )
    centre = np.concatenate([src, dst])
    tri = patch_f[split_rows]
    fans = np.concatenate(
        [
            np.stack([tri[:, 0], tri[:, 1], centre], 1),
            np.stack([tri[:, 1], tri[:, 2], centre], 1),
            np.stack([tri[:, 2], tri[:, 0], centre], 1),
        ]
    )
    keep = np.ones(len(patch_f), bool)
    keep[split_rows] = False
    patch_f = np.vstack([patch_f[keep], fans])

    out[todo] = igl.exact_geodesic(patch_v, patch_f, src, _NO_INDEX, dst, _NO_INDEX)
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


def _off_edges(vertices, faces, points, point_faces, eps=1e-4):
    """Move points a hair inside their faces (a ten-thousandth of the face), so that splitting
    a face around one never makes the slivers that stall the MMP propagation."""
    tri = vertices[faces[point_faces]]
    bary = igl.barycentric_coordinates(points, tri[:, 0], tri[:, 1], tri[:, 2])
    bary = np.clip(bary, eps, None)
    bary /= bary.sum(1, keepdims=True)
    return np.einsum("ij,ijk->ik", bary, tri)
