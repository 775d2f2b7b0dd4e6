"""Closest points and interpolation on one triangle mesh, with libigl.

The particles that become facets live on the eye surface. Every step of
the relaxation puts them back on it through this object, which keeps the
libigl AABB tree of the mesh so that it is built once.
"""

import igl
import numpy as np


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
        # libigl's edge k of a face runs from corner k to corner k+1.
        self._open_edge = igl.triangle_triangle_adjacency(self.faces)[0] < 0

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
        frame = self._frame[faces]
        relative = points - frame[:, :3]
        normal = frame[:, 3:6]
        relative -= np.einsum("kj,kj->k", relative, normal)[:, None] * normal
        s = np.einsum("kj,kj->k", frame[:, 6:9], relative)
        t = np.einsum("kj,kj->k", frame[:, 9:12], relative)
        left = (s < 0.0) | (t < 0.0) | (s + t > 1.0)
        onto = frame[:, :3] + relative
        faces = np.array(faces)
        if left.any():
            onto[left], faces[left] = self.project(points[left])
        return onto, faces

    def on_rim_face(self, faces):
        """Whether each face has an edge on the mesh boundary."""
        return self._open_edge[faces].any(1)

    def barycentric(self, points, faces):
        """Barycentric coordinates of points (in their faces' planes) within their faces, shape (k, 3)."""
        frame = self._frame[faces]
        relative = np.asarray(points, float) - frame[:, :3]
        s = np.einsum("kj,kj->k", frame[:, 6:9], relative)
        t = np.einsum("kj,kj->k", frame[:, 9:12], relative)
        return np.column_stack([1.0 - s - t, s, t])

    def interpolate(self, values, points, faces):
        """Per-vertex ``values`` interpolated linearly at points on the mesh."""
        values = np.asarray(values, float)
        bary = self.barycentric(points, faces)
        corners = values[self.faces[faces]]
        if values.ndim == 1:
            return (corners * bary).sum(1)
        return np.einsum("kj,kjd->kd", bary, corners)
