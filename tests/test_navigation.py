"""Environment maps: an eye resampled from a map sees what it sees traced directly, at any pose."""

import copy

import numpy as np
import pytest
from scipy.special import ndtr

import beeoptics
from beeoptics import tracing
from beeoptics.eye.optics import acceptance_solid_angle
from beeoptics.io.errors import InputError
from beeoptics.light.batching import TraceSettings
from beeoptics.light.sensors import cone_sigma
from beeoptics.navigation import envmap
from beeoptics.replicates import standard_error
from beeoptics.vision.catches import quantum_catches
from beeoptics.vision.receptorset import load_receptor_set
from conftest import DATA

EYE = DATA / "eyes" / "tiny" / "eye.yaml"
FLOWER = DATA / "scenes" / "flower" / "scene.yaml"
#: The tiny eye's receptors given this acceptance angle, degrees, so that the rule's map (a quarter of it apart,
#: 7,704 directions in rings of multiples of 36) traces in a second; the method is the same at any Δρ.
DELTA_RHO_DEG = 10.0
#: The maps' heading step, degrees: every heading below a whole number of them.
STEP_DEG = 10.0


def horizon_map(spacing_deg):
    """A map of a bright sky over a black ground, as a map's own acceptance sees it: the horizon's step
    blurred by the map's Gaussian, Φ(elevation/σ_map) (a great circle's, in the small-angle limit)."""
    n = len(envmap.ring_grid(spacing_deg, STEP_DEG).directions)
    env = envmap.EnvironmentMap(np.zeros(3), spacing_deg, STEP_DEG, np.zeros(1), None, {}, np.zeros(n), 8, 1, 1)
    elevation = np.arcsin(env.grid.directions[:, 2])
    return env, ndtr(elevation / cone_sigma(env.delta_rho_deg))


def test_a_horizon_resampled_is_the_receptors_own_gaussian_edge():
    # A receptor across the horizon sees Φ(e/σ) of its own σ: the map's blur and the kernel's together make
    # exactly its acceptance, where the kernel alone of its Δρ would make it 12 % wider (Φ 0.841 → 0.814 at e = σ).
    env, sky = horizon_map(0.5)
    rng = np.random.default_rng(1)
    delta_rho = np.repeat([4.0, 5.0, 6.0], 40) * env.spacing_deg
    sigma = cone_sigma(delta_rho)
    elevation, azimuth = rng.uniform(-2.0, 2.0, len(sigma)) * sigma, rng.uniform(0.0, 2.0 * np.pi, len(sigma))
    axes = np.column_stack([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                            np.sin(elevation)])
    weights = envmap.resampling_matrix(env, axes, delta_rho)
    np.testing.assert_allclose(weights @ sky, ndtr(elevation / sigma), atol=0.001)
    np.testing.assert_allclose(weights @ np.ones(len(sky)), 1.0, rtol=1e-12)
    with pytest.raises(InputError, match="spacing_deg"):
        envmap.resampling_matrix(env, axes, 3.0 * env.spacing_deg)


def test_a_few_narrow_receptors_set_no_spacing_and_are_resampled_at_the_narrowest_the_map_resolves():
    # An eye of 2° receptors with 1 % at 0.2° (as a bumblebee's lattice edge, its facet angles' artefacts): the
    # rule's spacing is its 2nd percentile's 2° over four, 0.5°, not the least's 0.05° (21 million directions);
    # the narrow ones are counted and resampled as receptors of 4 spacings, the narrowest the map resolves.
    delta_rho = np.r_[np.full(990, 2.0), np.full(10, 0.2)]
    assert envmap.map_spacing_deg(delta_rho) == 0.5
    env, sky = horizon_map(0.5)
    assert envmap.clamped(env, delta_rho).sum() == 10
    # One narrow receptor among 2° ones about one axis across the horizon: its kernel is theirs.
    axes = np.tile([[1.0, 0.0, 0.02]], (100, 1)) / np.hypot(1.0, 0.02)
    weights = envmap.resampling_matrix(env, axes, np.r_[0.2, np.full(99, 2.0)])
    assert weights.nnz > 0 and (weights[0] != weights[1]).nnz == 0
    np.testing.assert_allclose(weights[0] @ sky, ndtr(np.arctan(0.02) / cone_sigma(2.0)), atol=0.001)


@pytest.fixture(scope="module")
def eye():
    tiny = beeoptics.load_eye(EYE)
    tiny.table = tiny.table._replace(delta_rho_deg=np.full(len(tiny.table.id), DELTA_RHO_DEG))
    return tiny


@pytest.fixture(scope="module")
def scene():
    return beeoptics.load_scene(FLOWER, step_nm=20)


@pytest.fixture(scope="module")
def env(eye, scene):
    return envmap.environment_map(scene, scene.scene.eye_position, eye, heading_step_deg=STEP_DEG, samples=8, depth=1,
                                  seed=5)


def test_resampled_catches_equal_direct_ones_within_their_errors(eye, scene, env):
    # Headings round the flower and a pitch, the map traced once from the head's centre; the tiny eye's
    # facets lie up to 1.6 mm from it, 0.8° at the flower 12 cm away against a Δρ of 10°: below the noise here.
    classes = list(eye.receptor_set.classes)
    q, weights = envmap.map_catches(env, eye), envmap.eye_weights(env, eye, pitch_deg=-10.0)
    z = []
    for heading, pitch in ((0.0, -10.0), (120.0, -10.0), (240.0, -10.0), (35.0, 35.0)):
        catches, se = envmap.resampled_catches(env, eye, heading_deg=heading, pitch_deg=pitch,
                                               weights=weights if pitch == -10.0 else None, q=q)
        view = beeoptics.look(eye, scene, heading_deg=heading, pitch_deg=pitch, roll_deg=0.0, samples=64, depth=1,
                              seed=3)
        direct = view.catches[classes].to_numpy()
        z.append((catches - direct) / np.hypot(se, view.catches[[f"se_{k}" for k in classes]].to_numpy()))
    z = np.concatenate(z).ravel()
    # Differences over errors from 8 replicates each: Student-like, rms about 1.1; a bias or a kernel of the
    # wrong width shows as a mean or an rms well away from it.
    assert np.isfinite(z).all()
    assert abs(z.mean()) < 0.15 and 0.8 < np.sqrt(np.mean(z * z)) < 1.4, (z.mean(), np.sqrt(np.mean(z * z)))


#: A dark ball 1.5 cm in radius, its near side 2.5 cm from the head's centre, under the flower scene's light: the
#: tiny eye's facets, 1.2–1.6 mm from the centre, see its edge up to 3.7° (one σ of the kernel) off where the
#: centre sees it.
BALL = """name: ball
light: {sky: hosek_wilkie, turbidity: 3.0, sun: true, sun_elevation_deg: 50.0, sun_azimuth_deg: 150.0}
eye: {position_m: [0.0, 0.0, 0.1]}
materials:
  dark: {reflectance: {sigmoid: {low: 0.01, high: 0.5, edge_nm: 500, width_nm: 10}}}
  leaf: {reflectance: {sigmoid: {low: 0.04, high: 0.45, edge_nm: 520, width_nm: 15}}}
objects:
  - {name: ground, primitive: {plane: {size_m: 100.0}}, material: leaf}
  - {name: ball, primitive: {sphere: {radius_m: 0.015}}, material: dark, translate_m: [0.04, 0.0, 0.1]}
"""


def test_a_near_surface_is_seen_from_each_facet_not_the_head_centre(eye, tmp_path):
    # The receptors whose kernels meet the ball (a nearness above 15 m⁻¹: within 6.7 cm), at three poses: their
    # kernels turned by the parallax, the resampled catches equal look's, which traces from every facet, within
    # their errors but for the cones across the ball's edge, which turn as a whole by their mean nearness (rms
    # 1.49 of the errors); the kernels left about their axes, as seen from the head's centre, 3.12.
    (tmp_path / "scene.yaml").write_text(BALL)
    scene = beeoptics.load_scene(tmp_path / "scene.yaml", step_nm=20)
    env = envmap.environment_map(scene, scene.scene.eye_position, eye, heading_step_deg=STEP_DEG, samples=16,
                                 depth=1, seed=5)
    classes = list(eye.receptor_set.classes)
    z = []
    for heading, pitch in ((0.0, 0.0), (20.0, 10.0), (340.0, -10.0)):
        weights = envmap.eye_weights(env, eye, pitch_deg=pitch)
        near = weights.kernel @ env.nearness[envmap.turn_order(env.grid, heading)] > 15.0
        catches, se = envmap.resampled_catches(env, eye, heading_deg=heading, pitch_deg=pitch, weights=weights)
        view = beeoptics.look(eye, scene, heading_deg=heading, pitch_deg=pitch, roll_deg=0.0, samples=256, depth=1,
                              seed=3)
        direct, direct_se = view.catches[classes].to_numpy(), view.catches[[f"se_{k}" for k in classes]].to_numpy()
        z.append(((catches - direct) / np.hypot(se, direct_se))[near])
    z = np.concatenate(z).ravel()
    assert len(z) > 300 and np.isfinite(z).all()
    assert abs(z.mean()) < 0.5 and np.sqrt(np.mean(z * z)) < 2.0, (len(z), z.mean(), np.sqrt(np.mean(z * z)))


def test_a_turn_by_whole_steps_is_the_grid_reordered(eye, env):
    # The heading's own matrix and the heading-0 matrix applied to the map turned ring by ring are the same sums.
    turned = envmap.eye_weights(env, eye, heading_deg=250.0, pitch_deg=20.0, roll_deg=5.0)
    by_order = envmap.eye_weights(env, eye, pitch_deg=20.0, roll_deg=5.0)
    order = envmap.turn_order(env.grid, 250.0)
    for matrix in envmap.Weights._fields:
        q = envmap.map_catches(env, eye)[0]
        np.testing.assert_allclose(getattr(by_order, matrix) @ q[order], getattr(turned, matrix) @ q,
                                   rtol=1e-10, atol=1e-12 * np.abs(q).max())


def test_a_map_file_is_read_back_or_refused_in_one_line(env, eye, scene, tmp_path):
    for position in ([0.0, np.nan, 0.1], [0.0, 0.1], "here"):
        with pytest.raises(InputError, match="environment_map: position_m"):
            envmap.environment_map(scene, position, eye)
    # A map finer than the tracer's random streams allow (the finest bumblebee receptors' by the rule), before
    # any tracing.
    with pytest.raises(InputError, match="environment_map: spacing_deg: 0.045° apart makes 21,119,760 directions"):
        envmap.environment_map(scene, scene.scene.eye_position, eye, spacing_deg=0.045)
    path = tmp_path / "map.npz"
    envmap.write_map(path, env)
    back = envmap.read_map(path)
    for field in envmap.ARRAYS:
        np.testing.assert_array_equal(getattr(back, field), getattr(env, field))
    for a, b in zip(back.catches[eye.receptor_set.name], env.catches[eye.receptor_set.name]):
        np.testing.assert_array_equal(a, b)
    assert (back.spacing_deg, back.heading_step_deg, back.samples, back.depth, back.seed) == (2.5, STEP_DEG, 8, 1, 5)
    # Without its spectral radiance (the default) a map serves eyes of its own sets and curves, and refuses
    # others in one line.
    assert back.radiance is None
    with pytest.raises(InputError, match=r"map\.npz: sets: the map holds the catches of apis_mellifera only"):
        envmap.map_catches(back, eye, sensitivities="template")
    data = dict(np.load(path))
    np.savez(path, **{**data, "q_se.apis_mellifera": data["q_se.apis_mellifera"][:-1]})
    with pytest.raises(InputError, match=r"map\.npz: q_se\.apis_mellifera: shape"):
        envmap.read_map(path)
    # A map of the files before the catches were kept per set: refused, not read as a map of no set.
    np.savez(path, **{k: v for k, v in data.items() if "." not in k and k != "sets"}, q=data["q.apis_mellifera"])
    with pytest.raises(InputError, match=r"map\.npz: sets: missing: the map was written before"):
        envmap.read_map(path)
    path.write_text("not a map")
    with pytest.raises(InputError, match=r"map\.npz: not an environment map"):
        envmap.read_map(path)


def test_a_map_keeps_its_catches_errors_as_traced_without_making_the_radiances(eye, scene, monkeypatch):
    made = []
    monkeypatch.setattr(tracing, "standard_error", lambda *a, **k: made.append(1) or standard_error(*a, **k))
    env = envmap.environment_map(scene, scene.scene.eye_position, eye, heading_step_deg=STEP_DEG, samples=2, depth=1,
                                 seed=5)
    assert not made  # the radiance's standard error, which a map does not keep
    # The same directions traced at once, each its own stream, with every error made as a trace makes them.
    n, wl, errors = len(env.nearness), scene.wavelengths_nm, {}
    q = env.catches[eye.receptor_set.name]
    settings = TraceSettings(samples=2, depth=1, seed=5, batch_rays=1 << 17)
    tracing.trace_cones(scene.scene, np.broadcast_to(env.position_m, (n, 3)), env.grid.directions,
                        np.full(n, env.delta_rho_deg), np.arange(n), 0, n, settings, len(wl), rs=scene.raycasting,
                        sensitivities=(wl, q.curves), errors=errors)
    np.testing.assert_array_equal(q.q_se, standard_error(errors["catches"])
                                  / acceptance_solid_angle(np.full(n, env.delta_rho_deg))[:, None])


def test_a_map_of_two_receptor_sets_gives_each_eye_its_own_catches(eye, scene, tmp_path):
    # The tiny eye as a honey bee and as a bumblebee (Skorupski et al.'s 2007 curves, other peaks): one map
    # traced for both holds each set's catches as a map traced for that eye alone does (the same rays, streams
    # and replicates; the sets' curves only stacked, which moves the sums' last bits), and the radiance, which
    # it no longer keeps by default, gives them too.
    bee = copy.copy(eye)
    bee.receptor_set = load_receptor_set("bombus_terrestris")
    both = envmap.environment_map(scene, scene.scene.eye_position, [eye, bee], heading_step_deg=STEP_DEG,
                                  samples=2, depth=1, seed=5, radiance=True)
    assert list(both.catches) == ["apis_mellifera", "bombus_terrestris"]
    envmap.write_map(tmp_path / "both.npz", both._replace(radiance=None))
    lean = envmap.read_map(tmp_path / "both.npz")
    for one in (eye, bee):
        alone = envmap.environment_map(scene, scene.scene.eye_position, one, heading_step_deg=STEP_DEG, samples=2,
                                       depth=1, seed=5)
        assert alone.radiance is None and list(alone.catches) == [one.receptor_set.name]
        want = envmap.map_catches(alone, one)
        for got in (envmap.map_catches(both, one), envmap.map_catches(lean, one)):
            for a, b in zip(got, want):
                np.testing.assert_allclose(a, b, rtol=1e-9, atol=0.0)
        np.testing.assert_allclose(quantum_catches(both.radiance, alone.catches[one.receptor_set.name].curves,
                                                          both.wavelengths_nm), want[0], rtol=1e-9)
    # The two sets' catches differ (6 % in the median, 20–40 % in UV): the other set's would not pass for this eye's.
    honey, bumble = both.catches.values()
    assert np.median(np.abs(honey.q / bumble.q - 1.0)) > 0.03
