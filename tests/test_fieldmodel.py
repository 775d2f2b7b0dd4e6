"""The worker's measured field (Seidl 1982, as Stürzl et al. 2010 model it), the axis model that maps
a lattice onto it, the outline and cornea it implies, and the dorsal rim area."""

import igl
import numpy as np
import pytest
from scipy.spatial import cKDTree

from beeoptics.eye import fieldmodel
from beeoptics.eye.axismodel import field_axes
from beeoptics.eye.dorsalrim import dorsal_rim, microvillar_angle
from beeoptics.eye.lattice import hex_grid
from beeoptics.eye.shape import HEXAGON_AREA, cornea, field_outline
from beeoptics.headframe import RIGHT, eye_azimuth_elevation, eye_direction, eye_rotation


def test_interommatidial_angles_take_stuerzls_values():
    h = fieldmodel.delta_phi_horizontal
    assert h(0.0, 0.0) == pytest.approx(3.7) and h(45.0, 0.0) == pytest.approx(2.4)
    assert h(90.0, 0.0) == pytest.approx(3.7) and h(170.0, 0.0) == pytest.approx(4.6)
    assert h(-45.0, 0.0) == pytest.approx(4.6)
    # Towards the pole the excess over the frontal value shrinks: half of it at 70°.
    assert h(170.0, 70.0) == pytest.approx(3.7 + 0.45)
    assert fieldmodel.delta_phi_vertical([0.0, 45.0, -90.0]) == pytest.approx([1.5, 3.0, 4.5])


def test_the_border_is_the_measured_one(shared_data):
    border = np.genfromtxt(shared_data / "worker_eye_border_stuerzl2010.csv", delimiter=",", names=True)
    (low, high), medial, lateral = fieldmodel.border()
    np.testing.assert_allclose(lateral(border["elevation_1_2"]), border["azimuth_max_1_2"], atol=1e-9)
    np.testing.assert_allclose(medial(border["elevation_3_4"]), border["azimuth_max_3_4"], atol=1e-9)
    assert (low, high) == (-74.5, 69.0)
    assert fieldmodel.inside([0.0, 150.0, -20.0, 165.0], [0.0, 0.0, 0.0, 0.0]).tolist() == [True, True, False, False]
    # Near the top the field closes round the pole, behind the head too.
    assert fieldmodel.inside(-170.0, 68.0)


def test_the_model_holds_its_rows_of_ommatidia():
    # Integrated, the model's rows hold about as many ommatidia as Seidl & Kaiser (1981) counted.
    assert fieldmodel.ommatidia_count() == pytest.approx(5432, rel=0.1)
    # A row at the equator: 171° of azimuth in steps of 2.4–4.6°.
    assert 40 < fieldmodel.row_count(0.0) < 60
    # From pole to pole: the band the border draws, and the caps beyond where its ends close round.
    a, e = fieldmodel.direction_of_shares([0.0, 1.0, 0.5, 0.5], [0.5, 0.5, 0.0, 1.0])
    assert e[0] == pytest.approx(-90.0) and e[1] == pytest.approx(90.0)
    (low, high), medial, lateral = fieldmodel.border()
    assert a[2] == pytest.approx(medial(e[2]), abs=0.01) and a[3] == pytest.approx(lateral(e[3]), abs=0.01)
    # Above 69° and below -74.5° every azimuth is seen; within the band, the border's.
    assert fieldmodel.inside([-170.0, 0.0, 100.0], [80.0, -85.0, 75.0]).all()
    assert not fieldmodel.inside([-170.0, 0.0], [80.0, -85.0], caps=False).any()
    assert not fieldmodel.inside(-60.0, 0.0)


def seidl_array():
    """Stürzl et al.'s recipe for Seidl's array: rows Δφ_v/2 apart, ommatidia Δφ_h apart in a row, every other
    row shifted by half a step, between the border's limits (the band only); the right eye's axes."""
    (low, high), medial, lateral = fieldmodel.border()
    rows, elevation, shifted = [], low, False
    while elevation <= high:
        azimuth = float(medial(elevation))
        if shifted:
            azimuth += 0.5 * float(fieldmodel.azimuth_step(azimuth, elevation))
        while azimuth <= float(lateral(elevation)):
            rows.append((azimuth, elevation))
            azimuth += float(fieldmodel.azimuth_step(azimuth, elevation))
        elevation += 0.5 * float(fieldmodel.delta_phi_vertical(elevation))
        shifted = not shifted
    azimuth, elevation = np.array(rows).T
    return eye_direction(azimuth, elevation, RIGHT), azimuth, elevation


def test_seidls_ommatidia_stand_in_columns_in_the_visual_field():
    from beeoptics.eye.quality import vertical_neighbour_share

    # A hexagonal array of 2° about the equator, laid in horizontal rows: its neighbours stand at 30° and
    # 90° from the vertical, none within 15°; the same array in vertical columns has two of six straight up and down.
    grid = hex_grid(2.0, (30.0, -15.0), (130.0, 15.0))
    for columns, expected in ((False, 0.0), (True, 1.0 / 3.0)):
        azimuth, elevation = (grid[:, 1] + 80.0, grid[:, 0] - 80.0) if columns else grid.T
        axes = eye_direction(azimuth, elevation, RIGHT)
        inner = (np.abs(elevation) <= 10.0) & (azimuth >= 40.0) & (azimuth <= 120.0)
        assert vertical_neighbour_share(axes, axes)[inner].mean() == pytest.approx(expected, abs=0.02)
    # Stürzl et al.'s array of Seidl's ommatidia stands in columns, less its rows' wobble.
    axes, azimuth, elevation = seidl_array()
    middle = (np.abs(elevation) <= 20.0) & (azimuth >= 20.0) & (azimuth <= 140.0)
    assert 0.2 <= vertical_neighbour_share(axes, axes)[middle].mean() <= 1.0 / 3.0


def lattice_on_the_outline(count=None, diameter=0.02, lines="rows"):
    """A hexagonal lattice in ``lines`` filling the outline of ``count`` facets (the model's own count by default)."""
    count = round(fieldmodel.ommatidia_count()) if count is None else count
    outline = field_outline(count, diameter, lines)
    pitch = diameter
    points = hex_grid(pitch, outline.min(0), outline.max(0), lines=lines)
    from matplotlib.path import Path as Polygon

    points = points[Polygon(outline).contains_points(points)]
    return outline, np.column_stack([points, np.zeros(len(points))]), pitch


def test_the_axis_map_fills_the_measured_field_in_order():
    outline, points, pitch = lattice_on_the_outline()
    rotation = eye_rotation(90.0, 0.0)
    axes = field_axes(rotation, points, np.ones(len(points)), points, pitch)
    azimuth, elevation = eye_azimuth_elevation(axes @ rotation, RIGHT)
    # Every facet looks into the measured field, and the highest facets look highest.
    assert fieldmodel.inside(azimuth, elevation).mean() > 0.99
    assert np.corrcoef(points[:, 1], elevation)[0, 1] > 0.99
    assert elevation.min() < -70.0 and elevation.max() > 65.0
    # Along the equator's row the anterior facets look medially (the eye's x is anterior here).
    row = np.abs(elevation) < 2.0
    assert np.corrcoef(points[row, 0], azimuth[row])[0, 1] < -0.99
    # Neighbours in a row are Δφ_h apart, as the model says, once the rows hold the model's ommatidia.
    near = cKDTree(points[:, :2]).query_pairs(1.05 * pitch, output_type="ndarray")
    same_row = np.abs(points[near[:, 0], 1] - points[near[:, 1], 1]) < 1e-9
    pairs = near[same_row & (np.abs(elevation[near[:, 0]]) < 30.0)]
    angle = np.degrees(np.arccos(np.clip((axes[pairs[:, 0]] * axes[pairs[:, 1]]).sum(1), -1, 1)))
    model = fieldmodel.delta_phi_horizontal(azimuth[pairs[:, 0]], elevation[pairs[:, 0]])
    assert np.median(angle / model) == pytest.approx(1.0, abs=0.1)


@pytest.mark.parametrize("lines", ["rows", "columns"])
def test_a_lattice_keeps_seidls_angles_on_the_outline_laid_for_its_lines(lines):
    """Seidl's Δφ_v is a step along a column of the model, Δφ_h one along a row: lenses in rows hold them on
    an outline twice as tall as wide, as bee eyes are (Jander & Jander 2002), lenses in columns only on one
    wider than tall."""
    from scipy.spatial import Delaunay

    from beeoptics.eye.lattice import triangle_edges
    from beeoptics.eye.quality import anisotropy

    outline, points, pitch = lattice_on_the_outline(lines=lines)
    rotation = eye_rotation(90.0, 0.0)
    axes = field_axes(rotation, points, np.ones(len(points)), points, pitch) @ rotation
    edges = triangle_edges(Delaunay(points[:, :2]).simplices)
    edges = edges[np.linalg.norm(points[edges[:, 1]] - points[edges[:, 0]], axis=1) < 1.05 * pitch]
    shape = anisotropy(points, axes, edges, rotation, lines)
    assert shape["delta_phi_h_deg"]["median_ratio"] == pytest.approx(1.0, abs=0.1)
    assert shape["delta_phi_v_deg"]["median_ratio"] == pytest.approx(1.0, abs=0.1)
    aspect = np.ptp(outline[:, 1]) / np.ptp(outline[:, 0])
    assert aspect == pytest.approx(2.0, rel=0.2) if lines == "rows" else aspect < 1.0
    # Only in columns do a lens's neighbours above and below look straight above and below it.
    lenses = shape["vertical_neighbours"]["lenses"]["equator"]
    assert lenses >= 0.15 if lines == "columns" else lenses < 0.05


def test_the_cornea_has_the_facets_area_and_normals_spread():
    outline = field_outline(1500, 0.02)
    area = 1500 * HEXAGON_AREA * 0.02**2
    vertices, faces = cornea(outline, area, 3.0, 0.02)
    assert 0.5 * igl.doublearea(vertices, faces).sum() == pytest.approx(area, rel=0.02)
    t = vertices[faces]
    assert (np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])[:, 2] > 0).all()
    # The vertical about twice the horizontal, as bee eyes are (Jander & Jander 2002).
    assert np.ptp(vertices[:, 1]) / np.ptp(vertices[:, 0]) == pytest.approx(2.0, rel=0.2)


def test_microvillar_angles_are_measured_from_up_towards_anterior():
    lateral = np.array([[0.0, -1.0, 0.0]])
    assert microvillar_angle(lateral, np.array([[0.0, 0.0, 1.0]])) == pytest.approx(0.0)
    assert microvillar_angle(lateral, np.array([[1.0, 0.0, 0.0]])) == pytest.approx(90.0)
    assert microvillar_angle(lateral, np.array([[1.0, 0.0, 1.0]])) == pytest.approx(45.0)
    # The mirrored eye gives the same angle for the mirrored direction.
    assert microvillar_angle(-lateral, np.array([[1.0, 0.0, 1.0]])) == pytest.approx(45.0)


def test_the_dorsal_rim_area_is_the_strip_along_the_top():
    outline, points, pitch = lattice_on_the_outline()
    rim = np.column_stack([outline, np.zeros(len(outline))])
    rotation = eye_rotation(90.0, 0.0)
    axes = field_axes(rotation, points, np.ones(len(points)), points, pitch) @ rotation
    member, angle = dorsal_rim(points, axes, rim, rotation, 40)
    assert member.sum() == 40 and np.isnan(angle[~member]).all()
    # Along the top: within the top tenth of the eye's height (which narrows to the cap), looking skyward.
    top = points[:, 1].max()
    assert points[member, 1].min() >= top - 0.1 * np.ptp(outline[:, 1])
    _, elevation = eye_azimuth_elevation(axes, RIGHT)
    assert np.median(elevation[member]) > np.percentile(elevation, 95)


@pytest.mark.parametrize("lines", ["rows", "columns"])
@pytest.mark.filterwarnings("error")
def test_seidls_angles_are_read_off_a_lattice_in_rows_or_in_columns(lines):
    """Seidl's lattice near (60°, 0°): columns Δφ_h/2 apart, Δφ_v a step within a column, every other
    column shifted by half a step; its lenses in rows (Δφ_h along a row) or in columns (Δφ_v along one)."""
    from scipy.spatial import Delaunay

    from beeoptics.eye.lattice import triangle_edges
    from beeoptics.eye.quality import anisotropy

    h, v = fieldmodel.delta_phi_horizontal(60.0, 0.0), fieldmodel.delta_phi_vertical(0.0)
    grid = hex_grid(1.0, (-2.0, -2.0), (2.0, 2.0), lines=lines)
    # A unit step along the lines is Δφ_h in rows and Δφ_v in columns; across them, half the other.
    scale = (h, v / np.sqrt(3.0)) if lines == "rows" else (h / np.sqrt(3.0), v)
    azimuth, elevation = 60.0 + grid[:, 0] * scale[0], grid[:, 1] * scale[1]
    axes = eye_direction(azimuth, elevation, RIGHT)
    edges = triangle_edges(Delaunay(grid).simplices)
    edges = edges[np.linalg.norm(grid[edges[:, 1]] - grid[edges[:, 0]], axis=1) < 1.01]
    shape = anisotropy(np.column_stack([grid, np.zeros(len(grid))]), axes, edges, eye_rotation(60.0, 0.0), lines)
    assert shape["lines"] == lines and abs(shape["lines_off_deg"]) < 1e-6
    # Within the model's own change over the patch (Δφ_v rises by 0.1° from the equator to 5° up).
    assert shape["delta_phi_h_deg"]["median_ratio"] == pytest.approx(1.0, abs=0.05)
    assert shape["delta_phi_v_deg"]["median_ratio"] == pytest.approx(1.0, abs=0.05)
    # The patch lies within 5° of the equator: no facet at 45–75° of elevation, and no NaN for one.
    assert shape["delta_phi_v_deg"]["elevation_45_75"]["ours"] is None
