"""Open3D's ray casting (Embree), shared by every stage that casts a ray.

The eye stage casts rays to project its first grid onto the cornea and to
test directions against the lattice of receptor axes; the light stage casts
every ray of its paths. All of them go through one Open3D
``RaycastingScene`` built here, and the time spent in its ray calls is
counted, in wall and in CPU seconds (:func:`embree_seconds`), so that a
benchmark can say what share of a trace Embree takes.
"""

import functools
import threading
import time

import numpy as np

_embree = {"seconds": 0.0, "cpu_seconds": 0.0, "lock": threading.Lock()}


def embree_seconds():
    """Wall seconds spent in Open3D's ray calls by all threads of the process so far, and the process's CPU
    seconds (on all its cores) during them: Embree's own, when no other thread of the process is working."""
    return _embree["seconds"], _embree["cpu_seconds"]


@functools.cache
def open3d():
    """Open3D, imported when a ray is first to be cast: jobs that only draw or tabulate never load it."""
    import open3d as o3d

    return o3d


def _timed(call, rays):
    start, cpu = time.perf_counter(), time.process_time()
    out = call(open3d().core.Tensor(rays))
    spent, cpu_spent = time.perf_counter() - start, time.process_time() - cpu
    with _embree["lock"]:
        _embree["seconds"] += spent
        _embree["cpu_seconds"] += cpu_spent
    return out


def embree_scene(meshes):
    """An Open3D ``RaycastingScene`` of triangle meshes; geometry ids follow their order.

    Parameters
    ----------
    meshes : iterable of (vertices, faces)
        Vertices (n, 3) and triangles (m, 3), in any float and integer type;
        Embree takes them in single precision.
    """
    o3d = open3d()
    scene = o3d.t.geometry.RaycastingScene()
    for vertices, faces in meshes:
        scene.add_triangles(o3d.core.Tensor(np.asarray(vertices).astype(np.float32)),
                            o3d.core.Tensor(np.asarray(faces).astype(np.uint32)))
    return scene


def first_hits(scene, rays):
    """``cast_rays`` on rays (n, 6), origin then direction, float32: Open3D's result as numpy arrays."""
    return {k: v.numpy() for k, v in _timed(scene.cast_rays, rays).items()}


def occluded(scene, rays):
    """``test_occlusions`` on rays (n, 6), float32: whether each meets any triangle."""
    return _timed(scene.test_occlusions, rays).numpy().astype(bool)


def cast_rate(scene, rays, count):
    """Rays per second of bare ``cast_rays`` on ``scene``: the batch ``rays`` (n, 6) cast until ``count`` rays,
    after one cast to warm Embree up (a benchmark's yardstick for the rays a trace cast)."""
    batch = open3d().core.Tensor(np.ascontiguousarray(rays, np.float32))
    scene.cast_rays(batch)
    start, cast = time.perf_counter(), 0
    while cast < count:
        scene.cast_rays(batch)["t_hit"].numpy()
        cast += len(rays)
    return cast / (time.perf_counter() - start)
