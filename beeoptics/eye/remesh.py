"""Remeshing a hand-made eye mesh with pymeshlab.

A modeller's eye mesh is low-poly: its faces are flat, and facets placed on
it would share one normal per face. The mesh is first refined by
interpolating (modified butterfly) subdivision, which keeps every vertex the
modeller placed and rounds the surface between them, then remeshed
isotropically (Hoppe's explicit remeshing, as in VCG/MeshLab) to a target
edge length well below the facet size, reprojecting onto the refined
surface; the boundary is kept, since it is the rim of the eye and sets its
field of view, and slivers left along it (T-vertices) are collapsed. Vertex normals are finally smoothed over a few rings, so
that the normal field the receptor axes are read from varies at the scale
of the eye's curvature and not of the triangles.

References
----------
Zorin D, Schröder P, Sweldens W (1996) Interpolating subdivision for meshes
with arbitrary topology. Proc SIGGRAPH 96:189–192.
Hoppe H (1996) Progressive meshes. Proc SIGGRAPH 96:99–108.
Cignoni P et al. (2008) MeshLab: an open-source mesh processing tool.
Eurographics Italian Chapter Conference.
"""

import igl
import numpy as np
import pymeshlab


def remesh(vertices, faces, edge_length, *, subdivisions=2, iterations=8, normal_smoothing=20):
    """Refine and isotropically remesh a triangle mesh.

    Parameters
    ----------
    vertices : ndarray, shape (n, 3)
    faces : ndarray, shape (m, 3)
    edge_length : float
        Target edge length, in mesh units.
    subdivisions : int
        Butterfly subdivision steps before remeshing.
    iterations : int
        Remeshing passes.
    normal_smoothing : int
        Uniform-Laplacian smoothing steps applied to the vertex normals.

    Returns
    -------
    vertices, faces, normals : ndarray
    """
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.asarray(vertices, float), np.asarray(faces, np.int32)))
    if subdivisions:
        ms.meshing_surface_subdivision_butterfly(
            iterations=subdivisions, threshold=pymeshlab.PercentageValue(0.0)
        )
    ms.meshing_isotropic_explicit_remeshing(
        iterations=iterations,
        targetlen=pymeshlab.PureValue(edge_length),
        featuredeg=180.0,
        maxsurfdist=pymeshlab.PureValue(edge_length / 10.0),
    )
    # A rim vertex can end up on its neighbour's edge, leaving a sliver whose
    # cotangent weights, and with them the heat geodesics, are infinite.
    ms.meshing_remove_t_vertices(method="Edge Collapse", threshold=40, repeat=True)
    ms.meshing_remove_unreferenced_vertices()
    m = ms.current_mesh()
    v = m.vertex_matrix().astype(np.float64)
    f = m.face_matrix().astype(np.int64)
    return v, f, smooth_normals(v, f, normal_smoothing)


def target_edge_mm(eye, edge_fraction):
    """The remeshing edge: ``edge_fraction`` of the mean facet diameter of the eye's anchors, mm.

    With the default third, a third of a typical facet and at most half of
    the smallest (the drone's 17.7 µm against its mean of 27 µm). An
    anchor the facets fill (:mod:`beeoptics.eye.facetmap`) does not count.
    """
    return edge_fraction * (np.mean([a["diameter_um"] for a in eye.anchors if a["diameter_um"] != "fill"]) * 1e-3)


def smooth_normals(vertices, faces, steps):
    """Vertex normals, smoothed ``steps`` times by averaging over the one-ring."""
    n = igl.per_vertex_normals(vertices, faces)
    for _ in range(steps):
        n = igl.per_vertex_attribute_smoothing(n, faces)
        n /= np.linalg.norm(n, axis=1, keepdims=True)
    return n
