import numpy as np
import pytest

from beeoptics.headframe import direction_from_x_towards_y
from beeoptics.light.materials import ground_albedo
from beeoptics.sky import hosekwilkie
from beeoptics.sky.daylight import clear_sky
from beeoptics.sky.dome import CLEAR_SKIES, clear_sky_dome, horizontal_irradiance, sky_coefficients, uniform_sky
from beeoptics.sky.sampling import sample_sky, sky_table
from beeoptics.sky.sun import sun_disc


@pytest.fixture(scope="module")
def grass(wavelengths):
    return ground_albedo("grass", wavelengths, "test", "grass")


def dome(model, wavelengths, albedo, elevation=40.0, turbidity=3.0, azimuth=30.0):
    daylight = clear_sky(wavelengths, elevation, turbidity, albedo)
    return clear_sky_dome(model, daylight, direction_from_x_towards_y(azimuth, elevation), turbidity, albedo), daylight


def radiance(sky, dirs):
    return sky_coefficients(sky, np.atleast_2d(dirs)) @ sky.basis


def upper(n, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    d[:, 2] = np.abs(d[:, 2])
    return d / np.linalg.norm(d, axis=1, keepdims=True)


# Radiance, W m⁻² sr⁻¹ nm⁻¹, of Hosek & Wilkie's reference implementation (version 1.4a:
# its ArHosekSkyModel_CookConfiguration, _CookRadianceConfiguration and
# _GetRadianceInternal, written out in C and compiled against the authors' own
# ArHosekSkyModelData_Spectral.h): turbidity, albedo, sun elevation, view zenith angle,
# view azimuth from the sun (degrees), channel (nm), radiance.
REFERENCE = [
    (3.0, 0.1, 40, 30, 60, 360, 6.6194553130e-02),
    (2.5, 0.3, 10, 80, 20, 440, 1.4773708712e-01),
    (6.7, 0.0, 65, 0, 150, 560, 1.2818908482e-01),
    (3.0, 1.0, 25, 60, 100, 680, 3.0986477973e-02),
    (10.0, 0.5, 5, 85, 0, 720, 3.1886327616e-01),
    (1.7, 0.2, 80, 20, 90, 320, 6.3897645690e-02),
]


@pytest.mark.parametrize("turbidity, albedo, elevation, zenith, azimuth, channel, want", REFERENCE)
def test_hosek_wilkie_radiance_is_the_reference_implementations(turbidity, albedo, elevation, zenith, azimuth,
                                                                channel, want):
    view = direction_from_x_towards_y(azimuth, 90.0 - zenith)[None]
    got = hosekwilkie.channel_radiance(view, direction_from_x_towards_y(0.0, elevation), turbidity,
                                       np.full(11, albedo))
    assert got[0, list(hosekwilkie.CHANNELS_NM).index(channel)] == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize("model", CLEAR_SKIES)
@pytest.mark.parametrize("elevation", [10.0, 50.0])
def test_a_clear_sky_gives_the_clear_sky_models_diffuse_irradiance(model, elevation, wavelengths, grass):
    # Integrated here by uniform Monte Carlo over the hemisphere, independently of
    # the cosine-weighted quadrature the sky is scaled with: E = 2π ⟨L cos θ⟩.
    sky, daylight = dome(model, wavelengths, grass, elevation)
    d = upper(400_000, seed=1)
    e = 2.0 * np.pi * (radiance(sky, d) * d[:, 2:]).mean(0)
    np.testing.assert_allclose(e, daylight.diffuse, rtol=0.01)


@pytest.mark.parametrize("model", CLEAR_SKIES)
def test_the_sky_brightens_towards_the_sun_and_is_dark_below_the_horizon(model, wavelengths, grass):
    sky, _ = dome(model, wavelengths, grass)
    near = direction_from_x_towards_y(45.0, 40.0)
    far = direction_from_x_towards_y(210.0, 40.0)
    assert radiance(sky, near).sum() > 2 * radiance(sky, far).sum()
    assert radiance(sky, [0.3, 0.0, -0.9]).max() == 0.0


def test_the_hosek_wilkie_sky_is_bluer_overhead_than_at_the_horizon(wavelengths, grass):
    # Near the horizon the light has crossed more air, which scatters blue out of it
    # (Hosek & Wilkie 2012, fig. 1): the blue-to-red ratio falls from zenith to horizon.
    # The Preetham-shaped sky has one shape at every wavelength and cannot show it.
    sky, _ = dome("hosek_wilkie", wavelengths, grass)
    zenith, horizon = radiance(sky, [[0.0, 0.0, 1.0], direction_from_x_towards_y(210.0, 3.0)])
    blue, red = list(wavelengths).index(440.0), list(wavelengths).index(640.0)
    assert zenith[blue] / zenith[red] > 1.3 * horizon[blue] / horizon[red]


@pytest.mark.parametrize("model", CLEAR_SKIES)
@pytest.mark.parametrize("elevation", [1.0, 5.0, 20.0, 80.0])
@pytest.mark.parametrize("turbidity", [1.7, 6.0, 10.0])
def test_a_clear_sky_is_never_negative(model, elevation, turbidity, wavelengths, grass):
    sky, _ = dome(model, wavelengths, grass, elevation, turbidity)
    assert radiance(sky, upper(20_000)).min() >= 0.0


def test_the_sun_carries_the_direct_irradiance_over_its_disc(wavelengths, grass):
    daylight = clear_sky(wavelengths, 35.0, 3.0, grass)
    sun = sun_disc(daylight, 120.0)
    np.testing.assert_allclose(sun.radiance * sun.solid_angle, daylight.direct_normal, rtol=1e-9)
    np.testing.assert_allclose(horizontal_irradiance(None, sun, len(wavelengths)),
                               daylight.direct_normal * np.sin(np.radians(35.0)), rtol=1e-9)
    assert sun.direction @ direction_from_x_towards_y(120.0, 35.0) == pytest.approx(1.0)


def test_uniform_sky_is_the_same_everywhere(wavelengths):
    l = np.linspace(0.01, 0.02, len(wavelengths))
    sky = uniform_sky(l)
    dirs = np.random.default_rng(0).normal(size=(20, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    np.testing.assert_allclose(radiance(sky, dirs), np.tile(l, (20, 1)))


def test_a_uniform_hemisphere_of_unit_radiance_gives_pi_on_a_horizontal_surface(wavelengths):
    sky = uniform_sky(np.ones(len(wavelengths)), hemisphere=True)
    np.testing.assert_allclose(horizontal_irradiance(sky, None, len(wavelengths)), np.pi, rtol=1e-12)


def test_a_uniform_skys_sampling_table_is_empty_at_any_level():
    # MIS compensation: a sky nowhere above its mean leaves nothing to sample, however its level rounds.
    rng = np.random.default_rng(6)
    for k in range(60):
        sky = uniform_sky(rng.uniform(0.0, 10.0, 5) * 10.0 ** rng.uniform(-6.0, 6.0), hemisphere=bool(k % 2))
        row_cdf, _, density = sky_table(sky, sky.basis)
        assert not density.any() and row_cdf[-1] == 0.0


def test_a_clear_skys_sampling_table_holds_its_light_above_the_mean_and_is_drawn_as_often(wavelengths, grass):
    sky, _ = dome("hosek_wilkie", wavelengths, grass, elevation=30.0, turbidity=6.0)
    row_cdf, col_cdf, density = sky_table(sky, sky.basis)
    cell = 4.0 * np.pi / density.size
    # Its density integrates to the share it is drawn with, the part of the sky's light above the mean.
    assert density.sum() * cell == pytest.approx(row_cdf[-1], rel=1e-12)
    assert 0.05 < row_cdf[-1] < 0.5
    assert not density[: len(density) // 2].any()  # nothing below the horizon
    # The densest cell is in the sun's aureole.
    z = -1.0 + 2.0 * (np.arange(len(density)) + 0.5) / len(density)
    phi = 2.0 * np.pi * (np.arange(density.shape[1]) + 0.5) / density.shape[1]
    r, c = np.unravel_index(np.argmax(density), density.shape)
    s = np.sqrt(1.0 - z[r] ** 2)
    assert np.array([s * np.cos(phi[c]), s * np.sin(phi[c]), z[r]]) @ sky.sun > np.cos(np.radians(10.0))
    # A draw past the share gives no direction: density 0.
    assert sample_sky(row_cdf, col_cdf, density, 0.99, 0.5)[3] == 0.0
    assert sample_sky(row_cdf, col_cdf, density, 0.5 * row_cdf[-1], 0.5)[3] > 0.0
