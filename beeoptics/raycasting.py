"""Open3D's ray casting (Embree), shared by every stage that casts a ray.

The eye stage casts rays to project its first grid onto the cornea and to
test directions against the lattice of receptor axes; the light stage casts
every ray of its paths. All of them go through one Open3D
``RaycastingScene`` built here.
"""

import numpy as np
import open3d as o3d


def embree_scene(meshes):
    """An Open3D ``RaycastingScene`` of triangle meshes; geometry ids follow their order.

    Parameters
    ----------
    meshes : iterable of (vertices, faces)
        Vertices (n, 3) and triangles (m, 3), in any float and integer type;
        Embree takes them in single precision.
    """
    scene = o3d.t.geometry.RaycastingScene()
    for vertices, faces in meshes:
        scene.add_triangles(o3d.core.Tensor(np.asarray(vertices).astype(np.float32)),
                            o3d.core.Tensor(np.asarray(faces).astype(np.uint32)))
    return scene


def first_hits(scene, rays):
    """``cast_rays`` on rays (n, 6), origin then direction, float32: Open3D's result as numpy arrays."""
    out = scene.cast_rays(o3d.core.Tensor(rays))
    return {k: v.numpy() for k, v in out.items()}


def occluded(scene, rays):
    """``test_occlusions`` on rays (n, 6), float32: whether each meets any triangle."""
    return scene.test_occlusions(o3d.core.Tensor(rays)).numpy().astype(bool)
