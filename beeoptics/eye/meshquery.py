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
        corner = self._corner[faces]
        normal = self.face_normals[faces]
        onto = points - ((points - corner) * normal).sum(1, keepdims=True) * normal
        left = (self.barycentric(onto, faces) < 0.0).any(1)
        faces = np.array(faces)
        if left.any():
            onto[left], faces[left] = self.project(points[left])
        return onto, faces

    def on_rim_face(self, faces):
        """Whether each face has an edge on the mesh boundary."""
        return self._open_edge[faces].any(1)

    def barycentric(self, points, faces):
        """Barycentric coordinates of points within their faces, shape (k, 3)."""
        t = self.vertices[self.faces[faces]]
        return igl.barycentric_coordinates(
            np.ascontiguousarray(points, dtype=np.float64),
            np.ascontiguousarray(t[:, 0]),
            np.ascontiguousarray(t[:, 1]),
            np.ascontiguousarray(t[:, 2]),
        )

    def interpolate(self, values, points, faces):
        """Per-vertex ``values`` interpolated linearly at points on the mesh."""
        values = np.asarray(values, float)
        bary = self.barycentric(points, faces)
        corners = values[self.faces[faces]]
        if values.ndim == 1:
            return (corners * bary).sum(1)
        return np.einsum("kj,kjd->kd", bary, corners)
