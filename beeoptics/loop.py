"""A closed loop: a bee that flies by what it sees, as a Gymnasium environment.

At each step the agent chooses a forward speed and a turning rate in the
horizontal plane (and, with ``climb=True``, a vertical speed); the head
moves at those rates for one time step, kinematics only (no mass, drag or
wind), its pitch and roll the scene's own, unless the step would carry it
into a surface of the scene: then it stays where it was and the step has
*met* a surface (a ray along the step, cast into the scene's Embree scene).
Then its eyes look (:func:`beeoptics.look`): the observation is every
receptor's catch of each class, both eyes, and, with ``errors=True``,
their standard errors. Reward and termination are functions of the step
(:class:`Step`) given to the constructor: by default the metres gained
towards a target (:func:`approach`), and an end when a step meets a surface
(:func:`met_surface`); an episode is truncated after ``max_steps``.

Each look's random seed is drawn from the environment's ``np_random``, so
that ``reset(seed=…)`` and the same actions give the same observations, on
any number of threads.

>>> import gymnasium, beeoptics.loop                                  # doctest: +SKIP
>>> env = gymnasium.make("beeoptics/BeeView-v0", eye="eyes/worker/eye.yaml",
...                      scene="scenes/meadow/scene.yaml", target_m=[0.4, 0.0, 0.3])  # doctest: +SKIP
>>> catches, info = env.reset(seed=1)                                 # doctest: +SKIP
"""

import functools
from typing import NamedTuple

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from threadpoolctl import ThreadpoolController

from beeoptics.api import Eye, Scene, _config, _placed, _settings, _traced_view, load_eye, load_scene
from beeoptics.io.errors import InputError
from beeoptics.raycasting import first_hits

#: The fastest forward (and vertical) speed, m/s: the cruising speed of unloaded honey bees outdoors,
#: 7.5 m/s (Wenner 1963, J Apic Res 2:25, as Barron & Srinivasan 2006, J Exp Biol 209:978 cite it). No
#: honey bee's climbing rate was found: the vertical speed is bounded by the flight speed alone.
SPEED_MAX_M_S = 7.5
#: The time step, s: the views' frame rate along a flight (the configuration's ``flights.*.fps``, 10 a second).
STEP_S = 0.1
#: A few samples at depth 1: the first surfaces met, lit directly by the sun and the sky (``BeeView(...,
#: **LOW_FIDELITY)``); ``benchmarks/loop.py`` prints its error against the views' 16 samples: for the worker
#: in the meadow, receptor by receptor, a median difference of 10 % of the catch (UV 10.0 %, B 9.8 %, G 9.6 %)
#: and a root mean square of 84–85 %, made by a tail (at one pose, a tenth of the receptors' catches at 2 samples
#: are off those at 256 by 100 % or more; the README's "Closed loop").
LOW_FIDELITY = {"samples": 2, "depth": 1}


class Step(NamedTuple):
    """One step of the loop, as the reward and the termination see it.

    Attributes
    ----------
    position_m : ndarray (3,)
        The head's position after the step, m (world, +z up).
    heading_deg : float
        Its heading after the step, degrees from +x towards +y.
    previous_m : ndarray (3,)
        Its position before the step, m.
    met : bool
        Whether the step would have met a surface (the head then stays at ``previous_m``).
    view : View
        What it sees after the step (:class:`beeoptics.View`).
    time_s : float
        Time since the reset, s.
    """

    position_m: np.ndarray
    heading_deg: float
    previous_m: np.ndarray
    met: bool
    view: object
    time_s: float


@functools.cache
def _blas():
    """The process's BLAS libraries, found once (threadpoolctl), to be held to one thread while a loop looks."""
    return ThreadpoolController()


def approach(target_m):
    """A reward: the metres the step brought the head closer to ``target_m`` (m, (3,)); negative away."""
    target = np.asarray(target_m, float)
    return lambda step: float(np.linalg.norm(step.previous_m - target) - np.linalg.norm(step.position_m - target))


def met_surface(step):
    """A termination: the step met the ground or an object of the scene."""
    return step.met


class BeeView(gym.Env):
    """A bee's eyes in a scene, flown by an agent from what they see.

    Parameters
    ----------
    eye : Eye or str or Path
        An eye (:func:`beeoptics.load_eye`), or a file it loads from.
    scene : Scene or str or Path
        A scene (:func:`beeoptics.load_scene`), or its ``scene.yaml``.
    target_m : array_like (3,), optional
        The point the default reward (:func:`approach`) pays for approaching, m.
    reward, terminated : callable, optional
        Functions of a :class:`Step`: the step's reward (float) and whether
        the episode ends (bool). By default :func:`approach` of ``target_m``
        and :func:`met_surface`.
    samples, depth : int
        Each look's rays per receptor and scattering events per path
        (:data:`LOW_FIDELITY` the fast setting); by default the views' along
        a flight, 16 at depth 1.
    errors : bool
        Observe the catches' standard errors too: a Dict of ``catches`` and ``se``.
    climb : bool
        A third action, the vertical speed (m/s); otherwise the head keeps its height.
    step_s : float
        The time step, s.
    max_steps : int
        Steps before an episode is truncated.
    threads : int, optional
        Threads tracing each look; all cores by default. The observations do not depend on it.
    render_mode : {None, "rgb_array"}
        ``"rgb_array"``: :meth:`render` draws the last look's visual field.

    Attributes
    ----------
    observation_space : Box (receptors, classes) or Dict
        Catches per receptor (both eyes, in the eye's table's order) and class
        (the receptor set's, UV, B, G for a bee), float32, ≥ 0; a class a
        receptor lacks (a fly's mosaic) is 0. With ``errors``, ``{"catches": …, "se": …}``.
    action_space : Box (2,) or (3,)
        Forward speed, 0 to :data:`SPEED_MAX_M_S` m/s; turning rate, deg/s
        (positive towards +y, to the left), at most half a turn a step: no
        honey bee's peak yaw rate could be read here (the gap is open), and
        more than half a turn is the same as turning the other way; with
        ``climb``, the vertical speed, ±:data:`SPEED_MAX_M_S` m/s. Actions are
        clipped to it.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 1.0 / STEP_S}

    def __init__(self, eye, scene, *, target_m=None, reward=None, terminated=None, samples=16, depth=1,
                 errors=False, climb=False, step_s=STEP_S, max_steps=200, threads=None, render_mode=None):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise InputError("BeeView", "render_mode", f"{render_mode!r}: None or 'rgb_array'")
        self.render_mode = render_mode
        if reward is None and target_m is None:
            raise InputError("BeeView", "target_m", "the default reward approaches a target: give one, or a reward")
        if not (np.isfinite(step_s) and step_s > 0):
            raise InputError("BeeView", "step_s", f"{step_s!r}: a time step is a positive number of seconds")
        if int(max_steps) != max_steps or max_steps < 1:
            raise InputError("BeeView", "max_steps", f"{max_steps!r}: a whole number of steps, at least 1")
        self.eye = eye if isinstance(eye, Eye) else load_eye(eye)
        self.scene = scene if isinstance(scene, Scene) else load_scene(scene)
        self.reward = approach(target_m) if reward is None else reward
        self.terminated = met_surface if terminated is None else terminated
        self.samples, self.depth, self.errors, self.threads = samples, depth, errors, threads
        # The look's settings, checked once: a step's look only draws its seed.
        config = _config(self.scene, samples, depth, None, None, None, None, None, "BeeView")
        self._settings = _settings(config, threads, self.eye.receptor_set)
        self._colour = config["colour"]
        self.step_s, self.max_steps = float(step_s), int(max_steps)
        self.classes = list(self.eye.receptor_set.classes)
        catches = spaces.Box(0.0, np.inf, (len(self.eye.table.id), len(self.classes)), np.float32)
        self.observation_space = spaces.Dict({"catches": catches, "se": catches}) if errors else catches
        turn = 180.0 / self.step_s
        low, high = [0.0, -turn, -SPEED_MAX_M_S][:2 + climb], [SPEED_MAX_M_S, turn, SPEED_MAX_M_S][:2 + climb]
        self.action_space = spaces.Box(np.array(low, np.float32), np.array(high, np.float32))
        # The scene's own pose: where an episode starts unless reset's options say otherwise.
        forward = self.scene.scene.eye_rotation[:, 0]
        self.start_m = np.array(self.scene.scene.eye_position, float)
        self.start_heading_deg = float(np.degrees(np.arctan2(forward[1], forward[0])))

    def reset(self, *, seed=None, options=None):
        """Place the head at its start and look: (observation, info).

        Parameters
        ----------
        seed : int, optional
            Seeds the environment's ``np_random``, from which every look's trace seed is drawn.
        options : dict, optional
            ``position_m`` (m, (3,)) and ``heading_deg`` (degrees) to start from
            in place of the scene's own ``eye``.
        """
        super().reset(seed=seed)
        options = options or {}
        self._position = np.array(options.get("position_m", self.start_m), float)
        self._heading = float(options.get("heading_deg", self.start_heading_deg))
        if self._position.shape != (3,) or not np.isfinite(self._position).all():
            raise InputError("reset", "position_m", f"{options['position_m']!r}: three finite numbers, m")
        self._time = 0.0
        self._steps = 0
        observation, _ = self._look()
        return observation, self._info(False)

    def step(self, action):
        """Fly one time step at ``action``'s rates, then look: (observation, reward, terminated, truncated, info)."""
        action = np.asarray(action, float)
        if action.shape != self.action_space.shape or not np.isfinite(action).all():
            raise InputError("step", "action", f"{action!r}: {self.action_space.shape[0]} finite numbers")
        speed, turn, *climb = np.clip(action, self.action_space.low, self.action_space.high)
        # At constant speed and turning rate the head flies an arc: its chord bisects the turn, and is
        # shorter than the arc by sinc(half the turn).
        turned = np.radians(turn * self.step_s)
        along = np.radians(self._heading) + turned / 2.0
        chord = speed * self.step_s * np.sinc(turned / 2.0 / np.pi)
        move = np.array([chord * np.cos(along), chord * np.sin(along), (climb[0] if climb else 0.0) * self.step_s])
        length = np.linalg.norm(move)
        ray = np.concatenate([self._position, move / max(length, np.finfo(float).tiny)])[None].astype(np.float32)
        met = bool(length > 0.0 and first_hits(self.scene.raycasting, ray)["t_hit"][0] <= length)
        previous = self._position.copy()
        if not met:
            self._position = self._position + move
        self._heading = float((self._heading + np.degrees(turned)) % 360.0)
        self._time += self.step_s
        self._steps += 1
        observation, view = self._look()
        step = Step(self._position.copy(), self._heading, previous, met, view, self._time)
        return (observation, float(self.reward(step)), bool(self.terminated(step)), self._steps >= self.max_steps,
                self._info(met))

    def _look(self):
        """The view from the head's pose, traced with a seed drawn from ``np_random``: (observation, View),
        :func:`beeoptics.look`'s view. Whether the eye sits enclosed is asked at a reset only (a step stops
        at surfaces), and the errors are made only where observed (the view makes them when asked)."""
        placed = _placed(self.scene, {"position_m": self._position, "heading_deg": self._heading})
        # BLAS on one thread: the tracer's threads keep the cores busy, and OpenBLAS's own, woken by the
        # catches' products, would spin on after them, taking a core from the next look's trace (a quarter of
        # a low-fidelity step's CPU seconds).
        with _blas().limit(limits=1, user_api="blas"):
            view = _traced_view(self.eye, self.scene, placed,
                                self._settings._replace(seed=int(self.np_random.integers(2**31))), self._colour, 0,
                                len(self.eye.table.id), enclosure=self._steps == 0, deferred=True)
            self._view = view
            catches, se = view.class_catches(errors=self.errors)
        catches = np.nan_to_num(catches, nan=0.0).astype(np.float32)
        return ({"catches": catches, "se": np.nan_to_num(se, nan=0.0).astype(np.float32)} if self.errors
                else catches), view

    def render(self):
        """With ``render_mode="rgb_array"``, the last look's visual field of both eyes in the bee's colours
        (map3, equirectangular: azimuth +180° to −180° left to right, elevation +90° to −90° top to bottom;
        :meth:`beeoptics.View.images`), (h, w, 3) uint8, black where no receptor sees; otherwise None."""
        if self.render_mode is None:
            return None
        field = self._view.images(retina=False)["field_map3"]
        return (np.nan_to_num(field, nan=0.0) * 255.0).round().astype(np.uint8)

    def _info(self, met):
        return {"position_m": self._position.copy(), "heading_deg": self._heading, "met": met,
                "time_s": self._time}


gym.register(id="beeoptics/BeeView-v0", entry_point=BeeView)
