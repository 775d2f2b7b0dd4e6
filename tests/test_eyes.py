"""The three castes' eyes, built from their hand-made meshes, against the bee's measured optics."""

import json

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

from beeoptics.eye.description import load_eye
from beeoptics.headframe import eye_azimuth_elevation
from beeoptics.io.receptortable import read_receptors
from conftest import ROOT, build_eye_files

CASTES = ("worker", "drone", "queen")


@pytest.fixture(scope="session")
def built(tmp_path_factory):
    out = {}
    for caste in CASTES:
        d = tmp_path_factory.mktemp(caste)
        eye = ROOT / "eyes" / caste / "eye.yaml"
        # BLAS on two threads, as on this two-core machine by default.
        with threadpool_limits(limits=2, user_api="blas"):
            build_eye_files(eye, d)
        out[caste] = {"quality": json.loads((d / "quality.json").read_text()),
                      "receptors": read_receptors(d / "receptors.csv"), "eye": load_eye(eye), "dir": d}
    return out


@pytest.mark.parametrize("caste", CASTES)
def test_every_published_bound_is_met(built, caste):
    checks = built[caste]["quality"]["checks"]
    assert checks and all(checks.values()), checks


@pytest.mark.parametrize("caste", CASTES)
def test_lattice_is_hexagonal_and_follows_the_facet_map(built, caste):
    lattice = built[caste]["quality"]["lattice"]
    assert lattice["six_neighbour_fraction"] >= 0.85
    assert lattice["spacing_median_abs_relative_error"] <= 0.05
    for band in lattice["spacing_error_by_diameter_band"]:
        assert band["median_abs_relative_error"] <= 0.05


def test_facet_counts_lie_within_the_biological_spread(built):
    assert abs(built["worker"]["quality"]["facets_per_eye"] - 4752) <= 35
    assert abs(built["drone"]["quality"]["facets_per_eye"] - 9973) <= 56
    assert built["queen"]["quality"]["facets_per_eye"] < built["worker"]["quality"]["facets_per_eye"]


def test_worker_optics(built):
    q = built["worker"]["quality"]["optics"]
    assert 1.7 <= q["delta_phi_deg"]["p50"] <= 3.1
    assert q["delta_phi_deg"]["p5"] >= 1.2 and q["delta_phi_deg"]["p95"] <= 4.8
    fov = q["field_of_view_deg"]
    np.testing.assert_allclose(fov["azimuth_at_equator"], [-15.0, 157.0], atol=10.0)
    np.testing.assert_allclose(fov["elevation"], [-75.0, 70.0], atol=10.0)
    finest = q["finest_sampling_direction_deg"]
    assert 0.0 <= finest["azimuth"] <= 90.0 and abs(finest["elevation"]) <= 30.0


def test_drone_has_a_dorsal_acute_zone(built):
    zone = built["drone"]["quality"]["acute_zone"]
    assert zone["facet_diameter_um"]["inside"] > zone["facet_diameter_um"]["outside"]
    assert zone["delta_phi_deg"]["inside"] < zone["delta_phi_deg"]["outside"]


def test_queen_eye_is_less_specialised_than_the_workers(built):
    def spread(caste):
        p = built[caste]["quality"]["optics"]["delta_phi_deg"]
        return p["p95"] / p["p5"]

    assert spread("queen") < spread("worker") < spread("drone")


def test_left_eye_is_the_mirror_image_of_the_right(built):
    r = built["worker"]["receptors"]
    right, left = r.side == "right", r.side == "left"
    np.testing.assert_allclose(r.position[left] * [1, -1, 1], r.position[right])
    np.testing.assert_allclose(r.axis[left] * [1, -1, 1], r.axis[right])


def test_worker_field_of_view_matches_stuerzls_border(built, shared_data):
    border = np.genfromtxt(shared_data / "worker_eye_border_stuerzl2010.csv", delimiter=",", names=True)
    equator = border["elevation_1_2"] == 0.0
    lateral = border["azimuth_max_1_2"][equator][0]
    medial = border["azimuth_max_3_4"][border["elevation_3_4"] == 0.0][0]
    r = built["worker"]["receptors"]
    az, el = eye_azimuth_elevation(r.axis[r.side == "right"], "right")
    band = np.abs(el) <= 2.0
    assert az[band].max() == pytest.approx(lateral, abs=10.0)
    assert az[band].min() == pytest.approx(medial, abs=10.0)
    assert el.max() == pytest.approx(border["elevation_1_2"].max(), abs=10.0)
    assert el.min() == pytest.approx(border["elevation_1_2"].min(), abs=10.0)


def test_relaxation_snapshots_show_the_lattice_forming(built):
    data = np.load(built["worker"]["dir"] / "relaxation.npz")
    assert data["iterations"][0] == 0 and len(data["iterations"]) >= 3
    assert data["snapshots"].shape[1:] == (4752, 3)
    moved = np.linalg.norm(data["snapshots"][-1] - data["snapshots"][0], axis=1)
    assert np.median(moved) > 1e-3  # the grid did move, by micrometres


def test_an_eye_builds_to_the_same_bytes_whatever_the_blas_threads(built, tmp_path):
    """The queen, whose FIRE norms are long enough for OpenBLAS to split them across threads."""
    with threadpool_limits(limits=1, user_api="blas"):
        outputs = build_eye_files(ROOT / "eyes" / "queen" / "eye.yaml", tmp_path)
    for name in ("receptors", "relaxation"):
        assert outputs[name].read_bytes() == (built["queen"]["dir"] / outputs[name].name).read_bytes(), name
