"""CompoundRay eye files and PLY point clouds of receptor tables."""

import igl
import numpy as np
import pymeshlab
import pytest

from beeoptics.io.errors import InputError
from beeoptics.headframe import mirror
from beeoptics.io.interchange import (
    read_compoundray_eye,
    read_directions,
    read_receptor_ply,
    write_compoundray_eye,
    write_receptor_ply,
)
from beeoptics.eye.receptors import delta_phi, measure_spacing
from beeoptics.io.receptortable import COLUMNS, ReceptorTable, read_receptors, write_receptors
from beeoptics.light.sensors import cone_samples
from conftest import cap_mesh

SPATIAL = ("x", "y", "z", "ax", "ay", "az")


def receptor_table(half_angle_deg=50.0):
    """Both eyes of a small synthetic bee: a cap of axes turned to face -y, mirrored for the left."""
    v, f = cap_mesh(radius=1.0, half_angle_deg=half_angle_deg)
    # Local +z (the cap's centre) to the head's -y, the right eye's lateral.
    turn = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    axes = v @ turn.T
    points = 0.8 * axes + np.array([0.1, -0.6, 0.2])
    n = len(v)
    rng = np.random.default_rng(7)
    p = np.vstack([points, mirror(points)])
    a = np.vstack([axes, mirror(axes)])
    dphi = delta_phi(axes, np.unique(np.sort(igl.edges(f), axis=1), axis=0))
    return ReceptorTable(
        id=np.arange(2 * n), side=np.repeat(np.array(["right", "left"]), n), position=p, axis=a,
        facet_diameter_um=np.tile(rng.uniform(15.0, 25.0, n), 2), delta_phi_deg=np.tile(dphi, 2),
        delta_rho_deg=np.tile(rng.uniform(1.5, 3.0, n), 2),
    )


@pytest.fixture(scope="module")
def table():
    return receptor_table()


def rows(table, side):
    """The columns of one eye's rows."""
    keep = table.side == side
    return {k: np.asarray(v)[keep] for k, v in table.columns().items()}


def select(table, keep):
    """The table's rows ``keep`` (a mask or indices)."""
    return ReceptorTable(*(None if v is None else np.asarray(v)[keep] for v in table))


def eye_file(tmp_path, text):
    path = tmp_path / "bad.eye"
    path.write_text(text)
    return path


GOOD = "0 0 0.1 0 0 1 0.04 0\n0.1 0 0 1 0 0 0.04 0\n0 0.1 0 0 1 0 0.04 0\n"


# --- CompoundRay -------------------------------------------------------------------------


@pytest.mark.parametrize("units", ["m", "mm", 0.5])
@pytest.mark.parametrize("frame", ["camera", "head"])
@pytest.mark.parametrize("convention", ["fwhm", "variance"])
def test_eye_round_trip_keeps_positions_axes_and_delta_rho(tmp_path, table, units, frame, convention):
    path = tmp_path / "right.eye"
    write_compoundray_eye(path, table, side="right", units=units, frame=frame, angle_convention=convention)
    got = read_compoundray_eye(path, side="right", units=units, frame=frame, angle_convention=convention)
    want = rows(table, "right")
    # Nine significant digits in the file (rounding ≤ 5e-9 relative): float32, which CompoundRay reads, round-trips.
    for c in (*SPATIAL, "delta_rho_deg"):
        np.testing.assert_allclose(got.columns()[c], want[c], rtol=5e-9, atol=1e-12, err_msg=c)
    assert (got.side == "right").all()
    np.testing.assert_array_equal(got.id, np.arange(len(want["id"])))
    np.testing.assert_array_equal(got.position, np.column_stack([got.columns()[c] for c in ("x", "y", "z")]))
    np.testing.assert_allclose(np.linalg.norm(got.axis, axis=1), 1.0, atol=1e-12)


def test_eye_lines_are_what_compoundray_parses(tmp_path, table):
    path = tmp_path / "right.eye"
    write_compoundray_eye(path, table, side="right", focal_offset_mm=0.2)
    text = path.read_text()
    lines = text.split("\n")
    # getline + split on single spaces + stof of fields 0-7: no header, no blank line, no tabs.
    assert text.endswith("\n") and lines[-1] == ""
    assert len(lines) - 1 == (table.side == "right").sum()
    assert all(len(line.split(" ")) == 8 for line in lines[:-1])
    first = np.array(lines[0].split(" "), float)
    r = rows(table, "right")
    # Millimetres, as CompoundRay's eye specification has them, in the camera frame:
    # (right, up, forward) = (-y, z, x) of the head.
    np.testing.assert_allclose(first[:3], np.array([-r["y"][0], r["z"][0], r["x"][0]]), rtol=1e-8)
    np.testing.assert_allclose(first[3:6], [-r["ay"][0], r["az"][0], r["ax"][0]], rtol=1e-8)
    np.testing.assert_allclose(first[6], np.radians(r["delta_rho_deg"][0]), rtol=1e-8)
    np.testing.assert_allclose(first[7], 0.2, rtol=1e-8)
    got = read_compoundray_eye(path)
    np.testing.assert_allclose(got.focal_offset_mm, 0.2, rtol=1e-8)


def compoundray_rays(axis, alpha, n, rng):
    """Sample directions as CompoundRay's __raygen__ommatidium does (libEyeRenderer3/shaders.cu)."""
    sigma = alpha / 2.35482004503094938
    splay = rng.normal(0.0, sigma, n)
    around = rng.uniform(0.0, np.pi, n)
    perp = np.cross([0.0, 1.0, 0.0], axis)
    perp /= np.linalg.norm(perp)

    def rotate(p, angle, k):  # Rodrigues, as rotatePoint
        c, s_ = np.cos(angle)[:, None], np.sin(angle)[:, None]
        return c * p + s_ * np.cross(k, p) + (1 - c) * (p @ k)[:, None] * k

    return rotate(rotate(np.tile(axis, (n, 1)), splay, perp), around, axis)


@pytest.mark.parametrize("convention, ratio", [("variance", 1.0), ("fwhm", 0.5)])
def test_variance_convention_gives_compoundray_the_spread_of_snyders_gaussian(tmp_path, convention, ratio):
    one = select(receptor_table(), [0])
    path = tmp_path / "one.eye"
    write_compoundray_eye(path, one, angle_convention=convention, frame="head")
    alpha = float(path.read_text().split()[6])
    axis = one.axis
    rays = compoundray_rays(axis[0], alpha, 100_000, np.random.default_rng(0))
    theirs = np.mean(np.arccos(np.clip(rays @ axis[0], -1, 1)) ** 2)
    directions, weights = cone_samples(axis, one.delta_rho_deg, 4096, seed=1)
    theta = np.arccos(np.clip(directions[0] @ axis[0], -1, 1))
    ours = np.sum(weights[0] * theta**2) / np.sum(weights[0])
    # Same mean squared off-axis angle with α = √2 Δρ; half of it with α = Δρ.
    assert theirs == pytest.approx(ratio * ours, rel=0.02)


def test_a_file_whose_eyes_look_backwards_in_the_camera_frame_needs_its_frame_named(tmp_path, table):
    """The camera frame turned through the head's centre (a micro-CT frame) would give eyes that look backwards."""
    # The test eyes, which look out sideways, turned to look forwards as bees' eyes do.
    axis = table.axis + [1.0, 0.0, 0.0]
    table = table._replace(axis=axis / np.linalg.norm(axis, axis=1, keepdims=True))
    path = tmp_path / "both.eye"
    write_compoundray_eye(path, table)
    assert read_compoundray_eye(path).axis[:, 0].mean() > 0.5
    turned = tmp_path / "turned.eye"
    write_compoundray_eye(turned, table, frame="x=left,y=ventral,z=posterior")
    with pytest.raises(InputError) as e:
        read_compoundray_eye(turned)
    assert (e.value.path, e.value.field) == (str(turned), "frame") and "look backwards" in str(e.value)
    for frame in ("x=left,y=ventral,z=posterior", "camera"):  # named, it is read as named
        read_compoundray_eye(turned, frame=frame)


def test_a_micro_ct_eye_read_without_its_frame_is_refused_and_with_it_looks_forwards(shared_data):
    """Taylor et al.'s (2019) files, as CompoundRay ships them: x left, y ventral, z posterior."""
    path = shared_data / "eyes_ct" / "BT_77970-real.eye"
    with pytest.raises(InputError, match="frame: .* look backwards"):
        read_compoundray_eye(path)
    eye = read_compoundray_eye(path, frame="x=left,y=ventral,z=posterior")
    # As the shipped eyes look, half of each axis anterior.
    assert eye.axis[:, 0].mean() > 0.5


def test_both_eyes_in_one_file_split_by_side(tmp_path, table):
    path = tmp_path / "both.eye"
    write_compoundray_eye(path, table)
    got = measure_spacing(read_compoundray_eye(path, side="auto"), path)
    np.testing.assert_array_equal(got.side, table.side)
    for c in SPATIAL:
        np.testing.assert_allclose(got.columns()[c], table.columns()[c], rtol=5e-9, atol=1e-12, err_msg=c)
    # Each eye is triangulated on its own, so the left eye's Δφ mirrors the right's.
    np.testing.assert_allclose(got.delta_phi_deg, table.delta_phi_deg, rtol=1e-6)


def test_delta_phi_is_measured_on_the_delaunay_neighbours(tmp_path, table):
    path = tmp_path / "right.eye"
    write_compoundray_eye(path, table, side="right")
    got = measure_spacing(read_compoundray_eye(path), path)
    # The cap's own mesh edges, rim included, are the triangulation's edges.
    np.testing.assert_allclose(got.delta_phi_deg, rows(table, "right")["delta_phi_deg"], rtol=1e-6)
    assert np.isnan(got.facet_diameter_um).all()
    fixed = read_compoundray_eye(path, delta_phi_deg=2.0, facet_diameter_um=20.0)
    assert (fixed.delta_phi_deg == 2.0).all() and (fixed.facet_diameter_um == 20.0).all()
    spaced = measure_spacing(read_compoundray_eye(path), path, facet_diameter_um=True)
    # Axes on a sphere of 0.8 mm: neighbours are 0.8·Δφ apart (chord ≈ arc).
    np.testing.assert_allclose(spaced.facet_diameter_um, 800 * np.radians(got.delta_phi_deg), rtol=0.01)


def test_read_eye_is_a_receptor_table(tmp_path, table):
    eye, csv = tmp_path / "right.eye", tmp_path / "receptors.csv"
    write_compoundray_eye(eye, table, side="left")
    got = measure_spacing(read_compoundray_eye(eye, side="left"), eye)
    write_receptors(csv, got)
    back = read_receptors(csv).columns()
    for c in COLUMNS:
        if c == "side":
            np.testing.assert_array_equal(back[c], got.columns()[c])
        else:
            np.testing.assert_allclose(back[c], got.columns()[c], rtol=1e-8, err_msg=c)


def test_eye_output_is_deterministic_and_atomic(tmp_path, table):
    a, b = tmp_path / "a.eye", tmp_path / "b.eye"
    write_compoundray_eye(a, table)
    write_compoundray_eye(b, table)
    assert a.read_bytes() == b.read_bytes()
    bad = table._replace(delta_rho_deg=np.where(table.id == 3, np.nan, table.delta_rho_deg))
    with pytest.raises(ValueError, match="delta_rho_deg of receptor 3"):
        write_compoundray_eye(tmp_path / "c.eye", bad)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.eye", "b.eye"]


def test_wrong_number_of_columns_names_file_and_line(tmp_path):
    path = eye_file(tmp_path, GOOD + "\n0 0 -0.1 0 0 -1 0.04\n")
    with pytest.raises(InputError) as e:
        read_compoundray_eye(path, delta_phi_deg=2.0)
    assert e.value.path == str(path) and e.value.field == "line 5"
    assert str(path) in str(e.value) and "has 7 values" in str(e.value)


@pytest.mark.parametrize("value, field", [("nan", "dx"), ("inf", "acceptance_angle_rad"), ("1,5", "x")])
def test_values_that_are_not_finite_numbers_are_refused(tmp_path, value, field):
    fields = ["x", "y", "z", "dx", "dy", "dz", "acceptance_angle_rad", "focal_point_offset"]
    line = ["0", "0", "0.1", "0", "0", "1", "0.04", "0"]
    line[fields.index(field)] = value
    path = eye_file(tmp_path, GOOD + " ".join(line) + "\n")
    with pytest.raises(InputError) as e:
        read_compoundray_eye(path, delta_phi_deg=2.0)
    assert e.value.field == f"line 4: {field}" and str(path) in str(e.value)


def test_zero_length_direction_is_refused(tmp_path):
    path = eye_file(tmp_path, GOOD.replace("0.1 0 0 1 0 0", "0.1 0 0 0 0 0"))
    with pytest.raises(InputError) as e:
        read_compoundray_eye(path, delta_phi_deg=2.0)
    assert e.value.field == "line 2: direction" and "zero length" in str(e.value)


@pytest.mark.parametrize("text, field", [
    ("", ""),
    ("0 0 0.1 0 0 1 -0.04 0\n", "line 1: acceptance_angle_rad"),
    ("0 0 0.1 0 0 1 0.04 -1\n", "line 1: focal_point_offset"),
])
def test_empty_files_and_negative_angles_are_refused(tmp_path, text, field):
    with pytest.raises(InputError) as e:
        read_compoundray_eye(eye_file(tmp_path, text), delta_phi_deg=2.0)
    assert e.value.field == field


def test_untriangulable_axes_ask_for_delta_phi(tmp_path):
    path = eye_file(tmp_path, GOOD)
    with pytest.raises(InputError, match="delta_phi"):
        measure_spacing(read_compoundray_eye(path), path)
    assert len(read_compoundray_eye(path, delta_phi_deg=2.0).id) == 3


def test_an_eye_in_other_units_than_named_is_refused(tmp_path, table):
    path = tmp_path / "metres.eye"
    write_compoundray_eye(path, table, units="m")
    with pytest.raises(InputError) as e:
        read_compoundray_eye(path)
    assert e.value.field == "x, y, z" and "in other units" in str(e.value) and str(path) in str(e.value)
    assert len(read_compoundray_eye(path, units="m").id) == len(table.id)


def test_missing_eye_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_compoundray_eye(tmp_path / "none.eye")


# --- PLY ---------------------------------------------------------------------------------


def test_ply_round_trip_is_exact(tmp_path, table):
    path = tmp_path / "receptors.ply"
    t = table._replace(facet_diameter_um=np.where(table.id % 5 == 0, np.nan, table.facet_diameter_um))
    write_receptor_ply(path, t)
    got = read_receptor_ply(path)
    for c in COLUMNS:
        np.testing.assert_array_equal(got.columns()[c], t.columns()[c], err_msg=c)
    assert got.id.dtype.kind == "i" and got.side.dtype.kind == "U"
    np.testing.assert_array_equal(got.axis, t.axis)


def test_ply_opens_in_meshlab_with_normals_and_quality(tmp_path, table):
    path = tmp_path / "receptors.ply"
    write_receptor_ply(path, table, quality="delta_rho_deg")
    header = path.read_bytes().split(b"end_header")[0].decode()
    assert "format binary_little_endian 1.0" in header
    for prop in ("double nx", "int id", "uchar side", "double facet_diameter_um",
                 "double delta_phi_deg", "double delta_rho_deg", "double quality"):
        assert f"property {prop}\n" in header
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    m = ms.current_mesh()
    assert m.vertex_number() == len(table.id) and m.face_number() == 0
    np.testing.assert_allclose(m.vertex_matrix(), table.position)
    np.testing.assert_allclose(m.vertex_normal_matrix(), table.axis)
    np.testing.assert_allclose(m.vertex_scalar_array(), table.delta_rho_deg)


def test_ply_output_is_deterministic(tmp_path, table):
    write_receptor_ply(tmp_path / "a.ply", table)
    write_receptor_ply(tmp_path / "b.ply", table)
    assert (tmp_path / "a.ply").read_bytes() == (tmp_path / "b.ply").read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.ply", "b.ply"]


def test_ply_without_a_property_names_it(tmp_path, table):
    import open3d as o3d

    path = tmp_path / "partial.ply"
    cloud = o3d.t.geometry.PointCloud(o3d.core.Tensor(table.position))
    cloud.point.normals = o3d.core.Tensor(table.axis)
    o3d.t.io.write_point_cloud(str(path), cloud)
    with pytest.raises(InputError) as e:
        read_receptor_ply(path)
    assert e.value.field == "id" and str(path) in str(e.value)


def test_ply_that_is_not_a_ply(tmp_path):
    path = tmp_path / "junk.ply"
    path.write_text("not a ply file\n")
    with pytest.raises(InputError):
        read_receptor_ply(path)
    with pytest.raises(InputError, match="no such file"):
        read_receptor_ply(tmp_path / "none.ply")


def directions_file(tmp_path, axes):
    path = tmp_path / "directions.csv"
    path.write_text("".join(",".join(f"{c:.12g}" for c in a) + "\n" for a in axes))
    return path


def test_a_table_of_directions_is_placed_on_its_sphere(tmp_path):
    table = receptor_table()
    left = table.axis[table.side == "left"]
    # strawlab's layout: the left eye first, then its mirror, the right.
    path = directions_file(tmp_path, np.vstack([left, mirror(left)]))
    got = read_directions(path, halves=("left", "right"), radius_mm=0.2, centre_mm=(0.05, -0.3, 0.0))
    right = got.side == "right"
    np.testing.assert_allclose(got.axis[right], mirror(left), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(got.position[right] - [0.05, -0.3, 0.0], axis=1), 0.2)
    np.testing.assert_allclose(np.linalg.norm(got.position[~right] - [0.05, 0.3, 0.0], axis=1), 0.2)
    assert np.isnan(got.delta_rho_deg).all()
    # Without halves each direction's eye is the sign of its y, as the .eye reader finds it.
    assert (read_directions(path, radius_mm=0.2, centre_mm=(0, -0.3, 0)).side == np.where(
        got.axis[:, 1] < 0, "right", "left")).all()


@pytest.mark.parametrize("text, field, message", [
    ("1,0,0\n0,1\n", "line 2", "holds 2 values"),
    ("1,0,0\n0,x,1\n", "line 2", "is not three numbers"),
    ("1,0,0\n0,0,0\n", "line 2: direction", "zero length"),
    ("1,0,0\n0,nan,1\n", "line 2", "three finite numbers"),
    ("", "", "holds no directions"),
])
def test_a_bad_table_of_directions_names_its_line(tmp_path, text, field, message):
    path = tmp_path / "d.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as e:
        read_directions(path, radius_mm=0.2, centre_mm=(0, -0.3, 0))
    assert e.value.field == field


def test_uneven_halves_are_refused(tmp_path):
    path = directions_file(tmp_path, np.eye(3))
    with pytest.raises(InputError, match="two halves"):
        read_directions(path, halves=("left", "right"), radius_mm=0.2, centre_mm=(0, -0.3, 0))


def test_a_lone_receptor_at_the_rim_still_gets_its_delta_phi():
    # A receptor every triangle through it is dropped for (a rim point far from the rest) takes its
    # nearest axes as neighbours rather than no Δφ at all.
    table = receptor_table()
    right = table.side == "right"
    axes = table.axis[right]
    lone = axes.mean(0) - 1.6 * (axes[0] - axes.mean(0))
    axes = np.vstack([axes, lone / np.linalg.norm(lone)])
    n = len(axes)
    nan = np.full(n, np.nan)
    sparse = ReceptorTable(id=np.arange(n), side=np.full(n, "right"), position=axes, axis=axes,
                           facet_diameter_um=nan, delta_phi_deg=nan.copy(), delta_rho_deg=np.ones(n))
    assert np.isfinite(measure_spacing(sparse, "x").delta_phi_deg).all()
