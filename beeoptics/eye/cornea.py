"""Measured corneas: an eye's surface and frame from micro-CT points with their normals.

Micro-CT eyes (Taylor et al. 2019, as CompoundRay ships them) sample the
cornea every 25 µm, whatever the bee's size, with the surface normal at
each point: they are the eye's measured surface, not its facets. An eye
description that names such a ``cornea`` (a receptor table of the right
eye's points and normals, head frame, written by ``beeoptics convert``) is
built the paper's way on it (Collins §4.1): the surface is reconstructed
from the oriented points by screened Poisson reconstruction (Kazhdan &
Hoppe 2013, pymeshlab's filter), trimmed to where the points are, and the
facet lattice is relaxed on it at the count and diameters published for
the species or specimen.

The eye's local frame is the one the relaxation needs, a height field over
its xy-plane: local z is the axis of the narrowest cone that holds every
normal of the points (their most even compromise), local y the head's
dorsal direction made perpendicular to it (:func:`beeoptics.headframe.eye_rotation`),
the origin the points' centroid.

References
----------
Kazhdan M, Hoppe H (2013) Screened Poisson surface reconstruction. ACM
Trans Graph 32(3):29.
Taylor GJ, Tichit P, Schmidt MD, Bodey AJ, Rau C, Baird E (2019) Bumblebee
visual allometry results in locally improved resolution and globally
improved sensitivity. eLife 8:e40613.
Millward BF, Maddock S, Mangan M (2022) CompoundRay, an open-source tool for
high-speed and high-fidelity rendering of compound eyes. eLife 11:e73893.
"""

import igl
import numpy as np
import pymeshlab
from scipy.optimize import minimize
from scipy.spatial import cKDTree

from beeoptics.headframe import RIGHT, eye_azimuth_elevation, eye_rotation
from beeoptics.io.errors import InputError

#: Octree depth of the Poisson reconstruction: 2⁸ cells across the eye, a few µm each, finer than
#: the 25 µm between the points.
POISSON_DEPTH = 8
#: The reconstructed surface is kept where the points are: within this many point spacings of one.
TRIM_SPACINGS = 1.5
#: Laplacian smoothing steps after the reconstruction, and at most how many rings of the rim are peeled.
SMOOTHING_STEPS = 3
PEEL_RINGS = 10
#: The measured normals a surface vertex takes its own from: its nearest points, by inverse distance.
NORMAL_NEIGHBOURS = 4


def cornea_frame(positions, normals):
    """The local frame of a measured cornea: its rotation (rows: local axes, head frame) and origin (mm).

    Local z is the axis of the narrowest cone holding every normal: the
    direction whose smallest dot product with the normals is largest.
    """
    normals = np.asarray(normals, float)
    mean = normals.mean(0) / np.linalg.norm(normals.mean(0))
    # The smallest dot product is concave along the sphere near the mean: from there, up it.
    az, el = eye_azimuth_elevation(mean, RIGHT)

    def worst(angles):
        return -float((normals @ eye_rotation(*angles)[2]).min())

    best = minimize(worst, [float(az), float(el)], method="Nelder-Mead",
                    options={"xatol": 1e-6, "fatol": 1e-9, "maxiter": 4000}).x
    return eye_rotation(*best), np.asarray(positions, float).mean(0)


def reconstruct(points, normals, source):
    """The cornea's surface from its points and normals in its local frame: (vertices, faces), mm.

    Screened Poisson reconstruction of the oriented points, lightly
    smoothed, the surface kept within :data:`TRIM_SPACINGS` point spacings
    of a point, its largest piece, less the faces along its rim that turn
    away from +z. ``source`` names the cornea file in errors.

    Raises
    ------
    InputError
        If the normals do not all lie within 90° of the frame's z (the
        cornea is then no height field), or the surface comes out other
        than one sheet with one rim.
    """
    points, normals = np.asarray(points, float), np.asarray(normals, float)
    if (normals[:, 2] <= 0.0).any():
        raise InputError(source, "ax, ay, az", "the cornea's normals span more than a hemisphere: it is no height "
                         "field, which the facet lattice needs")
    spacing = float(np.median(cKDTree(points).query(points, k=2)[0][:, 1]))
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points, v_normals_matrix=normals))
    # One thread: the octree's sums then run in one order, and the surface comes out the same every run.
    ms.generate_surface_reconstruction_screened_poisson(depth=POISSON_DEPTH, preclean=True, threads=1)
    # A few steps of Laplacian smoothing take out the folds of a cell or two Poisson leaves in places.
    ms.apply_coord_laplacian_smoothing(stepsmoothnum=SMOOTHING_STEPS)
    mesh = ms.current_mesh()
    vertices, faces = mesh.vertex_matrix(), mesh.face_matrix().astype(np.int64)
    near = cKDTree(points).query(vertices)[0] <= TRIM_SPACINGS * spacing
    faces = faces[near[faces].all(1)]
    _, piece = igl.facet_components(faces)
    faces = faces[piece == np.bincount(piece).argmax()]
    # Where the cornea curls over at its rim, faces turn away from +z: peel them off, ring by ring.
    for _ in range(PEEL_RINGS):
        corner = vertices[faces]
        down = np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])[:, 2] <= 0.0
        rim = np.zeros(len(vertices), bool)
        rim[np.concatenate(igl.boundary_loop_all(faces))] = True
        if not (down & rim[faces].any(1)).any():
            break
        faces = faces[~(down & rim[faces].any(1))]
    used, index = np.unique(faces, return_inverse=True)
    vertices, faces = vertices[used], index.reshape(-1, 3)
    loops = igl.boundary_loop_all(faces)
    if len(loops) != 1 or not igl.is_edge_manifold(faces)[0]:
        raise InputError(source, "x, y, z", f"the cornea's surface came out with {len(loops)} rims; it must be "
                         "one sheet (are the points one eye's, sampled evenly?)")
    return vertices, faces


def measured_normals(points, normals, at):
    """The cornea's measured normals carried to the points ``at`` (all in one frame): unit vectors (n, 3).

    Each is the mean of the :data:`NORMAL_NEIGHBOURS` nearest measured
    normals, weighted by inverse distance. The receptors' axes are the
    measured normals so, not the reconstructed surface's, whose smoothing
    turns its rim inwards by several degrees and shrinks the eye's field.
    """
    distance, nearest = cKDTree(points).query(at, k=NORMAL_NEIGHBOURS)
    weight = 1.0 / np.maximum(distance, 1e-12)
    out = np.einsum("nk,nkd->nd", weight, np.asarray(normals, float)[nearest])
    return out / np.linalg.norm(out, axis=1, keepdims=True)
