"""Light transport against cases with known answers."""

import numpy as np
import pytest
from scipy.optimize import curve_fit

from beeoptics.io.receptortable import ReceptorTable, write_receptors
from beeoptics.light.batching import SAMPLE_BLOCK, TraceSettings, trace_bundles
from beeoptics.light.integrator import trace_paths
from beeoptics.light.sampler import REPLICATE_SHIFT, tangent_frames
from beeoptics.light.scene import load_scene
from beeoptics.light.sensors import cone_samples, cone_sigma
from beeoptics.pipeline.trace import trace_part
from beeoptics.vision.receptorset import load_receptor_set
from conftest import ROOT, write_scene

MEADOW = ROOT / "tests" / "data" / "scenes" / "meadow_tiny" / "scene.yaml"
SKY = {"gaussian": {"base": 0.01, "peak": 0.05, "centre_nm": 400, "width_nm": 50}}
LEAF = {"sigmoid": {"low": 0.05, "high": 0.5, "edge_nm": 520, "width_nm": 15}}


def fan(n, around, spread_deg, rng):
    """n unit axes scattered within spread_deg of ``around``."""
    t = tangent_frames(np.array([around], float))[0]
    a = np.radians(rng.uniform(-spread_deg, spread_deg, (n, 2)))
    axes = np.asarray(around, float) + a[:, :1] * t[0] + a[:, 1:] * t[1]
    return axes / np.linalg.norm(axes, axis=1, keepdims=True)


def look(scene, axes, spp, depth=3, seed=1, delta_rho=2.6, sky_sampling="nee"):
    dirs, w = cone_samples(axes, delta_rho, spp, seed)
    return trace_paths(scene, np.tile(scene.eye_position, (len(axes), 1)), dirs, w, depth=depth, seed=seed,
                       sky_sampling=sky_sampling)


def test_uniform_sky_alone_gives_every_receptor_the_sky_spectrum(tmp_path, wavelengths):
    path = write_scene(tmp_path / "s.yaml", {
        "name": "sky", "light": {"sky": "uniform", "radiance": SKY, "sun": False},
        "eye": {"position_m": [0, 0, 0]}, "materials": {"grey": {"reflectance": 0.3}},
        # Something to trace against, far out of sight behind the sky's radiance:
        # an object is required, and a uniform sky surrounds the whole scene.
        "objects": [{"primitive": {"plane": {"size_m": 1.0}}, "material": "grey", "translate_m": [0, 0, -1.0e4]}]})
    scene = load_scene(path, wavelengths)
    axes = np.random.default_rng(0).normal(size=(300, 3))
    axes = axes[axes[:, 2] > -0.9]
    l = look(scene, axes / np.linalg.norm(axes, axis=1, keepdims=True), 32)
    np.testing.assert_allclose(l, np.tile(scene.sky.basis[0], (len(l), 1)), rtol=1e-12)


def test_lambertian_plane_under_a_uniform_sky_looks_like_rho_times_the_sky(tmp_path, wavelengths):
    path = write_scene(tmp_path / "s.yaml", {
        "name": "plane", "light": {"sky": "uniform", "radiance": SKY, "sun": False},
        "eye": {"position_m": [0, 0, 0.5]}, "materials": {"leaf": {"reflectance": LEAF}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0e5}}, "material": "leaf"}]})
    scene = load_scene(path, wavelengths)
    axes = fan(100, [0, 0, -1], 40, np.random.default_rng(1))
    want = scene.reflectance[0] * scene.sky.basis[0]
    # Escaping, each path sees the plane, then the sky: ρL exactly, up to Monte Carlo error (none here).
    np.testing.assert_allclose(look(scene, axes, 64, sky_sampling="escape"), np.tile(want, (len(axes), 1)), rtol=1e-9)
    # Sampling the sky too (half the table's samples fall below the plane), ρL on average: unbiased.
    nee = look(scene, axes, 64)
    np.testing.assert_allclose(nee.mean(axis=0), want, rtol=0.01)
    assert np.abs(nee / want - 1.0).max() < 0.2


@pytest.mark.parametrize("rho", [0.3, 0.6])
def test_furnace_radiance_is_emission_over_one_minus_albedo(tmp_path, wavelengths, rho):
    path = write_scene(tmp_path / "s.yaml", {
        "name": "furnace", "light": {"sky": "none", "sun": False},
        "eye": {"position_m": [0, 0, 0]},
        "materials": {"wall": {"reflectance": rho, "emission": 1.0}},
        "objects": [{"primitive": {"sphere": {"radius_m": 1.0, "subdivisions": 3}}, "material": "wall"}]})
    scene = load_scene(path, wavelengths)
    axes = np.random.default_rng(2).normal(size=(200, 3))
    l = look(scene, axes / np.linalg.norm(axes, axis=1, keepdims=True), 256, depth=16)
    assert l.mean() == pytest.approx(1.0 / (1.0 - rho), rel=0.01)
    # Grey everywhere: every wavelength the same.
    np.testing.assert_allclose(l.std(axis=1), 0.0, atol=1e-9)


def test_a_small_disc_swept_across_the_axis_traces_the_acceptance_function(tmp_path, wavelengths):
    # A virtual version of Eheim & Wehner's (1972) recordings: a bright disc 0.2° in
    # radius at 1 m, swept across the receptor's axis, against a black background.
    radius = float(np.tan(np.radians(0.2)))
    path = write_scene(tmp_path / "s.yaml", {
        "name": "disc", "light": {"sky": "none", "sun": False},
        "eye": {"position_m": [0, 0, 0]},
        "materials": {"lamp": {"reflectance": 0.0, "emission": 1.0}},
        "objects": [{"primitive": {"sphere": {"radius_m": radius, "subdivisions": 5}},
                     "material": "lamp", "translate_m": [1.0, 0, 0]}]})
    scene = load_scene(path, wavelengths)
    delta_rho = 2.6
    offsets = np.linspace(-3.0, 3.0, 61)
    axes = np.column_stack([np.cos(np.radians(offsets)), np.sin(np.radians(offsets)), np.zeros_like(offsets)])
    response = look(scene, axes, 16384, depth=1, delta_rho=delta_rho)[:, 0]

    def gaussian(x, a, s):
        return a * np.exp(-0.5 * (x / s) ** 2)

    (a, s), _ = curve_fit(gaussian, offsets, response, p0=[response.max(), 1.0])
    fwhm = 2.0 * np.sqrt(2.0 * np.log(2.0)) * abs(s)
    # The disc itself widens the curve by 0.4 % (its own variance, a²/4).
    assert fwhm == pytest.approx(delta_rho, rel=0.03)


def test_noise_falls_as_one_over_the_square_root_of_the_samples(tmp_path, wavelengths):
    path = write_scene(tmp_path / "s.yaml", {
        "name": "noise", "light": {"sky": "preetham", "sun": True, "sun_elevation_deg": 40},
        "eye": {"position_m": [0, 0, 0.5]}, "materials": {"leaf": {"reflectance": LEAF}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0e5}}, "material": "leaf"}]})
    scene = load_scene(path, wavelengths)
    # Identical receptors: their spread is the estimator's noise (from sampling the sky).
    axes = np.tile([0.0, 0.0, -1.0], (400, 1))
    spread = {spp: look(scene, axes, spp)[:, 40].std() for spp in (16, 256)}
    assert spread[16] / spread[256] == pytest.approx(4.0, rel=0.2)


def traced_fan(tmp_path, n, rng_seed, samples, depth, step_nm, runs):
    """Radiance of n receptors fanned below the horizon, traced in the meadow once per (batch_rays, threads)."""
    axes = fan(n, [1.0, 0.0, -0.3], 40, np.random.default_rng(rng_seed))
    table = ReceptorTable(id=np.arange(n), side=np.repeat(["right"], n), position=np.zeros((n, 3)), axis=axes,
                          facet_diameter_um=np.full(n, 20.0), delta_phi_deg=np.full(n, 2.0),
                          delta_rho_deg=np.full(n, 2.6))
    write_receptors(tmp_path / "receptors.csv", table)
    radiance = []
    for batch_rays, threads in runs:
        out = tmp_path / f"radiance_{batch_rays}_{threads}.npz"
        trace_part(tmp_path / "receptors.csv", MEADOW, {"radiance": out},
                   spectral={"start_nm": 300, "end_nm": 700, "step_nm": step_nm},
                   trace={"samples_per_receptor": samples, "depth": depth, "seed": 5, "batch_rays": batch_rays},
                   threads=threads,
                   receptor_set=load_receptor_set())
        radiance.append(np.load(out)["radiance"])
    assert radiance[0].max() > 0.0
    return radiance


def test_a_trace_is_bit_identical_however_it_is_batched_and_threaded(tmp_path):
    """Batch size and threads change how rays are grouped, never a receptor's result."""
    radiance = traced_fan(tmp_path, 1024, 2, 128, 3, 5, [(1 << 17, 1), (1 << 14, 1), (5000, 2)])
    for other in radiance[1:]:
        np.testing.assert_array_equal(other, radiance[0])


def test_bundles_of_any_sample_count_are_traced_in_batches_no_larger_than_asked():
    """A receptor with more samples than a batch holds is split into blocks, summed in order."""
    seen = []

    def fake(blocks):
        seen.append(len(blocks.bundle) * blocks.samples)
        # Each block's mean and weight follow from its bundle and samples alone.
        mean = (blocks.bundle * 1000.0 + blocks.first_sample / 7.0)[:, None] * [1.0, 2.0]
        return mean, np.full(len(blocks.bundle), float(blocks.samples))

    samples = 5000  # a replicate in four blocks of 1024 and one of 904
    want = None
    for batch_rays, threads in [(1024, 1), (3000, 2), (1 << 17, 2)]:
        seen.clear()
        got = trace_bundles(fake, 3, 9, TraceSettings(samples, 1, 1, batch_rays, threads), 2, np.full(6, samples),
                            [2, 5])
        assert max(seen) <= batch_rays and sum(seen) == 2 * 6 * samples
        if want is None:
            starts = np.arange(0, samples, SAMPLE_BLOCK)
            counts = np.minimum(SAMPLE_BLOCK, samples - starts)
            # Replicate j's samples are numbered from j << REPLICATE_SHIFT.
            want = np.array([[[(b * 1000.0 + ((j << REPLICATE_SHIFT) + starts) / 7.0) @ counts / samples]
                              for j in (2, 5)] for b in range(3, 9)]) * [1.0, 2.0]
            np.testing.assert_allclose(got, want, rtol=1e-12)
            want = got
        np.testing.assert_array_equal(got, want)
    # 10⁸ samples a receptor: the first batch is made without listing all the blocks.
    from beeoptics.light.batching import _batches

    first = next(_batches(0, np.full(600, 10**8), range(8), 1024))
    assert sum(len(b.bundle) * b.samples for b in first) == 1024


def test_bundles_of_many_sample_counts_are_traced_in_few_calls():
    """An adaptive trace's receptors each take their own samples: batched as listed, 100 sizes made a call
    of a few bundles for every size in every batch; ordered by size, a batch holds one or two."""
    from beeoptics.light.batching import _batches

    samples = np.arange(2000) % 100 + 8
    batches = list(_batches(0, samples, range(8), 1 << 14))
    calls = sum(len(batch) for batch in batches)
    assert calls <= len(np.unique(samples)) + len(batches)
    # Every replicate of every bundle once, whatever the order.
    units = np.concatenate([np.repeat(b.bundle, b.samples) for batch in batches for b in batch])
    assert np.array_equal(np.bincount(units), 8 * samples)


def test_the_scrambled_sequence_is_made_once_a_seed_and_drawn_from_by_threads_at_once(monkeypatch):
    """Its digit permutations took a quarter of a small trace call's time besides the rays; threads tracing
    batches at once each draw from their own place in it."""
    from concurrent.futures import ThreadPoolExecutor

    from scipy.stats import qmc

    from beeoptics.light import sampler

    sampler._scrambled_halton.cache_clear()
    made, halton = [], qmc.Halton
    monkeypatch.setattr(qmc, "Halton", lambda *a, **k: made.append(a) or halton(*a, **k))
    streams = np.arange(64)
    firsts = [np.full(64, start) for start in (0, 5, 100, 7)]

    def points(first):
        return sampler.shifted_halton(32, 11, streams, (1, 2), first)

    alone = [points(first) for first in firsts]
    with ThreadPoolExecutor(4) as pool:
        together = list(pool.map(points, firsts * 20))
    assert len(made) == 1
    for i, drawn in enumerate(together):
        np.testing.assert_array_equal(drawn, alone[i % 4])


def test_a_trace_in_blocks_is_bit_identical_however_it_is_batched_and_threaded(tmp_path):
    """8,800 samples a receptor: eight replicates each in blocks of 1,024 and 76, batched two ways."""
    first, second = traced_fan(tmp_path, 6, 4, 8800, 2, 20, [(1024, 1), (4096, 2)])
    np.testing.assert_array_equal(first, second)


@pytest.mark.parametrize("delta_rho", [2.6, 10.0])
def test_the_sun_swept_across_a_cone_is_resolved_with_little_noise(tmp_path, wavelengths, delta_rho):
    # A receptor's direct sunlight is L ∫A dω over the disc, over ∫A dω over the sphere.
    # Cone samples alone hit the 0.27° disc a few times in a thousand: at 64 samples a
    # receptor saw the sky alone or a flash tens of times too bright. Sampling the disc
    # too, weighed against the cone's samples (Veach 1997), leaves little noise.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "sun", "light": {"sky": "none", "sun": True, "sun_elevation_deg": 40.0, "sun_azimuth_deg": 0.0},
        "eye": {"position_m": [0, 0, 0]}, "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0}}, "material": "grey", "translate_m": [0, 0, -1.0e4]}]})
    scene = load_scene(path, wavelengths)
    sigma = cone_sigma(delta_rho)
    offsets = np.radians(np.linspace(0.0, 2.0 * delta_rho, 9))
    elevation = np.radians(40.0) + offsets
    axes = np.column_stack([np.cos(elevation), np.zeros_like(elevation), np.sin(elevation)])
    seen = np.array([trace_paths(scene, np.zeros((len(axes), 3)), *cone_samples(axes, delta_rho, 64, seed),
                                 depth=1, seed=seed, cones=(axes, np.full(len(axes), sigma)))[:, 40]
                     for seed in range(1, 9)])
    theta = np.linspace(0.0, np.pi, 200_001)
    z = 2.0 * np.pi * np.trapezoid(np.exp(-0.5 * (theta / sigma) ** 2) * np.sin(theta), theta)
    # The disc's mean acceptance, by a polar midpoint grid uniform over its solid angle.
    u = (np.arange(400) + 0.5) / 400
    cos_a, phi = np.meshgrid(1.0 - u * (1.0 - scene.sun.cos_radius), 2 * np.pi * u, indexing="ij")
    around_sun = np.stack([np.sqrt(1 - cos_a**2) * np.cos(phi), np.sqrt(1 - cos_a**2) * np.sin(phi), cos_a], -1)
    frame = tangent_frames(scene.sun.direction[None])[0]
    disc = around_sun[..., :1] * frame[0] + around_sun[..., 1:2] * frame[1] + around_sun[..., 2:] * scene.sun.direction
    mean_a = [np.exp(-0.5 * (np.arccos(np.clip(disc @ a, -1, 1)) / sigma) ** 2).mean() for a in axes]
    want = scene.sun.radiance[40] * scene.sun.solid_angle * np.array(mean_a) / z
    # Out to twice Δρ from the axis, where the receptor takes 10⁻⁵ of its peak: the
    # mean of eight seeds within 1 %, each seed's noise below 3 % (measured: 0.7–2.2 %).
    np.testing.assert_allclose(seen.mean(0), want, rtol=0.01)
    assert (seen.std(0) / want).max() < 0.03


def test_the_trace_knows_what_share_of_a_cone_met_a_target_first(tmp_path, wavelengths):
    # A ball 0.05 m across at 0.5 m, behind it a wall; a target sphere drawn round the ball.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "ball", "light": {"sky": "uniform", "radiance": SKY, "sun": False},
        "eye": {"position_m": [0, 0, 0]}, "materials": {"grey": {"reflectance": 0.3}},
        "objects": [{"primitive": {"sphere": {"radius_m": 0.025}}, "material": "grey", "translate_m": [0.5, 0, 0]},
                    {"primitive": {"plane": {"size_m": 4.0}}, "material": "grey", "rotate_deg": [0, -90, 0],
                     "translate_m": [2.0, 0, 0]}]})
    scene = load_scene(path, wavelengths)
    at, away = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    # Bundle 0 all at the ball, 1 all away from it, 2 half and half (by weight 1 : 3), 3 at the ball
    # but with the target drawn elsewhere.
    half = np.vstack([np.tile(at, (2, 1)), np.tile(away, (2, 1))])
    dirs = np.stack([np.tile(at, (4, 1)), np.tile(away, (4, 1)), half, np.tile(at, (4, 1))])
    weights = np.array([[1.0] * 4, [1.0] * 4, [1.0, 1.0, 3.0, 3.0], [1.0] * 4])
    centres = np.array([[0.5, 0, 0]] * 3 + [[0.0, 0.5, 0.0]])
    radiance, cover = trace_paths(scene, np.zeros((4, 3)), dirs, weights, depth=1, seed=1,
                                  target=(centres, np.full(4, 0.03)))
    np.testing.assert_allclose(cover, [1.0, 0.0, 0.25, 0.0])
    # Asking for the share changes nothing else.
    np.testing.assert_array_equal(radiance, trace_paths(scene, np.zeros((4, 3)), dirs, weights, depth=1, seed=1))


@pytest.mark.parametrize("sky_sampling", ["nee", "escape"])
def test_a_white_ball_in_a_uniform_sky_is_as_bright_as_its_albedo_times_the_sky(tmp_path, wavelengths, sky_sampling):
    # The white furnace's open form: a convex ball sees only the sky, so ρL leaves every point of it.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "ball", "light": {"sky": "uniform", "radiance": 1.0, "sun": False},
        "eye": {"position_m": [0, 0, 0]}, "materials": {"white": {"reflectance": 0.8}},
        "objects": [{"primitive": {"sphere": {"radius_m": 0.2, "subdivisions": 5}}, "material": "white",
                     "translate_m": [1.0, 0, 0]}]})
    scene = load_scene(path, wavelengths)
    l = look(scene, fan(200, [1, 0, 0], 6, np.random.default_rng(3)), 64, sky_sampling=sky_sampling)
    assert l.mean() == pytest.approx(0.8, rel=0.01)


def test_sampling_the_sky_changes_the_noise_of_a_meadow_not_its_mean(wavelengths):
    scene = load_scene(MEADOW, wavelengths)
    axes = fan(300, [0.9, 0.0, -0.45], 25, np.random.default_rng(4))
    nee, escape = (look(scene, axes, 256, sky_sampling=s).sum(axis=1) for s in ("nee", "escape"))
    ratio = nee / escape - 1.0
    # Unbiased: the receptors' mean difference within four of its standard errors, and under 2 %.
    assert abs(ratio.mean()) < max(4.0 * ratio.std() / np.sqrt(len(ratio)), 1e-3)
    assert abs(ratio.mean()) < 0.02


def test_sampling_the_sky_carries_its_polarisation_through_a_glossy_reflection(tmp_path, wavelengths):
    # A glossy dark ground under a clear, polarised sky, the sun left out: both estimators give the
    # same Stokes vectors on average.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "pond", "light": {"sky": "hosek_wilkie", "sun": False, "sun_elevation_deg": 30.0,
                                  "sun_azimuth_deg": 90.0},
        "eye": {"position_m": [0, 0, 1.0]},
        "materials": {"pond": {"reflectance": 0.05, "gloss": {"specular": 0.5, "exponent": 30.0,
                                                                "refractive_index": 1.33}}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0e5}}, "material": "pond"}]})
    scene = load_scene(path, wavelengths)
    axes = fan(200, [0.6, 0.0, -0.8], 20, np.random.default_rng(5))
    frames = np.tile([0.0, 1.0, 0.0], (len(axes), 1))
    out = {}
    for s in ("nee", "escape"):
        dirs, w = cone_samples(axes, 2.6, 128, 1)
        out[s] = trace_paths(scene, np.tile([0.0, 0.0, 1.0], (len(axes), 1)), dirs, w, depth=1, seed=1, frames=frames,
                             sky_sampling=s).sum(axis=2)
    intensity = out["escape"][:, 0].mean()
    for q in range(3):
        difference = (out["nee"][:, q] - out["escape"][:, q]) / intensity
        assert abs(difference.mean()) < max(4.0 * difference.std() / np.sqrt(len(axes)), 2e-3), q
    # The reflection polarises: Q is a good part of I.
    assert abs(out["escape"][:, 1].mean()) > 0.1 * intensity


@pytest.mark.parametrize("hemisphere", [False, True])
def test_a_uniform_sky_is_left_to_the_surfaces_own_sampling_without_a_shadow_ray(tmp_path, wavelengths, hemisphere):
    # Its compensated table is empty (MIS compensation): the default traces it as escape does, to the bit.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "plane", "light": {"sky": "uniform", "radiance": SKY, "sun": False, "hemisphere": hemisphere},
        "eye": {"position_m": [0, 0, 0.5]},
        "materials": {"leaf": {"reflectance": LEAF, "gloss": {"specular": 0.2, "exponent": 20.0}}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0e5}}, "material": "leaf"}]})
    scene = load_scene(path, wavelengths)
    dirs, w = cone_samples(fan(50, [0.6, 0, -0.8], 40, np.random.default_rng(7)), 2.6, 32, 1)
    out = {}
    for sky_sampling in ("nee", "escape"):
        counts = {}
        out[sky_sampling] = trace_paths(scene, np.tile(scene.eye_position, (50, 1)), dirs, w, depth=3, seed=1,
                                        counts=counts, sky_sampling=sky_sampling)
        assert counts["shadow"] == 0
    np.testing.assert_array_equal(out["nee"], out["escape"])


def test_sampling_a_sky_with_a_bright_aureole_from_its_compensated_table_is_unbiased(tmp_path, wavelengths):
    # A hazy sky, its sun's disc left out, over a glossy ground that mirrors its aureole: the default, which
    # draws from the table the aureole's light above the sky's mean, gives escape's mean.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "aureole", "light": {"sky": "hosek_wilkie", "turbidity": 6.0, "sun": False,
                                     "sun_elevation_deg": 30.0, "sun_azimuth_deg": 0.0},
        "eye": {"position_m": [0, 0, 1.0]},
        "materials": {"leaf": {"reflectance": LEAF, "gloss": {"specular": 0.3, "exponent": 40.0}}},
        "objects": [{"primitive": {"plane": {"size_m": 1.0e5}}, "material": "leaf"}]})
    scene = load_scene(path, wavelengths)
    axes = fan(200, [np.cos(np.radians(30.0)), 0.0, -np.sin(np.radians(30.0))], 25, np.random.default_rng(8))
    dirs, w = cone_samples(axes, 2.6, 64, 1)
    out, shadows = {}, {}
    for sky_sampling in ("nee", "escape"):
        counts = {}
        out[sky_sampling] = trace_paths(scene, np.tile(scene.eye_position, (len(axes), 1)), dirs, w, depth=2, seed=1,
                                        counts=counts, sky_sampling=sky_sampling).sum(axis=1)
        shadows[sky_sampling] = counts["shadow"]
    assert shadows["nee"] > 0 and shadows["escape"] == 0
    ratio = out["nee"] / out["escape"] - 1.0
    assert abs(ratio.mean()) < max(4.0 * ratio.std() / np.sqrt(len(ratio)), 1e-3)
    assert abs(ratio.mean()) < 0.02


#: A scene with every kind of light and surface the tracer's stages handle: a clear sky with its sun, a
#: Lambertian lawn, a coated ball, a glossy pond that polarises, a glowing ball.
EVERY_STAGE = {
    "name": "every stage",
    "light": {"sky": "hosek_wilkie", "turbidity": 3.0, "sun": True, "sun_elevation_deg": 40.0,
              "sun_azimuth_deg": 60.0},
    "eye": {"position_m": [0, 0, 0.3]},
    "materials": {"lawn": {"reflectance": LEAF},
                  "glaze": {"reflectance": 0.3, "coating": {"roughness": 0.2, "refractive_index": 1.5}},
                  "pond": {"reflectance": 0.05, "gloss": {"specular": 0.5, "exponent": 30.0, "refractive_index": 1.33}},
                  "lamp": {"reflectance": 0.2, "emission": 0.5}},
    "objects": [{"primitive": {"plane": {"size_m": 50.0}}, "material": "lawn"},
                {"primitive": {"sphere": {"radius_m": 0.15, "subdivisions": 3}}, "material": "glaze",
                 "translate_m": [1.0, 0, 0.15]},
                {"primitive": {"sphere": {"radius_m": 0.15, "subdivisions": 3}}, "material": "lamp",
                 "translate_m": [0.8, 0.6, 0.15]},
                {"primitive": {"plane": {"size_m": 1.0}}, "material": "pond", "translate_m": [0.7, -0.5, 0.01]}]}
#: What :func:`every_stage_traced` gave before the kernel was split into stages (at cbedd1d with the sky table
#: of MIS compensation and the replicates merged, the kernel still of 50 arguments).
EVERY_STAGE_TRACED = ROOT / "tests" / "data" / "traced" / "every_stage.npz"


def every_stage_traced(scene):
    """Each way of tracing EVERY_STAGE (depth 1 and 3, the sky sampled or met by escape; intensity, Stokes
    vectors, and cones with their sun and a target), each bundle's radiance summed over the grid and weighed by
    the wavelength's index: a few numbers that any change to the tracer's light moves."""
    axes = np.vstack([fan(4, np.subtract(at, scene.eye_position), 3, np.random.default_rng(8))
                      for at in ([2.0, 0.0, 0.0], [0.8, 0.6, 0.15], [1.0, 0.0, 0.15], [0.7, -0.5, 0.01])]
                     + [fan(4, scene.sun.direction, 1.5, np.random.default_rng(9))])
    n = len(axes)
    dirs, w = cone_samples(axes, 2.6, 32, 3)
    origins = np.tile(scene.eye_position, (n, 1))
    frames = tangent_frames(axes)[:, 0]
    cones = (axes, np.full(n, cone_sigma(2.6)))
    out = {}
    for depth in (1, 3):
        for sky in ("nee", "escape"):
            case = dict(depth=depth, seed=5, sky_sampling=sky)
            traced = {"intensity": trace_paths(scene, origins, dirs, w, **case),
                      "stokes": trace_paths(scene, origins, dirs, w, frames=frames, **case)}
            traced["cones"], out[f"d{depth}_{sky}_target"] = trace_paths(
                scene, origins, dirs, w, cones=cones, target=([1.0, 0.0, 0.15], 0.3), streams=np.arange(n) + 11,
                first_samples=np.full(n, 32), **case)
            for name, radiance in traced.items():
                out[f"d{depth}_{sky}_{name}"] = np.stack([radiance.sum(-1), radiance @ np.arange(radiance.shape[-1])])
    return out


def test_the_tracer_gives_the_light_it_gave_before_its_kernel_was_split_into_stages(tmp_path, wavelengths):
    """The same numbers as the kernel of 50 arguments gave, to the last digits the machine's maths library may
    change: a refactoring of the tracer's stages must leave its light as it was."""
    scene = load_scene(write_scene(tmp_path / "s.yaml", EVERY_STAGE), wavelengths)
    got = every_stage_traced(scene)
    with np.load(EVERY_STAGE_TRACED) as want:
        assert sorted(got) == sorted(want.files)
        for name in want.files:
            assert want[name].any(), name
            np.testing.assert_allclose(got[name], want[name], rtol=1e-12, atol=1e-12 * np.abs(want[name]).max(),
                                       err_msg=name)


def test_a_stream_beyond_the_samplers_numbering_is_refused(tmp_path, wavelengths):
    # Streams from 2²⁴ share their key's bits with the random dimensions': two would draw the same numbers.
    path = write_scene(tmp_path / "s.yaml", {
        "name": "plane", "light": {"sky": "uniform", "radiance": SKY, "sun": False}, "eye": {"position_m": [0, 0, 0.5]},
        "materials": {"leaf": {"reflectance": LEAF}},
        "objects": [{"primitive": {"plane": {"size_m": 10.0}}, "material": "leaf"}]})
    scene = load_scene(path, wavelengths)
    dirs, w = cone_samples(fan(2, [0, 0, -1], 10, np.random.default_rng(1)), 2.6, 4, 1)
    origins = np.tile(scene.eye_position, (2, 1))
    trace_paths(scene, origins, dirs, w, depth=1, seed=1, streams=np.array([0, (1 << 24) - 1]))
    with pytest.raises(ValueError, match="streams must lie in 0"):
        trace_paths(scene, origins, dirs, w, depth=1, seed=1, streams=np.array([0, 1 << 24]))
