"""Bee colour spaces: geometry, invariants, and pavo's formula chain on pavo's own data."""

import warnings
from itertools import combinations

import numpy as np
import pytest

from beeoptics.vision.colourspace import (COC_WEIGHTS, HEXAGON_VERTICES, TRIANGLE_VERTICES, coc, coc_distance,
                                          colour_coordinates, excitation, hexagon, hexagon_polar, hexagon_sector, neural_noise,
                                   reflectance_catches, rnl_distance, spectral_locus, triangle, von_kries,
                                   widest_spectral_locus)
from beeoptics.vision.receptorset import load_receptor_set
from beeoptics.vision.sensitivity import measured_sensitivities, receptor_sensitivities
from beeoptics.spectra import read_pavo_csv
from beeoptics.io.table import read_table

APIS = load_receptor_set("apis_mellifera")

R3 = np.sqrt(3.0)


@pytest.fixture
def rng():
    return np.random.default_rng(20240611)


def test_excitation_is_one_half_at_the_adapting_background(rng):
    assert excitation(1.0) == 0.5
    np.testing.assert_allclose(excitation([0.0, 3.0, 1e9]), [0.0, 0.75, 1.0])
    q = rng.uniform(0.1, 5.0, (4, 3))
    np.testing.assert_allclose(excitation(von_kries(q, q[2]))[2], 0.5)


def test_hexagon_vertices_are_where_chittka_places_them():
    xy = hexagon(np.eye(3))
    np.testing.assert_allclose(xy, [[-R3 / 2, -0.5], [0.0, 1.0], [R3 / 2, -0.5]], atol=1e-15)
    np.testing.assert_allclose(xy, HEXAGON_VERTICES)
    hue, r = hexagon_polar(xy)
    np.testing.assert_allclose(r, 1.0)
    np.testing.assert_allclose(hue, [240.0, 0.0, 120.0], atol=1e-12)
    # The other three corners: two receptors fully excited, the third not.
    hue, r = hexagon_polar(hexagon([[1, 1, 0], [0, 1, 1], [1, 0, 1]]))
    np.testing.assert_allclose(r, 1.0)
    np.testing.assert_allclose(hue, [300.0, 60.0, 180.0], atol=1e-12)


def test_hue_runs_clockwise_from_the_blue_vertex():
    hue, r = hexagon_polar([[0, 1], [1, 0], [0, -1], [-1, 0], [1, 1], [0, 0]])
    np.testing.assert_allclose(hue, [0, 90, 180, 270, 45, 90])  # pavo puts the undefined centre at 90°
    np.testing.assert_allclose(r, [1, 1, 1, 1, np.sqrt(2), 0])


def test_hue_agrees_with_pavos_older_quadrant_formula(rng):
    # pavo's first angle360 (R/internal.R before the atan2 rewrite), by quadrant.
    x, y = rng.uniform(-1, 1, (2, 200))
    ax, ay = np.abs(x), np.abs(y)
    deg = 180.0 / np.pi
    old = np.select(
        [(x > 0) & (y > 0), (x > 0) & (y < 0), (x < 0) & (y < 0), (x < 0) & (y > 0)],
        [np.arctan(ax / ay) * deg, np.arctan(ay / ax) * deg + 90, np.arctan(ax / ay) * deg + 180,
         np.arctan(ay / ax) * deg + 270],
    )
    np.testing.assert_allclose(hexagon_polar(np.column_stack([x, y]))[0], old, atol=1e-10)


def test_coarse_sectors_follow_chittka_et_al_1994():
    hue = np.array([0, 29.9, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330, 359.9, 90])
    r = np.array([0.5] * 14 + [0.0])
    expected = ["blue", "blue", "bluegreen", "bluegreen", "green", "green", "uvgreen", "uvgreen", "uv", "uv",
                "uvblue", "uvblue", "blue", "blue", "achro"]
    assert list(hexagon_sector(hue, r)) == expected
    # Each receptor's vertex lies in its own sector.
    assert list(hexagon_sector(*hexagon_polar(HEXAGON_VERTICES))) == ["uv", "blue", "green"]


@pytest.mark.parametrize("level", [0.0, 0.2, 0.5, 0.9])
def test_achromatic_stimuli_fall_at_the_centre(level):
    e = np.full((2, 3), level)
    np.testing.assert_allclose(hexagon(e), 0.0, atol=1e-15)
    np.testing.assert_allclose(coc(e), 0.0, atol=1e-13)
    if level > 0:
        np.testing.assert_allclose(triangle(e), 0.0, atol=1e-15)


def test_the_background_sits_at_the_centre_after_adaptation(wavelengths, rng):
    s = receptor_sensitivities(wavelengths, APIS.lambda_max_nm)
    background = rng.uniform(0.05, 0.6, len(wavelengths))
    light = rng.uniform(0.5, 2.0, len(wavelengths))
    qb = reflectance_catches(background, light, s, wavelengths)
    e = excitation(von_kries(qb, qb))
    np.testing.assert_allclose(e, 0.5)
    np.testing.assert_allclose(hexagon(e), 0.0, atol=1e-15)


def test_triangle_of_pure_channels_is_its_vertices():
    np.testing.assert_allclose(triangle(np.eye(3) * 7.0), TRIANGLE_VERTICES)
    # UV at the top, B left, G right, as pavo's trispace.
    np.testing.assert_allclose(TRIANGLE_VERTICES, [[0, np.sqrt(2 / 3)], [-1 / np.sqrt(2), -1 / np.sqrt(6)],
                                                   [1 / np.sqrt(2), -1 / np.sqrt(6)]])
    sides = np.linalg.norm(TRIANGLE_VERTICES - np.roll(TRIANGLE_VERTICES, 1, axis=0), axis=1)
    np.testing.assert_allclose(sides, np.sqrt(2))
    np.testing.assert_allclose(TRIANGLE_VERTICES.mean(0), 0.0, atol=1e-15)


def test_triangle_matches_pavos_formula_and_ignores_intensity(rng):
    q = rng.uniform(0.01, 3.0, (50, 3))
    rel = q / q.sum(1, keepdims=True)
    s, m, l = rel.T
    expected = np.column_stack([(l - m) / np.sqrt(2), np.sqrt(2) / np.sqrt(3) * (s - (l + m) / 2)])
    np.testing.assert_allclose(triangle(q), expected, atol=1e-14)
    np.testing.assert_allclose(triangle(q * 40.0), triangle(q), atol=1e-14)


def test_coc_weights_sum_to_zero_and_distance_is_city_block(rng):
    np.testing.assert_allclose(COC_WEIGHTS.sum(1), 0.0, atol=1e-12)
    np.testing.assert_allclose(coc([1, 0, 0]), [-9.86, -5.17])
    np.testing.assert_allclose(coc([0, 1, 0]), [7.70, 20.25])
    np.testing.assert_allclose(coc([0, 0, 1]), [2.16, -15.08])
    e1, e2 = rng.uniform(0, 1, (2, 20, 3))
    d = coc_distance(e1, e2)
    np.testing.assert_allclose(d, np.abs(coc(e1) - coc(e2)).sum(1))
    np.testing.assert_allclose(d, coc_distance(e2, e1))
    assert (coc_distance(e1, e1) == 0).all()
    # Adding the same excitation to every receptor moves nothing.
    np.testing.assert_allclose(coc_distance(e1, e1 + 0.1), 0.0, atol=1e-12)


def _pavo_rnl(f1, f2, e):
    """pavo's n-receptor ΔS (newreceptornoise, neural noise) written out by subsets, for one pair."""
    idx = range(len(e))
    num = sum((np.prod(e[list(c)]) * ((f1 - f2)[d] - (f1 - f2)[g])) ** 2
              for c in combinations(idx, len(e) - 2)
              for d, g in [tuple(i for i in idx if i not in c)])
    den = sum(np.prod(e[list(c)]) ** 2 for c in combinations(idx, len(e) - 1))
    return np.sqrt(num / den)


def test_rnl_distance_matches_pavos_general_formula_and_the_quadratic_form(rng):
    e = np.array([0.2, 0.5, 0.1])
    q1, q2 = rng.uniform(0.05, 4.0, (2, 30, 3))
    d = rnl_distance(q1, q2, e)
    pavo = [_pavo_rnl(np.log(a), np.log(b), e) for a, b in zip(q1, q2)]
    np.testing.assert_allclose(d, pavo, rtol=1e-12)
    # Equivalently Δfᵀ(W − w wᵀ/Σw)Δf, w = 1/e²: noise-weighted Δf with its brightness component removed.
    w = 1.0 / e**2
    df = np.log(q1 / q2)
    quad = np.einsum("ni,ij,nj->n", df, np.diag(w) - np.outer(w, w) / w.sum(), df)
    np.testing.assert_allclose(d**2, quad, rtol=1e-10)


def test_rnl_distance_invariants(rng):
    e = np.array([0.3, 0.15, 0.2])
    q1 = rng.uniform(0.05, 4.0, (25, 3))
    direction = rng.normal(size=(25, 3))
    q2 = q1 * np.exp(0.05 * direction)
    d = rnl_distance(q1, q2, e)
    assert (d > 0).all()
    np.testing.assert_allclose(rnl_distance(q1, q1, e), 0.0)
    np.testing.assert_allclose(rnl_distance(q2, q1, e), d)
    # ΔS is linear in the log-catch difference and inverse in the noise.
    np.testing.assert_allclose(rnl_distance(q1, q1 * np.exp(0.15 * direction), e), 3 * d, rtol=1e-12)
    np.testing.assert_allclose(rnl_distance(q1, q2, 2 * e), d / 2, rtol=1e-12)
    # Brightness alone is invisible, and so is a shared receptor-wise adaptation.
    np.testing.assert_allclose(rnl_distance(q1, 3.7 * q1, e), 0.0, atol=1e-7)
    k = np.array([2.0, 0.3, 5.0])
    np.testing.assert_allclose(rnl_distance(q1 * k, q2 * k, e), d, rtol=1e-10)


def test_neural_noise_follows_pavos_density_rule():
    n, weber = np.array([1.0, 2.0, 4.0]), 0.1
    reln = n / n.sum()
    pavo = weber * np.sqrt(reln[-1]) / np.sqrt(reln)  # coldist: v = weber·√reln[ref], e = v/√reln
    np.testing.assert_allclose(neural_noise(n, weber), pavo)
    assert neural_noise(n, weber)[-1] == pytest.approx(weber)
    assert neural_noise(n, weber, reference=0)[0] == pytest.approx(weber)


def test_reflectance_catches_shape_and_grid_step(wavelengths, rng):
    s = receptor_sensitivities(wavelengths, APIS.lambda_max_nm)
    r = rng.uniform(0, 1, (len(wavelengths), 4))
    light = rng.uniform(0.5, 1.0, len(wavelengths))
    q = reflectance_catches(r, light, s, wavelengths)
    assert q.shape == (4, 3)
    np.testing.assert_allclose(q, (r * light[:, None]).T @ s * 5.0)
    np.testing.assert_allclose(reflectance_catches(r[:, 1], light, s, wavelengths), q[1])


def test_spectral_locus_is_the_catch_of_a_spike(wavelengths):
    s = receptor_sensitivities(wavelengths, APIS.lambda_max_nm)
    background = np.full(len(wavelengths), 0.2)
    light = np.ones(len(wavelengths))
    qb = reflectance_catches(background, light, s, wavelengths)
    locus = spectral_locus(s, wavelengths, qb, flux=3.0)
    spikes = 3.0 * np.eye(len(wavelengths))  # I·R = 3 in one bin, one spike per column
    q = von_kries(reflectance_catches(spikes, light, s, wavelengths), qb)
    np.testing.assert_allclose(locus.triangle, triangle(q))
    np.testing.assert_allclose(locus.hexagon, hexagon(excitation(q)))
    # Only the hexagon locus depends on the light's intensity.
    brighter = spectral_locus(s, wavelengths, qb, flux=30.0)
    np.testing.assert_allclose(brighter.triangle, locus.triangle)
    assert np.abs(brighter.hexagon - locus.hexagon).max() > 0.05


def test_spectral_locus_stays_inside_and_runs_uv_to_green(wavelengths):
    s = receptor_sensitivities(wavelengths, APIS.lambda_max_nm)
    locus = spectral_locus(s, wavelengths, np.ones(3), flux=1.0)
    bary = np.linalg.solve(np.vstack([TRIANGLE_VERTICES.T, np.ones(3)]),
                           np.vstack([locus.triangle.T, np.ones(len(wavelengths))]))
    assert (bary > -1e-12).all()
    assert (hexagon_polar(locus.hexagon)[1] <= 1.0).all()
    nearest = np.argmin(np.linalg.norm(locus.triangle[:, None] - TRIANGLE_VERTICES, axis=2), axis=1)
    at = dict(zip(wavelengths, nearest))
    assert (at[300.0], at[440.0], at[650.0]) == (0, 1, 2)


def test_the_widest_locus_puts_each_light_as_far_out_as_any_searched_intensity(wavelengths):
    s = receptor_sensitivities(wavelengths, APIS.lambda_max_nm)
    qb = reflectance_catches(np.full(len(wavelengths), 0.2), np.ones(len(wavelengths)), s, wavelengths)
    widest, intensity = widest_spectral_locus(s, wavelengths, qb, 3.0)
    radius = np.hypot(*widest.hexagon.T)
    for k in (1e-2, 1.0, 1e2):
        assert (radius >= np.hypot(*spectral_locus(s, wavelengths, qb, 3.0 * k).hexagon.T) - 1e-12).all()
    np.testing.assert_allclose(widest.hexagon, spectral_locus(s, wavelengths, qb, 3.0 * intensity).hexagon)
    np.testing.assert_allclose(widest.triangle, spectral_locus(s, wavelengths, qb, 3.0).triangle)


# pavo's documented hexagon example: vismodel(flowers, visual = "apis", qcatch = "Ei", relative = FALSE,
# vonkries = TRUE, achromatic = "l", bkg = "green"), with the default illuminant "ideal".
@pytest.mark.parametrize("illuminant", ["ideal", "D65", "bluesky"])
def test_pipeline_reproduces_pavos_formula_chain_on_pavos_data(shared_data, illuminant):
    # pavo's chain, transliterated from R/vismodel.R, R/hexagon.R, R/coc.R and R/internal.R with plain numpy.
    raw = np.loadtxt(shared_data / "flowers_pavo.csv", delimiter=",", skiprows=1)[:, 1:]
    y = raw / 100 if raw.max() > 1 else raw
    sens = np.loadtxt(shared_data / "apis_sensitivity_peitsch1992.csv", delimiter=",", skiprows=1)[:, 1:]
    table = read_table(shared_data / "illuminants_backgrounds_pavo.csv")
    illum, bkg = np.asarray(table[illuminant], float), np.asarray(table["green"], float)
    bkg = bkg / 100 if bkg.max() > 1 else bkg
    k = 1 / (sens * bkg[:, None] * illum[:, None]).sum(0)
    qi = y.T @ (sens * illum[:, None]) * k
    ei = qi / (qi + 1)
    s, m, l = ei.T
    x_ref, y_ref = (np.sqrt(3) / 2) * (l - s), m - 0.5 * (s + l)
    hue_ref = (90 - np.arctan2(y_ref, x_ref) * 180 / np.pi) % 360
    coc_ref = np.column_stack([-9.86 * s + 7.7 * m + 2.16 * l, -5.17 * s + 20.25 * m - 15.08 * l])

    # Ours, through the package's readers.
    _, wl, flowers = read_pavo_csv(shared_data / "flowers_pavo.csv")
    assert flowers.shape == (401, 36)
    s_apis = measured_sensitivities(shared_data / "apis_sensitivity_peitsch1992.csv", wl, APIS.classes)
    qb = reflectance_catches(bkg, illum, s_apis, wl)
    e = excitation(von_kries(reflectance_catches(flowers, illum, s_apis, wl), qb))
    xy = hexagon(e)
    hue, r = hexagon_polar(xy)

    np.testing.assert_allclose(e, ei, rtol=1e-6)
    np.testing.assert_allclose(xy, np.column_stack([x_ref, y_ref]), atol=1e-6)
    np.testing.assert_allclose(hue, hue_ref, atol=1e-4)
    np.testing.assert_allclose(r, np.hypot(x_ref, y_ref), atol=1e-6)
    np.testing.assert_allclose(coc(e), coc_ref, atol=1e-5)
    # Flowers are less saturated than a single receptor's vertex, and differ from the foliage.
    assert (r < 1).all() and (r > 0.01).all()


def test_triangle_reproduces_pavos_trispace_on_pavos_data(shared_data):
    # pavo: colspace(vismodel(flowers, visual = "apis")), i.e. relative Qi under the ideal illuminant.
    raw = np.loadtxt(shared_data / "flowers_pavo.csv", delimiter=",", skiprows=1)[:, 1:]
    sens = np.loadtxt(shared_data / "apis_sensitivity_peitsch1992.csv", delimiter=",", skiprows=1)[:, 1:]
    qi = (raw / 100).T @ sens
    s, m, l = (qi / qi.sum(1, keepdims=True)).T
    expected = np.column_stack([(l - m) / np.sqrt(2), np.sqrt(2 / 3) * (s - (l + m) / 2)])

    _, wl, flowers = read_pavo_csv(shared_data / "flowers_pavo.csv")
    s_apis = measured_sensitivities(shared_data / "apis_sensitivity_peitsch1992.csv", wl, APIS.classes)
    ours = triangle(reflectance_catches(flowers, np.ones(len(wl)), s_apis, wl))
    np.testing.assert_allclose(ours, expected, atol=1e-6)


def test_a_receptor_that_caught_no_light_has_no_colour_and_no_warning():
    q = np.array([[0.0, 0.0, 0.0], [2.0, 1.0, 0.5]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        columns = colour_coordinates(q, np.ones(3), APIS)
    assert list(columns["lit"]) == [0, 1]
    for name, values in columns.items():
        if name != "lit":
            assert np.isnan(values[0]) and np.isfinite(values[1]), name
    # A lit receptor's coordinates do not depend on a dark one beside it.
    alone = colour_coordinates(q[1:], np.ones(3), APIS)
    for k in columns:
        np.testing.assert_allclose(alone[k][0], columns[k][1], rtol=1e-12, err_msg=k)
