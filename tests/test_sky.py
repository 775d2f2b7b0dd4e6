import colour
import numpy as np
import pytest

from beeoptics.headframe import direction_from_x_towards_y
from beeoptics.light.sky import luminance, preetham_sky, sky_coefficients, uniform_sky
from beeoptics.light.sun import sun_disc


@pytest.fixture(scope="module")
def clear(wavelengths):
    s = direction_from_x_towards_y(30.0, 40.0)
    return preetham_sky(wavelengths, s, 3.0), s


def radiance(sky, dirs):
    return sky_coefficients(sky, np.atleast_2d(dirs)) @ sky.basis


def test_zenith_spectrum_has_the_models_luminance_and_chromaticity(clear, wavelengths):
    sky, s = clear
    zenith = radiance(sky, [0.0, 0.0, 1.0])[0]
    p = sky.params
    assert luminance(wavelengths, zenith) == pytest.approx(p["norm"]["Y"] * 1.0 * _perez0(p, "Y", s), rel=0.02)
    sd = colour.SpectralDistribution(zenith[wavelengths >= 360], wavelengths[wavelengths >= 360])
    xy = colour.XYZ_to_xy(colour.sd_to_XYZ(sd, method="Integration"))
    np.testing.assert_allclose(xy, [p["norm"]["x"] * _perez0(p, "x", s), p["norm"]["y"] * _perez0(p, "y", s)],
                               atol=0.004)


def _perez0(p, k, s):
    from beeoptics.light.sky import _perez

    return _perez(1.0, np.arccos(s[2]), p["perez"][k])


def test_preetham_zenith_luminance_formula():
    # Preetham et al. (1999): Yz = (4.0453T − 4.9710) tan χ − 0.2155T + 2.4192 kcd m⁻².
    sky = preetham_sky(np.arange(300.0, 701.0, 5.0), direction_from_x_towards_y(0.0, 60.0), 2.0)
    chi = (4 / 9 - 2 / 120) * (np.pi - 2 * np.radians(30.0))
    assert sky.params["norm"]["Y"] * 1.0 == pytest.approx(
        ((4.0453 * 2 - 4.9710) * np.tan(chi) - 0.2155 * 2 + 2.4192) * 1e3
        / _perez0(sky.params, "Y", direction_from_x_towards_y(0.0, 60.0)))


def test_sky_brightens_towards_the_sun_and_is_dark_below_the_horizon(clear):
    sky, s = clear
    near = direction_from_x_towards_y(45.0, 40.0)
    far = direction_from_x_towards_y(210.0, 40.0)
    assert radiance(sky, near).sum() > 2 * radiance(sky, far).sum()
    assert radiance(sky, [0.3, 0.0, -0.9]).max() == 0.0
    assert radiance(sky, [[0, 0, 1.0], near, far]).min() >= 0.0


def test_sun_is_attenuated_most_in_the_ultraviolet(wavelengths):
    high = sun_disc(wavelengths, 70.0, 0.0, 2.0)
    low = sun_disc(wavelengths, 10.0, 0.0, 2.0)
    hazy = sun_disc(wavelengths, 70.0, 0.0, 6.0)
    ratio = low.radiance / high.radiance
    assert ratio[wavelengths == 320.0] < ratio[wavelengths == 550.0] < ratio[wavelengths == 700.0] < 1.0
    assert np.all(hazy.radiance < high.radiance)
    # Ozone (Huggins band) leaves a few percent of 320 nm's light at 300 nm.
    assert high.radiance[0] < 0.05 * high.radiance[wavelengths == 320.0][0]
    # A sun below the horizon sends nothing.
    assert sun_disc(wavelengths, -5.0, 0.0, 3.0).radiance.max() == 0.0


def test_rayleigh_optical_depth_at_550_nm():
    # Preetham's Rayleigh term at one air mass, 550 nm; Bucholtz (1995) tabulates 0.0973.
    assert 0.008735 * 0.55**-4.08 == pytest.approx(0.0973, rel=0.03)


def test_uniform_sky_is_the_same_everywhere(wavelengths):
    l = np.linspace(0.01, 0.02, len(wavelengths))
    sky = uniform_sky(l)
    dirs = np.random.default_rng(0).normal(size=(20, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    np.testing.assert_allclose(radiance(sky, dirs), np.tile(l, (20, 1)))


def test_a_uniform_hemisphere_of_unit_radiance_gives_pi_on_a_horizontal_surface(wavelengths):
    from beeoptics.light.sky import horizontal_irradiance, uniform_sky

    sky = uniform_sky(np.ones(len(wavelengths)), hemisphere=True)
    np.testing.assert_allclose(horizontal_irradiance(sky, None, len(wavelengths)), np.pi, rtol=1e-12)


@pytest.mark.parametrize("elevation", [1.0, 5.0, 20.0, 80.0])
@pytest.mark.parametrize("turbidity", [2.0, 6.0, 10.0])
def test_preetham_sky_radiance_is_never_negative(elevation, turbidity, wavelengths):
    # With the sun low, Preetham's chromaticities leave the daylight locus, off which the
    # CIE daylight basis gives negative UV; the sky must stay physical everywhere.
    s = preetham_sky(wavelengths, direction_from_x_towards_y(30.0, elevation), turbidity)
    d = np.random.default_rng(0).normal(size=(20000, 3))
    d[:, 2] = np.abs(d[:, 2])
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    assert radiance(s, d).min() >= 0.0
