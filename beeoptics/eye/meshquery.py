"""Closest points and interpolation on one triangle mesh, with libigl.

The particles that become facets live on the eye surface. Every step of
the relaxation puts them back on it through this object, which keeps the
libigl AABB tree of the mesh so that it is built once.
"""

import igl
import numpy as np

from beeoptics.jit import kernel


class MeshQuery:
    """A triangle mesh with its AABB tree, for closest-point and barycentric queries.

    Parameters
    ----------
    vertices : ndarray, shape (n, 3)
    faces : ndarray, shape (m, 3)
    """

    def __init__(self, vertices, faces):
        self.vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self._tree = igl.AABB()
        self._tree.init(self.vertices, self.faces)
        self.face_normals = igl.per_face_normals(
            self.vertices, self.faces, np.array([0.0, 0.0, 1.0])
        )
        self.area = float(igl.doublearea(self.vertices, self.faces).sum() / 2.0)
        self._corner = self.vertices[self.faces[:, 0]]
        # Each face's dual basis: barycentric coordinates of a point p in the face's plane are
        # (1 − s − t, s, t) with (s, t) = dual · (p − corner), the relaxation's most frequent query.
        e1 = self.vertices[self.faces[:, 1]] - self._corner
        e2 = self.vertices[self.faces[:, 2]] - self._corner
        d11, d12, d22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
        det = (d11 * d22 - d12 * d12)[:, None]
        dual = np.hstack([(d22[:, None] * e1 - d12[:, None] * e2) / det, (d11[:, None] * e2 - d12[:, None] * e1) / det])
        # Corner, normal and dual basis side by side: one gather per point, the relaxation's hot path.
        self._frame = np.ascontiguousarray(np.hstack([self._corner, self.face_normals, dual]))
        # A face on the rim has a corner on the boundary: a face that touches it at a corner
        # only holds a particle pushed into that corner as firmly as one with an edge there.
        on_boundary = np.zeros(len(self.vertices), bool)
        on_boundary[igl.boundary_facets(self.faces)[0].ravel()] = True
        self._rim_face = on_boundary[self.faces].any(1)

    def project(self, points):
        """Closest points on the mesh and the faces that hold them."""
        _, faces, closest = self._tree.squared_distance(
            self.vertices, self.faces, np.ascontiguousarray(points, dtype=np.float64)
        )
        return closest, faces

    def slide(self, points, faces):
        """Put points that moved a little away from their faces back on the mesh.

        A point whose projection onto its old face's plane still falls in
        that triangle lands there; only points that left their face are
        looked up in the AABB tree. Same contract as :meth:`project`, for
        moves shorter than a triangle.
        """
        faces = np.array(faces, np.int64)
        onto, left = _onto_own_faces(self._frame, np.ascontiguousarray(points, dtype=np.float64), faces)
        if left.any():
            onto[left], faces[left] = self.project(points[left])
        return onto, faces

    def on_rim_face(self, faces):
        """Whether each face has a corner on the mesh boundary."""
        return self._rim_face[faces]

    def barycentric(self, points, faces):
        """Barycentric coordinates of points (in their faces' planes) within their faces, shape (k, 3)."""
        return _barycentric(self._frame, np.ascontiguousarray(points, dtype=np.float64), np.asarray(faces, np.int64))

    def interpolate(self, values, points, faces):
        """Per-vertex ``values`` interpolated linearly at points on the mesh."""
        values = np.asarray(values, float)
        bary = self.barycentric(points, faces)
        corners = values[self.faces[faces]]
        if values.ndim == 1:
            return (corners * bary).sum(1)
        return np.einsum("kj,kjd->kd", bary, corners)


@kernel
def _onto_own_faces(frame, points, faces):
    """Each point projected onto the plane of its face, and whether it landed outside the triangle.

    Compiled: the relaxation slides every particle at every step, and the
    gathers and temporaries of the same in NumPy cost more than the arithmetic.
    """
    onto = np.empty_like(points)
    left = np.empty(len(points), np.bool_)
    for k in range(len(points)):
        f = frame[faces[k]]
        r0, r1, r2 = points[k, 0] - f[0], points[k, 1] - f[1], points[k, 2] - f[2]
        up = r0 * f[3] + r1 * f[4] + r2 * f[5]
        r0, r1, r2 = r0 - up * f[3], r1 - up * f[4], r2 - up * f[5]
        s = f[6] * r0 + f[7] * r1 + f[8] * r2
        t = f[9] * r0 + f[10] * r1 + f[11] * r2
        left[k] = s < 0.0 or t < 0.0 or s + t > 1.0
        onto[k, 0], onto[k, 1], onto[k, 2] = f[0] + r0, f[1] + r1, f[2] + r2
    return onto, left


@kernel
def _barycentric(frame, points, faces):
    """Barycentric coordinates of points in the planes of their faces, compiled as :func:`_onto_own_faces`."""
    bary = np.empty((len(points), 3))
    for k in range(len(points)):
        f = frame[faces[k]]
        r0, r1, r2 = points[k, 0] - f[0], points[k, 1] - f[1], points[k, 2] - f[2]
        s = f[6] * r0 + f[7] * r1 + f[8] * r2
        t = f[9] * r0 + f[10] * r1 + f[11] * r2
        bary[k, 0], bary[k, 1], bary[k, 2] = 1.0 - s - t, s, t
    return bary
