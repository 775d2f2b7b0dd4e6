"""The command-line tool ``beeoptics``: the workflow's stages one at a time, outside Snakemake.

Options the workflow's config also has default to ``beeoptics/io/schemas/config.schema.yaml``
and are checked against it, so a one-off run equals a workflow run with the default
config. Bad input ends a run with one line naming the file and the field, exit status
2, and the output folder as it was. The stages, and the libraries they need (Open3D,
pymeshlab, libigl, colour-science), are imported by the command that runs them, so that
``--help`` and ``--version`` answer at once.
"""

import argparse
import inspect
import os
import shutil
import sys
import tempfile
from contextlib import contextmanager
from functools import reduce
from pathlib import Path

import numpy as np
from tqdm import tqdm

from beeoptics import __version__
from beeoptics.eye.receptors import FORMATS, read_receptor_file, receptor_format
from beeoptics.headframe import SIDES, eye_azimuth_elevation
from beeoptics.io.atomic import Terminated, raise_stop, sigterm_as_interrupt, stop_behind
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import MEASURES, read_receptors, rows_of, write_receptors
from beeoptics.io.validation import (CONFIG_SCHEMA, check_background, config_default, load_yaml, validate,
                                     validate_config)
from beeoptics.pipeline.outputs import (COLOUR_FIGURES, FACET_OUTPUTS, FIELD_MAPS, IMAGES, VIEWER, colour_figures,
                                        retinal_images)

#: Options that set a key of the workflow's config: option, dotted key, type, help (units included).
GRID = [
    ("--start-nm", "spectral.start_nm", float, "first wavelength of the spectral grid, nm"),
    ("--end-nm", "spectral.end_nm", float, "last wavelength of the spectral grid, nm"),
    ("--step-nm", "spectral.step_nm", float, "spacing of the spectral grid, nm"),
]
SETTINGS = {
    "build-eye": [
        ("--edge-fraction", "eye.edge_fraction", float,
         "remeshing edge length, as a fraction of the mean facet diameter of the eye's anchors"),
        ("--tolerance-um", "eye.tolerance_um", float, "relax the facets until none would move further than this, µm"),
        ("--delta-rho-model", "eye.delta_rho.model", str, "acceptance angle Δρ: 'species' (the eye's own, its "
         "eye.yaml's optics.delta_rho: measured values, Snyder's model or a published multiple of Δφ; "
         "--delta-rho-deg where it names none), 'fixed' (--delta-rho-deg everywhere) or 'snyder' (from each "
         "facet's diameter and the eye's rhabdom width)"),
        ("--delta-rho-deg", "eye.delta_rho.fixed_deg", float,
         "Δρ of the fixed model, and of the measured one for eyes without measurements, degrees (full width "
         "at half maximum)"),
        ("--wavelength-nm", "eye.delta_rho.wavelength_nm", float,
         "wavelength of the snyder model's diffraction term, nm"),
    ],
    "render": [
        ("--samples", "trace.samples_per_receptor", int, "rays per receptor, drawn from its acceptance cone, at most "
         "65,536 (where the noise is well below the measured reflectances' spread; see the config schema)"),
        ("--precision", "trace.precision.target", lambda text: None if text == "fixed" else text,
         "the precision asked of each receptor's catches: a number (0.03: a relative standard error of 3 %%), "
         "'auto' (a quarter of a just-noticeable difference in the receptor set's colour and achromatic "
         "distances, where it gives their receptor noise) or 'fixed' (--samples each)"),
        ("--max-samples", "trace.precision.max_samples", int, "the most samples a receptor takes to reach --precision"),
        ("--depth", "trace.depth", int, "scattering events per path; 1 is direct light only"),
        ("--seed", "trace.seed", int, "random seed: the same seed and options give identical files"),
        ("--batch-rays", "trace.batch_rays", int, "rays one thread traces at once; bounds memory (about 600 "
         "bytes a ray, times --threads)"),
        *GRID,
        ("--background", "colour.background", str, "von Kries adapting background: 'scene' (the mean over the "
         "receptors of each one's catch over its acceptance solid angle) or a material of the scene (a Lambertian "
         "surface under its sky and sun)"),
        ("--sensitivities", "colour.sensitivities", str, "receptor curves: 'species' (the receptor set's own: "
         "measured where measured, for the honey bee Peitsch et al. 1992), 'template' (the A1 template at the set's "
         "λmax) or a CSV in pavo's layout with a column per receptor class of the set (UV, B, G for a bee)"),
        ("--width-px", "images.width_px", int, "width of each eye's panel in the retinal images, pixels"),
        ("--field-width-px", "images.visual_field_width_px", int,
         "width of the visual-field map (with --figures), pixels; its height is half of it"),
    ],
    "daylight": GRID,
}
#: The formats in words, for the help: ".csv, .eye, .ply, .gltf or .glb".
FORMAT_LIST = f"{', '.join(list(FORMATS)[:-1])} or {list(FORMATS)[-1]}"


def settings(args):
    """The config the options give, checked against the schema; an error names the option."""
    config = {}
    for option, key, _, _ in SETTINGS[args.command]:
        *parents, leaf = key.split(".")
        reduce(lambda node, part: node.setdefault(part, {}), parents, config)[leaf] = \
            getattr(args, option[2:].replace("-", "_"))
    try:
        return validate_config(config, CONFIG_SCHEMA, source="command line", folders=False)
    except InputError as e:
        option = next((o for o, k, *_ in SETTINGS[args.command] if k == e.field), e.field)
        raise InputError("command line", option, str(e).removeprefix(f"{e.path}: {e.field}: ")) from None


#: Scratch folders of a run in its output folder: ``.partial-<pid>-<random>``.
SCRATCH_PREFIX = ".partial-"


@contextmanager
def staged(outdir, names):
    """A scratch folder inside ``outdir`` whose files ``names`` move into it only if the block succeeds.

    Each stage writes its files atomically, but a run failing half-way would
    still leave some files beside older ones; this leaves ``outdir`` as it
    was. A run killed outright (SIGKILL, a lost node) cannot clean up after
    itself: the next command writing to the same folder removes the scratch
    folders whose process is gone.
    """
    outdir = Path(outdir)
    created = not outdir.exists()
    try:
        outdir.mkdir(parents=True, exist_ok=True)
        for old in outdir.glob(f"{SCRATCH_PREFIX}*"):
            pid = old.name.removeprefix(SCRATCH_PREFIX).split("-")[0]
            if pid.isdigit() and not _running(int(pid)):
                shutil.rmtree(old, ignore_errors=True)
        scratch = Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-", dir=outdir))
    except OSError as e:
        raise InputError(outdir, "", f"cannot write there ({e.strerror})") from None
    try:
        yield scratch
        raise_stop()
        for name in names:
            os.replace(scratch / name, outdir / name)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
        if created and not any(outdir.iterdir()):
            outdir.rmdir()


def _running(pid):
    """Whether a process of this id is alive (or belongs to another user)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _meadow_made(scene_file):
    """Generate the scene's meadow first if it places one not yet generated (a fresh clone's), saying so."""
    from beeoptics.pipeline.world import missing_meadow

    missing_meadow(scene_file, starting=lambda mesh: print(f"beeoptics: generating {mesh} from the meadow file "
                                                           "beside it, once", file=sys.stderr))


def _bar(args, desc, unit, total=None):
    # The delay keeps quick runs, and input refused before the work starts, free of bars.
    return tqdm(desc=desc, unit=unit, total=total, delay=0.5, disable=args.quiet, file=sys.stderr,
                dynamic_ncols=True)


def settled(first_mm, largest_mm, tolerance_mm):
    """How far a relaxation has come, in percent: from its first move down to the tolerance, on a log scale."""
    if largest_mm <= tolerance_mm or first_mm <= tolerance_mm:
        return 100
    return int(np.clip(100.0 * np.log(first_mm / largest_mm) / np.log(first_mm / tolerance_mm), 0.0, 99.0))


def build_eye(args):
    """Remesh an eye, place and relax its facets, and describe every receptor of both eyes."""
    from beeoptics.eye.optics import AcceptanceModel
    from beeoptics.io import interchange
    from beeoptics.pipeline.eyes import build_facets, remesh_eye

    eye = settings(args)["eye"]
    names = ["remeshed.ply", *FACET_OUTPUTS.values()] + ["receptors.ply"] * args.ply
    with staged(args.output, names) as tmp:
        remesh_eye(args.eye, {"remeshed": tmp / "remeshed.ply"}, edge_fraction=eye["edge_fraction"])
        with _bar(args, "relaxing facets", "%", total=100) as bar:
            first = []

            def progress(iteration, largest_mm):
                # The iterations needed are not known in advance; the largest move falls, roughly
                # geometrically, from the first towards the tolerance: show how far it has come. It rises
                # again now and then (when the springs are first measured along the surface, and in the
                # dynamics' own overshoots); the bar holds its furthest point rather than go back.
                first[:] = first or [largest_mm]
                bar.set_postfix_str(f"iteration {iteration + 1}, largest move {largest_mm * 1e3:.3g} µm "
                                    f"(stops below {eye['tolerance_um']:g})", refresh=False)
                bar.update(max(settled(first[0], largest_mm, eye["tolerance_um"] * 1e-3) - bar.n, 0))
            build_facets(args.eye, tmp / "remeshed.ply", {k: tmp / name for k, name in FACET_OUTPUTS.items()},
                         tolerance_um=eye["tolerance_um"], acceptance=AcceptanceModel.from_config(eye["delta_rho"]),
                         progress=progress, as_given=args.as_given)
        table = read_receptors(tmp / "receptors.csv")
        if args.ply:
            interchange.write_receptor_ply(tmp / "receptors.ply", table)
    print(f"{args.output}: {len(table.id) // 2} facets per eye; wrote {', '.join(names)}")


def render(args):
    """Trace an eye's receptors through a scene, gather their responses and draw the retinal images.

    Receptors without an eye file (imported from a CompoundRay eye, say) get
    no retinal images, which need the eye's placement on the head. Receptors
    in another format than a receptor table (a CompoundRay .eye, a .ply, an
    OCES glTF) are read as convert reads them, and the table their ids refer
    to is written beside the responses (receptors.csv).
    """
    from beeoptics.eye.description import check_receptors_of, load_eye
    from beeoptics.pipeline import images
    from beeoptics.pipeline.trace import gather_responses, trace_part
    from beeoptics.vision.receptorset import DEFAULT_SET, load_receptor_set, receptor_set_of

    config = settings(args)
    spectral, background = config["spectral"], config["colour"]["background"]
    # Refused now rather than after a trace of minutes.
    if args.eye is not None:
        check_receptors_of(load_eye(args.eye), args.receptors, read_receptors(args.receptors))
    receptor_set = (receptor_set_of(args.eye) if args.eye is not None and args.receptors_set is None else
                    load_receptor_set(args.receptors_set or DEFAULT_SET, source="command line",
                                      field="--receptor-set"))
    check_background(args.scene, background, args.scene, "materials")
    table = None if receptor_format(args.receptors) == ".csv" else _read_receptors(args.receptors, args)
    _meadow_made(args.scene)
    retinal = retinal_images(receptor_set) if args.eye is not None else {}
    spaces = colour_figures(receptor_set) if args.figures else {}
    figures = {**FIELD_MAPS, **spaces, **VIEWER} if args.figures else {}
    # As the workflow titles them: the eye class (its folder) in the scene (its folder).
    who = Path(args.eye).resolve().parent.name if args.eye else Path(args.receptors).stem
    title = f"{who} in {Path(args.scene).resolve().parent.name}"
    names = ["responses.csv", "irradiance.npz", *retinal.values(), *figures.values()]
    names += ["receptors.csv"] * (table is not None)
    with staged(args.output, names) as tmp:
        receptors = args.receptors
        if table is not None:
            receptors = tmp / "receptors.csv"
            write_receptors(receptors, table)
        with _bar(args, "tracing", " receptors") as bar:
            def progress(done, total):
                bar.total = total
                bar.update(done - bar.n)
            curves = config["colour"]["sensitivities"]
            trace_part(receptors, args.scene, {"radiance": tmp / "radiance.npz"}, spectral=spectral,
                       trace=config["trace"], threads=args.threads,
                       receptor_set=receptor_set,
                       progress=progress, receptor_curves=curves)
        gather_responses(receptors, args.scene, [tmp / "radiance.npz"],
                         {"responses": tmp / "responses.csv", "irradiance": tmp / "irradiance.npz"},
                         spectral=spectral, receptor_set=receptor_set, background=background, receptor_curves=curves)
        if args.eye is not None:
            images.retinal_images(args.eye, receptors, tmp / "responses.csv", tmp / "irradiance.npz",
                                  {key: tmp / name for key, name in retinal.items()}, receptor_set=receptor_set,
                                  width_px=config["images"]["width_px"], title=title)
        if args.figures:
            images.visual_field_maps(receptors, tmp / "responses.csv", tmp / "irradiance.npz", None,
                                     {key: tmp / name for key, name in FIELD_MAPS.items()}, receptor_set=receptor_set,
                                     width_px=config["images"]["visual_field_width_px"])
            images.colour_figures(tmp / "responses.csv", tmp / "irradiance.npz",
                                  {key: tmp / name for key, name in spaces.items()}, receptor_set=receptor_set,
                                  title=title, receptor_curves=curves)
            images.viewer(receptors, tmp / "responses.csv", tmp / "irradiance.npz",
                          {key: tmp / name for key, name in VIEWER.items()}, receptor_set=receptor_set, title=title,
                          receptor_curves=curves)
    print(f"{args.output}: wrote {', '.join(names)}")


def _read_receptors(path, args):
    """Receptors in any format convert reads, in the conventions the options give (their dests are
    :func:`beeoptics.eye.receptors.read_receptor_file`'s keywords)."""
    keywords = list(inspect.signature(read_receptor_file).parameters)[1:]  # after the path
    return read_receptor_file(path, **{k: v for k, v in vars(args).items() if k in keywords})


def daylight(args):
    """Write clear-sky daylight (SPECTRL2, Bird & Riordan 1986) or a scene's light in pavo's layout.

    Columns: wl (nm), then the global, direct and diffuse spectral irradiance
    on an unshaded horizontal surface, W m⁻² nm⁻¹, for pavo's or
    micaToolbox's illuminant.
    """
    from beeoptics.api import load_scene
    from beeoptics.light.materials import ground_albedo
    from beeoptics.sky.daylight import clear_sky, write_daylight
    from beeoptics.sky.dome import horizontal_irradiance
    from beeoptics.spectra import grid

    spectral = settings(args)["spectral"]
    wl = grid(**spectral)
    if args.scene:
        _meadow_made(args.scene)
        scene = load_scene(args.scene, **spectral).scene
        direct = horizontal_irradiance(None, scene.sun, len(wl))
        diffuse = horizontal_irradiance(scene.sky, None, len(wl))
    else:
        for option, value, low, high in (("--sun-elevation-deg", args.sun_elevation_deg, 0.0, 90.0),
                                         ("--turbidity", args.turbidity, 1.7, 10.0),
                                         ("--day-of-year", args.day_of_year, 1, 366)):
            if not low <= value <= high:
                raise InputError("command line", option, f"{value:g} is outside {low:g}–{high:g}")
        albedo = ground_albedo(args.ground, wl, "command line", "--ground")
        light = clear_sky(wl, args.sun_elevation_deg, args.turbidity, albedo, args.day_of_year)
        direct, diffuse = light.direct_horizontal, light.diffuse
    write_daylight(args.output, wl, direct, diffuse)
    print(f"{args.output}: {len(wl)} wavelengths, {wl[0]:g}–{wl[-1]:g} nm; global irradiance at 550 nm "
          f"{np.interp(550.0, wl, direct + diffuse):.3g} W m-2 nm-1")


def meadow(args):
    """Generate a meadow (grass, flowering plants, rough ground) as one coloured mesh.

    Prints the triangles of each species and the colour of every part, for
    the palette of the scene that places the mesh.
    """
    from beeoptics.world.meadow import read_meadow
    from beeoptics.world.species import species_table
    from beeoptics.pipeline.world import generate_meadow

    counts = generate_meadow(args.meadow_file, {"mesh": args.output, **({"flowers": args.flowers} if args.flowers
                                                                       else {})})
    print(f"{args.output}: {sum(counts.values())} triangles ({', '.join(f'{k} {v}' for k, v in counts.most_common())})")
    described = read_meadow(args.meadow_file)
    table = species_table(described["species"])
    print(f"palette: soil {described['ground']['colour']}, grass {described['grass']['colour']}")
    for name in dict.fromkeys(e["species"] for e in described["specimens"] + described["plants"]):
        print(f"palette: {name}: " + ", ".join(f"{part} {c}" for part, c in table[name]["colours"].items()))


def convert(args):
    """Convert a receptor table to another format, each chosen by the file's extension.

    What a format cannot hold is lost on the way: a CompoundRay .eye holds each
    receptor's position, axis and acceptance angle only, so converting receptors.csv
    to .eye and back drops facet_diameter_um, dorsal_rim and microvilli_deg, and the
    table read back measures Δφ afresh from the axes' neighbours (for the worker a
    median of 1.98° against the 2.49° of the table it came from). Keep
    receptors.csv beside the .eye to keep them.
    """
    from beeoptics.io import interchange, oces

    kind = receptor_format(args.output)
    table = _read_receptors(args.input, args)
    side = args.only
    if side is not None:
        # One eye only: a micro-CT file of both eyes is kept so, the other its mirror.
        table = rows_of(table, np.asarray(table.side).astype(str) == side)
        if not len(table.id):
            raise InputError(args.input, "side", f"holds no receptor of the {side} eye")
    try:
        if kind == ".csv":
            write_receptors(args.output, table)
        elif kind == ".ply":
            interchange.write_receptor_ply(args.output, table, quality=None if args.quality == "none" else args.quality)
        elif kind in (".gltf", ".glb"):
            oces.write_oces(args.output, table, name=Path(args.output).stem)
        else:
            focal = args.focal_offset_mm
            if focal is None:
                focal = 0.0 if table.focal_offset_mm is None else table.focal_offset_mm
            interchange.write_compoundray_eye(args.output, table, units=args.units, frame=args.frame or "camera",
                                              angle_convention=args.acceptance, focal_offset_mm=focal)
    except InputError:
        raise
    except ValueError as e:
        # The writers refuse what the table holds (a NaN, no receptor on a side): the input is at fault.
        raise InputError(args.input, "", str(e)) from None
    print(f"{args.output}: {len(table.id)} receptors")


def _readable(value):
    """A value of a YAML file as text: numbers as written, pairs as ranges, mappings as "key value" lists."""
    if isinstance(value, dict):
        return ", ".join(f"{k.replace('_', ' ')} {_readable(v)}" for k, v in value.items() if k != "source")
    if isinstance(value, (list, tuple)):
        if len(value) == 2 and all(isinstance(v, (int, float)) for v in value):
            return f"{value[0]:g} to {value[1]:g}"
        return "(" + ", ".join(_readable(v) for v in value) + ")"
    return f"{value:g}" if isinstance(value, float) else str(value)


def _stats(values):
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if not v.size:
        return "not given"
    return f"min {v.min():.4g}, median {np.median(v):.4g}, mean {v.mean():.4g}, max {v.max():.4g}"


def info(args):
    """Describe an eye.yaml, a scene.yaml, or a receptor table (.csv, .eye, .ply, .gltf or .glb)."""
    import igl

    from beeoptics.api import load_scene
    from beeoptics.eye.description import load_eye, load_eye_mesh

    path = Path(args.path)
    if path.suffix.lower() not in (".yaml", ".yml"):
        t = _read_receptors(path, args)
        side = np.asarray(t.side).astype(str)
        print(f"receptors: {len(side)} ({', '.join(f'{s} {np.sum(side == s)}' for s in SIDES)})")
        for label, column in (("facet diameter, µm", t.facet_diameter_um), ("Δφ, degrees", t.delta_phi_deg),
                              ("Δρ, degrees", t.delta_rho_deg)):
            print(f"{label}: {_stats(column)}")
        if t.dorsal_rim is not None:
            print(f"dorsal rim area: {int(np.sum(t.dorsal_rim))} receptors, microvilli at {_stats(t.microvilli_deg)}°")
        return
    data = load_yaml(path)
    if isinstance(data, dict) and {"mesh", "cornea", "placement", "facets", "facet_diameter"} & set(data):
        eye = load_eye(path)
        vertices, faces = load_eye_mesh(eye)
        doc = eye.document
        print(f"eye: {eye.name}" + "".join(f", {k} {doc[k]}" for k in ("species", "caste") if k in doc))
        print(f"facets per eye, published: {eye.facet_count}"
              + (f" ± {eye.facet_count_sd}" if eye.facet_count_sd is not None else ""))
        surface = f"{len(vertices)} vertices, {len(faces)} faces, {np.ptp(vertices, axis=0).max():.3g} mm across"
        azimuth, elevation = eye_azimuth_elevation(eye.rotation[2])
        measured = eye.cornea_path or eye.ommatidia_path
        if measured is not None:
            area = igl.doublearea(vertices, faces).sum() / 2
            what = "cornea" if eye.cornea_path is not None else "ommatidia"
            print(f"{what}: {measured}, measured; its surface {surface}, {area:.3g} mm²")
            print(f"placement: from the {what}, axis azimuth {azimuth:.1f}°, elevation {elevation:.1f}°, "
                  f"origin {_readable(eye.origin.round(4).tolist())} mm")
        else:
            p = doc["placement"]
            print(f"mesh: {eye.mesh_path}, {surface}")
            print(f"placement: axis azimuth {p['axis_azimuth_deg']}°, elevation {p['axis_elevation_deg']}°, "
                  f"roll {p['roll_deg']}°, origin {_readable(p['origin_mm'])} mm")
        print("axes: " + ("the measured ommatidia's (beeoptics.eye.given)" if eye.ommatidia_path is not None else
                          f"{eye.axis_model} (the measured field, beeoptics.eye.axismodel)" if eye.axis_model == "field"
                          else f"{eye.axis_model} (interpolated corneal normals)"))
        for a in eye.anchors:
            print(f"anchor {a['name']}: {a['diameter_um']} µm at azimuth {a['azimuth_deg']}°, "
                  f"elevation {a['elevation_deg']}°")
        for a in eye.delta_rho_anchors:
            print(f"measured Δρ {a['name']}: {a['delta_rho_deg']}° at azimuth {a['azimuth_deg']}°, "
                  f"elevation {a['elevation_deg']}°")
        if eye.dorsal_rim is not None:
            print(f"dorsal rim area: {eye.dorsal_rim['count']} facets")
        for section in ("shape", "optics", "published"):
            for key, value in doc.get(section, {}).items():
                if key not in ("source", "delta_rho_anchors"):
                    print(f"{section} {key.replace('_', ' ')}: {_readable(value) or 'compared'}")
        return
    _meadow_made(path)
    scene = load_scene(path).scene
    data = validate(data, "scene", path)
    light, head, cam = data["light"], data["eye"], scene.camera
    print(f"scene: {scene.name}")
    sun = f"sun at elevation {light['sun_elevation_deg']}°, azimuth {light['sun_azimuth_deg']}°"
    print(f"light: {light['sky']} sky, turbidity {light['turbidity']}, {sun if light['sun'] else 'no sun'}")
    print(f"eye: at {_readable(head['position_m'])} m, heading {head['heading_deg']}°, pitch {head['pitch_deg']}°, "
          f"roll {head['roll_deg']}°")
    print(f"camera: at {_readable(cam['position_m'])} m looking at {_readable(cam['look_at_m'])} m, "
          f"{cam['vertical_fov_deg']}° high, "
          f"{cam['width_px']} × {cam['height_px']} px" + ("" if "camera" in data else " (default: the bee's view)"))
    print(f"materials: {', '.join(scene.material_names)}")
    for o in scene.objects:
        ids = np.unique(o.face_material if o.texture is None else o.texture)
        print(f"object {o.name}: {len(o.faces)} triangles of {', '.join(scene.material_names[i] for i in ids)}")


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        # One line, as for every other bad input; the usage is one --help away.
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _positive_or(*words):
    def parse(text):
        try:
            value = text if text in words else float(text)
        except ValueError:
            value = float("nan")
        if not (value in words or np.isfinite(value) and value > 0):
            raise argparse.ArgumentTypeError(f"expected {''.join(w + ' or ' for w in words)}a positive number, "
                                             f"not {text!r}")
        return value
    return parse


_positive = _positive_or()


def _vector(text):
    try:
        value = [float(v) for v in text.split(",")]
    except ValueError:
        value = []
    if len(value) != 3 or not np.isfinite(value).all():
        raise argparse.ArgumentTypeError(f"expected three numbers x,y,z, not {text!r}")
    return value


def _sides(text):
    value = text.split(",")
    if len(value) != 2 or not set(value) <= set(SIDES):
        raise argparse.ArgumentTypeError(f"expected two eyes, {SIDES[0]} or {SIDES[1]}, as FIRST,SECOND, not {text!r}")
    return value


def _frame(text):
    from beeoptics.headframe import frame_axes

    try:
        frame_axes(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None
    return text


def _count(text):
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number of at least 1, not {text!r}")
    return value


def compile_kernels(args):
    """Compile every compiled kernel (the tracer's, the facet relaxation's) into numba's cache, as a toy eye
    and scene call them, so that no later run pays for compiling (beeoptics.pipeline.kernels). make runs it
    at set-up; a run without it compiles each kernel on its first call instead."""
    from beeoptics.pipeline.kernels import compile_kernels as compile_all

    compile_all()


def parser():
    """The parser of every subcommand; the config settings' defaults come from the schema."""
    top = _Parser(prog="beeoptics", description=__doc__.split("\n\n")[0].replace("``", ""))
    top.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND")
    eyefile = _Parser(add_help=False)
    g = eyefile.add_argument_group("CompoundRay .eye conventions (see beeoptics.io.interchange)")
    g.add_argument("--units", type=_positive_or("m", "mm"), default="mm",
                   help="lengths in the .eye file: mm (CompoundRay's eye specification), m, or file units per mm "
                        "(default: %(default)s)")
    g.add_argument("--frame", type=_frame,
                   help="camera: x right, y up, z forward of a camera looking where the bee faces (the head "
                        "frame's -y, z, x); head: head-frame coordinates unchanged; or x=…,y=…,z=… naming the "
                        "head direction (anterior, posterior, left, right, dorsal, ventral) of each of the file's "
                        "axes, as micro-CT eyes need (Taylor et al.'s: x=left,y=ventral,z=posterior) (default: "
                        "camera when writing; when reading, camera unless the eyes would then look backwards, "
                        "which is refused)")
    g.add_argument("--acceptance", choices=["fwhm", "variance"], default="fwhm",
                   help="the file's acceptance angle, radians, is Δρ (fwhm, CompoundRay's definition) or √2·Δρ "
                        "(variance: the same angular blur as the receptor's) (default: %(default)s)")
    g.add_argument("--side", choices=[*SIDES, "auto"],
                   help="reading a .eye: the eye it holds, or auto, the default, to find each receptor's eye by "
                        "the sign of its head-frame y")
    g.add_argument("--delta-phi-deg", type=float,
                   help="reading a .eye: Δφ of every receptor, degrees (default: measured from neighbouring axes)")
    g.add_argument("--facet-diameter-um", type=_positive_or("spacing"), help="reading a .eye: facet diameter of "
                   "every receptor, µm, or 'spacing', the mean distance to its neighbours (default: none, NaN)")
    quiet = dict(action="store_true", help="no progress bars (which go to stderr)")

    p = sub.add_parser("build-eye", help="build an eye's facets and receptors from its eye.yaml",
                       description=build_eye.__doc__)
    p.add_argument("eye", metavar="EYE_YAML", help="eye description, e.g. eyes/worker/eye.yaml")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR", type=Path,
                   help="folder for remeshed.ply, receptors.csv, quality.json and relaxation.npz")
    p.add_argument("--ply", action="store_true", help="also write receptors.ply, the receptors as a PLY point cloud")
    p.add_argument("--as-given", action="store_true", help="a measured cornea's eye: each of its points a receptor "
                   "with the file's acceptance angle, as CompoundRay renders it, instead of relaxed facets "
                   "(beeoptics.eye.given)")
    p.add_argument("--quiet", **quiet)
    p.set_defaults(run=build_eye)
    p = sub.add_parser("render", parents=[eyefile], help="trace an eye in a scene: responses and retinal images",
                       description=render.__doc__)
    p.add_argument("receptors", metavar="RECEPTORS", help="receptor table, as build-eye writes it, or receptors in "
                   f"another format convert reads ({FORMAT_LIST})")
    p.add_argument("scene", metavar="SCENE_YAML", help="scene description, e.g. scenes/meadow/scene.yaml")
    p.add_argument("--eye", metavar="EYE_YAML", help="the receptors' eye, for the retinal-plane images "
                   "(without it, only responses.csv and irradiance.npz are written) and its receptor set")
    p.add_argument("--receptor-set", dest="receptors_set", metavar="SET", help="the receptor classes to catch "
                   "light with: a set the package ships (apis_mellifera, bombus_terrestris, drosophila_melanogaster) "
                   "or a set file (default: the --eye's own, else apis_mellifera)")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR", type=Path, help="folder for responses.csv, "
                   "irradiance.npz and the images " + ", ".join(IMAGES.values()) + " and one channel image per "
                   "receptor class (channel_uv.png, ... for a bee)")
    p.add_argument("--figures", action="store_true", help="also write the visual field of both eyes ("
                   + ", ".join(FIELD_MAPS.values()) + ") and the colour-space figures the receptor set has ("
                   + ", ".join(COLOUR_FIGURES.values()) + " for a bee) and the interactive viewer ("
                   + ", ".join(VIEWER.values()) + ", one page that opens offline in a browser)")
    p.add_argument("--threads", type=_count, default=os.cpu_count(),
                   help="batches traced at once; the result is the same for any number (default: %(default)s, "
                   "the machine's cores)")
    p.add_argument("--quiet", **quiet)
    p.set_defaults(run=render)
    p = sub.add_parser("daylight", help="clear-sky daylight, or a scene's light, as irradiance in pavo's layout",
                       description=daylight.__doc__)
    p.add_argument("--sun-elevation-deg", type=float, default=45.0, help="the sun's elevation (default: %(default)s)")
    p.add_argument("--turbidity", type=float, default=3.0,
                   help="Preetham et al.'s turbidity, 1.7-10: 2 very clear, 3 clear, 6 hazy (default: %(default)s)")
    p.add_argument("--ground", default="grass", help="the ground under the sky, measured by Feister & Grewe (1995): "
                   "grass, lawn, loam, sand, snow, ... (default: %(default)s)")
    p.add_argument("--day-of-year", type=int, default=172, help="for the Earth-Sun distance (default: %(default)s)")
    p.add_argument("--scene", metavar="SCENE_YAML", help="instead, write this scene's sky and sun as they light an "
                   "unshaded horizontal surface (the options above are then the scene's)")
    p.add_argument("-o", "--output", required=True, metavar="CSV", type=Path,
                   help="wl, then global, direct and diffuse horizontal irradiance, W m-2 nm-1")
    p.set_defaults(run=daylight)
    for command, options in SETTINGS.items():
        for option, key, kind, text in options:
            sub.choices[command].add_argument(option, type=kind, default=config_default(key),
                                              help=f"{text} (default: %(default)s)")

    p = sub.add_parser("meadow", help="generate a meadow's mesh (and its flowers) from its meadow.yaml",
                       description=meadow.__doc__)
    p.add_argument("meadow_file", metavar="MEADOW_YAML", help="meadow description, e.g. scenes/meadow/meadow.yaml")
    p.add_argument("-o", "--output", required=True, metavar="PLY", type=Path,
                   help="the mesh to write (binary PLY with each part's colour on its faces' corners)")
    p.add_argument("--flowers", metavar="CSV", type=Path, help="also write the table of its flowers: species, "
                   "the sphere about each (x_m, y_m, z_m, radius_m) and the way it faces (facing_x, _y, _z)")
    p.set_defaults(run=meadow)
    p = sub.add_parser("convert", parents=[eyefile],
                       help=f"convert receptors from one format to another: {FORMAT_LIST}",
                       description=convert.__doc__)
    p.add_argument("input", metavar="IN", help="receptors.csv, a CompoundRay .eye, a receptor .ply or an OCES "
                   ".gltf or .glb")
    p.add_argument("output", metavar="OUT", help=f"the file to write: {FORMAT_LIST}")
    p.add_argument("--only", choices=SIDES, help="write only this eye's receptors (default: every receptor)")
    g = p.add_argument_group("tables of directions (see beeoptics.io.interchange)")
    g.add_argument("--directions", action="store_true", help="IN is a table of bare unit directions, x,y,z a line "
                   "and no header (strawlab's digitisation of Buchner's Drosophila map), in --frame")
    g.add_argument("--halves", type=_sides, metavar="FIRST,SECOND", help="the eyes of the file's first and second "
                   "halves, e.g. left,right (default: each direction's eye by the sign of its head-frame y)")
    g.add_argument("--sphere-mm", type=_positive, metavar="R", help="place the receptors on a sphere of this "
                   "radius, mm: position = centre + R · direction")
    g.add_argument("--centre-mm", type=_vector, metavar="X,Y,Z", help="the right eye's sphere centre, head frame, "
                   "mm (the left eye's is its mirror)")
    g.add_argument("--delta-rho-per-delta-phi", type=_positive, metavar="RATIO",
                   help="each receptor's Δρ, as a multiple of its Δφ measured from neighbouring axes")
    p.add_argument("--focal-offset-mm", type=float,
                   help="writing a .eye: focal point offset of every receptor, mm (default: the input's, else 0)")
    p.add_argument("--quality", choices=[*MEASURES, "none"], default="delta_phi_deg",
                   help="writing a .ply: the column MeshLab shows as vertex quality (default: %(default)s)")
    p.set_defaults(run=convert)
    p = sub.add_parser("info", parents=[eyefile], help=f"describe an eye, a scene or receptors ({FORMAT_LIST})",
                       description=info.__doc__)
    p.add_argument("path", metavar="PATH", help=f"eye.yaml, scene.yaml, or receptors: {FORMAT_LIST}")
    p.set_defaults(run=info)
    p = sub.add_parser("compile-kernels", help="compile the tracer's and the relaxation's kernels into numba's "
                       "cache (make does it at set-up)", description=compile_kernels.__doc__)
    p.set_defaults(run=compile_kernels)
    return top


def main(argv=None):
    """Run the tool on ``argv`` (default: the command line); return the exit status."""
    try:
        with sigterm_as_interrupt():
            args = parser().parse_args(argv)
            args.run(args)
    except SystemExit as e:  # --help, and argparse's own errors
        return e.code
    except InputError as e:
        print(f"beeoptics: error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped to a reader that stopped early (| head): stop quietly
        # Python's own advice: point stdout at devnull so that its flush at exit cannot fail again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as e:  # an unwritable output folder, a full disk
        # The file and the cause, without Python's "[Errno N]".
        where = f"{e.filename}: " if e.filename else ""
        print(f"beeoptics: error: {where}{e.strerror or e}", file=sys.stderr)
        return 1
    except (KeyboardInterrupt, ImportError) as e:  # Ctrl-C; SIGTERM (a scheduler's time limit, kill)
        stop = stop_behind(e)
        if stop is None:
            raise
        terminated = isinstance(stop, Terminated)
        print(f"beeoptics: {'terminated' if terminated else 'interrupted'}", file=sys.stderr)
        return Terminated.status if terminated else 130
    return 0


def entry():
    """The console command ``beeoptics``: :func:`main`, and after a stop, out without the interpreter's teardown.

    A Ctrl-C or SIGTERM can come while a trace batch runs in Embree's
    threads; the teardown then meets Open3D's objects still held, which its
    allocator reports as leaks on stderr and ends the process with status 1
    in place of the stop's. The partial outputs are removed by then.
    """
    status = main()
    if status in (130, Terminated.status):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    sys.exit(status)


if __name__ == "__main__":
    entry()
