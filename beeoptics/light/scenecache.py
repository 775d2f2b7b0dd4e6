"""A cache of loaded scenes: their geometry and materials as arrays numpy memory-maps, and their light,
reused while the files that made them are unchanged.

Loading a generated meadow reads and checks a 40 MB PLY of a million faces
and looks up FReD's spectra, seconds each time a job starts. A loaded
scene's objects (vertices, faces, each face's or texel's material, texture
coordinates) and its materials on the spectral grid are therefore written,
once, as ``.npy`` files beside a ``manifest.json`` in a folder named by a
key: the SHA-256 of the package's version, the code and data that read and
make a scene (:data:`CODE`: every reader, schema and table, and this
module, so that a change to any starts new keys whatever the version
says), the scene's checked ``materials`` and ``objects`` sections, the spectral grid, the
contents of every file they name (meshes, textures, spectra) and the
versions of the packages whose data they read (dreye's FReD). The files
that made the scene are more than those it names: an OBJ's material
libraries (the colours its palette maps), a glTF's external buffers and the
images read with it, the package's own tables (Feister & Grewe's albedos).
Its readers name every file they read (:mod:`beeoptics.io.provenance`), and
the manifest keeps the SHA-256 of each the key does not hold. A later load
with the same key whose files are all as they were maps the arrays instead
of reading the files again (a stage that needs only the materials takes
them alone); one of them changed or gone, the scene is read from its files
again (and a file gone is then reported as missing) and the entry written
anew.

The light (sky and sun) is kept apart, since sweeps, flights and the
compass change it while the geometry stays: each light the scene's
``light`` section (with its overrides) makes on a grid is a ``.npz`` in
``lights/``, keyed likewise by that section, the grid and the files it
names, with the other files it read checked as a scene's are, so that a
stage need not compute the daylight again (SPECTRL2 through pvlib, measured
albedos resampled with colour-science: a second or two of imports and
arithmetic).

The cache lives in ``$BEEOPTICS_CACHE``, else ``$XDG_CACHE_HOME/beeoptics``,
else ``~/.cache/beeoptics``; a folder that cannot be written is simply not
used. An entry is written into a scratch folder and renamed into place, so
a reader never meets half of one, and is checked when read: a manifest
that does not parse, or an array whose file is missing or whose shape or
type is not the manifest's, is refused with a warning naming it, and the
scene is loaded from its files and the entry written again.
"""

import functools
import hashlib
import json
import logging
import os
import shutil
import tempfile
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from beeoptics import __version__

log = logging.getLogger("beeoptics")

#: The package's code and data that read and make a scene, the cache's own layout among them (its files, or
#: folders of files): their contents are part of every key.
CODE = ("io", "light", "sky", "spectra.py")
#: Packages whose installed data a scene's spectra may read.
DATA_PACKAGES = ("dreye",)
#: Entries kept: when one more is written, the least recently used beyond these are removed (scenes, lights).
MAX_ENTRIES = 16
MAX_LIGHTS = 256
#: The arrays of an object, and those of the materials, as the manifest names them.
OBJECT_ARRAYS = ("vertices", "faces", "face_material", "texture", "uv")
MATERIAL_ARRAYS = ("reflectance", "emission", "specular", "exponent", "roughness", "refractive_index")


def cache_root():
    """The cache's folder (see the module notes)."""
    if os.environ.get("BEEOPTICS_CACHE"):
        return Path(os.environ["BEEOPTICS_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "beeoptics"


def _named_files(data, base, sections=("objects", "materials")):
    """Every file the scene's ``sections`` name, relative to its folder, in order."""
    files = []

    def walk(value):
        if isinstance(value, dict):
            for k, v in value.items():
                if k in ("mesh", "image", "file") and isinstance(v, str):
                    files.append(base / v)
                else:
                    walk(v)
        elif isinstance(value, list):
            for v in value:
                walk(v)

    walk({k: data[k] for k in sections})
    return files


def scene_key(data, base, wavelengths, sections=("objects", "materials")):
    """The key of a checked scene's ``sections`` (its geometry and materials, or its light) on a spectral grid
    (see the module notes)."""
    h = hashlib.sha256()
    h.update(f"beeoptics {__version__} code {code_digest()} {' '.join(sections)}\n".encode())
    for name in DATA_PACKAGES:
        try:
            h.update(f"{name} {version(name)}\n".encode())
        except PackageNotFoundError:
            h.update(f"{name} absent\n".encode())
    h.update(json.dumps({k: data[k] for k in sections}, sort_keys=True, default=str).encode())
    h.update(np.ascontiguousarray(wavelengths, float).tobytes())
    for path in _named_files(data, base, sections):
        h.update(f"{path.name} {file_digest(path)}\n".encode())
    return h.hexdigest()


@functools.cache
def code_digest(package=Path(__file__).parents[1], names=CODE):
    """The SHA-256 of the files ``names`` (files or folders, by default :data:`CODE`) in ``package`` (their names
    in it and contents; compiled caches left out), once a process."""
    files = sorted(p for name in names for p in [package / name, *(package / name).rglob("*")]
                   if p.is_file() and "__pycache__" not in p.parts)
    return hashlib.sha256("".join(f"{p.relative_to(package)} {file_digest(p)}\n" for p in files).encode()).hexdigest()


def file_digest(path):
    """The SHA-256 of a file's contents (hex), or "missing" if it cannot be read."""
    h = hashlib.sha256()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 22), b""):
                h.update(block)
    except OSError:
        return "missing"
    return h.hexdigest()


def companions(data, base, read, sections=("objects", "materials")):
    """The files of ``read`` (every file loading the scene's ``sections`` read; :mod:`beeoptics.io.provenance`)
    that the key does not hash, each with its SHA-256: what an entry checks before it is used."""
    named = {p.absolute() for p in _named_files(data, base, sections)}
    return {str(p): file_digest(p) for p in read if p not in named}


def _changed(files):
    """The first of ``files`` (path: SHA-256) whose contents are no longer those, or None."""
    return next((path for path, digest in files.items() if file_digest(path) != digest), None)


def read(key):
    """The cached objects and materials of ``key``: (objects as dicts of arrays, materials dict), or None."""
    folder = cache_root() / key
    manifest = folder / "manifest.json"
    if not manifest.is_file():
        return None
    try:
        spec = json.loads(manifest.read_text())

        def array(entry):
            if entry is None:
                return None
            a = np.load(folder / entry["file"], mmap_mode="r", allow_pickle=False)
            if list(a.shape) != entry["shape"] or str(a.dtype) != entry["dtype"]:
                raise ValueError(f"{entry['file']} is {a.dtype}{list(a.shape)}, not {entry['dtype']}{entry['shape']}")
            return a

        changed = _changed(spec["companions"])
        if changed:
            log.info("scene cache %s was made with another %s: loading the scene from its files", folder, changed)
            return None
        objects = [{"name": o["name"], **{k: array(o["arrays"][k]) for k in OBJECT_ARRAYS}} for o in spec["objects"]]
        materials = {k: array(spec["materials"][k]) for k in MATERIAL_ARRAYS}
        os.utime(manifest)  # used: the last to be evicted
        return objects, {**materials, "names": spec["material_names"]}
    except (OSError, ValueError, KeyError, TypeError) as e:
        log.warning("scene cache %s is unreadable (%s): loading the scene from its files", folder, e)
        return None


def write(key, objects, materials, names, files):
    """Write a loaded scene's objects (SceneObjects) and materials (dict of arrays) as entry ``key``, with the
    files it was read from beyond the key (path: SHA-256, :func:`companions`); False if the cache's folder
    cannot be written."""
    root = cache_root()
    try:
        root.mkdir(parents=True, exist_ok=True)
        scratch = Path(tempfile.mkdtemp(prefix=f".{key[:12]}-", dir=root))
    except OSError:
        return False
    try:
        def put(name, value):
            if value is None:
                return None
            value = np.ascontiguousarray(value)
            np.save(scratch / f"{name}.npy", value, allow_pickle=False)
            return {"file": f"{name}.npy", "shape": list(value.shape), "dtype": str(value.dtype)}

        spec = {"key": key, "companions": files, "material_names": list(names),
                "materials": {k: put(k, materials[k]) for k in MATERIAL_ARRAYS},
                "objects": [{"name": o.name, "arrays": {k: put(f"object{i}_{k}", getattr(o, k)) for k in OBJECT_ARRAYS}}
                            for i, o in enumerate(objects)]}
        (scratch / "manifest.json").write_text(json.dumps(spec, indent=1))
        target = root / key
        if target.exists():
            shutil.rmtree(target, ignore_errors=True)
        os.replace(scratch, target)
        _evict(root)
        return True
    except OSError:
        shutil.rmtree(scratch, ignore_errors=True)
        return False


def _evict(root):
    """Remove the least recently used entries beyond :data:`MAX_ENTRIES`."""
    entries = sorted((p for p in root.iterdir() if (p / "manifest.json").is_file()),
                     key=lambda p: (p / "manifest.json").stat().st_mtime, reverse=True)
    for old in entries[MAX_ENTRIES:]:
        shutil.rmtree(old, ignore_errors=True)


def read_light(key):
    """The cached light of ``key``: a dict of its sky's and sun's fields (``sky_*``, ``sun_*``, each absent where
    the scene has none), or None."""
    path = cache_root() / "lights" / f"{key}.npz"
    try:
        with np.load(path, allow_pickle=False) as f:
            light = {k: f[k] for k in f.files}
        changed = _changed(dict(zip(light.pop("companion_paths").tolist(), light.pop("companion_digests").tolist())))
        if changed:
            log.info("cached light %s was made with another %s: computing the light", path, changed)
            return None
        os.utime(path)  # used: the last to be evicted
        return light
    except FileNotFoundError:
        return None
    except (OSError, ValueError, KeyError) as e:
        log.warning("cached light %s is unreadable (%s): computing the light", path, e)
        return None


def write_light(key, fields, files):
    """Write a light's fields (a dict of arrays, :func:`read_light`'s) as entry ``key``, with the files it was
    made from beyond the key (path: SHA-256, :func:`companions`); False if the cache's folder cannot be
    written."""
    folder = cache_root() / "lights"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, scratch = tempfile.mkstemp(prefix=f".{key[:12]}-", suffix=".npz", dir=folder)
    except OSError:
        return False
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **{k: np.asarray(v) for k, v in fields.items()},
                     companion_paths=np.array(list(files), str), companion_digests=np.array(list(files.values()), str))
        os.replace(scratch, folder / f"{key}.npz")
    except OSError:
        Path(scratch).unlink(missing_ok=True)
        return False
    old = sorted(folder.glob("*.npz"), key=lambda p: p.stat().st_mtime, reverse=True)[MAX_LIGHTS:]
    for path in old:
        path.unlink(missing_ok=True)
    return True
