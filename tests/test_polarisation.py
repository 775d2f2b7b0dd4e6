"""Polarised light against analytic answers: Rayleigh's and Berry's skies, Fresnel, Malus, frames, the compass."""

import numpy as np
import pytest

from beeoptics.headframe import direction_from_x_towards_y, microvillar_angle
from beeoptics.light import mueller
from beeoptics.light.integrator import trace_paths
from beeoptics.light.scene import load_scene
from beeoptics.sky.hosekwilkie import CHANNELS_NM
from beeoptics.sky.skypolarisation import (degree, depolarisation_factor, king_factor, max_degree, neutral_points_deg,
                                              polarisations, sky_polarisation)
from beeoptics.vision import compass
from beeoptics.vision.polarisation import degree_and_angle, head_frame_stokes, receptor_catch
from conftest import write_scene

WATER = 1.3334
BREWSTER_DEG = float(np.degrees(np.arctan(WATER)))
RAYLEIGH = np.zeros(2)


def unit(v):
    """Rows of ``v`` made unit vectors."""
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def sphere(n, seed=0, min_z=-0.9):
    """n random unit directions with z above ``min_z`` (the sky chart is singular at the nadir)."""
    d = unit(np.random.default_rng(seed).normal(size=(n, 3)))
    return d[d[:, 2] > min_z]


def linear_stokes(degree, angle_rad):
    """Stokes vectors (..., 3) of unit intensity, degree p and angle ψ."""
    return np.stack(np.broadcast_arrays(1.0, degree * np.cos(2 * angle_rad), degree * np.sin(2 * angle_rad)), -1)


def rotate(stokes, alpha):
    """Stokes vectors (..., 3) in a frame turned by α from theirs (towards f)."""
    c, s = np.cos(2 * alpha), np.sin(2 * alpha)
    i, q, u = np.moveaxis(stokes, -1, 0)
    return np.stack([i, q * c + u * s, -q * s + u * c], -1)


def traced(scene, directions, frames, samples=1, depth=1, seed=3, origin=(0.0, 0.0, 1.0)):
    """trace_paths of one bundle per direction (n, 3), all its samples along it: (n, 3, wl); (n, wl) without frames."""
    n = len(directions)
    return trace_paths(scene, np.tile(origin, (n, 1)), np.repeat(unit(directions)[:, None], samples, 1),
                       np.ones((n, samples)), depth=depth, seed=seed, frames=frames)


def scene_file(tmp_path, wavelengths, light, materials=None, objects=()):
    """A scene of ``light``, with the bee at 1 m, written to tmp_path and loaded."""
    return load_scene(write_scene(tmp_path / "scene.yaml", {
        "name": "pol", "light": light, "eye": {"position_m": [0, 0, 1.0]},
        "materials": materials or {}, "objects": list(objects)}), wavelengths)


def ground(material):
    """A horizontal plane of ``material``, 100 km wide, at z = 0."""
    return {"primitive": {"plane": {"size_m": 1.0e5}}, "material": material}


CLEAR = {"sky": "hosek_wilkie", "sun": True, "sun_elevation_deg": 35.0, "sun_azimuth_deg": 70.0}


# Rayleigh's and Berry's skies.


@pytest.mark.parametrize("sun_az, sun_el", [(0.0, 30.0), (130.0, 55.0), (-75.0, 5.0), (0.0, 90.0)])
def test_rayleigh_sky_follows_sin2_over_1_plus_cos2_perpendicular_to_the_scattering_plane(sun_az, sun_el):
    """Rayleigh's pattern: p = sin²γ/(1 + cos²γ), 0 at sun and anti-sun, 1 at 90°, e ⟂ the ray and scattering plane."""
    sun = direction_from_x_towards_y(sun_az, sun_el)
    d = sphere(2000)
    degree, e = polarisations(d, sun, RAYLEIGH, 1.0)
    cos_g = d @ sun
    np.testing.assert_allclose(degree, (1 - cos_g**2) / (1 + cos_g**2), atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(e, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose((e * d).sum(1), 0.0, atol=1e-9)
    clear = np.abs(cos_g) < 0.999  # away from the sun and anti-sun, where the plane is undefined
    normal = unit(np.cross(d[clear], sun))
    np.testing.assert_allclose(np.abs((e[clear] * normal).sum(1)), 1.0, atol=1e-9)

    # The sun and the anti-sun, and a great circle of points 90° from the sun (off the nadir).
    poles = np.vstack([sun, -sun])
    np.testing.assert_allclose(polarisations(poles[poles[:, 2] > -0.9], sun, RAYLEIGH, 1.0)[0], 0.0, atol=1e-12)
    side = unit(np.cross(sun, [0.0, 0.0, 1.0] if sun_el < 80 else [1.0, 0.0, 0.0]))
    t = np.linspace(0, 2 * np.pi, 37)[:, None]
    ninety = np.cos(t) * side + np.sin(t) * np.cross(side, sun)
    np.testing.assert_allclose(polarisations(ninety[ninety[:, 2] > -0.9], sun, RAYLEIGH, 1.0)[0], 1.0, atol=1e-12)


@pytest.mark.parametrize("sun", [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
def test_sky_polarisation_is_defined_at_the_zenith_and_the_nadir(sun):
    """Sky polarisation with the sun at the zenith (a uniform sky's) or along the nadir: Rayleigh's p, a unit e ⟂ d."""
    d = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.6, 0.0, -0.8], [0.0, 0.6, 0.8]])
    degree, e = polarisations(d, np.array(sun), RAYLEIGH, 1.0)
    cos_g = d @ sun
    np.testing.assert_allclose(degree, (1 - cos_g**2) / (1 + cos_g**2), atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(e, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose((e * d).sum(1), 0.0, atol=1e-12)


@pytest.mark.parametrize("sun_el", [10.0, 40.0, 64.0])
def test_berry_sky_is_unpolarised_at_the_babinet_and_brewster_points(sun_el):
    """Berry's pattern: degree 0 at Babinet's point above the sun and Brewster's below it, on the sun's vertical."""
    neutral, p_max = sky_polarisation("berry", sun_el, 3.0)
    np.testing.assert_allclose(np.degrees(neutral), neutral_points_deg(sun_el), rtol=1e-12)
    sun_az = 40.0
    sun = direction_from_x_towards_y(sun_az, sun_el)
    babinet = direction_from_x_towards_y(sun_az, sun_el + np.degrees(neutral[0]))
    brewster = direction_from_x_towards_y(sun_az, sun_el - np.degrees(neutral[1]))
    points = np.vstack([babinet, brewster])
    degree = polarisations(points, sun, neutral, p_max)[0]
    np.testing.assert_allclose(degree, 0.0, atol=1e-9)
    # Rayleigh's sky is polarised there (if only a little when Babinet's point is near the sun), and Berry's a
    # few degrees away.
    assert polarisations(points, sun, RAYLEIGH, 1.0)[0].min() > 1e-3
    off = direction_from_x_towards_y(sun_az + 8.0, np.array([sun_el + np.degrees(neutral[0]),
                                                              sun_el - np.degrees(neutral[1])]))
    assert polarisations(off, sun, neutral, p_max)[0].min() > 1e-3


def test_berry_sky_is_never_more_polarised_than_its_maximum_which_falls_with_turbidity():
    """p ≤ p_max(T) over the sky, nearly reached; p_max = exp(−(T − 0.6)/4) falls with turbidity."""
    turbidity = np.array([1.7, 2.0, 3.0, 6.0, 10.0])
    p_max = np.array([max_degree(t) for t in turbidity])
    assert np.all(np.diff(p_max) < 0)
    np.testing.assert_allclose(p_max[1:3], [0.7047, 0.5488], atol=1e-4)
    d = sphere(4000, seed=1, min_z=0.0)
    for t in turbidity:
        neutral, top = sky_polarisation("berry", 35.0, t)
        degree = polarisations(d, direction_from_x_towards_y(10.0, 35.0), neutral, top)[0]
        assert degree.max() <= top * (1 + 1e-12)
        assert degree.max() > 0.9 * top
        assert degree.min() >= 0.0


def test_berry_sky_with_its_neutral_points_at_the_sun_and_anti_sun_is_rayleighs():
    """The rayleigh model is Berry's with merged neutral points and p_max 1, and Berry's formula tends to it."""
    neutral, p_max = sky_polarisation("rayleigh", 35.0, 3.0)
    np.testing.assert_array_equal(neutral, 0.0)
    assert p_max == 1.0
    sun = direction_from_x_towards_y(200.0, 35.0)
    d = sphere(1000, seed=2)
    want, e_want = polarisations(d, sun, RAYLEIGH, 1.0)
    got, e_got = polarisations(d, sun, np.full(2, 1e-7), 1.0)
    np.testing.assert_allclose(got, want, atol=1e-5)
    np.testing.assert_allclose(np.abs((e_got * e_want).sum(1)), 1.0, atol=1e-5)


# Fresnel.


def test_fresnel_reflectances_are_born_and_wolfs():
    """R_s = sin²(θi−θt)/sin²(θi+θt), R_p = tan²(θi−θt)/tan²(θi+θt); ((n−1)/(n+1))² at 0°, R_p = 0 at Brewster's."""
    theta = np.radians(np.linspace(1.0, 89.0, 45))
    theta_t = np.arcsin(np.sin(theta) / WATER)
    got = np.array([mueller.fresnel(c, WATER) for c in np.cos(theta)])
    np.testing.assert_allclose(got[:, 0], (np.sin(theta - theta_t) / np.sin(theta + theta_t)) ** 2, rtol=1e-10)
    np.testing.assert_allclose(got[:, 1], (np.tan(theta - theta_t) / np.tan(theta + theta_t)) ** 2, rtol=1e-8,
                               atol=1e-16)
    rs2, rp2, rsrp = mueller.fresnel(1.0, WATER)
    normal = ((WATER - 1) / (WATER + 1)) ** 2
    np.testing.assert_allclose([rs2, rp2, rsrp], [normal, normal, -normal], rtol=1e-12)
    rs2, rp2, rsrp = mueller.fresnel(np.cos(np.radians(BREWSTER_DEG)), WATER)
    assert rp2 < 1e-20 and rs2 > 0.03 and abs(rsrp) < 1e-10


@pytest.mark.parametrize("alpha_deg", [0.0, 25.0, 90.0, 137.0])
def test_reflection_at_brewsters_angle_polarises_unpolarised_light_along_the_s_direction(alpha_deg):
    """m·R(2α)·F of unpolarised light: degree 1 at Brewster's angle, along s (angle α); 0 at normal incidence."""
    a = np.radians(alpha_deg)
    c2, s2 = np.cos(2 * a), np.sin(2 * a)
    brewster = np.cos(np.radians(BREWSTER_DEG))
    column = np.array(mueller.reflect_column(np.eye(3), c2, s2, brewster, WATER))
    np.testing.assert_allclose(column, linear_stokes(1.0, a), atol=1e-12)
    m = np.eye(3)
    mueller.reflect(m, c2, s2, brewster, WATER)
    np.testing.assert_allclose(m[:, 0], column, atol=1e-12)
    m = np.eye(3)
    mueller.reflect(m, c2, s2, 1.0, WATER)
    np.testing.assert_allclose(m[:, 0], [1.0, 0.0, 0.0], atol=1e-12)
    # A mirror at normal incidence keeps fully polarised light fully polarised.
    np.testing.assert_allclose(degree_and_angle(m @ linear_stokes(1.0, 0.3))[0], 1.0, rtol=1e-12)


def test_traced_glossy_water_polarises_an_unpolarised_sky_horizontally_at_brewsters_angle(tmp_path, wavelengths):
    """Traced: a black mirror of water under a uniform sky reflects p ≈ 1 at Brewster's angle, e-vector horizontal."""
    scene = scene_file(tmp_path, wavelengths, {"sky": "uniform", "hemisphere": True, "radiance": 1.0, "sun": False},
                       {"water": {"reflectance": 0.0, "gloss": {"specular": 1.0, "exponent": 1.0e5,
                                                                 "refractive_index": WATER}}},
                       [ground("water")])
    incidence = np.radians([BREWSTER_DEG, BREWSTER_DEG, BREWSTER_DEG, 20.0, 20.0])
    # Looking down along +x: the plane of incidence is xz, its normal (s) is y.
    down = np.column_stack([np.sin(incidence), np.zeros(5), -np.cos(incidence)])
    # Frames: y itself (the e-vector at 0°); z made perpendicular to the ray (at 90°); y turned by 30° towards
    # d × y, f (at −30°).
    y = np.array([0.0, 1.0, 0.0])
    turned = np.cos(np.radians(30.0)) * y + np.sin(np.radians(30.0)) * np.cross(down[2], y)
    frames = np.array([y, [0, 0, 1.0], turned, y, [0, 0, 1.0]])
    stokes = traced(scene, down, frames, samples=64)
    degree, angle = degree_and_angle(np.moveaxis(stokes, 1, -1))
    assert degree[:3].min() > 0.999
    assert degree[3:].max() < 0.5
    rs2, rp2, _ = mueller.fresnel(np.cos(np.radians(20.0)), WATER)
    # The lobe spreads the incidence by ~0.2°: 0.2 % (measured).
    np.testing.assert_allclose(degree[3:], (rs2 - rp2) / (rs2 + rp2), rtol=0.01)
    want = np.array([0.0, 90.0, -30.0, 0.0, 90.0])[:, None]
    np.testing.assert_allclose(compass.wrap_deg(2 * (angle - want)) / 2, 0.0, atol=0.1)


# Receptors.


def test_an_ideal_analyser_follows_malus_and_an_insensitive_receptor_catches_the_intensity():
    """receptor_catch of fully polarised light: 2I cos²(φ − ψ) with PS = ∞, I with PS = 1, I(1 + d cos 2(φ − ψ))."""
    phi = np.linspace(0.0, 180.0, 37)
    for psi in (0.0, 30.0, 100.0):
        stokes = 3.0 * linear_stokes(1.0, np.radians(psi))
        np.testing.assert_allclose(receptor_catch(stokes, phi, np.inf), 6.0 * np.cos(np.radians(phi - psi)) ** 2,
                                   atol=1e-12)
        np.testing.assert_allclose(receptor_catch(stokes, phi, 1.0), 3.0, rtol=1e-12)
        np.testing.assert_allclose(receptor_catch(0.5 * stokes, phi, 7.0),
                                   1.5 * (1 + 0.75 * np.cos(np.radians(2 * (phi - psi)))), rtol=1e-12)


# Frames.


def test_turning_the_frame_keeps_intensity_and_degree_and_turns_the_angle():
    """Q' = Q cos 2α + U sin 2α, U' = −Q sin 2α + U cos 2α: I and degree unchanged, angle less α."""
    rng = np.random.default_rng(4)
    degree, psi = rng.uniform(0, 1, 50), rng.uniform(0, np.pi, 50)
    stokes = 2.0 * linear_stokes(degree, psi)
    for alpha in np.radians([0.0, 17.0, 90.0, 133.0, -60.0]):
        turned = rotate(stokes, alpha)
        np.testing.assert_allclose(turned[:, 0], stokes[:, 0], rtol=1e-15)
        p, angle = degree_and_angle(turned)
        np.testing.assert_allclose(p, degree, rtol=1e-12)
        np.testing.assert_allclose(compass.wrap_deg(2 * (angle - np.degrees(psi - alpha))), 0.0, atol=1e-9)


def test_traced_stokes_vectors_do_not_depend_on_the_frame_but_turn_with_it(tmp_path, wavelengths):
    """trace_paths in two frames: the same I and degree, Q and U turned by the angle between the frames."""
    scene = scene_file(tmp_path, wavelengths, CLEAR,
                       {"leaf": {"reflectance": 0.2, "gloss": {"specular": 0.3, "exponent": 30.0}}}, [ground("leaf")])
    d = unit([[0.3, 0.2, 0.9], [-0.5, 0.6, 0.3], [0.9, 0.1, -0.4], [-0.2, -0.5, -0.8], [0.1, 0.9, -0.2]])
    a, b = unit(np.random.default_rng(5).normal(size=(2, len(d), 3)))
    first = traced(scene, d, a, samples=32, depth=3)
    second = traced(scene, d, b, samples=32, depth=3)
    np.testing.assert_allclose(second[:, 0], first[:, 0], rtol=1e-12)
    p1, p2 = degree_and_angle(np.moveaxis(first, 1, -1))[0], degree_and_angle(np.moveaxis(second, 1, -1))[0]
    assert p1.max() > 0.05  # polarised enough for the check to mean something
    # Not to 1e-12: the rays are these directions rounded to single precision (6e-8 off), about which the
    # frames were not made perpendicular.
    np.testing.assert_allclose(p2, p1, rtol=1e-6)
    # The angle from frame a's e to frame b's e, towards a's f = d × e.
    e_a, e_b = (unit(f - (f * d).sum(1, keepdims=True) * d) for f in (a, b))
    alpha = np.arctan2((e_b * np.cross(d, e_a)).sum(1), (e_b * e_a).sum(1))
    np.testing.assert_allclose(rotate(np.moveaxis(first, 1, -1), alpha[:, None]), np.moveaxis(second, 1, -1),
                               rtol=1e-6, atol=1e-9 * first[:, 0].max())


@pytest.fixture(scope="module")
def lambertian_meadow(tmp_path_factory, wavelengths):
    """A clear sky over a Lambertian ground, traced without and with polarisation, looking up and down."""
    scene = scene_file(tmp_path_factory.mktemp("meadow"), wavelengths, CLEAR,
                       {"grass": {"reflectance": {"sigmoid": {"low": 0.05, "high": 0.4, "edge_nm": 520,
                                                              "width_nm": 15}}}}, [ground("grass")])
    d = unit([[0.3, 0.2, 0.9], [-0.5, 0.6, 0.3], [0.9, 0.1, -0.4], [-0.2, -0.5, -0.8], [0.1, 0.9, -0.2]])
    frames = np.tile([0.0, 0.0, 1.0], (len(d), 1))
    return d, traced(scene, d, None, samples=32, depth=3), traced(scene, d, frames, samples=32, depth=3)


def test_polarisation_leaves_the_intensity_of_lambertian_scenes_unchanged(lambertian_meadow):
    """Tracing Stokes vectors changes no intensity where only Lambertian surfaces scatter (bit for bit)."""
    _, intensity, stokes = lambertian_meadow
    assert intensity.min() > 0.0
    np.testing.assert_array_equal(stokes[:, 0], intensity)


def test_a_lambertian_surface_depolarises_the_polarised_sky(lambertian_meadow):
    """The sky seen directly is polarised; seen through a Lambertian ground, not at all."""
    d, _, stokes = lambertian_meadow
    degree = degree_and_angle(np.moveaxis(stokes, 1, -1))[0]
    assert degree[d[:, 2] > 0].min() > 0.05
    np.testing.assert_array_equal(stokes[d[:, 2] < 0, 1:], 0.0)


def test_airs_depolarisation_factor_follows_its_king_factor_and_falls_with_wavelength():
    """Bodhaine et al.'s (1999) King factor gives ρ by F = (6 + 3ρ)/(6 − 7ρ): falling with wavelength, and
    within 2 % of the visible-light value 0.0279 (Young 1980) from 550 to 700 nm."""
    wl = np.arange(300.0, 701.0, 10.0)
    rho, f = depolarisation_factor(wl), king_factor(wl)
    np.testing.assert_allclose((6 + 3 * rho) / (6 - 7 * rho), f, rtol=1e-14)
    assert np.all(np.diff(rho) < 0)
    np.testing.assert_allclose(rho[wl >= 550], 0.0279, rtol=0.02)


def test_anisotropic_molecules_polarise_as_the_rayleigh_phase_matrix():
    """The degree of air's single scattering is −P12/P11 of Hansen & Travis's (1974) phase matrix with
    Δ = (1 − ρ)/(1 + ρ/2), (1 − ρ)/(1 + ρ) at 90° from the sun, Rayleigh's sin²γ/(1 + cos²γ) at ρ = 0."""
    gamma = np.radians(np.linspace(0.0, 180.0, 37))
    for rho in (0.0, 0.0279, 0.0317, 0.2):
        delta = (1 - rho) / (1 + rho / 2)
        p11 = delta * 0.75 * (1 + np.cos(gamma) ** 2) + 1 - delta
        p12 = -delta * 0.75 * np.sin(gamma) ** 2
        got = np.array([degree(np.sin(g) ** 2, 1.0, rho) for g in gamma])
        np.testing.assert_allclose(got, -p12 / p11, atol=1e-14)
        assert degree(1.0, 1.0, rho) == pytest.approx((1 - rho) / (1 + rho), abs=1e-15)


def test_a_traced_clear_sky_has_the_models_degree_at_each_channel_and_less_in_the_uv(tmp_path, wavelengths):
    """Berry's sky traced on the full grid: at each of Hosek & Wilkie's channels the degree is the model's
    with air's depolarisation there, and the UV's degree is below the green's wherever the sky is polarised."""
    scene = scene_file(tmp_path, wavelengths, dict(CLEAR, polarisation="berry"))
    axes = sphere(300, seed=8, min_z=0.05)
    stokes = traced(scene, axes, np.tile([0.0, 0.0, 1.0], (len(axes), 1)))
    traced_degree = degree_and_angle(np.moveaxis(stokes, 1, -1))[0]
    neutral, p_max = sky_polarisation("berry", 35.0, 3.0)
    for nm in CHANNELS_NM[CHANNELS_NM <= wavelengths[-1]]:
        want = polarisations(axes, scene.sky.sun, neutral, p_max, float(depolarisation_factor(nm)))[0]
        np.testing.assert_allclose(traced_degree[:, np.flatnonzero(wavelengths == nm)[0]], want, atol=1e-6)
    uv, green = (traced_degree[:, np.flatnonzero(wavelengths == nm)[0]] for nm in (360.0, 520.0))
    polarised = green > 0.05
    assert polarised.sum() > 100 and np.all(uv[polarised] < green[polarised])


def test_traced_sky_in_the_eye_frame_is_the_sky_models(tmp_path, wavelengths):
    """A traced Rayleigh sky, in the eye's frame (head_frame_stokes), has the model's degree and e-vector angle."""
    scene = scene_file(tmp_path, wavelengths, dict(CLEAR, polarisation="rayleigh"))
    axes = sphere(400, seed=6, min_z=0.05)
    axes = axes[np.abs(axes[:, 1]) > 0.05]  # off the sagittal plane, where the eye's angle is undefined
    stokes = traced(scene, axes, np.tile([0.0, 0.0, 1.0], (len(axes), 1)))
    degree, angle = degree_and_angle(head_frame_stokes(np.moveaxis(stokes, 1, -1), axes))
    want, e = polarisations(axes, scene.sky.sun, RAYLEIGH, 1.0)
    # To 1e-6: the tracer looks along the axes rounded to single precision.
    np.testing.assert_allclose(degree, np.broadcast_to(want[:, None], degree.shape), atol=1e-6)
    diff = compass.wrap_deg(2 * (angle - microvillar_angle(axes, e)[:, None])) / 2
    np.testing.assert_allclose(diff[want > 1e-3], 0.0, atol=1e-4)


# The compass.


def sky_along(axes, suns, neutral, p_max):
    """The sky's degree (k, n) and electric vectors (k, n, 3) along ``axes`` (n, 3) under each of ``suns`` (k, 3)."""
    skies = [polarisations(axes, sun, neutral, p_max) for sun in suns]
    return np.array([p for p, _ in skies]), np.array([e for _, e in skies])


@pytest.mark.parametrize("model, bound_deg", [("rayleigh", 0.05), ("berry", 6.0)])
def test_the_compass_reads_the_suns_azimuth_at_every_heading(model, bound_deg):
    """Ideal POL units round the dorsal sky read the solar azimuth at 36 headings, within a bound, turning with it."""
    rng = np.random.default_rng(7)
    n, sun_el = 100, 30.0
    azimuth = np.linspace(0.0, 360.0, n, endpoint=False) + rng.uniform(0.0, 3.6, n)
    axes = direction_from_x_towards_y(azimuth, rng.uniform(40.0, 70.0, n))
    microvilli = microvillar_angle(axes, direction_from_x_towards_y(azimuth + 90.0, np.zeros(n)))  # tangent
    headings = np.arange(0.0, 360.0, 10.0) + 3.3
    degree, e = sky_along(axes, direction_from_x_towards_y(headings, np.full(36, sun_el)),
                          *sky_polarisation(model, sun_el, 3.0))
    angle = np.stack([microvillar_angle(axes, ek) for ek in e], 1)
    pol = compass.pol_responses(linear_stokes(degree.T, np.radians(angle)), microvilli, np.inf)
    candidates, candidate_az = compass.candidate_suns(sun_el)
    expected = compass.expected_responses(*sky_along(axes, candidates, RAYLEIGH, 1.0), axes, microvilli)
    estimate = np.array([compass.read_out(pol[:, k], expected, candidate_az)[0] for k in range(len(headings))])
    assert np.abs(compass.wrap_deg(estimate - headings)).max() < bound_deg
    # Turning the sun by 10° turns the estimate by 10°.
    turned = compass.wrap_deg(np.diff(estimate, append=estimate[:1]) - 10.0)
    assert np.abs(turned).max() < 2 * bound_deg
