"""Checking a mesh file in Python, before any native library reads it.

pymeshlab and libigl trust a mesh's indices: a face that names a vertex past
the last one crashes them (a segmentation fault, a corrupted heap) or is
dropped without a word. So a mesh file is first read here in Python: PLY
with plyfile (every variant of the format: ASCII and binary, faces with
colours and other properties, as MeshLab writes them), OFF and STL with
meshio, glTF from its JSON and buffers, and OBJ line by line, and every
vertex and index is checked:
coordinates finite, indices within the vertices (and, in an OBJ, within
its texture coordinates and normals), no face repeating a vertex or of zero
area. A file that cannot be parsed (a binary PLY cut short, an OBJ face of
texture or normal indices only) is refused with the parser's message.
Faces and vertices are counted from 1, in the file's order. A PLY file is
read here whole, with its face or vertex colours and texture coordinates
(:func:`read_ply`), and no native library reads it after: pymeshlab's PLY
importer sees none of the files users bring.

MeshLab's OBJ reader and this one need not split a line alike (a vertex
line that starts with a tab is one MeshLab skips), so an OBJ is handed to
pymeshlab as the canonical text read here (:func:`canonical_obj`): one
statement a line, single spaces, the material library by its full path.

References
----------
Schlömer N (2022) meshio: I/O for mesh files. Zenodo, doi:10.5281/zenodo.1173115.
Dlugosz D (2024) plyfile: NumPy-based PLY format input and output for Python. github.com/dranjan/python-plyfile.
Turk G (1994) The PLY polygon file format. (The format as plyfile and MeshLab read it.)
Khronos Group (2021) glTF 2.0 Specification, version 2.0.1, §3.6 Geometry and §5.1 Accessors.
"""

import base64
import json
import struct
import warnings
from pathlib import Path

import numpy as np
import plyfile

from beeoptics.io.errors import InputError
from beeoptics.io.provenance import note

#: File suffixes meshio reads, and its name for each format.
MESHIO_FORMATS = {".off": "off", ".stl": "stl"}
#: Names writers give a PLY face's corner list, a vertex's texture coordinates, a face's corners' (MeshLab's).
PLY_CORNERS = ("vertex_indices", "vertex_index")
PLY_VERTEX_UV = (("s", "t"), ("u", "v"), ("texture_u", "texture_v"))
PLY_FACE_UV = "texcoord"
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
                       else _ply(_ply_data(path), path) if suffix == ".ply" else _meshio(path))
    return _checked(path, vertices, faces)


def _checked(path, vertices, faces):
    """The mesh, once every coordinate is finite and every face names three distinct vertices it has and
    has an area; else the error naming the first that does not."""
    if len(vertices) == 0 and len(faces) == 0:
        raise InputError(path, "", "cannot read mesh: it holds no vertices and no faces")
    bad = np.flatnonzero(~np.isfinite(vertices).all(1))
    if bad.size:
        raise InputError(path, f"vertex {bad[0] + 1}", "a coordinate is not a finite number")
    # Embree takes coordinates in single precision: beyond its range they would be infinite.
    huge = np.flatnonzero((np.abs(vertices) > np.finfo(np.float32).max).any(1))
    if huge.size:
        raise InputError(path, f"vertex {huge[0] + 1}", "a coordinate is beyond single precision's range (3.4e38)")
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


def read_ply(path):
    """Vertices, triangles, face colours, texture coordinates of a PLY file, every index and value checked.

    Returns
    -------
    vertices : ndarray (n, 3)
    faces : ndarray (m, 3)
    colours : ndarray (m, 3) in [0, 1], or None
        Each face's colour: its own (``red``, ``green``, ``blue`` of the
        face element, as MeshLab writes ``save_face_color``), or where the
        faces have none their corners' if every face's three corners agree.
    uv : ndarray (m, 3, 2), or None
        Each corner's texture coordinates: the face's ``texcoord`` list
        (MeshLab's per-wedge coordinates) or its vertices' ``s, t`` (or ``u, v``).

    Raises
    ------
    InputError
        As :func:`check_mesh_file` does.
    """
    path = Path(path)
    data = _ply_data(path)
    vertices, faces = _checked(path, *_ply(data, path))
    face, vertex = data["face"].data, data["vertex"].data
    colours = _ply_colours(face, path, "face")
    if colours is None:
        corners = _ply_colours(vertex, path, "vertex")
        if corners is not None and (corners[faces] == corners[faces][:, :1]).all():
            colours = corners[faces][:, 0]
    uv = None
    if PLY_FACE_UV in face.dtype.names:
        uv = _lists(face[PLY_FACE_UV], 6, path, PLY_FACE_UV, "texcoord lists hold six numbers, u and v of each corner")
        uv = uv.astype(float).reshape(-1, 3, 2)
    else:
        names = next((pair for pair in PLY_VERTEX_UV if set(pair) <= set(vertex.dtype.names)), None)
        if names is not None:
            uv = np.column_stack([vertex[n] for n in names]).astype(float)[faces]
    if uv is not None and not np.isfinite(uv).all():
        raise InputError(path, "texture coordinates", "a texture coordinate is not a finite number")
    return vertices, faces, colours, uv


def _ply_data(path):
    """plyfile's view of a PLY file of triangles; a file it cannot parse, or of other polygons, refused."""
    # Known list lengths let plyfile read the lists as fixed-width records (a million faces in
    # a fraction of a second) while it still checks every list's length.
    known = {"face": {**{name: 3 for name in PLY_CORNERS}, PLY_FACE_UV: 6}}
    try:
        with warnings.catch_warnings():
            # numpy's loadtxt warns of an ASCII element with no rows: the checks below refuse what matters.
            warnings.simplefilter("ignore", UserWarning)
            data = plyfile.PlyData.read(str(path), known_list_len=known)
    except plyfile.PlyElementParseError as e:
        if "unexpected list length" in str(e) and e.prop is not None and e.prop.name in PLY_CORNERS:
            raise InputError(path, f"face {e.row + 1}", "faces must be triangles; this one is not") from None
        raise InputError(path, "", f"cannot read mesh: {' '.join(str(e).split())}") from None
    except (plyfile.PlyParseError, ValueError, TypeError, IndexError, OverflowError, OSError) as e:
        raise InputError(path, "", f"cannot read mesh: {' '.join(str(e).split()) or type(e).__name__}") from None
    except MemoryError:
        # plyfile makes room for the elements the header declares before it reads them.
        raise InputError(path, "", "cannot read mesh: its header declares more elements than memory holds") from None
    for element in ("vertex", "face"):
        if element not in data:
            raise InputError(path, element, f"the file has no {element} element")
    return data


def _ply_colours(records, path, element):
    """The ``red, green, blue`` of a PLY element's records in [0, 1] (n, 3), or None; uchar values are 0–255."""
    if records.dtype.names is None or not {"red", "green", "blue"} <= set(records.dtype.names):
        return None
    rgb = np.column_stack([records[c] for c in ("red", "green", "blue")])
    scale = 255.0 if rgb.dtype.kind in "iu" else 1.0
    rgb = rgb.astype(float) / scale
    if not (np.isfinite(rgb).all() and (rgb >= 0.0).all() and (rgb <= 1.0).all()):
        raise InputError(path, f"{element} colours", "colours must lie in 0–255 (integers) or 0–1 (floats)")
    return rgb


def _ply(data, path):
    """Vertices and triangles of a PLY file's data (:func:`_ply_data`)."""
    vertex, face = data["vertex"].data, data["face"].data
    if not {"x", "y", "z"} <= set(vertex.dtype.names or ()):
        raise InputError(path, "vertex", "vertices need the properties x, y and z")
    corners = next((n for n in PLY_CORNERS if n in (face.dtype.names or ())), None)
    if corners is None:
        raise InputError(path, "face", f"faces need a corner list ({' or '.join(PLY_CORNERS)})")
    vertices = np.column_stack([vertex[c] for c in ("x", "y", "z")]).astype(float).reshape(-1, 3)
    faces = _lists(face[corners], 3, path, corners, "faces must be triangles; this one is not")
    if faces.dtype.kind not in "iu":
        raise InputError(path, "face", f"corner indices must be integers, not {faces.dtype}")
    return vertices, faces.astype(np.int64)


def _lists(values, width, path, name, refusal):
    """The PLY list property ``name`` of each face as an array (m, width); a face whose list is not ``width``
    long refused with ``refusal``."""
    if values.ndim != 2 and values.dtype != object:
        raise InputError(path, "face", f"{name} must be a list property")
    if values.dtype == object:
        # ASCII files: plyfile reads each face's list on its own (a binary file's, at a known length, at once).
        lengths = np.array([len(v) for v in values])
        if (lengths != width).any():
            raise InputError(path, f"face {np.argmax(lengths != width) + 1}", refusal)
        values = np.stack(values) if len(values) else np.zeros((0, width), np.int64)
    return np.asarray(values).reshape(-1, width)


def _meshio(path):
    kind = MESHIO_FORMATS.get(path.suffix.lower())
    if kind is None:
        raise InputError(path, "", f"unknown mesh format {path.suffix!r}; use "
                         + ", ".join([".obj", ".ply", *MESHIO_FORMATS, ".gltf", ".glb"]))
    import meshio  # imported where used: every stage imports this module, few read a mesh meshio reads (0.1 s)

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
            # MeshLab reads the rest of the line as one file name, which may hold spaces.
            library = path.parent.joinpath(" ".join(args)).resolve()
            note(library)
            if not library.is_file():
                raise InputError(path, f"line {number}", f"its material library {' '.join(args)} does not exist")
            args = [str(library)]
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
        materials = len(doc.get("materials", []))
        for m, mesh in enumerate(doc.get("meshes", [])):
            for k, primitive in enumerate(mesh["primitives"]):
                if primitive.get("mode", GLTF_TRIANGLES) != GLTF_TRIANGLES:
                    raise InputError(path, "faces", "faces must be triangles; a primitive is not")
                # Else pymeshlab gives its faces no colour, and a palette reports a colour it lacks.
                material = primitive.get("material")
                if material is not None and not (isinstance(material, int) and 0 <= material < materials):
                    raise InputError(path, f"meshes.{m}.primitives.{k}.material",
                                     f"material {material!r} does not exist (the file has {materials} materials)")
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
        note(path.parent / uri)
        if not (path.parent / uri).is_file():
            raise InputError(path, "buffers", f"its buffer {uri} does not exist")
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
