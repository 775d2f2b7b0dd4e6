"""The dielectric coating (GGX over a Lambertian base): its BSDF, and as the tracer carries it."""

import numpy as np
import pytest

from beeoptics.io.errors import InputError
from beeoptics.light import coating, layered, mueller
from beeoptics.light.materials import material
from beeoptics.light.scattering import glossy_share, lobes
from beeoptics.vision.polarisation import degree_and_angle
from test_polarisation import ground, scene_file, traced

UNIFORM = {"sky": "uniform", "hemisphere": True, "radiance": 1.0, "sun": False}
NORMAL = np.array([0.0, 0.0, 1.0])


def fresnel_mean_and_degree(theta_deg, eta):
    rs2, rp2, _ = np.array([mueller.fresnel.py_func(np.cos(np.radians(t)), eta) for t in theta_deg]).T
    return (rs2 + rp2) / 2, (rs2 - rp2) / (rs2 + rp2)


def looking_down(theta_deg):
    t = np.radians(theta_deg)
    return np.column_stack([np.sin(t), np.zeros(len(t)), -np.cos(t)])


@pytest.mark.parametrize("alpha", [0.01, 0.3, 1.0])
def test_a_white_coated_plane_under_a_uniform_sky_returns_the_sky(tmp_path, wavelengths, alpha):
    """The white furnace: a non-absorbing base under the coating reflects all the sky gives it, any roughness
    (what the coating does not reflect reaches the base and leaves through it)."""
    scene = scene_file(tmp_path, wavelengths, UNIFORM,
                       {"white": {"reflectance": 1.0, "coating": {"roughness": alpha, "refractive_index": 1.5}}},
                       [ground("white")])
    radiance = traced(scene, looking_down([0.0, 40.0, 80.0]), None, samples=4096).mean(axis=1)
    np.testing.assert_allclose(radiance, 1.0, atol=0.02)


def test_a_smooth_coating_on_black_reflects_fresnels_mean_and_polarises_as_fresnel(tmp_path, wavelengths):
    """The smooth limit: α = 10⁻³ on a black base reflects Fresnel's (R_s + R_p)/2 of the sky, with Fresnel's
    degree of polarisation, from 0° to 80°: 0.040 at 10° and 0.39 at 80° for η = 1.5, where a Phong lobe of
    constant albedo gives its albedo times cos θ."""
    eta = 1.5
    scene = scene_file(tmp_path, wavelengths, UNIFORM,
                       {"glaze": {"reflectance": 0.0, "coating": {"roughness": 1.0e-3, "refractive_index": eta}}},
                       [ground("glaze")])
    theta = np.array([0.0, 10.0, 30.0, np.degrees(np.arctan(eta)), 70.0, 80.0])
    frames = np.tile([0.0, 1.0, 0.0], (len(theta), 1))
    stokes = traced(scene, looking_down(theta), frames, samples=256)
    degree, angle = degree_and_angle(np.moveaxis(stokes, 1, -1))
    mean, fresnel_degree = fresnel_mean_and_degree(theta, eta)
    np.testing.assert_allclose(stokes[:, 0].mean(axis=1), mean, rtol=0.01)
    np.testing.assert_allclose(degree.mean(axis=1), fresnel_degree, atol=0.005)
    # The e-vector perpendicular to the plane of incidence: along y, the frame's 0°.
    assert np.abs((angle[1:] + 90.0) % 180.0 - 90.0).max() < 0.5


def test_the_coating_and_its_base_are_reciprocal():
    rng = np.random.default_rng(7)
    table = coating.albedo_table(0.3, 1.5)
    for _ in range(200):
        a, b = (v / np.linalg.norm(v) for v in np.abs(rng.normal(size=(2, 3))) * [1, 1, 1])
        mirror_a, mirror_b = 2 * a[2] * NORMAL - a, 2 * b[2] * NORMAL - b
        d_ab, f_ab, _, _ = lobes.py_func(NORMAL, mirror_a, a, *b, 0.0, 1.0, 0.3, 1.5, table, 0.5)
        d_ba, f_ba, _, _ = lobes.py_func(NORMAL, mirror_b, b, *a, 0.0, 1.0, 0.3, 1.5, table, 0.5)
        np.testing.assert_allclose([d_ab, f_ab], [d_ba, f_ba], rtol=1e-9)


@pytest.mark.parametrize("alpha", [0.1, 0.5])
def test_sampled_microfacet_normals_follow_the_ggx_distribution(alpha):
    """At normal incidence the visible normals are D(h) cos θ_h, whose share within θ_h is
    tan²θ_h / (α² + tan²θ_h) (Walter et al. 2007): rougher surfaces spread the lobe as GGX says."""
    n = 200
    u = (np.arange(n) + 0.5) / n
    out = np.array([coating.sample.py_func(NORMAL, NORMAL, alpha, a, b) for a in u for b in u[::10]])
    theta_h = np.arccos(np.clip(out[:, 2], -1, 1)) / 2  # the half vector of the normal and the reflection
    grid = np.radians(np.linspace(1, 80, 40))
    empirical = (theta_h[None, :] <= grid[:, None]).mean(axis=1)
    analytic = np.tan(grid) ** 2 / (alpha**2 + np.tan(grid) ** 2)
    np.testing.assert_allclose(empirical, analytic, atol=0.01)


def test_the_albedo_table_is_fresnels_in_the_smooth_limit_and_falls_with_roughness():
    mean, _ = fresnel_mean_and_degree(np.degrees(np.arccos((np.arange(64) + 0.5) / 64)), 1.5)
    smooth = coating.albedo_table(1.0e-3, 1.5)
    np.testing.assert_allclose(smooth[:-1][8:], mean[8:], rtol=0.01)
    rough = coating.albedo_table(0.5, 1.5)
    assert (rough[:-1] <= smooth[:-1] + 1e-3).all() and rough[-1] < smooth[-1]
    # Sampling prefers the base where the coating reflects little.
    assert glossy_share.py_func(1.0, 0.0, 0.5, 0.3, coating.albedo_table(0.3, 1.5)) < 0.15


@pytest.mark.parametrize("coat, field", [({"roughness": 0.0}, "coating.roughness"),
                                         ({"roughness": 2.0}, "coating.roughness"),
                                         ({"roughness": 0.1, "refractive_index": 0.5}, "coating.refractive_index"),
                                         ({"rough": 0.1}, "coating"),
                                         ({"roughness": 0.1, "in_reflectance": "yes"}, "coating.in_reflectance")])
def test_a_bad_coating_is_named(tmp_path, wavelengths, coat, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        scene_file(tmp_path, wavelengths, UNIFORM, {"wax": {"reflectance": 0.2, "coating": coat}}, [ground("wax")])


def test_a_reflectance_measured_whole_is_what_the_coated_surface_reflects_at_normal_incidence(tmp_path, wavelengths):
    """A leaf's spectrum holds its cuticle's reflection (in_reflectance): under a uniform sky, seen from above,
    the coated surface returns the measured reflectance (its directional albedo at normal incidence, by
    reciprocity), the coating's reflection not counted twice; taken as the base's, it returns more."""
    rho = 0.3
    measured = {"roughness": 0.35, "refractive_index": 1.32}
    radiance = {}
    for whole in (True, False):
        scene = scene_file(tmp_path / str(whole), wavelengths, UNIFORM,
                           {"leaf": {"reflectance": rho, "coating": {**measured, "in_reflectance": whole}}},
                           [ground("leaf")])
        radiance[whole] = traced(scene, looking_down([0.0]), None, samples=16384).mean()
    reflected = 1.0 - coating.through(1.0, coating.albedo_table(0.35, 1.32))
    assert 0.015 < reflected < 0.03  # about Fresnel's ((η − 1)/(η + 1))² = 0.019
    np.testing.assert_allclose(radiance[True], rho, rtol=0.005)
    # Taken as the base's own, it is returned through the coating's internal reflections, ρ' < ρ.
    through = coating.base_albedo(rho, 0.35, 1.32)
    assert through < rho
    np.testing.assert_allclose(radiance[False], reflected + through * (1.0 - reflected), rtol=0.005)


def test_the_random_walk_is_the_smooth_coatings_closed_form():
    """A smooth interface (α 10⁻⁴) over a grey or white base: the walk gives ρ T_i T_o / (π η² (1 − ρ F_dr)) within its
    noise, T = 1 − F Fresnel's transmittance and F_dr = 2∫ F(μ, 1/η) μ dμ its internal diffuse reflectance (0.596 for
    η = 1.5), Saunderson's (1942) sum of the internal reflections."""
    eta, mu = 1.5, np.array([1.0, 0.5, 0.2])
    cos = (np.arange(100000) + 0.5) / 100000
    internal = 2.0 * np.mean(layered.fresnel_mean(cos, 1.0 / eta) * cos)
    assert abs(internal - 0.596) < 0.001
    for rho in (0.5, 1.0):
        walk = layered.base_reflection(mu[:, None], mu, rho, 1.0e-4, eta, paths=10000, seed=2)
        t = 1.0 - layered.fresnel_mean(mu, eta)
        np.testing.assert_allclose(walk, rho * t[:, None] * t / (np.pi * eta**2 * (1.0 - rho * internal)), rtol=0.02)


@pytest.mark.parametrize("alpha, eta", [(0.1, 1.5), (0.35, 1.32)])
def test_the_base_depends_on_its_albedo_as_the_layered_models_random_walk(tmp_path, alpha, eta):
    """The coated base's light relative to a white base's, f(ρ)/f(1), is the layered model's exact answer (the random
    walk between interface and base, :mod:`beeoptics.light.layered`) within 2 % (the walk's noise) for grey bases of
    ρ 0.2 and 0.5, seen at 0° and 60° lit at 60° and 0°; Kelemen's coupling with ρ itself (ρ × a white base's) is
    18–100 % too bright. The walk's interface, scattering once, loses light the coating gives to the base, so that a
    white base returns the sky (the white furnace above): the two differ by that, the same for every ρ, which the ratio
    leaves."""
    rho = np.array([0.2, 0.5, 1.0])
    spec = {"roughness": alpha, "refractive_index": eta}
    base = np.array([material({"reflectance": r, "coating": spec}, np.array([500.0]), tmp_path, tmp_path / "s.yaml",
                              "m")["reflectance"][0] for r in rho])
    walk = layered.base_reflection(np.array([[1.0], [0.5]]), np.array([[0.5], [1.0]]), rho, alpha, eta, paths=12000,
                                   seed=1)
    np.testing.assert_allclose(np.tile(base[:2] / base[2], (2, 1)), walk[:, :2] / walk[:, 2:], rtol=0.02)
