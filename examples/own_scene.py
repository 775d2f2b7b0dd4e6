# %% [markdown]
# # The worker's view of your own scene
#
# The honey-bee worker's two eyes placed in a scene of yours, as a table (each receptor's catches and
# colour, one row a receptor) and a figure (the visual field in Collins's map3, and the UV channel alone).
#
# Run it from the repository's folder, `.venv/bin/python examples/own_scene.py`, or cell by cell in
# an editor that runs `# %%` cells (VS Code, Spyder, PyCharm; Jupytext opens it as a notebook).
# The environment sets:
#
# - `BEEOPTICS_EXAMPLES_SCENE`: your `scene.yaml` ("Adding a scene" in the README); the patches scene
#   by default, nine coloured patches on a board in front of the bee;
# - `BEEOPTICS_EXAMPLES_SMALL=1`: a small test eye, a toy scene and few rays, seconds in all (as the
#   tests run it);
# - `BEEOPTICS_EXAMPLES_OUT`: the folder the table and the figure go to, `out/examples` by default.

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import beeoptics
from beeoptics.images.display import encode, map3
from beeoptics.io.errors import InputError

SMALL = os.environ.get("BEEOPTICS_EXAMPLES_SMALL") == "1"
EYE = "tests/data/eyes/tiny/eye.yaml" if SMALL else "eyes/worker/eye.yaml"
SCENE = os.environ.get("BEEOPTICS_EXAMPLES_SCENE",
                       "tests/data/scenes/flower/scene.yaml" if SMALL else "scenes/patches/scene.yaml")
# Small: 4 rays a receptor, direct light, a 20-nm spectrum. Else the configuration's: 256 rays, three
# bounces, 5 nm (config/config.yaml), the numbers `beeoptics render` writes.
TRACE = {"samples": 4, "depth": 1} if SMALL else {}
STEP_NM = 20 if SMALL else None
OUT = Path(os.environ.get("BEEOPTICS_EXAMPLES_OUT", "out/examples"))
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# The eye is built from its `eye.yaml` the first time (some seconds) and read from the cache after;
# the scene is loaded once. The look places the eye where the scene's `eye` section puts it; pass
# `position_m=[x, y, z]`, `heading_deg=…`, `pitch_deg=…` to place it elsewhere.

# %%
try:
    scene = beeoptics.load_scene(SCENE, step_nm=STEP_NM)
except InputError as error:
    # A scene file that cannot be used: one line naming the file and the field, rather than a traceback.
    raise SystemExit(f"error: {error}") from None
eye = beeoptics.load_eye(EYE)
view = beeoptics.look(eye, scene, seed=1, **TRACE)
print(eye, scene, sep="\n")

# %% [markdown]
# ## The table
#
# A row per receptor: its id and eye, its axis in the world (azimuth from +x towards +y, elevation
# above the horizontal, degrees), the catch of each receptor class with its Monte Carlo standard
# error, and its colour against the adapting background (the mean of the scene's receptors): the
# catches over the background's (`q_*`), the colour hexagon (`hex_x`, `hex_y`, its distance from the
# background `hex_r`), Backhaus's COC and the receptor-noise-limited distance `rnl_dS` (in
# just-noticeable differences), each with its `se_*`. The README's "What the workflow makes" gives
# every column.

# %%
table = view.catches.merge(view.colour, on=["id", "side"])
table.to_csv(OUT / "own_scene.csv", index=False)
classes = list(eye.receptor_set.classes)
print(table[["id", "side", "azimuth_deg", "elevation_deg", *classes, "hex_r", "rnl_dS"]].head())
print(table.groupby("side")[[*classes, "hex_r", "rnl_dS"]].median())

# %% [markdown]
# ## The figure
#
# Each receptor a dot at its axis' direction. Left, map3 (Collins §4.4): the receptor set's display
# classes (the worker's UV, G and B as red, green and blue), each over the background's catch, so the
# background shows grey and a flower that reflects UV shows red, the brightest 1 % of values at
# full brightness. Right,
# the UV catch alone. Azimuth increases to the left, as the scene looks from the bee.

# %%
q = table[[f"q_{k}" for k in classes]].to_numpy()
rgb = map3(q, eye.receptor_set.display)
# A receptor that caught no light has no colour: black.
colours = np.nan_to_num(encode(rgb, np.nanpercentile(rgb, 99)))
fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4), sharey=True, layout="constrained")
left.scatter(table.azimuth_deg, table.elevation_deg, c=colours, s=2, linewidths=0)
left.set_facecolor("0.85")
left.set_title("map3: UV, G, B over the background's")
# The few receptors that see the sun's disc would take the whole scale: it ends at the 99th percentile.
dots = right.scatter(table.azimuth_deg, table.elevation_deg, c=table[classes[0]], s=2, linewidths=0, cmap="magma",
                     vmax=np.nanpercentile(table[classes[0]], 99))
fig.colorbar(dots, ax=right, label=f"{classes[0]} catch (photons m⁻² s⁻¹)", extend="max")
right.set_title(f"{classes[0]} channel")
for ax in (left, right):
    ax.set_xlim(180, -180)
    ax.set_xlabel("azimuth (°)")
    ax.set_aspect("equal")
left.set_ylabel("elevation (°)")
fig.suptitle(f"{Path(EYE).parent.name} in {Path(SCENE).parent.name}")
fig.savefig(OUT / "own_scene.png", dpi=150)
