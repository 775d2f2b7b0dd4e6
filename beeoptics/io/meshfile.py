"""Reading triangle meshes, and refusing the ones that cannot be used.

Meshes are read with pymeshlab, which knows OBJ, STL, OFF and glTF
(``.gltf`` and ``.glb``), once every index and value of the file has been
checked in Python (:mod:`beeoptics.io.meshcheck`), since a bad index crashes
it; PLY files are read whole in Python (plyfile), colours and texture
coordinates included, and pymeshlab never sees them.
An eye or scene mesh must exist, hold faces, be made of triangles (a
polygon would be split along an arbitrary diagonal, so its shape would
depend on the reader) and be manifold along its edges.
"""

import tempfile
from pathlib import Path

import numpy as np

from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.meshcheck import canonical_obj, check_mesh_file, read_ply
from beeoptics.io.provenance import note


def read_mesh(path, patterns=False, source=None, field=""):
    """Vertices (n, 3) and triangles (m, 3) of a mesh file, checked.

    With ``patterns``, also the face colours (m, 3) in [0, 1] and the
    texture coordinates of each face's corners (m, 3, 2), either None
    where the file has none. A missing file is reported against ``source``
    and ``field``, the file and key that name the mesh, when given.

    Raises
    ------
    InputError
        If the file is missing or unreadable, empty, not all triangles,
        or not edge-manifold, or as :func:`~beeoptics.io.meshcheck.check_mesh_file`.
    """
    path = Path(path)
    note(path)
    if not path.is_file():
        raise InputError(source or path, field, f"no such mesh file {path}")
    if path.stat().st_size == 0:
        raise InputError(path, "faces", "the file is empty: the mesh has no faces")
    if path.suffix.lower() == ".ply":
        vertices, faces, colours, uv = read_ply(path)
        _check_manifold(path, faces)
        return (vertices, faces, colours, uv) if patterns else (vertices, faces)
    # Also refuses faces that are not triangles, in every format: pymeshlab's own
    # polygon list took a fifth of loading a meadow of a million triangles.
    check_mesh_file(path)
    # pymeshlab and libigl are imported where used: a stage that meets a scene through the scene cache
    # (beeoptics.light.scenecache) reads no mesh, and need not pay for them.
    import pymeshlab

    ms = pymeshlab.MeshSet()
    try:
        if path.suffix.lower() == ".obj":
            with tempfile.TemporaryDirectory() as folder:
                canonical = Path(folder) / path.name
                canonical.write_text(canonical_obj(path))
                ms.load_new_mesh(str(canonical))
        else:
            ms.load_new_mesh(str(path))
    except pymeshlab.PyMeshLabException as e:
        # pymeshlab's message spans several lines and repeats the path; keep one line.
        detail = " ".join(str(e).replace(str(path), path.name).split())
        raise InputError(path, "", f"cannot read mesh: {detail}") from None
    mesh = ms.current_mesh()
    # The images pymeshlab read for the mesh (a glTF's); one it did not find is named "dummy.png" and not read.
    # (It looks for an OBJ's map_Kd beside the canonical copy, so reads none: a face's colour is its Kd.)
    for name in mesh.textures():
        if (path.parent / name).is_file():
            note(path.parent / name)
    if mesh.face_number() == 0:
        raise InputError(path, "faces", "the mesh has no faces")
    vertices = mesh.vertex_matrix().astype(np.float64)
    faces = mesh.face_matrix().astype(np.int64)
    _check_manifold(path, faces)
    if not patterns:
        return vertices, faces
    uv = mesh.wedge_tex_coord_matrix().reshape(-1, 3, 2) if mesh.has_wedge_tex_coord() else None
    return vertices, faces, _face_colours(mesh, faces), uv


def _check_manifold(path, faces):
    import igl

    if not igl.is_edge_manifold(faces)[0]:
        raise InputError(path, "faces", "the mesh is not manifold: an edge is shared by more than two faces")


def _face_colours(mesh, faces):
    """Face colours (m, 3), or None.

    glTF has no face colours: pymeshlab puts a primitive's material colour
    (``baseColorFactor``) on the primitive's own vertices. A face whose three
    corners agree has that colour; if any face's corners differ, the mesh has
    no face colours.
    """
    if mesh.has_face_color():
        return mesh.face_color_matrix()[:, :3]
    if mesh.has_vertex_color():
        corners = mesh.vertex_color_matrix()[:, :3][faces]
        if (corners == corners[:, :1]).all():
            return corners[:, 0]
    return None


def write_mesh(path, vertices, faces, normals=None):
    """Write a triangle mesh as binary PLY, with vertex normals if given, atomically."""
    import igl

    extra = {} if normals is None else {"N": np.ascontiguousarray(normals, dtype=np.float64)}
    with atomic_path(path) as tmp:
        igl.writePLY(
            str(tmp),
            np.ascontiguousarray(vertices, dtype=np.float64),
            np.ascontiguousarray(faces, dtype=np.int64),
            **extra,
        )


def read_mesh_normals(path):
    """Vertices, faces and vertex normals of a mesh this package wrote."""
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    m = ms.current_mesh()
    return (
        m.vertex_matrix().astype(np.float64),
        m.face_matrix().astype(np.int64),
        m.vertex_normal_matrix().astype(np.float64),
    )
