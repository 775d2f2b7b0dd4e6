"""Each traced mean's standard error is calibrated: the truth lies within its 95 % interval 95 % of the time."""

import numpy as np
import pytest
from scipy import stats

from beeoptics.light.batching import TraceSettings
from beeoptics.light.precision import Precision, adaptive_samples, class_forms
from beeoptics.replicates import REPLICATES, T95, mean_covariance, standard_error
from beeoptics.light.scene import load_scene, raycasting_scene
from beeoptics.light.sensors import cone_samples, cone_sigma
from beeoptics.light.sampler import tangent_frames
from beeoptics.tracing import trace_cones
from conftest import ROOT, write_scene

MEADOW = ROOT / "tests" / "data" / "scenes" / "meadow_tiny" / "scene.yaml"
SEEDS = 40
#: The band a calibrated interval's coverage falls in over the cases here: 95 ± 3 %.
BAND = (0.92, 0.98)


def coverage(estimate, se, truth):
    """The share of cases whose truth lies within the estimate ± T95 · se."""
    return float(np.mean(np.abs(estimate - truth) <= T95 * se))


def horizon_fan(n, sigma, rng):
    """n unit axes within 1.5 σ of the horizon, at random azimuths."""
    elevation, azimuth = rng.uniform(-1.5, 1.5, n) * sigma, rng.uniform(0.0, 2.0 * np.pi, n)
    return np.column_stack([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                            np.sin(elevation)])


def below_horizon(axes, sigma, dip, steps=1500):
    """The share of each Gaussian acceptance cone (σ, radians) below ``dip`` (radians, each axis's) under the
    horizon, by quadrature over the sphere."""
    theta = (np.arange(steps) + 0.5) * 8.0 * sigma / steps
    phi = (np.arange(steps) + 0.5) * 2.0 * np.pi / steps
    frames = tangent_frames(axes)
    a = np.exp(-0.5 * (theta / sigma) ** 2) * np.sin(theta)
    z = (np.cos(theta)[None, :, None] * axes[:, 2, None, None]
         + np.sin(theta)[None, :, None] * (np.cos(phi)[None, None, :] * frames[:, 0, 2, None, None]
                                          + np.sin(phi)[None, None, :] * frames[:, 1, 2, None, None]))
    return ((z < -np.sin(dip)[:, None, None]) * a[None, :, None]).sum(axis=(1, 2)) / (a.sum() * steps)


def test_the_standard_errors_of_a_cone_across_a_bright_sky_and_a_grey_ground_are_calibrated(tmp_path, wavelengths):
    """A cone across the horizon of a grey plane under a uniform sky sees L above and ρL below, exactly.

    Without sampling the sky, each sample is L or ρL as its direction falls,
    so the only noise is the cone's quasi-random sampling, whose points are
    correlated: the plain variance of the samples over their count
    overstates the error (it ignores the stratification), and the
    replicates' deviation over K instead of √K understates it.
    """
    rho, n, samples, height, size = 0.3, 50, 256, 0.5, 1.0e5
    path = write_scene(tmp_path / "s.yaml", {
        "name": "horizon", "light": {"sky": "uniform", "radiance": 1.0, "sun": False},
        "eye": {"position_m": [0, 0, height]}, "materials": {"grey": {"reflectance": rho}},
        "objects": [{"primitive": {"plane": {"size_m": size}}, "material": "grey"}]})
    scene = load_scene(path, wavelengths)
    sigma = float(cone_sigma(2.6))
    axes = horizon_fan(n, sigma, np.random.default_rng(3))
    # Beyond the square's edge, seen 0.0006° below the horizon, the sky again.
    edge = size / 2.0 / np.abs(axes[:, :2]).max(axis=1) * np.hypot(axes[:, 0], axes[:, 1])
    truth = 1.0 - (1.0 - rho) * below_horizon(axes, sigma, np.arctan(height / edge))
    origins = np.tile(scene.eye_position, (n, 1))
    estimate, se, plain, over_k = [], [], [], []
    for seed in range(SEEDS):
        errors = {}
        settings = TraceSettings(samples, 3, seed, 1 << 17, sky_sampling="escape")
        radiance, _ = trace_cones(scene, origins, axes, np.full(n, 2.6), np.arange(n), 0, n, settings,
                                  len(wavelengths), errors=errors)
        estimate.append(radiance[:, 0])
        se.append(errors["radiance_se"][:, 0])
        # The same samples' values, each L or ρL, and their plain variance over their count.
        m = samples // REPLICATES
        value = np.concatenate([np.where(cone_samples(axes, 2.6, m, seed, first_samples=np.full(n, j << 24))[0][..., 2]
                                         < -np.sin(np.arctan(height / edge))[:, None], rho, 1.0)
                                for j in range(REPLICATES)], axis=1)
        plain.append(value.std(axis=1, ddof=1) / np.sqrt(samples))
        replicates = value.reshape(n, REPLICATES, m).mean(axis=2)
        over_k.append(replicates.std(axis=1, ddof=1) / REPLICATES)
        # The traced samples are these (the escape estimator is exact sample by sample), but for a sample
        # or so that grazes the plane's far edge in single precision.
        assert np.abs(radiance[:, 0] - value.mean(axis=1)).max() < 1.5 * (1.0 - rho) / samples
    estimate, se = np.array(estimate), np.array(se)
    assert BAND[0] <= coverage(estimate, se, truth) <= BAND[1]
    assert coverage(estimate, np.array(plain), truth) > BAND[1]
    assert coverage(estimate, np.array(over_k), truth) < BAND[0]


def test_the_standard_errors_of_a_meadow_are_calibrated_against_a_trace_of_32_times_the_samples(wavelengths):
    """Receptors in the tiny meadow, 64 samples under each of 40 seeds, against 2,048 samples under another."""
    scene = load_scene(MEADOW, wavelengths)
    n = 24
    rng = np.random.default_rng(5)
    axes = rng.normal(size=(n, 3)) + [1.0, 0.0, -0.6]
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    origins, drho, ids = np.tile(scene.eye_position, (n, 1)), np.full(n, 2.6), np.arange(n)

    def traced(samples, seed):
        errors = {}
        radiance, _ = trace_cones(scene, origins, axes, drho, ids, 0, n, TraceSettings(samples, 3, seed, 1 << 17),
                                  len(wavelengths), errors=errors)
        return radiance, errors["radiance_se"]

    reference, reference_se = traced(64 * 32, 1000)
    runs = [traced(64, seed) for seed in range(SEEDS)]
    estimate, se = np.array([r for r, _ in runs]), np.array([s for _, s in runs])
    # At the green, where grass reflects most; the reference's own error widens the interval a little.
    k = np.searchsorted(wavelengths, 550.0)
    assert (se[..., k] > 0.0).all()
    assert BAND[0] <= coverage(estimate[..., k], np.hypot(se[..., k], reference_se[:, k]), reference[:, k]) <= BAND[1]
    assert coverage(estimate[..., k], se[..., k] * np.sqrt(REPLICATES) / REPLICATES, reference[:, k]) < BAND[0]


def test_one_replicate_gives_no_standard_error():
    assert np.isnan(standard_error(np.ones((3, 1, 2)))).all()
    assert standard_error(np.array([[1.0, 3.0]]))[0] == pytest.approx(1.0)
    assert T95 == pytest.approx(stats.t.ppf(0.975, REPLICATES - 1), abs=1e-4)


def test_the_replicates_covariance_of_their_mean_is_numpy_s_over_their_count():
    replicates = np.random.default_rng(4).normal(size=(5, REPLICATES, 3))
    got = mean_covariance(replicates)
    for n in range(5):
        np.testing.assert_allclose(got[n], np.cov(replicates[n], rowvar=False) / REPLICATES)
    np.testing.assert_allclose(np.diagonal(got, axis1=1, axis2=2), standard_error(replicates) ** 2)


@pytest.fixture(scope="module")
def lamp(tmp_path_factory, wavelengths):
    """A bright ball 0.4° in radius, 1 m away along +x, on black, and its Embree scene: each receptor below
    sees it in its cone's tail, one sample in fifty. Built once for the tests that share it."""
    radius = float(np.tan(np.radians(0.4)))
    path = write_scene(tmp_path_factory.mktemp("lamp") / "lamp.yaml", {
        "name": "lamp", "light": {"sky": "none", "sun": False}, "eye": {"position_m": [0, 0, 0]},
        "materials": {"lamp": {"reflectance": 0.0, "emission": 1.0}},
        "objects": [{"primitive": {"sphere": {"radius_m": radius, "subdivisions": 4}}, "material": "lamp",
                     "translate_m": [1.0, 0, 0]}]})
    scene = load_scene(path, wavelengths)
    return scene, raycasting_scene(scene)


def off_the_lamp(n, offset_deg, rng):
    """n unit axes ``offset_deg`` off +x, at random azimuths about it."""
    phi, t = rng.uniform(0.0, 2.0 * np.pi, n), np.radians(offset_deg)
    return np.column_stack([np.full(n, np.cos(t)), np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi)])


def test_adaptive_sampling_is_unbiased_where_a_stopping_rule_is_not(lamp, wavelengths):
    """A rare bright patch: a pilot that misses it reads zero, precisely. Stein's two stages set its samples
    from the pilot and estimate from fresh ones, so their means agree with fixed sampling's within their
    errors; adding rounds until the error looks small, keeping them all, stops early on the receptors that
    missed it and reads low."""
    scene, rs = lamp
    n, seeds, rounds = 200, 6, 32
    axes = off_the_lamp(n, 1.65, np.random.default_rng(7))
    origins, drho, ids = np.zeros((n, 3)), np.full(n, 2.6), np.arange(n)
    flat = (wavelengths, np.ones((len(wavelengths), 1)))
    target = 0.2
    precision = Precision(class_forms(target, 1), 0.0, 64, 2048)

    def replicates(settings):
        """Each receptor's replicate catches (n, K) of a flat receptor, and its samples."""
        errors = {}
        trace_cones(scene, origins, axes, drho, ids, 0, n, settings, len(wavelengths), rs=rs, sensitivities=flat,
                    errors=errors)
        return errors["catches"][..., 0], errors["samples"]

    fixed, adaptive, stopped, taken = [], [], [], []
    for seed in range(seeds):
        fixed.append(replicates(TraceSettings(2048, 1, seed, 1 << 17))[0].mean(axis=1))
        q, samples = replicates(TraceSettings(2048, 1, seed + 100, 1 << 17, precision=precision))
        adaptive.append(q.mean(axis=1))
        taken.append(samples)
        # The stopping rule: rounds of 8 replicates of 8 samples (each round under a seed of its own), all
        # kept, until the replicates' relative standard error is within the target.
        kept, estimate, done = np.empty((n, 0)), np.zeros(n), np.zeros(n, bool)
        for round_ in range(rounds):
            kept = np.hstack([kept, replicates(TraceSettings(64, 1, 1000 * (seed + 1) + round_, 1 << 17))[0]])
            mean = kept.mean(axis=1)
            now = ~done & ((standard_error(kept) <= target * mean) | (round_ == rounds - 1))
            estimate[now], done = mean[now], done | now
        stopped.append(estimate)
    fixed, adaptive, stopped = np.array(fixed), np.array(adaptive), np.array(stopped)

    def z(estimates):
        """The mean difference from fixed sampling over the receptor-seed cases, in its standard errors."""
        d = (estimates - fixed).ravel()
        return d.mean() / (d.std(ddof=1) / np.sqrt(d.size))

    assert np.ptp(np.concatenate(taken)) > 0  # the samples did adapt
    assert abs(z(adaptive)) < 3.0
    assert z(stopped) < -3.0


def test_pooling_the_pilots_of_a_neighbourhood_meets_the_target_where_a_cone_s_own_pilot_misses(
        lamp, wavelengths, monkeypatch):
    """A ring of cones sees a bright ball in their tails, one sample in fifty: a pilot of 64 misses it in a
    quarter of them, which, judged by their own pilots alone, keep the fewest samples and err by most of
    their catch. Pooled with its neighbours' pilots (each seeing alike), every cone gets its samples. The
    cones being alike, the spread of their estimates over the ring is each one's error."""
    import beeoptics.light.precision

    scene, rs = lamp
    n = 48
    axes = off_the_lamp(n, 1.65, np.random.default_rng(9))
    flat = (wavelengths, np.ones((len(wavelengths), 1)))
    target = 0.2
    settings = TraceSettings(256, 1, 51, 1 << 17, precision=Precision(class_forms(target, 1), 0.0, 64, 4096))

    def ring_error():
        """The relative standard deviation of the ring's estimates."""
        errors = {}
        trace_cones(scene, np.zeros((n, 3)), axes, np.full(n, 2.6), np.arange(n), 0, n, settings, len(wavelengths),
                    rs=rs, sensitivities=flat, errors=errors)
        q = errors["catches"][..., 0].mean(axis=1)
        return q.std(ddof=1) / q.mean()

    assert ring_error() < 1.3 * target
    monkeypatch.setattr(beeoptics.light.precision, "NEIGHBOURHOOD", 1)  # each cone's own pilot alone
    assert ring_error() > 2.0 * target


def test_auto_holds_the_tracer_s_error_to_a_quarter_jnd_of_the_colour_and_of_the_achromatic_distance():
    """``auto`` asks of a catch's error what the receptor-noise-limited distances feel of it: an error common
    to the three classes (a cone's samples meeting more or less of a sunlit blade) moves no colour, and
    is held to a quarter of the green receptor's Weber fraction, 3 %, not to a quarter of blue's, 1.5 %; an
    error of the blue catch alone moves colour, by √(M_BB) JND per unit of log catch."""
    from beeoptics.io.errors import InputError
    from beeoptics.io.validation import config_default
    from beeoptics.vision.colourspace import rnl_distance, rnl_metric
    from beeoptics.vision.receptorset import load_receptor_set
    from beeoptics.vision.uncertainty import noise_forms

    trace = config_default("trace")
    bee_set = load_receptor_set()
    bee = TraceSettings.from_config({**trace, "precision": {"target": "auto"}}, classes=3, noise=noise_forms(bee_set))
    weber = np.array([0.13, 0.06, 0.12])  # UV, B, G (Vorobyev et al. 2001)
    np.testing.assert_array_equal(bee_set.weber, weber)
    # The metric is the distance's: ΔS² = Δfᵀ M Δf.
    df = np.log([1.3, 0.8, 1.1])
    assert np.isclose(df @ rnl_metric(weber) @ df, rnl_distance(np.exp(df), np.ones(3), weber) ** 2)

    k, m0 = REPLICATES, bee.precision.min_samples // REPLICATES
    se = 0.05  # each receptor's relative standard error of the pilot's mean, in the classes it errs in
    signs = np.resize([1.0, -1.0], k)  # replicates at ± d: sd(ddof=1)/√K = d √(K/(K − 1))/√K
    d = se * np.sqrt(k - 1)
    q = np.array([2.0, 3.0, 5.0])
    common = q * (1.0 + d * signs[:, None])  # (K, 3): one error in all three classes
    blue = q * (1.0 + d * signs[:, None] * np.array([0.0, 1.0, 0.0]))
    pilot = np.stack([common, blue])
    dof = k - 1
    inflation = dof / stats.chi2.ppf(1.0 - 0.9, dof)
    got = adaptive_samples(pilot, np.ones((2, 3)), bee.precision, np.array([[0], [1]]))
    quarter_jnd = 0.25
    want = np.ceil(m0 * inflation * np.array([(se / (quarter_jnd * weber[2])) ** 2,
                                              rnl_metric(weber)[1, 1] * (se / quarter_jnd) ** 2]))
    np.testing.assert_array_equal(got, want)
    # A set without receptor noise traces its fixed samples; a number asks it of every class.
    fly = load_receptor_set("drosophila_melanogaster")
    assert TraceSettings.from_config({**trace, "precision": {"target": "auto"}}, classes=len(fly.classes),
                                     noise=noise_forms(fly)).precision is None
    asked = TraceSettings.from_config({**trace, "precision": {"target": 0.05}}, classes=3)
    np.testing.assert_array_equal(adaptive_samples(pilot, np.ones((2, 3)), asked.precision, np.array([[0], [1]])),
                                  np.ceil(m0 * inflation * (se / 0.05) ** 2))
    with pytest.raises(InputError, match="trace.precision.min_samples: 128 is more than max_samples, 64"):
        TraceSettings.from_config({**trace, "precision": {"min_samples": 128, "max_samples": 64}}, classes=3)


def test_adaptive_sampling_gives_the_same_bytes_for_any_batching_threads_or_share(lamp, wavelengths):
    """A receptor's pilot, and so its samples, depend on nothing but the seed and its own id (not on the fixed
    samples_per_receptor a precision stands in for, whose replicates are fewer below eight samples)."""
    scene, rs = lamp
    n = 20
    axes = off_the_lamp(n, 1.65, np.random.default_rng(8))
    precision = Precision(class_forms(0.3, 1), 0.0, 64, 1024)
    runs = []
    for samples, batch_rays, threads, shares in [(256, 1 << 17, 1, [(0, n)]), (256, 3000, 2, [(0, 7), (7, n)]),
                                                  (4, 1 << 17, 2, [(0, n)])]:
        settings = TraceSettings(samples, 1, 4, batch_rays, threads, precision=precision)
        parts = []
        for first, last in shares:
            errors = {}
            radiance, _ = trace_cones(scene, np.zeros((n, 3)), axes, np.full(n, 2.6), np.arange(n), first, last,
                                      settings, len(wavelengths), rs=rs, errors=errors)
            parts.append((radiance, errors["radiance_se"], errors["samples"]))
        runs.append([np.concatenate(a) for a in zip(*parts)])
    assert np.ptp(runs[0][2]) > 0
    for run in runs[1:]:
        for a, b in zip(runs[0], run):
            np.testing.assert_array_equal(a, b)
