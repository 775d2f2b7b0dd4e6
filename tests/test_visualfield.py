"""Visual-field maps on the sphere, and the acuity table: analytic cases."""

import json

import numpy as np
from scipy.spatial import cKDTree

from beeoptics.eye.fieldofview import EYE_BITS, directions, extent, visual_field
from beeoptics.images.fieldmaps import paint
from beeoptics.io.receptortable import ReceptorTable, write_receptors
from beeoptics.io.table import read_table
from beeoptics.pipeline.eyes import acuity_table
from conftest import ROOT

RIGHT, LEFT = EYE_BITS["right"], EYE_BITS["left"]


def fibonacci_sphere(n):
    """Nearly uniform unit vectors (the golden spiral)."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = np.pi * (1.0 + 5**0.5) * k
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def spacing_deg(n):
    """Mean angle between neighbours of n uniform points: a hexagonal cell of 4π/n sr."""
    return np.degrees(np.sqrt(4.0 * np.pi / n / (np.sqrt(3.0) / 2.0)))


def cap(axes, centre, half_angle_deg):
    return axes[axes @ centre >= np.cos(np.radians(half_angle_deg))]


def test_a_map_pixel_shows_the_receptor_whose_axis_is_nearest():
    axes = fibonacci_sphere(3000)
    sides = np.where(axes[:, 1] > 0, "left", "right")
    # Δρ/2 of a spacing bridges the seam between the two eyes' lattices.
    field = visual_field(axes, sides, np.full(len(axes), 2.0 * spacing_deg(3000)), np.full(len(axes), spacing_deg(3000)),
                         width_px=180)
    _, _, unit = directions(180)
    assert (field.receptor >= 0).all()
    # Each eye claims its own nearest receptor; where both see, the nearer one wins.
    np.testing.assert_array_equal(field.receptor.ravel(), cKDTree(axes).query(unit.reshape(-1, 3))[1])


def test_the_map_puts_the_left_eye_on_the_left_and_ahead_in_the_middle():
    az, el, unit = directions(360)
    assert az[0] > 179 and az[-1] < -179 and el[0] > 89 and el[-1] < -89
    np.testing.assert_allclose(unit[90, 180], [1.0, 0.0, 0.0], atol=0.02)
    assert unit[90, 90, 1] > 0.99  # a quarter of the way across: +y, the bee's left


def test_a_cap_of_axes_sees_the_cap_and_at_most_half_an_acceptance_angle_beyond():
    axes = fibonacci_sphere(40000)
    mine = cap(axes, np.array([1.0, 0.0, 0.0]), 40.0)
    drho = 1.5 * spacing_deg(40000)
    field = visual_field(mine, np.full(len(mine), "right"), np.full(len(mine), drho),
                         np.full(len(mine), spacing_deg(40000)), width_px=1440)
    # The outermost axes lie within half a spacing inside the 40° rim, and the
    # discs of Δρ/2 round them scallop the border: the field lies between the
    # cap less half a spacing and the cap grown by Δρ/2.
    inner = 2.0 * np.pi * (1.0 - np.cos(np.radians(40.0 - spacing_deg(40000) / 2.0)))
    outer = 2.0 * np.pi * (1.0 - np.cos(np.radians(40.0 + drho / 2.0)))
    got = extent(field)
    assert inner < got["right_sr"] < outer
    assert got["right_fraction"] == got["right_sr"] / (4.0 * np.pi)
    assert got["left_sr"] == 0.0 and got["binocular_sr"] == 0.0


def test_two_eyes_overlap_where_their_fields_do():
    axes = fibonacci_sphere(20000)
    # Each eye sees a 100° cap centred 60° to its side: the fields overlap in a
    # 20°-wide band ahead (azimuth −10° to +10° on the equator) and behind.
    right = cap(axes, np.array([np.cos(np.radians(-60)), np.sin(np.radians(-60)), 0.0]), 70.0)
    left = right * [1.0, -1.0, 1.0]
    all_axes = np.vstack([right, left])
    sides = np.repeat(["right", "left"], [len(right), len(left)])
    field = visual_field(all_axes, sides, np.full(len(all_axes), 2.6), np.full(len(all_axes), spacing_deg(20000)),
                         width_px=720)
    equator = field.eyes[len(field.elevation_deg) // 2]
    az = field.azimuth_deg
    assert (equator[np.abs(az) < 8] == RIGHT | LEFT).all()
    assert (equator[(az > 20) & (az < 100)] == LEFT).all()
    assert (equator[(az < -20) & (az > -100)] == RIGHT).all()
    assert (equator[np.abs(az) > 150] == 0).all()
    painted = paint(field.receptor, np.where(sides == "left", 1.0, 2.0))
    assert np.isnan(painted[field.eyes == 0]).all()
    assert set(np.unique(painted[field.eyes == LEFT])) == {1.0}


def test_acuity_table_gives_nyquist_and_rayleigh_limits(tmp_path, monkeypatch):
    from beeoptics.eye import acuity as acuity_module
    from beeoptics.pipeline import eyes as eye_stages

    # Each eye's field is mapped once, for its row and its figure alike (it was mapped twice, a second an eye).
    fields = []
    for module in (eye_stages, acuity_module):
        monkeypatch.setattr(module, "visual_field", lambda *args: fields.append(1) or visual_field(*args),
                            raising=False)
    n = 500
    axes = fibonacci_sphere(2 * n)
    table = ReceptorTable(id=np.arange(2 * n), side=np.repeat(["right", "left"], n), position=np.zeros((2 * n, 3)),
                          axis=axes, facet_diameter_um=np.full(2 * n, 20.0), delta_phi_deg=np.full(2 * n, 2.0),
                          delta_rho_deg=np.full(2 * n, 2.6))
    write_receptors(tmp_path / "receptors.csv", table)
    # A honey bee's eye (the tiny test eye names no receptor set: the honey bee's, λmax 544 nm for G).
    quality = {"facets_per_eye": n, "facets_published": n, "size": {"eye_length_mm": 1.0, "corneal_area_mm2": 0.9}}
    (tmp_path / "quality.json").write_text(json.dumps(quality))
    acuity_table({"test": (ROOT / "tests" / "data" / "eyes" / "tiny" / "eye.yaml", tmp_path / "receptors.csv",
                           tmp_path / "quality.json")},
                 {"acuity": tmp_path / "acuity.csv", "fields": tmp_path / "fields.png"}, width_px=90)
    row = read_table(tmp_path / "acuity.csv", numeric=["f_max_cpd_median", "rayleigh_deg_G_median_facet",
                                                        "delta_rho_deg_p50", "receptors"], text=["eye"])
    assert list(row["eye"]) == ["test"] and row["receptors"][0] == 2 * n and len(fields) == 1
    np.testing.assert_allclose(row["f_max_cpd_median"], 0.25)
    np.testing.assert_allclose(row["rayleigh_deg_G_median_facet"], np.degrees(1.22 * 544e-9 / 20e-6), rtol=1e-6)
    np.testing.assert_allclose(row["delta_rho_deg_p50"], 2.6)
