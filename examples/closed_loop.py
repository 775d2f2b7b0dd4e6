# %% [markdown]
# # A closed loop: a bee that turns towards a flower by what it sees
#
# The Gymnasium environment `beeoptics.loop.BeeView` flies a bee's head through a scene: each step
# the agent gives a forward speed (m/s) and a turning rate (deg/s), the head moves for a tenth of a
# second, and both eyes look. This agent steers by UV–green contrast: each receptor's
# (UV − G) / (UV + G), against its median over the receptors looking below the horizon (mostly
# green leaves), is a flower's signal where it is higher; the agent turns towards the side, left or
# right, where it is stronger. Flowers whose petals reflect UV stand out so against foliage, which
# reflects little of it (Chittka et al. 1994, Vision Res 34:1489).

# %%
import sys

import numpy as np

import beeoptics
from beeoptics.loop import BeeView, Step

EYE = "tests/data/eyes/tiny/eye.yaml"  # a small test eye; eyes/worker/eye.yaml the worker
SCENE = "tests/data/scenes/flower/scene.yaml"  # one daisy-like flower with a UV bullseye, over leaves
FLOWER_M = np.array([0.12, 0.0, 0.06])  # the flower head's centre (the scene's translate_m)
REACHED_M = 0.04  # the flower head's radius (3 cm) and a centimetre
START = ([-0.10, 0.12, 0.09], 0.0)  # 12 cm to the left of the flower's line and 22 cm short of it, facing past it


# %%
def towards_uv_contrast(eye, scene, speed_m_s=0.5, gain_deg_s=3000.0):
    """A policy: from the catches (receptors, classes) to (forward speed, turning rate).

    It looks at the receptors whose axes point below the horizon by more than their acceptance
    angle, so that no sky (UV-bright, and bright in everything) enters their cones; a head that only
    turns about the vertical keeps them (the scene's pitch and roll are held). Each side's signal is
    its strongest contrast above the background's median. The speed and the gain (deg/s of turning
    for a unit of contrast between the sides) are the agent's settings for this scene, not measured
    of bees.
    """
    classes = list(eye.receptor_set.classes)
    uv, g = classes.index("UV"), classes.index("G")
    axes = eye.table.axis  # the head frame: x anterior, y left, z dorsal
    below = axes @ scene.scene.eye_rotation[2] < -np.sin(np.radians(eye.table.delta_rho_deg))
    left = axes[:, 1] > 0.0

    def act(catches):
        contrast = (catches[:, uv] - catches[:, g]) / (catches[:, uv] + catches[:, g])
        signal = contrast - np.median(contrast[below])
        turn = gain_deg_s * (signal[below & left].max() - signal[below & ~left].max())
        return np.array([speed_m_s, turn], np.float32)

    return act


def straight(catches, speed_m_s=0.5):
    """A blind policy: straight on, whatever it sees."""
    return np.array([speed_m_s, 0.0], np.float32)


def reached(step: Step):
    """The end: at the flower, or against any surface."""
    return step.met or np.linalg.norm(step.position_m - FLOWER_M) < REACHED_M


def fly(env, policy, start_m, heading_deg, seed=1):
    """An episode: the head's positions, m (steps + 1, 3)."""
    catches, info = env.reset(seed=seed, options={"position_m": start_m, "heading_deg": heading_deg})
    path = [info["position_m"]]
    done = False
    while not done:
        catches, reward, terminated, truncated, info = env.step(policy(catches))
        path.append(info["position_m"])
        done = terminated or truncated
    return np.array(path)


# %%
def main(samples=16, max_steps=20, step_nm=None):
    eye = beeoptics.load_eye(EYE)
    scene = beeoptics.load_scene(SCENE, step_nm=step_nm)
    env = BeeView(eye, scene, target_m=FLOWER_M, terminated=reached, samples=samples, depth=1,
                  max_steps=max_steps)
    paths = {name: fly(env, policy, *START) for name, policy in
             (("UV-green contrast", towards_uv_contrast(eye, scene)), ("straight", straight))}
    for name, path in paths.items():
        closest = np.linalg.norm(path - FLOWER_M, axis=1).min()
        print(f"{name}: {len(path) - 1} steps, closest {100 * closest:.1f} cm to the flower")
    return paths


# %%
if __name__ == "__main__":
    main(*map(int, sys.argv[1:2]))
