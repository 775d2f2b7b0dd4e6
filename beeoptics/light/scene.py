"""Scenes: geometry, spectral materials and daylight, read from ``scenes/<name>/scene.yaml``.

The format is described in ``beeoptics/io/schemas/scene.schema.yaml`` and in
the README. In short: metres, world +z up, azimuths from +x towards +y;
``light`` sets the sky (``hosek_wilkie``, ``preetham``, ``uniform`` or
``none``) and the sun (elevation, azimuth, turbidity, the ground's albedo,
the day of the year; :mod:`beeoptics.sky.daylight`); ``eye`` places the bee's head (position,
heading, pitch); ``camera`` a pinhole for the human view; ``materials``
name spectral materials (:mod:`beeoptics.light.materials`); ``objects`` are
meshes (read with pymeshlab: PLY, OBJ, glTF, STL, OFF) or primitives, each
with one material, or a pattern: face colours mapped to materials by a
``palette`` (per face), or a texture image whose colours a palette maps
to materials (per texel).
"""

import difflib
import logging
from pathlib import Path
from typing import NamedTuple

import numpy as np
from scipy.spatial.transform import Rotation

from beeoptics.headframe import head_rotation
from beeoptics.io import provenance
from beeoptics.io.errors import InputError
from beeoptics.io.imagefile import read_image
from beeoptics.io.meshfile import read_mesh
from beeoptics.io.validation import load_yaml, validate
from beeoptics.light import scenecache
from beeoptics.light.materials import material, spectrum
from beeoptics.raycasting import embree_scene, first_hits, open3d
from beeoptics.sky.daylight import clear_sky
from beeoptics.sky.dome import CLEAR_SKIES, Sky, clear_sky_dome, luminance, uniform_sky
from beeoptics.sky.sun import Sun, sun_disc

log = logging.getLogger("beeoptics")
#: A bee's scene is metres across: a meadow patch of a few, a pond, a board of patches (the ground planes that
#: fill the horizon are primitives). A mesh larger than this, metres, or an eye placed farther from the origin,
#: is warned of as likely modelled in millimetres (a 4 m meadow in mm is 4 km; its eye 0.35 m up, 350 m up).
MILLIMETRES_HINT_M = 100.0


class SceneObject(NamedTuple):
    """A triangle mesh of the scene, in metres, and where its faces get their materials.

    ``face_material`` (m,) holds each face's material index, or is None for
    a textured object, whose ``texture`` (h, w) holds each texel's material
    index and ``uv`` (m, 3, 2) each face's corner texture coordinates.
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    face_material: np.ndarray
    texture: np.ndarray
    uv: np.ndarray


class Scene(NamedTuple):
    """A loaded scene: geometry, materials on the spectral grid, the light, the bee and the camera.

    ``reflectance`` and ``emission`` are (materials, wavelengths); ``specular``,
    ``exponent`` (materials,) each material's Phong lobe, ``roughness`` its
    coating's α (0 for none) and ``refractive_index`` the η of either; ``sky``
    and ``sun`` are None where the scene has none. ``eye_rotation`` has the
    head's axes as columns, in the world frame; ``extent`` is the diagonal of
    the scene's bounding box, m.
    """

    name: str
    path: Path
    objects: list
    material_names: list
    reflectance: np.ndarray
    emission: np.ndarray
    specular: np.ndarray
    exponent: np.ndarray
    roughness: np.ndarray
    refractive_index: np.ndarray
    sky: Sky | None
    sun: Sun | None
    eye_position: np.ndarray
    eye_rotation: np.ndarray
    camera: dict
    extent: float


def _hex(colours):
    """The distinct colours (k,) as "#rrggbb", and which of them each colour is (n,)."""
    rgb = np.rint(np.asarray(colours).reshape(-1, 3) * 255.0).astype(np.int64)
    distinct, which = np.unique((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2], return_inverse=True)
    return np.array([f"#{k:06x}" for k in distinct]), which.ravel()


def _unknown_material(name, names, source, field, user):
    """The error for a material the scene does not define, naming who asked for it, with a suggestion."""
    close = difflib.get_close_matches(name, names, n=1)
    return InputError(source, field, f"{user} asks for material {name!r}, which the scene does not define; "
                      + (f"did you mean {close[0]!r}?" if close else f"its materials: {', '.join(names)}"))


def _palette_ids(colours, palette, names, source, field, user):
    lookup = {k.lower(): v for k, v in palette.items()}
    for m in lookup.values():
        if m not in names:
            raise _unknown_material(m, names, source, field, user)
    hexes, which = _hex(colours)
    missing = sorted(set(hexes) - set(lookup))
    if missing:
        more = f" and {len(missing) - 5} more" if len(missing) > 5 else ""
        raise InputError(source, field, f"colours {', '.join(map(str, missing[:5]))}{more} are not in the palette")
    return np.array([names.index(lookup[h]) for h in hexes], dtype=np.int32)[which]


def _primitive(spec):
    (kind, args), = spec.items()
    if kind == "plane":
        h = args["size_m"] / 2.0
        v = np.array([[-h, -h, 0.0], [h, -h, 0.0], [h, h, 0.0], [-h, h, 0.0]])
        return v, np.array([[0, 1, 2], [0, 2, 3]])
    mesh = open3d().geometry.TriangleMesh.create_sphere(args["radius_m"], resolution=4 * 2 ** args["subdivisions"])
    return np.asarray(mesh.vertices), np.asarray(mesh.triangles)


def _object(spec, base, names, source, index):
    field = f"objects.{index}"
    if "mesh" in spec:
        v, f, colours, uv = read_mesh(base / spec["mesh"], patterns=True, source=source, field=f"{field}.mesh")
    else:
        (v, f), colours, uv = _primitive(spec["primitive"]), None, None
    rot = Rotation.from_euler("xyz", spec["rotate_deg"], degrees=True).as_matrix()
    v = (spec["scale"] * v) @ rot.T + np.asarray(spec["translate_m"])
    name = spec.get("name", f"object {index}")
    if "material" in spec:
        if spec["material"] not in names:
            raise _unknown_material(spec["material"], names, source, f"{field}.material", f"object {name!r}")
        return SceneObject(name, v, f, np.full(len(f), names.index(spec["material"]), np.int32), None, None)
    if "palette" in spec:
        if colours is None:
            raise InputError(base / spec.get("mesh", ""), "faces",
                             "a palette needs one colour per face (OBJ: a material per face; "
                             "glTF: a material per primitive)")
        return SceneObject(name, v, f, _palette_ids(colours, spec["palette"], names, source, f"{field}.palette",
                                                    f"object {name!r}"),
                           None, None)
    if "texture" in spec:
        if uv is None:
            raise InputError(base / spec.get("mesh", ""), "faces", "a texture needs texture coordinates in the mesh")
        pixels = read_image(base / spec["texture"]["image"])[0][:, :, :3]
        ids = _palette_ids(pixels.reshape(-1, 3), spec["texture"]["palette"], names, source,
                           f"{field}.texture.palette", f"object {name!r}")
        return SceneObject(name, v, f, None, ids.reshape(pixels.shape[:2]), uv)
    raise InputError(source, field, "an object needs a material, a palette or a texture")


def bee_camera(position, head, width_px=320, height_px=240):
    """The human view a scene gets by default: from the bee's head, looking where it looks, 60° high."""
    at = np.asarray(position, float) + head[:, 0]
    return {"position_m": [float(v) for v in position], "look_at_m": at.tolist(), "vertical_fov_deg": 60.0,
            "width_px": width_px, "height_px": height_px}


def _warn_of_millimetres(data, objects, path):
    """Warn, in one line naming the file and the field, of a scene whose sizes suggest millimetres
    (:data:`MILLIMETRES_HINT_M`): a mesh object larger, or the eye farther from the origin."""
    sizes = [(f"objects.{i}", float(np.ptp(o.vertices, axis=0).max()) if len(o.vertices) else 0.0)
             for i, (o, spec) in enumerate(zip(objects, data["objects"])) if "mesh" in spec]
    sizes.append(("eye.position_m", float(np.linalg.norm(data["eye"]["position_m"]))))
    field, size = max(sizes, key=lambda item: item[1])
    if size > MILLIMETRES_HINT_M:
        log.warning("%s: %s: %.4g m %s: is the scene modelled in millimetres? (a bee's scene is metres: beyond "
                    "%g m this warning is given; scale: 0.001 reads a mesh in mm)", path, field, size,
                    "from the origin" if field == "eye.position_m" else "across", MILLIMETRES_HINT_M)


def load_scene(path, wavelengths, light=None, eye=None, geometry=True, cache=True):
    """Read and check a scene file.

    Parameters
    ----------
    path : str or Path
    wavelengths : ndarray
        The spectral grid, nm.
    light : dict, optional
        Overrides for the scene's ``light`` section (for sweeps).
    eye : dict, optional
        Overrides for its ``eye`` section (a flight's frame).
    geometry : bool
        Read its objects; without them (for what needs only the light and
        the materials) the scene has none, and is not checked for light.
    cache : bool
        Take its objects and materials from the scene cache, or put them
        there (:mod:`beeoptics.light.scenecache`), when its files are as
        they were.
    """
    path = Path(path)
    data = load_yaml(path)
    if isinstance(data, dict) and light:
        data.setdefault("light", {}).update(light)
    if isinstance(data, dict) and eye:
        data.setdefault("eye", {}).update(eye)
    data = validate(data, "scene", path)
    base = path.parent
    wl = np.asarray(wavelengths, float)
    names = list(data["materials"])
    key = scenecache.scene_key(data, base, wl) if cache else None
    cached = scenecache.read(key) if key else None
    if cached is not None:
        objects = [SceneObject(**o) for o in cached[0]] if geometry else []
        mats = [{k: cached[1][k][i] for k in scenecache.MATERIAL_ARRAYS} for i in range(len(names))]
    else:
        with provenance.recording() as read:
            mats = [material(data["materials"][n], wl, base, path, n) for n in names]
            objects = [_object(o, base, names, path, i) for i, o in enumerate(data["objects"])] if geometry else []

    sky, sun = _light(data, wl, base, path, cache)
    # An emitting material lights the scene only if some object is made of it.
    used = set()
    for o in objects:
        for ids in (o.face_material, o.texture):
            if ids is not None:
                used.update(np.unique(ids).tolist())
    emitting = any(mats[i]["emission"].max() > 0 for i in used)
    lit = (sky is not None and sky.basis.max() > 0) or (sun is not None and sun.radiance.max() > 0)
    if geometry and not (lit or emitting):
        raise InputError(path, "light", "the scene has no light: no sky, no sun above the horizon, "
                         "no object of an emitting material")

    _warn_of_millimetres(data, objects, path)
    e = data["eye"]
    head = head_rotation(e["heading_deg"], e["pitch_deg"], e["roll_deg"])
    every = np.vstack([o.vertices for o in objects] + [np.zeros((1, 3))])
    n_wl = len(wl)
    if key and cached is None and geometry:
        scenecache.write(key, objects, {k: np.array([m[k] for m in mats]) for k in scenecache.MATERIAL_ARRAYS}, names,
                         scenecache.companions(data, base, read))
    return Scene(
        name=data["name"], path=path, objects=objects, material_names=names,
        reflectance=np.array([m["reflectance"] for m in mats]).reshape(-1, n_wl),
        emission=np.array([m["emission"] for m in mats]).reshape(-1, n_wl),
        specular=np.array([m["specular"] for m in mats]),
        exponent=np.array([m["exponent"] for m in mats]),
        roughness=np.array([m["roughness"] for m in mats]),
        refractive_index=np.array([m["refractive_index"] for m in mats]),
        sky=sky, sun=sun,
        eye_position=np.asarray(e["position_m"], float), eye_rotation=head,
        camera=data.get("camera") or bee_camera(data["eye"]["position_m"], head),
        extent=float(np.linalg.norm(np.ptp(every, axis=0))),
    )


def _light(data, wl, base, path, cache=True):
    """The sky and the sun (each None if absent) of a checked scene's ``light`` section, on the grid ``wl``:
    from the scene cache where it holds them (``cache``), else made and put there."""
    key = scenecache.scene_key(data, base, wl, ("light",)) if cache else None
    fields = scenecache.read_light(key) if key else None
    if fields is None:
        with provenance.recording() as read:
            sky, sun = _made_light(data["light"], wl, base, path)
        if key:
            scenecache.write_light(key, {f"{name}_{k}": v for name, part in (("sky", sky), ("sun", sun))
                                         if part is not None for k, v in part._asdict().items()},
                                   scenecache.companions(data, base, read, ("light",)))
        return sky, sun

    def stored(name, kind):
        if f"{name}_{kind._fields[0]}" not in fields:
            return None
        values = {k: fields[f"{name}_{k}"] for k in kind._fields}
        # Scalars come back as numpy's 0-d arrays: as Python's, as the light was made.
        return kind(**{k: v.item() if v.ndim == 0 else v for k, v in values.items()})

    return stored("sky", Sky), stored("sun", Sun)


def _made_light(lt, wl, base, path):
    """The sky and the sun (each None if absent) of a checked ``light`` section, on the grid ``wl``."""
    sky = None
    if lt["sky"] == "uniform":
        if "radiance" not in lt:
            raise InputError(path, "light.radiance", "a uniform sky needs a radiance spectrum")
        radiance = spectrum(lt["radiance"], wl, base, path, "light.radiance")
        if not np.isfinite(radiance).all() or radiance.min() < 0.0:
            raise InputError(path, "light.radiance", "a sky's radiance must be finite and non-negative")
        if "luminance_cd_m2" in lt:
            radiance = radiance * lt["luminance_cd_m2"] / luminance(wl, radiance)
        sky = uniform_sky(radiance, lt["hemisphere"])
    clear = lt["sky"] in CLEAR_SKIES
    if clear and lt["sun_elevation_deg"] <= 0.0:
        raise InputError(path, "light.sun_elevation_deg",
                         f"the {lt['sky']} sky is a daylight model: it needs the sun above the horizon")
    sun = None
    if lt["sun"] or clear:
        albedo = spectrum(lt["ground_albedo"], wl, base, path, "light.ground_albedo")
        if not np.isfinite(albedo).all() or albedo.min() < 0.0 or albedo.max() > 1.0:
            raise InputError(path, "light.ground_albedo", "an albedo must lie between 0 and 1")
        daylight = clear_sky(wl, lt["sun_elevation_deg"], lt["turbidity"], albedo, lt["day_of_year"])
        sun = sun_disc(daylight, lt["sun_azimuth_deg"])
    if clear:
        sky = clear_sky_dome(lt["sky"], daylight, sun.direction, lt["turbidity"], albedo, lt["polarisation"])
    if not lt["sun"]:
        sun = None
    return sky, sun


def posed(scene, eye):
    """``scene`` with the bee's head moved to ``eye``, a scene's ``eye`` section (``position_m``, and
    ``heading_deg``, ``pitch_deg``, ``roll_deg``, 0 unless given)."""
    return scene._replace(eye_position=np.asarray(eye["position_m"], float),
                          eye_rotation=head_rotation(eye.get("heading_deg", 0.0), eye.get("pitch_deg", 0.0),
                                                     eye.get("roll_deg", 0.0)))


def lit_by(path, light):
    """A scene file's contents, checked and its defaults filled in, with the overrides ``light`` of its
    ``light`` section."""
    data = load_yaml(path)
    data.setdefault("light", {}).update(light)
    return validate(data, "scene", path)


def relit(scene, wavelengths, light):
    """``scene`` under its scene file's light with the overrides ``light``: a new sky and sun, the
    same geometry and materials (no mesh or spectrum read again)."""
    data = lit_by(scene.path, light)
    sky, sun = _light(data, np.asarray(wavelengths, float), scene.path.parent, scene.path)
    return scene._replace(sky=sky, sun=sun)


def raycasting_scene(scene):
    """Open3D's Embree scene for the scene's objects; geometry ids follow their order."""
    return embree_scene((o.vertices, o.faces) for o in scene.objects)


def back_faces_met(rs, origins, axes):
    """Of receptors at ``origins`` (m) looking along ``axes`` in an Embree scene ``rs``, how many first meet
    a surface along the axis, and how many of those meet its back (its triangle's winding facing away).

    A receptor inside a closed mesh, or below a ground, meets only back faces;
    among two-sided open surfaces (blades, petals) about as many backs as
    fronts face a receptor at random, so nearly all backs says the eye is
    enclosed rather than among them.
    """
    hits = first_hits(rs, np.column_stack([origins, axes]).astype(np.float32))
    met = np.isfinite(hits["t_hit"])
    back = met & ((hits["primitive_normals"] * axes).sum(1) > 0.0)
    return int(met.sum()), int(back.sum())


def receptors_in_world(scene, positions_mm, axes):
    """Receptor positions (m) and axes in the scene, from the head frame (mm)."""
    r = scene.eye_rotation
    return positions_mm * 1e-3 @ r.T + scene.eye_position, axes @ r.T
