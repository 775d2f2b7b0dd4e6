"""Receptor tables in other tools' formats: CompoundRay eye files and PLY point clouds.

CompoundRay ``.eye`` files
--------------------------
CompoundRay (Millward et al. 2022) renders the view of a compound eye with
NVIDIA OptiX. What follows was checked against its source,
github.com/BrainsOnBoard/compound-ray:

``data/eyes/eye-specification.txt``
    One ommatidium per line: position (x, y, z), axis direction (x, y, z),
    acceptance angle in radians, focal point offset, "all in millimeters".
``libEyeRenderer3/MulticamScene.cpp`` (``processGLTFNode``)
    Reads the file line by line, splits each line on single spaces (runs of
    spaces collapse; tabs and commas are not separators) and converts the
    first eight fields with ``std::stof``, i.e. to float32. There is no
    header and no comment syntax, and a blank line makes it index fields
    that are not there.
``libEyeRenderer3/cameras/CompoundEyeDataTypes.h``
    ``struct Ommatidium {float3 relativePosition; float3 relativeDirection;
    float acceptanceAngleRadians; float focalPointOffset;}``.
``libEyeRenderer3/shaders.cu`` (``__raygen__ommatidium``)
    ``standardDeviation = acceptanceAngleRadians / FWHM_SD_RATIO`` with
    ``FWHM_SD_RATIO`` = 2√(2 ln 2) = 2.3548…: the acceptance angle is the
    *full width at half maximum* of a Gaussian, neither a half-width nor σ
    (so too Millward et al. 2022, Fig. 3).
    Each sample ray is the axis tilted by a splay angle s ~ N(0, σ²) and
    then turned about the axis by an angle uniform in [0, π). The direction
    enters Rodrigues' rotation, which needs a unit axis, unnormalised, so
    directions must be unit vectors. Rays start ``focalPointOffset`` behind
    the position along the axis, with that offset as their tmin.
``MulticamScene.cpp`` and ``cameras/DataRecordCamera.h``
    Positions and directions are in the eye camera's local space: a point
    (x, y, z) is ``position + x·right + y·up + z·forward``, where right, up
    and forward are the glTF camera node's +x, +y and −z.

Units. ``data/eyes/eye-specification.txt`` gives every length "in
millimeters", and CompoundRay's eyes, its micro-CT honey-bee eyes among
them, are written so; files are therefore read and written in millimetres
by default. The renderer itself converts nothing (positions are added to
the camera position in the glTF scene's units, which glTF 2.0 defines as
metres), so ``units="m"``, or a number of file units per millimetre,
matches a scene built in other units. An eye read at a size bee eyes do
not have (:data:`beeoptics.headframe.EYE_SIZE_MM`) is refused: it is in
other units than those named.

Frame. With ``frame="camera"`` (the default) the eye file is in the frame
of a camera at the head origin looking anterior with dorsal up: right =
−y, up = +z, forward = +x of the head frame, so a file's (x, y, z)
is the head frame's (−y, z, x). A compound-eye camera posed like an ordinary
camera pointing where the bee faces then renders the bee's view, and the
right eye falls at +x and the left at −x of the file, the halves that
CompoundRay's ``spherical_split_orientationwise`` projection shows on the
right and on the left. ``frame="head"`` writes head-frame coordinates
unchanged; any other frame is named by the head direction of each of the
file's axes (:func:`beeoptics.headframe.frame_axes`), as micro-CT eyes need:
Taylor et al.'s (2019) are in the frame their scans were registered in
(x left, y ventral, z posterior), the camera frame turned through the head's
centre, so that read in the camera frame their eyes look backwards (the
mean axis 0.48–0.65 posterior, where the shipped eyes' is 0.5 anterior). A
file read without a frame named is read in the camera frame and refused
if its eyes then look backwards (:data:`BACKWARDS`), since no insect's do:
its frame must be named (``frame="camera"`` reads it so regardless).

Acceptance angle. Δρ of a receptor table is the FWHM of Snyder's (1977)
Gaussian A(θ) (see :mod:`beeoptics.eye.optics`), and CompoundRay's acceptance
angle is an FWHM too, so ``angle_convention="fwhm"`` (the default) only changes
degrees to radians: α = Δρ. CompoundRay's rays are not spread like A(θ),
though: a normal splay angle with a uniform azimuth crowds rays towards the
axis (the sampling :mod:`beeoptics.eye.optics` warns against). For the same
FWHM, the mean squared off-axis angle of CompoundRay's rays is σ², that of
A(θ) 2σ²; half of it is the variance of the blur along any line through the
axis, which sets the contrast kept at low spatial frequencies.
``angle_convention="variance"`` writes α = √2·Δρ, which gives the rendered
ommatidium the same angular variance, and so the same blur of coarse
patterns, as our receptor. Reading inverts whichever convention is named.

Reading a file gives the positions, axes and acceptance angles; Δφ and the
facet diameter are not in the format. They are NaN unless given, and
:func:`beeoptics.eye.receptors.measure_spacing` measures them from the
neighbouring axes and positions. The focal point offset is kept as
``focal_offset_mm``.

Tables of directions
--------------------
Some eye maps give each ommatidium's direction only: strawlab's
digitisation of Buchner's (1971) map of *Drosophila* is a CSV of unit
vectors, one ``x,y,z`` a line and no header, the left eye's 699 then the
right eye's, their mirror (``drosophila_eye_map/precompute_buchner71_optics.py``).
:func:`read_directions` reads such a file, names each half's eye, and
places the receptors on a sphere of a given radius about a given centre
(the right eye's; the left's is its mirror), so that they have positions;
Δφ, Δρ and the facet diameter are NaN until measured or set.

PLY point clouds
----------------
A receptor table becomes one vertex per receptor: ``double x, y, z`` (mm,
head frame), ``double nx, ny, nz`` (the axes), ``int id``, ``uchar side``
(0 right, 1 left, the order of :data:`beeoptics.headframe.SIDES`),
``double facet_diameter_um, delta_phi_deg, delta_rho_deg`` and, for
MeshLab, ``double quality``, a copy of one column. The file is
binary_little_endian. It is written and read with Open3D's tensor I/O,
which keeps typed custom properties by name; ``igl.writePLY`` writes them
only as doubles and libigl's Python bindings have no PLY reader, and
pymeshlab's saver drops custom attributes. MeshLab (vcglib's PLY importer)
loads the positions, the normals and ``quality`` as per-vertex quality
(Filters ▸ Color Creation ▸ Colorize by vertex quality maps it) and skips
the other properties, so the file opens there with one column to colour by.

References
----------
Millward BF, Maddock S, Mangan M (2022) CompoundRay, an open-source tool
for high-speed and high-fidelity rendering of compound eyes. eLife
11:e73893.
Snyder AW (1977) Acuity of compound eyes: physical limitations and design.
J Comp Physiol 116:161–182.
Khronos Group (2021) glTF 2.0 Specification, version 2.0.1, §3.4 Coordinate System and Units.
"""

from pathlib import Path

import numpy as np

from beeoptics.headframe import SIDES, frame_axes
from beeoptics.io.atomic import atomic_path
from beeoptics.io.errors import InputError
from beeoptics.io.receptortable import MEASURES, ReceptorTable, checked

#: The eight fields of a line of a ``.eye`` file, as named in error messages.
EYE_FIELDS = ("x", "y", "z", "dx", "dy", "dz", "acceptance_angle_rad", "focal_point_offset")
#: File units per millimetre for the named units.
UNITS_PER_MM = {"m": 1e-3, "mm": 1.0}
#: CompoundRay acceptance angle over Δρ, per convention (see the module notes).
ANGLE_FACTOR = {"fwhm": 1.0, "variance": np.sqrt(2.0)}
#: Numeric columns of a receptor table stored as doubles in a PLY file.
PLY_FLOATS = MEASURES
#: Significant digits of numbers in ``.eye`` files: float32, which CompoundRay
#: reads, round-trips through 9, as in :mod:`beeoptics.io.table`.
EYE_FORMAT = "%.9g"


#: The anterior component of an eye's mean axis below which it looks backwards, in a file read without its
#: frame named: halfway between an eye that looks straight out sideways (0) and a micro-CT eye read in the
#: wrong frame (Taylor et al.'s eight files: −0.48 to −0.65).
BACKWARDS = -0.25


def read_compoundray_eye(path, side="auto", units="mm", frame=None, angle_convention="fwhm",
                         delta_phi_deg=None, facet_diameter_um=None):
    """Read a CompoundRay ``.eye`` file as a receptor table.

    Parameters
    ----------
    path : str or Path
        The eye file.
    side : {"auto", "right", "left"}
        The eye the file describes; "auto" splits it by the sign of head-frame
        y (negative: right), falling back on the axis where y is 0, so that
        a file of both eyes is read as both.
    units : {"m", "mm"} or float
        Units of the file, or file units per millimetre.
    frame : str, optional
        The file's frame: "camera", "head" or "x=…,y=…,z=…" (see the module notes);
        by default the camera frame, if the eyes then look forwards.
    angle_convention : {"fwhm", "variance"}
        How the file's acceptance angle relates to Δρ (see the module notes).
    delta_phi_deg, facet_diameter_um : float, optional
        Δφ (degrees) and facet diameter (µm) of every receptor; NaN if not
        given (:func:`beeoptics.eye.receptors.measure_spacing` measures them).

    Returns
    -------
    ReceptorTable
        mm, head frame, unit axes, degrees, with ``focal_offset_mm``. Rows
        keep the file's order; ids are 0 … n−1.

    Raises
    ------
    InputError
        If the file is missing, empty, has a line without exactly eight
        numbers, a value that is not finite, a direction of zero length, or a
        negative acceptance angle or focal point offset, an eye is not of
        a bee eye's size in the units named, or, no frame named, the eyes
        look backwards in the camera frame.
    """
    path = Path(path)
    scale, rotation, factor = _conventions(units, frame or "camera", angle_convention)
    if side not in (*SIDES, "auto"):
        raise ValueError(f"side must be 'right', 'left' or 'auto', not {side!r}")
    values, line = _parse_eye(path)
    length = np.linalg.norm(values[:, 3:6], axis=1)
    _refuse(path, line, length == 0.0, "direction", "has zero length; an ommatidium needs an axis")
    _refuse(path, line, values[:, 6] < 0.0, EYE_FIELDS[6], "is negative")
    _refuse(path, line, values[:, 6] > np.pi, EYE_FIELDS[6], "is wider than π radians; no ommatidium sees that much")
    _refuse(path, line, values[:, 7] < 0.0, EYE_FIELDS[7],
            "is negative; CompoundRay starts rays this far behind the lens")
    # The file holds row vectors e = R h, so h = e R.
    position = values[:, :3] / scale @ rotation
    axis = values[:, 3:6] / length[:, None] @ rotation
    # An eye looking straight out sideways has a mean axis of 0 anterior: refused well short of it.
    forward = axis[:, 0].mean()
    if frame is None and forward < BACKWARDS:
        raise InputError(path, "frame", f"in CompoundRay's camera frame, assumed when none is named, its eyes look "
                         f"backwards (mean axis {-forward:.2f} posterior): name the file's frame, e.g. "
                         "x=left,y=ventral,z=posterior for Taylor et al.'s micro-CT eyes (or camera to read it so)")
    n = len(values)
    if side == "auto":
        key = np.where(position[:, 1] != 0.0, position[:, 1], axis[:, 1])
        sides = np.where(key < 0.0, SIDES[0], SIDES[1])
    else:
        sides = np.full(n, side)
    return checked(ReceptorTable(
        id=np.arange(n), side=sides, position=position, axis=axis,
        facet_diameter_um=np.full(n, np.nan if facet_diameter_um is None else float(facet_diameter_um)),
        delta_phi_deg=np.full(n, np.nan if delta_phi_deg is None else float(delta_phi_deg)),
        delta_rho_deg=np.degrees(values[:, 6]) / factor,
        focal_offset_mm=values[:, 7] / scale,
    ), path)


def read_directions(path, halves=None, frame="head", radius_mm=None, centre_mm=None):
    """Read a table of bare ommatidial directions, placed on a sphere, as a receptor table.

    Parameters
    ----------
    path : str or Path
        A text file of one direction a line, three numbers separated by
        commas or spaces, no header.
    halves : (str, str), optional
        The eyes of the file's first and second halves, e.g. ("left",
        "right"); by default each row's eye is the sign of its head-frame y
        (negative: right), as :func:`read_compoundray_eye` finds it, which a
        map whose axes cross the midline defeats.
    frame : str
        The file's frame (see the module notes).
    radius_mm : float
        The sphere the receptors are placed on: position = centre + radius · direction.
    centre_mm : sequence of 3 floats
        The right eye's sphere centre, head frame, mm; the left eye's is its mirror.

    Returns
    -------
    ReceptorTable
        ids 0 … n−1 in the file's order; Δφ, Δρ and the facet diameter NaN,
        and so not yet a table :func:`~beeoptics.io.receptortable.checked`
        passes: Δρ is set from the measured Δφ
        (:func:`beeoptics.eye.receptors.measure_spacing`) or from a value.

    Raises
    ------
    InputError
        If the file is missing, a line does not hold three finite numbers, a
        direction has zero length, or the halves are uneven.
    """
    path = Path(path)
    _, rotation, _ = _conventions("mm", frame, "fwhm")
    try:
        lines = path.read_text(encoding="utf-8-sig").splitlines()
    except FileNotFoundError:
        raise InputError(path, "", "no such file") from None
    except UnicodeDecodeError:
        raise InputError(path, "", "not a text file") from None
    numbered = [(k, line.replace(",", " ").split()) for k, line in enumerate(lines, 1) if line.strip()]
    if not numbered:
        raise InputError(path, "", "holds no directions")
    line = np.array([k for k, _ in numbered])
    rows = []
    for k, tokens in numbered:
        try:
            values = [float(v) for v in tokens]
        except ValueError:
            raise InputError(path, f"line {k}", f"{' '.join(tokens)!r} is not three numbers x, y, z") from None
        if len(values) != 3 or not np.isfinite(values).all():
            raise InputError(path, f"line {k}", f"holds {len(values)} values; a direction is three finite "
                             "numbers x, y, z")
        rows.append(values)
    values = np.array(rows)
    length = np.linalg.norm(values, axis=1)
    _refuse(path, line, length == 0.0, "direction", "has zero length; an ommatidium needs an axis")
    axis = values / length[:, None] @ rotation
    n = len(axis)
    if halves is not None:
        if n % 2:
            raise InputError(path, "", f"holds {n} directions, which do not split into two halves")
        sides = np.repeat(np.asarray(halves), n // 2)
    else:
        sides = np.where(axis[:, 1] < 0.0, SIDES[0], SIDES[1])
    centre = np.tile(np.asarray(centre_mm, float), (n, 1))
    centre[sides != SIDES[0], 1] *= -1.0
    nan = np.full(n, np.nan)
    return ReceptorTable(id=np.arange(n), side=sides, position=centre + float(radius_mm) * axis, axis=axis,
                         facet_diameter_um=nan, delta_phi_deg=nan.copy(), delta_rho_deg=nan.copy())


def write_compoundray_eye(path, table, side=None, units="mm", frame="camera", angle_convention="fwhm",
                          focal_offset_mm=0.0):
    """Write a receptor table, or one side of it, as a CompoundRay ``.eye`` file, atomically.

    Lines hold eight numbers separated by single spaces, with nine
    significant digits, and nothing else, as CompoundRay's loader expects.

    Parameters
    ----------
    path : str or Path
    table : ReceptorTable
    side : {"right", "left"}, optional
        Write only that eye; by default every row, in the table's order.
    units : {"m", "mm"} or float
        Units of the file, or file units per millimetre.
    frame : str
        The file's frame: "camera", "head" or "x=…,y=…,z=…" (see the module notes).
    angle_convention : {"fwhm", "variance"}
        Acceptance angle = Δρ, or √2·Δρ for the same angular variance (see
        the module notes).
    focal_offset_mm : float or array_like
        Focal point offset, mm, for every row written or one per table row.

    Raises
    ------
    ValueError
        If no rows are selected, a column holds a value that is not finite, an axis has zero length, or an acceptance angle or focal
        offset is negative.
    """
    scale, rotation, factor = _conventions(units, frame, angle_convention)
    n_table = len(table.id)
    if side is None:
        rows = np.arange(n_table)
    elif side in SIDES:
        rows = np.flatnonzero(np.asarray(table.side).astype(str) == side)
    else:
        raise ValueError(f"side must be None, 'right' or 'left', not {side!r}")
    if rows.size == 0:
        raise ValueError(f"the receptor table has no rows for side {side!r}")
    cols = {c: np.asarray(v, float)[rows] for c, v in table.columns().items()
            if c in ("x", "y", "z", "ax", "ay", "az", "delta_rho_deg")}
    focal = np.asarray(focal_offset_mm, float)
    focal = focal[rows] if focal.ndim == 1 and len(focal) == n_table else np.broadcast_to(focal, rows.shape)
    cols["focal_offset_mm"] = focal
    ids = np.asarray(table.id)[rows]
    for name, column in cols.items():
        bad = np.flatnonzero(~np.isfinite(column))
        if bad.size:
            raise ValueError(f"{name} of receptor {ids[bad[0]]} is not finite")
    for name in ("delta_rho_deg", "focal_offset_mm"):
        bad = np.flatnonzero(cols[name] < 0.0)
        if bad.size:
            raise ValueError(f"{name} of receptor {ids[bad[0]]} is negative")
    position = np.column_stack([cols["x"], cols["y"], cols["z"]])
    axis = np.column_stack([cols["ax"], cols["ay"], cols["az"]])
    length = np.linalg.norm(axis, axis=1)
    if (length == 0.0).any():
        raise ValueError(f"the axis of receptor {ids[np.argmax(length == 0.0)]} has zero length")
    values = np.column_stack([
        scale * position @ rotation.T,
        # CompoundRay rotates about the direction as given, which must be a unit vector.
        axis / length[:, None] @ rotation.T,
        factor * np.radians(cols["delta_rho_deg"]),
        scale * focal,
    ])
    text = "".join(" ".join(row) + "\n" for row in np.char.mod(EYE_FORMAT, values))
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="ascii", newline="\n")


def write_receptor_ply(path, table, quality="delta_phi_deg"):
    """Write a receptor table as a binary PLY point cloud, atomically.

    Parameters
    ----------
    path : str or Path
        Must end in ``.ply``.
    table : ReceptorTable
    quality : str or None
        The numeric column copied into the ``quality`` property, which
        MeshLab shows as per-vertex quality; None for none.

    Raises
    ------
    ValueError
        If the path is not a ``.ply``, the table is empty, or has a side other than right and left or an id outside int32.
    """
    path = Path(path)
    if path.suffix.lower() != ".ply":
        raise ValueError(f"{path}: a PLY file must end in .ply (Open3D picks the format by it)")
    n = len(table.id)
    if n == 0:
        raise ValueError("the receptor table is empty")
    side = np.asarray(table.side).astype(str)
    code = np.full(n, 255, np.uint8)
    for k, s in enumerate(SIDES):
        code[side == s] = k
    if (code == 255).any():
        raise ValueError(f"side must be one of {SIDES}, not {side[np.argmax(code == 255)]!r}")
    ids = np.asarray(table.id)
    if ids.dtype.kind not in "iu" or ids.min() < np.iinfo(np.int32).min or ids.max() > np.iinfo(np.int32).max:
        raise ValueError("ids must be integers within int32, the widest integer PLY has")
    import open3d as o3d  # here, not at the top: jobs that never touch a PLY point cloud never load it

    def column(values, dtype):
        return o3d.core.Tensor(np.ascontiguousarray(np.asarray(values, dtype).reshape(n, -1)))

    cloud = o3d.t.geometry.PointCloud(column(table.position, np.float64))
    cloud.point.normals = column(table.axis, np.float64)
    cloud.point.id = column(ids, np.int32)
    cloud.point.side = column(code, np.uint8)
    for name in PLY_FLOATS:
        cloud.point[name] = column(getattr(table, name), np.float64)
    if quality is not None:
        cloud.point.quality = column(getattr(table, quality), np.float64)
    with atomic_path(path) as tmp:
        if not o3d.t.io.write_point_cloud(str(tmp), cloud, write_ascii=False, compressed=False):
            raise OSError(f"{path}: Open3D could not write the PLY file")


def read_receptor_ply(path):
    """Read a receptor table from a PLY file that :func:`write_receptor_ply` wrote.

    Returns
    -------
    ReceptorTable

    Raises
    ------
    InputError
        If the file is missing, is not a PLY point cloud, lacks a vertex
        property, or has a side code other than 0 (right) and 1 (left).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "", "no such file")
    import open3d as o3d  # here, not at the top: jobs that never touch a PLY point cloud never load it

    cloud = o3d.t.io.read_point_cloud(str(path))
    if cloud.is_empty():
        raise InputError(path, "", "not a PLY point cloud, or one without vertices")
    for name in ("normals", "id", "side", *PLY_FLOATS):
        if name not in cloud.point:
            field = "nx, ny, nz" if name == "normals" else name
            raise InputError(path, field, "missing vertex property")

    def column(name):
        return cloud.point[name].numpy()

    position = column("positions").astype(np.float64)
    axis = column("normals").astype(np.float64)
    code = column("side").ravel()
    if not np.isin(code, np.arange(len(SIDES))).all():
        raise InputError(path, "side", "side codes must be 0 (right) or 1 (left)")
    return checked(ReceptorTable(id=column("id").ravel().astype(np.int64), side=np.array(SIDES)[code.astype(np.int64)],
                                 position=position, axis=axis,
                                 **{name: column(name).ravel().astype(np.float64) for name in PLY_FLOATS}), path)


def _conventions(units, frame, angle_convention):
    """File units per mm, the head-to-file rotation and the acceptance-angle factor."""
    if isinstance(units, str):
        if units not in UNITS_PER_MM:
            raise ValueError(f"units must be one of {sorted(UNITS_PER_MM)} or a number, not {units!r}")
        scale = UNITS_PER_MM[units]
    else:
        scale = float(units)
        if not (np.isfinite(scale) and scale > 0.0):
            raise ValueError(f"units must be a positive number of file units per mm, not {units!r}")
    rotation = frame_axes(frame)
    if angle_convention not in ANGLE_FACTOR:
        raise ValueError(f"angle_convention must be one of {sorted(ANGLE_FACTOR)}, not {angle_convention!r}")
    return scale, rotation, ANGLE_FACTOR[angle_convention]


def _parse_eye(path):
    """The numbers of an eye file (n, 8) and the line number of each row."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(path, "", "no such file") from None
    except UnicodeDecodeError:
        raise InputError(path, "", "not a text file") from None
    # Blank lines, which CompoundRay cannot read, are let through here: nothing is lost.
    numbered = [(k, line.split()) for k, line in enumerate(text.splitlines(), 1) if line.strip()]
    if not numbered:
        raise InputError(path, "", "holds no ommatidia")
    line = np.array([k for k, _ in numbered])
    tokens = [t for _, t in numbered]
    counts = np.array([len(t) for t in tokens])
    wrong = np.flatnonzero(counts != len(EYE_FIELDS))
    if wrong.size:
        i = wrong[0]
        raise InputError(
            path, f"line {line[i]}",
            f"has {counts[i]} values; a CompoundRay eye line has 8, separated by spaces: "
            "position x y z, direction x y z, acceptance angle (rad), focal point offset",
        )
    try:
        values = np.array(tokens, dtype=float)
    except ValueError:
        # Only on failure: find the first field that is not a number, to name it.
        for i, row in enumerate(tokens):
            for j, token in enumerate(row):
                try:
                    float(token)
                except ValueError:
                    raise InputError(path, f"line {line[i]}: {EYE_FIELDS[j]}",
                                     f"{token!r} is not a number") from None
        raise
    bad = np.argwhere(~np.isfinite(values))
    if len(bad):
        i, j = bad[0]
        raise InputError(path, f"line {line[i]}: {EYE_FIELDS[j]}", "is not finite")
    return values, line


def _refuse(path, line, bad, field, message):
    """Raise an InputError for the first row flagged in ``bad``."""
    rows = np.flatnonzero(bad)
    if rows.size:
        raise InputError(path, f"line {line[rows[0]]}: {field}", message)
