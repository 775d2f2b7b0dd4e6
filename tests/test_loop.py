"""The closed loop: Gymnasium's own checker passes the environment, the head flies the arcs its rates give and
stops at surfaces, and the example agent finds its flower by UV–green contrast where a blind one does not."""

import importlib.util
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import beeoptics
import beeoptics.tracing
from beeoptics.io.errors import InputError
from beeoptics.light import integrator
from beeoptics.loop import SPEED_MAX_M_S, BeeView
from beeoptics.raycasting import first_hits
from beeoptics.replicates import standard_error
from conftest import ROOT

DATA = ROOT / "tests" / "data"
FLOWER = DATA / "scenes" / "flower" / "scene.yaml"
#: As tests/test_api.py looks: few rays on a coarse spectrum.
FAST = {"samples": 4, "depth": 1}


@pytest.fixture(scope="module")
def eye():
    return beeoptics.load_eye(DATA / "eyes" / "tiny" / "eye.yaml")


@pytest.fixture(scope="module")
def scene():
    return beeoptics.load_scene(FLOWER, step_nm=20)


def test_gymnasium_checks_the_environment_with_its_errors(eye, scene):
    env = gymnasium.make("beeoptics/BeeView-v0", eye=eye, scene=scene, target_m=[0.12, 0.0, 0.06], errors=True,
                         render_mode="rgb_array", **FAST)
    with warnings.catch_warnings():
        # Its two advices do not apply: actions are in m/s and deg/s, and a catch has no upper bound.
        warnings.filterwarnings("ignore", ".*For Box action spaces")
        warnings.filterwarnings("ignore", ".*A Box observation space maximum value is infinity")
        check_env(env.unwrapped)
    observation, _ = env.reset(seed=5)
    assert set(observation) == {"catches", "se"} and observation["catches"].shape == (len(eye.table.id), 3)
    assert (observation["se"] > 0).all() and (observation["se"] < observation["catches"]).all()
    # It renders the last look's visual field, in the bee's colours.
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3 and frame.any()
    with pytest.raises(InputError, match="render_mode"):
        BeeView(eye, scene, target_m=[0.0, 0.0, 0.0], render_mode="human")


def test_turning_at_a_constant_rate_flies_the_arc_and_a_step_into_the_ground_is_refused(eye, scene):
    env = BeeView(eye, scene, target_m=[0.0, 0.0, 0.0], climb=True, **FAST)
    _, start = env.reset(seed=1)
    # A quarter turn a step at 0.5 m/s: the chords of a circle of radius v/ω, back at the start after four.
    speed, rate = 0.5, 90.0 / env.step_s
    radius = speed / np.radians(rate)
    positions = [env.step([speed, rate, 0.0])[4]["position_m"] for _ in range(4)]
    np.testing.assert_allclose(np.linalg.norm(positions[0] - start["position_m"]), radius * np.sqrt(2.0), rtol=1e-12)
    np.testing.assert_allclose(positions[1] - start["position_m"], [0.0, 2.0 * radius, 0.0], atol=1e-12)
    np.testing.assert_allclose(positions[3], start["position_m"], atol=1e-12)
    # Down at full speed from 10 cm: the ground is met within the step; the head stays, and the episode ends.
    _, reward, terminated, truncated, info = env.step([0.0, 0.0, -SPEED_MAX_M_S])
    assert info["met"] and terminated and not truncated
    np.testing.assert_array_equal(info["position_m"], positions[3])


def test_the_same_seed_gives_the_same_flight_and_another_seed_other_catches(eye, scene):
    env = BeeView(eye, scene, target_m=[0.12, 0.0, 0.06], max_steps=2, **FAST)

    def flight(seed):
        first, _ = env.reset(seed=seed)
        return [first, *(env.step([0.3, 45.0])[0] for _ in range(2))]

    once, again, other = flight(3), flight(3), flight(4)
    for a, b, c in zip(once, again, other):
        np.testing.assert_array_equal(a, b)
        assert not np.array_equal(a, c)


def test_the_agent_reaches_its_flower_by_uv_green_contrast_and_a_blind_one_does_not(eye, scene, monkeypatch):
    monkeypatch.chdir(ROOT)
    spec = importlib.util.spec_from_file_location("closed_loop", ROOT / "examples" / "closed_loop.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    env = BeeView(eye, scene, target_m=example.FLOWER_M, terminated=example.reached, max_steps=8, **FAST)
    closest = {name: np.linalg.norm(example.fly(env, policy, *example.START) - example.FLOWER_M, axis=1).min()
               for name, policy in (("seeing", example.towards_uv_contrast(eye, scene)),
                                    ("blind", example.straight))}
    assert closest["seeing"] < example.REACHED_M < closest["blind"]


@pytest.mark.parametrize("make, field", [
    (lambda e, s: BeeView(e, s), "target_m"),
    (lambda e, s: BeeView(e, s, target_m=[0, 0, 0], step_s=0.0), "step_s"),
    (lambda e, s: BeeView(e, s, target_m=[0, 0, 0], max_steps=2.5), "max_steps"),
    (lambda e, s: BeeView(e, s, target_m=[0, 0, 0], **FAST).step([np.nan, 0.0]), "action"),
    (lambda e, s: BeeView(e, s, target_m=[0, 0, 0], **FAST).reset(options={"position_m": [0, 0]}), "position_m"),
])
def test_bad_input_is_refused_naming_the_field(eye, scene, make, field):
    with pytest.raises(InputError) as refused:
        make(eye, scene)
    assert refused.value.field == field


def test_a_step_leaves_the_errors_it_does_not_observe_to_be_made_when_asked_and_they_are_the_looks(
        eye, scene, monkeypatch):
    made = []
    monkeypatch.setattr(beeoptics.tracing, "standard_error",
                        lambda *a, **k: made.append(1) or standard_error(*a, **k))
    env = BeeView(eye, scene, target_m=[0.12, 0.0, 0.06], **FAST)
    env.reset(seed=2)
    observation, _, _, _, info = env.step([0.3, 45.0])
    assert not made
    # Drawn as the loop draws a look's seed: its generator's second number after the reset.
    rng = np.random.default_rng(2)
    seed = [int(rng.integers(2**31)) for _ in range(2)][1]
    # On other threads than the loop's (all the cores).
    view = beeoptics.look(eye, scene, position_m=info["position_m"], heading_deg=info["heading_deg"], seed=seed,
                          threads=1, **FAST)
    np.testing.assert_array_equal(observation, np.nan_to_num(view.class_catches()[0]).astype(np.float32))
    for field in ("radiance", "radiance_se", "replicate_catches"):
        np.testing.assert_array_equal(getattr(env._view, field), getattr(view, field))


def test_the_last_rays_asked_only_whether_they_meet_a_surface_give_the_nearest_hits_radiance(eye, scene, monkeypatch):
    nearest = []
    monkeypatch.setattr(integrator, "first_hits", lambda rs, rays: nearest.append(len(rays)) or first_hits(rs, rays))
    quick = beeoptics.look(eye, scene, seed=4, threads=1, **FAST)
    # At depth 1, only the sensors' rays are asked for their nearest hits; the scattered ones whether they meet any.
    assert nearest == [len(eye.table.id) * FAST["samples"]]
    monkeypatch.setattr(integrator, "occluded", lambda rs, rays: np.isfinite(first_hits(rs, rays)["t_hit"]))
    np.testing.assert_array_equal(quick.radiance, beeoptics.look(eye, scene, seed=4, threads=1, **FAST).radiance)
