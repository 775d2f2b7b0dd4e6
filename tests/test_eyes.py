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
#: Published bounds the eyes miss, for a reason documented in their eye.yaml and the README: the
#: worker's length (Ribi et al. 1989) and width (Jander & Jander 2002) disagree with its facet
#: count (Seidl & Kaiser 1981), facet sizes (Greiner et al. 2004) and field (Seidl 1982).
KNOWN_DISAGREEMENTS = {"worker": {"eye_length_mm_within_tolerance", "eye_width_mm_within_tolerance"}}


@pytest.fixture(scope="session")
def built(built_eyes):
    # The drone, the longest build, first.
    dirs = built_eyes("drone", "worker", "queen", "worker_collins")
    out = {}
    for caste, paths in dirs.items():
        d = paths["receptors"].parent
        out[caste] = {"quality": json.loads((d / "quality.json").read_text()),
                      "receptors": read_receptors(paths["receptors"]),
                      "eye": load_eye(ROOT / "eyes" / caste / "eye.yaml"), "dir": d}
    return out


@pytest.mark.parametrize("caste", CASTES)
def test_every_published_bound_is_met(built, caste):
    checks = built[caste]["quality"]["checks"]
    missed = {k for k, v in checks.items() if not v}
    assert checks and missed == KNOWN_DISAGREEMENTS.get(caste, set()), checks


@pytest.mark.parametrize("caste", CASTES)
def test_lattice_is_hexagonal_and_follows_the_facet_map(built, caste):
    lattice = built[caste]["quality"]["lattice"]
    assert lattice["six_neighbour_fraction"] >= 0.85
    assert lattice["spacing_median_abs_relative_error"] <= 0.05
    for band in lattice["spacing_error_by_diameter_band"]:
        assert band["median_abs_relative_error"] <= 0.05


def test_facet_counts_lie_within_the_biological_spread(built):
    assert built["worker"]["quality"]["facets_per_eye"] == 5432  # Seidl & Kaiser 1981
    assert abs(built["worker_collins"]["quality"]["facets_per_eye"] - 4752) <= 35
    assert abs(built["drone"]["quality"]["facets_per_eye"] - 9973) <= 56
    assert built["queen"]["quality"]["facets_per_eye"] < built["worker"]["quality"]["facets_per_eye"]


def test_worker_optics(built):
    q = built["worker"]["quality"]["optics"]
    assert 1.7 <= q["delta_phi_deg"]["p50"] <= 3.1
    assert q["delta_phi_deg"]["p5"] >= 1.2 and q["delta_phi_deg"]["p95"] <= 4.8
    fov = q["field_of_view_deg"]
    np.testing.assert_allclose(fov["azimuth_at_equator"], [-15.0, 157.0], atol=10.0)
    # The border closes round the whole ring at -74.5° and 69°: the eye sees the caps beyond, to the poles.
    np.testing.assert_allclose(fov["elevation"], [-90.0, 90.0], atol=10.0)
    finest = q["finest_sampling_direction_deg"]
    assert 0.0 <= finest["azimuth"] <= 90.0 and abs(finest["elevation"]) <= 30.0


def test_drone_has_a_dorsal_acute_zone(built):
    zone = built["drone"]["quality"]["acute_zone"]
    assert zone["facet_diameter_um"]["inside"] > zone["facet_diameter_um"]["outside"]
    assert zone["delta_phi_deg"]["inside"] < zone["delta_phi_deg"]["outside"]


def test_the_castes_share_the_workers_field_at_their_own_facet_counts(built):
    """No drone or queen field was available: theirs is the worker's, sampled by their own facets."""
    def median_delta_phi(caste):
        return built[caste]["quality"]["optics"]["delta_phi_deg"]["p50"]

    # The same field: fewer facets look further apart, more nearer.
    assert median_delta_phi("queen") > median_delta_phi("worker") > median_delta_phi("drone")
    for caste in ("drone", "queen"):
        q = built[caste]["quality"]
        assert built[caste]["eye"].axis_model == "field"
        assert q["field"]["coverage"]["covered"] >= 0.9
        # Their hand-made corneas' normals would see far less, and the quality file says how much.
        assert q["fields"]["normals"]["right_sr"] < 0.8 * q["fields"]["axes"]["right_sr"]
        # Δρ from Snyder's model, not the 2.6° placeholder.
        r = built[caste]["receptors"]
        assert np.ptp(r.delta_rho_deg) > 0.05 and not np.isclose(r.delta_rho_deg, 2.6).all()


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
    # The border closes round the ring at its ends; the eye sees the caps beyond.
    assert border["azimuth_max_1_2"].max() - border["azimuth_max_3_4"].min() == pytest.approx(360.0)
    assert el.max() > 80.0 and el.min() < -80.0
    coverage = built["worker"]["quality"]["field"]["coverage"]
    assert coverage["covered"] >= 0.9 and coverage["covered_without_caps"] >= 0.9


def test_relaxation_snapshots_show_the_lattice_forming(built):
    data = np.load(built["worker"]["dir"] / "relaxation.npz")
    assert data["iterations"][0] == 0 and len(data["iterations"]) >= 3
    assert data["snapshots"].shape[1:] == (5432, 3)
    moved = np.linalg.norm(data["snapshots"][-1] - data["snapshots"][0], axis=1)
    assert np.median(moved) > 1e-3  # the grid did move, by micrometres


def test_an_eye_builds_to_the_same_bytes_whatever_the_blas_threads(built, tmp_path):
    """The queen, whose FIRE norms are long enough for OpenBLAS to split them across threads."""
    with threadpool_limits(limits=1, user_api="blas"):
        outputs = build_eye_files(ROOT / "eyes" / "queen" / "eye.yaml", tmp_path)
    for name in ("receptors", "relaxation"):
        assert outputs[name].read_bytes() == (built["queen"]["dir"] / outputs[name].name).read_bytes(), name


def test_the_worker_sees_the_measured_field_with_the_measured_anisotropy(built):
    field = built["worker"]["quality"]["field"]
    assert field["coverage"]["covered"] >= 0.9 and field["coverage"]["outside"] <= 0.1
    shape = field["anisotropy"]
    for key in ("delta_phi_h_deg", "delta_phi_v_deg"):
        assert abs(shape[key]["median_ratio"] - 1.0) <= 0.1, key
        assert shape[key]["correlation"] >= 0.5, key
    # Seidl's vertical Δφ doubles from the equator to high elevations; the horizontal is wider.
    v = shape["delta_phi_v_deg"]
    assert v["elevation_45_75"]["ours"] > 1.8 * v["equator"]["ours"]
    ratio = shape["horizontal_over_vertical"]
    assert ratio["ours"] == pytest.approx(ratio["model"], rel=0.1) and ratio["ours"] > 1.2
    assert shape["lines"] == "rows" and abs(shape["lines_off_deg"]) <= 10.0
    # Lenses in rows on the cornea, ommatidia in Seidl's columns in the visual field.
    vertical = shape["vertical_neighbours"]
    assert vertical["field"]["equator"] >= 0.15 and vertical["lenses"]["equator"] < 0.05


def test_the_papers_eye_along_its_normals_misses_the_measured_field(built):
    """Collins's eye, kept for the paper's figures: the measure that guards the field model fails on it."""
    assert built["worker_collins"]["eye"].axis_model == "normals"
    field = built["worker_collins"]["quality"]["field"]
    assert field["coverage"]["covered"] < 0.9
    assert field["anisotropy"]["horizontal_over_vertical"]["ours"] < 1.0


def test_the_workers_cornea_holds_its_facets(built):
    size = built["worker"]["quality"]["size"]
    assert size["facets_area_mm2"] == pytest.approx(size["corneal_area_mm2"], rel=0.02)
    # Vertical about twice horizontal (Jander & Jander 2002).
    assert size["eye_length_mm"] / size["eye_width_mm"] == pytest.approx(2.0, rel=0.15)
    assert size["facet_diameter_max_um"] == pytest.approx(20.0, rel=0.01)


def test_the_dorsal_rim_area_looks_skyward_with_ordered_microvilli(built):
    r = built["worker"]["receptors"]
    rim = r.dorsal_rim == 1
    assert rim.sum() == 2 * 60  # Schinz 1975, each eye
    _, elevation = eye_azimuth_elevation(r.axis[rim & (r.side == "right")], "right")
    assert np.median(elevation) > 40.0
    angle = r.microvilli_deg
    assert np.isnan(angle[~rim]).all() and ((angle[rim] >= 0) & (angle[rim] < 180)).all()
    assert built["worker"]["quality"]["dorsal_rim"]["facets"] == 60


def test_measured_acceptance_angles_are_smallest_in_the_fronto_ventral_acute_zone(built):
    r = built["worker"]["receptors"]
    right = r.side == "right"
    azimuth, elevation = eye_azimuth_elevation(r.axis[right], "right")
    drho = r.delta_rho_deg[right]
    assert drho.min() == pytest.approx(1.9, abs=0.02) and drho.max() == pytest.approx(2.57, abs=0.02)
    nearest = np.argmin(np.hypot(azimuth - 10.0, elevation + 45.0))
    assert drho[nearest] < np.percentile(drho, 5)
