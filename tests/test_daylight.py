"""Clear-sky daylight (SPECTRL2 with a Hosek–Wilkie dome) against measured daylight, and `beeoptics daylight`."""

import importlib.util

import numpy as np
import pytest

from beeoptics.light.materials import ground_albedo
from beeoptics.sky.daylight import clear_sky
from beeoptics.sky.dome import clear_sky_dome, horizontal_irradiance
from beeoptics.sky.sun import sun_disc
from beeoptics.vision.receptorset import curves, load_receptor_set

# The scene light's UV/VIS photon ratio and UV/G catch ratio (Peitsch et al. 1992) at
# turbidity 3 over grass, from 300 nm (as Granada's records) and from 360 nm (as
# Spitschan et al.'s), printed by benchmarks/daylight.py. The Preetham sky of before
# gave 0.125, 0.119, 0.118, 0.113 and 0.443, 0.426, 0.419, 0.404 from 300 nm.
PINNED = {10: (0.0695, 0.2759, 0.0445, 0.1628), 30: (0.0636, 0.2448, 0.0402, 0.1448),
          50: (0.0706, 0.2669, 0.0436, 0.1544), 70: (0.0746, 0.2799, 0.0454, 0.1594)}


@pytest.fixture(scope="module")
def ranges(wavelengths):
    if importlib.util.find_spec("dreye") is None:
        pytest.skip("the measured daylight ships in dreye (pip install --no-deps dreye)")
    from beeoptics.sky.daylightrecords import measured_ranges

    grass = ground_albedo("grass", wavelengths, "test", "grass")
    out = {}
    for elevation in PINNED:
        daylight = clear_sky(wavelengths, elevation, 3.0, grass)
        sun = sun_disc(daylight, 0.0)
        sky = clear_sky_dome("hosek_wilkie", daylight, sun.direction, 3.0, grass)
        light = horizontal_irradiance(sky, sun, len(wavelengths))
        apis = curves(load_receptor_set("apis_mellifera"), wavelengths)
        out[elevation] = measured_ranges(wavelengths, light, elevation, apis)
    return out


@pytest.mark.parametrize("elevation", sorted(PINNED))
def test_daylight_has_the_uv_of_measured_daylight(ranges, elevation):
    r = ranges[elevation]
    g, s = r["granada"], r["spitschan"]
    np.testing.assert_allclose([g["model_uv_vis"], g["model_uv_g"], s["model_uv_vis"], s["model_uv_g"]],
                               PINNED[elevation], atol=5e-4)
    # Granada's records like this sky number 70–170 at each elevation: the model is
    # within 11% of their median (the Preetham sky was 40–60% above it) and below their
    # 90th percentile. It sits at their 10th percentile: UV/VIS from 0.2% below it to
    # just above, UV/G up to 2% below it at 30–70°, since SPECTRL2 has 12–23% less
    # light than they at 320–330 nm and 4–5% less at 350–400 nm.
    assert g["n"] >= 50
    for ratio in ("uv_vis", "uv_g"):
        assert g[f"model_{ratio}"] == pytest.approx(g[ratio][1], rel=0.11), ratio
        assert g[f"model_{ratio}"] <= g[ratio][2], ratio
    # Spitschan et al.'s, from 360 nm, lie 10–20% below Granada's there: the two
    # instruments disagree, and the model lies between their medians.
    if s["n"]:
        for ratio in ("uv_vis", "uv_g"):
            assert s[ratio][1] <= s[f"model_{ratio}"], ratio


def test_a_measured_daylight_as_a_uniform_sky_gives_its_records_irradiance(wavelengths, tmp_path):
    if importlib.util.find_spec("dreye") is None:
        pytest.skip("the measured daylight ships in dreye (pip install --no-deps dreye)")
    from beeoptics.light.scene import load_scene
    from beeoptics.sky.daylightrecords import granada
    from conftest import write_scene

    path = write_scene(tmp_path / "scene.yaml", {
        "name": "granada", "eye": {"position_m": [0, 0, 1]},
        "light": {"sky": "uniform", "hemisphere": True, "sun": False,
                  "radiance": {"measured_daylight": {"granada": 1500}}}})
    scene = load_scene(path, wavelengths)
    np.testing.assert_allclose(horizontal_irradiance(scene.sky, None, len(wavelengths)),
                               granada(wavelengths)[1500], rtol=1e-9, atol=1e-12)
