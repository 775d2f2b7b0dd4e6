"""Checking a mesh file in Python, before any native library reads it.

pymeshlab and libigl trust a mesh's indices: a face that names a vertex past
the last one crashes them (a segmentation fault, a corrupted heap) or is
dropped without a word. So a mesh file is first read here with meshio
(PLY, OFF, STL; pure Python and numpy), for glTF from its JSON and buffers,
and for OBJ line by line, and every vertex and index is checked:
coordinates finite, indices within the vertices (and, in an OBJ, within
its texture coordinates and normals), no face repeating a vertex or of zero
area. A file that cannot be parsed (a binary PLY cut short, an OBJ face of
texture or normal indices only) is refused with the parser's message.
Faces and vertices are counted from 1, in the file's order.

MeshLab's OBJ reader and this one need not split a line alike (a vertex
line that starts with a tab is one MeshLab skips), so an OBJ is handed to
pymeshlab as the canonical text read here (:func:`canonical_obj`): one
statement a line, single spaces, the material library by its full path.

References
----------
Schlömer N (2022) meshio: I/O for mesh files. Zenodo, doi:10.5281/zenodo.1173115.
Khronos Group (2021) glTF 2.0 Specification, version 2.0.1, §3.6 Geometry and §5.1 Accessors.
"""

import base64
import json
import struct
from pathlib import Path

import meshio
import numpy as np

from beeoptics.io.errors import InputError

#: File suffixes meshio reads, and its name for each format.
MESHIO_FORMATS = {".ply": "ply", ".off": "off", ".stl": "stl"}
#: glTF accessor component types of indices and positions: numpy type (glTF 2.0 §5.1.3).
GLTF_COMPONENTS = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
#: glTF primitive mode of triangles (glTF 2.0 §5.24.2), the default.
GLTF_TRIANGLES = 4


def check_mesh_file(path):
    """Vertices (n, 3) and triangles (m, 3) of a mesh file, every index and value checked.

    Raises
    ------
    InputError
        Naming the file and the vertex or face at fault: a file that cannot
        be parsed, no faces, faces that are not triangles, coordinates that
        are not finite, an index outside the vertices, a face repeating a
        vertex, a face of zero area.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    vertices, faces = (_gltf(path) if suffix in (".gltf", ".glb") else _obj(path)[:2] if suffix == ".obj"
                       else _meshio(path))
    if len(vertices) == 0 and len(faces) == 0:
        raise InputError(path, "", "cannot read mesh: it holds no vertices and no faces")
    bad = np.flatnonzero(~np.isfinite(vertices).all(1))
    if bad.size:
        raise InputError(path, f"vertex {bad[0] + 1}", "a coordinate is not a finite number")
    if len(faces) == 0:
        raise InputError(path, "faces", "the mesh has no faces")
    outside = np.flatnonzero(((faces < 0) | (faces >= len(vertices))).any(1))
    if outside.size:
        k = outside[0]
        index = faces[k][(faces[k] < 0) | (faces[k] >= len(vertices))][0]
        raise InputError(path, f"face {k + 1}", f"refers to vertex {index + 1}, but the mesh has "
                         f"{len(vertices)} vertices" + (" (relative indices are not read)" if index < 0 else ""))
    repeated = np.flatnonzero((faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 0] == faces[:, 2]))
    if repeated.size:
        raise InputError(path, f"face {repeated[0] + 1}", "names one vertex twice")
    corner = vertices[faces]
    with np.errstate(over="ignore", invalid="ignore"):  # coordinates near the float limit: an infinite area
        area = np.linalg.norm(np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0]), axis=1)
    flat = np.flatnonzero(area == 0.0)
    if flat.size:
        raise InputError(path, f"face {flat[0] + 1}", "has zero area: its corners lie on one line")
    return vertices, faces


def _meshio(path):
    kind = MESHIO_FORMATS.get(path.suffix.lower())
    if kind is None:
        raise InputError(path, "", f"unknown mesh format {path.suffix!r}; use "
                         + ", ".join([".obj", *MESHIO_FORMATS, ".gltf", ".glb"]))
    try:
        mesh = meshio.read(path, file_format=kind)
    except Exception as e:  # meshio raises what its parsers meet: ValueError, IndexError, its own ReadError
        raise InputError(path, "", f"cannot read mesh: {' '.join(str(e).split()) or type(e).__name__}") from None
    sides = sorted({c.data.shape[1] for c in mesh.cells if c.type not in ("vertex", "line")} - {3})
    if sides:
        raise InputError(path, "faces", f"faces must be triangles; found faces with {sides} sides")
    faces = [c.data for c in mesh.cells if c.type == "triangle"]
    return (np.asarray(mesh.points, float).reshape(-1, 3),
            np.concatenate(faces).astype(np.int64) if faces else np.zeros((0, 3), np.int64))


def _obj(path):
    """Vertices, triangles and the canonical statements of an OBJ file (Wavefront, as MeshLab reads it)."""
    try:
        text = path.read_text()
    except UnicodeDecodeError:
        raise InputError(path, "", "cannot read mesh: not a text file") from None
    counts = {"v": 0, "vt": 0, "vn": 0}
    vertices, faces, statements = [], [], []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        key, args = words[0], words[1:]
        try:
            if key in counts:
                values = [float(a) for a in args]
                if len(values) < (2 if key == "vt" else 3):
                    raise ValueError(f"{key} needs {2 if key == 'vt' else 3} numbers")
                if key == "v":
                    vertices.append(values[:3])
                counts[key] += 1
            elif key == "f":
                corners = [_obj_corner(a, counts) for a in args]
                if len(corners) != 3:
                    raise InputError(path, "faces", f"faces must be triangles; found faces with [{len(corners)}] sides")
                faces.append(corners)
        except InputError:
            raise
        except ValueError as e:
            raise InputError(path, f"line {number}", f"cannot read mesh: {e}") from None
        if key == "mtllib":
            args = [str(path.parent.joinpath(" ".join(args)).resolve())]
        statements.append(" ".join([key, *args]))
    return (np.asarray(vertices, float).reshape(-1, 3), np.asarray(faces, np.int64).reshape(-1, 3),
            "\n".join(statements) + "\n")


def _obj_corner(word, counts):
    """The 0-based vertex index of a face corner ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn``."""
    parts = word.split("/")
    if len(parts) > 3 or not parts[0]:
        raise ValueError(f"face corner {word!r} has no vertex index")
    for part, key in zip(parts, ("v", "vt", "vn")):
        if part and not 1 <= int(part) <= counts[key]:
            if key == "v":
                return int(part) - 1 if int(part) > 0 else int(part)  # named by check_mesh_file
            raise ValueError(f"face corner {word!r} names {key} {part}, but {counts[key]} came before it")
    return int(parts[0]) - 1


def canonical_obj(path):
    """The checked statements of an OBJ file, for pymeshlab to read (see the module notes)."""
    return _obj(Path(path))[2]


def _gltf(path):
    """Positions and triangles of every mesh primitive of a glTF file, in order."""
    try:
        doc, binary = _gltf_document(path)
        buffers = [_gltf_buffer(path, b, binary) for b in doc.get("buffers", [])]
        vertices, faces = [], []
        for mesh in doc.get("meshes", []):
            for primitive in mesh["primitives"]:
                if primitive.get("mode", GLTF_TRIANGLES) != GLTF_TRIANGLES:
                    raise InputError(path, "faces", "faces must be triangles; a primitive is not")
                position = _accessor(doc, buffers, primitive["attributes"]["POSITION"]).reshape(-1, 3)
                index = (_accessor(doc, buffers, primitive["indices"]) if "indices" in primitive
                         else np.arange(len(position)))
                if len(index) % 3:
                    raise InputError(path, "faces", "faces must be triangles; an index list is not")
                offset = sum(len(v) for v in vertices)
                vertices.append(position.astype(float))
                faces.append(index.astype(np.int64).reshape(-1, 3) + offset)
    except (KeyError, IndexError, TypeError, ValueError, struct.error) as e:
        if isinstance(e, InputError):
            raise
        raise InputError(path, "", f"cannot read mesh: not a glTF file this reads ({type(e).__name__}: {e})") \
            from None
    return (np.concatenate(vertices) if vertices else np.zeros((0, 3)),
            np.concatenate(faces) if faces else np.zeros((0, 3), np.int64))


def _gltf_document(path):
    """The JSON of a .gltf or .glb file, and a .glb's binary chunk (glTF 2.0 §4.4)."""
    data = path.read_bytes()
    if path.suffix.lower() == ".gltf":
        return json.loads(data), None
    magic, _, length = struct.unpack_from("<4sII", data)
    if magic != b"glTF" or length > len(data):
        raise ValueError("not a binary glTF, or cut short")
    chunks, at = {}, 12
    while at < length:
        size, kind = struct.unpack_from("<I4s", data, at)
        if at + 8 + size > length:
            raise ValueError("a chunk runs past the end of the file")
        chunks[kind] = data[at + 8:at + 8 + size]
        at += 8 + size
    return json.loads(chunks[b"JSON"]), chunks.get(b"BIN\x00")


def _gltf_buffer(path, buffer, binary):
    uri = buffer.get("uri")
    if uri is None:
        data = binary
    elif uri.startswith("data:"):
        data = base64.b64decode(uri.split(",", 1)[1])
    else:
        data = (path.parent / uri).read_bytes()
    if data is None or len(data) < buffer["byteLength"]:
        raise ValueError("a buffer is shorter than its byteLength")
    return data


def _accessor(doc, buffers, index):
    """The values of a glTF accessor, flattened."""
    accessor = doc["accessors"][index]
    view = doc["bufferViews"][accessor["bufferView"]]
    kind = np.dtype(GLTF_COMPONENTS[accessor["componentType"]]).newbyteorder("<")
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[accessor["type"]]
    stride = view.get("byteStride") or width * kind.itemsize
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    count = accessor["count"]
    end = start + (count - 1) * stride + width * kind.itemsize if count else start
    data = buffers[view["buffer"]]
    if end > view.get("byteOffset", 0) + view["byteLength"] or end > len(data):
        raise ValueError("an accessor runs past the end of its buffer view")
    rows = np.ndarray((count, width), kind, data, start, (stride, kind.itemsize))
    return rows.ravel()
