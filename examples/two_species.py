# %% [markdown]
# # Two species' views of one flower
#
# A honey-bee worker and a buff-tailed bumblebee worker (*Bombus terrestris*, the micro-CT eye of
# specimen BT_77970, Taylor et al. 2019) hover at the same place, 10 cm from one daisy of the
# generated meadow, looking at it. Each species sees it through its own eye (its facets and acceptance
# angles) and its own receptors (the honey bee's measured by Peitsch et al. 1992, the bumblebee's
# peaks by Skorupski et al. 2007): how many receptors fall on the flower, and how far its colour
# stands from the grass around it, the background each eye adapts to, in Chittka's colour hexagon,
# the space made for Hymenoptera.
#
# Run it from the repository's folder, `.venv/bin/python examples/two_species.py`, or cell by cell
# (`# %%` cells). `BEEOPTICS_EXAMPLES_SMALL=1` runs it in seconds, as the tests do: the small test eye
# twice, once with each species' receptors, by a toy meadow's flower, with few rays;
# `BEEOPTICS_EXAMPLES_OUT` is the folder the table and figure go to (`out/examples`).

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from scipy.spatial.transform import Rotation

import beeoptics
from beeoptics.headframe import direction_from_x_towards_y
from beeoptics.vision.colourspace import HEXAGON_OUTLINE

SMALL = os.environ.get("BEEOPTICS_EXAMPLES_SMALL") == "1"
if SMALL:
    # The species differ here in their receptors alone: one small eye, with each species' receptor set.
    EYES = {"honey bee": ("tests/data/eyes/tiny/eye.yaml", "apis_mellifera"),
            "bumblebee": ("tests/data/eyes/tiny/eye.yaml", "bombus_terrestris")}
    SCENE = "tests/data/scenes/meadow_tiny/scene.yaml"
    # Its "flower 1", a Senecio doronicum head: daisy.obj, of unit radius, facing +z, scaled by 0.025, turned by
    # rotate_deg and centred at translate_m.
    FLOWER_M, FLOWER_RADIUS_M = np.array([0.15, 0.0, 0.06]), 0.025
    # The colours' adapting background: the lawn around it, a surface of its albedo in the scene's light.
    BACKGROUND = "lawn"
    FLOWER_NORMAL = Rotation.from_euler("xyz", [0, -20, 0], degrees=True).apply([0.0, 0.0, 1.0])
    TRACE, STEP_NM = {"samples": 4, "depth": 1}, 20
else:
    # Each eye's own receptor set, named in its eye.yaml.
    EYES = {"honey bee": ("eyes/worker/eye.yaml", None),
            "bumblebee": ("eyes/bombus_terrestris_77970/eye.yaml", None)}
    # Its mesh is generated from scenes/meadow/meadow.yaml the first time, in some seconds.
    SCENE = "scenes/meadow/scene.yaml"
    # The specimen daisy: "its head, 4 cm across, faces up at (0.40, 0.00, 0.30) m" (scenes/meadow/meadow.yaml).
    FLOWER_M, FLOWER_RADIUS_M, FLOWER_NORMAL = np.array([0.40, 0.0, 0.30]), 0.02, np.array([0.0, 0.0, 1.0])
    # The colours' adapting background: the meadow's grass, a surface of its reflectance in the scene's light.
    BACKGROUND = "grass"
    # The configuration's rays, bounces and spectrum (config/config.yaml).
    TRACE, STEP_NM = {}, None
DISTANCE_M = 0.10
# From the front (-x), descending at 30° towards the flower, as the meadow's approach flight flies
# (scenes/meadow/flights/approach.csv), the head pitched down along the line of sight.
APPROACH_DEG = 30.0
OUT = Path(os.environ.get("BEEOPTICS_EXAMPLES_OUT", "out/examples"))
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# One scene, loaded once; each eye built once (then read from the cache); one pose for both.

# %%
scene = beeoptics.load_scene(SCENE, step_nm=STEP_NM)
along = np.radians(APPROACH_DEG)
to_flower = np.array([np.cos(along), 0.0, -np.sin(along)])
position = FLOWER_M - DISTANCE_M * to_flower
radius_deg = np.degrees(np.arctan(FLOWER_RADIUS_M / DISTANCE_M))
views = {}
for species, (path, receptors) in EYES.items():
    eye = beeoptics.load_eye(path, receptor_set=receptors)
    view = beeoptics.look(eye, scene, position_m=position, heading_deg=0.0, pitch_deg=-APPROACH_DEG, seed=1,
                          background=BACKGROUND, **TRACE)
    table = view.catches.merge(view.colour, on=["id", "side"]).merge(
        eye.receptors[["id", "delta_phi_deg"]], on="id")
    axes = direction_from_x_towards_y(table.azimuth_deg, table.elevation_deg)
    table["off_flower_deg"] = np.degrees(np.arccos(np.clip(axes @ to_flower, -1.0, 1.0)))
    # A receptor is on the flower when its axis meets the flower's head, a disc (its axis leaves the head
    # from a point within a millimetre or two of the eye's position, which the flower's centimetres dwarf).
    with np.errstate(divide="ignore", invalid="ignore"):
        reach = ((FLOWER_M - position) @ FLOWER_NORMAL) / (axes @ FLOWER_NORMAL)
    meets = position + reach[:, None] * axes
    table["on_flower"] = (reach > 0) & (np.linalg.norm(meets - FLOWER_M, axis=1) < FLOWER_RADIUS_M)
    views[species] = table
    print(eye)

# %% [markdown]
# ## The table
#
# Per species, the receptors whose axes fall on the flower (both eyes), their median interommatidial
# angle Δφ, and the mean of their colours in the hexagon: coordinates, and distance from the
# background `hex_r` (hexagon units, the corners at 1) with the mean's Monte Carlo standard error (the
# receptors' errors, independent, in quadrature over their number).

# %%
rows = {}
for species, table in views.items():
    on = table[table.on_flower]
    rows[species] = {"receptors": len(on), "delta_phi_deg": on.delta_phi_deg.median(),
                     "hex_x": on.hex_x.mean(), "hex_y": on.hex_y.mean(), "hex_r": on.hex_r.mean(),
                     "se_hex_r": np.sqrt((on.se_hex_r**2).sum()) / len(on)}
flower = pd.DataFrame(rows).T.rename_axis("species")
flower.to_csv(OUT / "two_species.csv")
print(f"the flower, {2 * radius_deg:.0f}° across at {100 * DISTANCE_M:.0f} cm:")
print(flower)

# %% [markdown]
# ## The figure
#
# Left, each species' view around the flower (its head's rim dashed), every receptor a dot coloured by its
# distance from the background in the hexagon; right, the flower's receptors in the hexagon, whose
# corners are each receptor class alone (Chittka 1992).

# %%
fig, panels = plt.subplots(1, len(views) + 1, figsize=(4.2 * (len(views) + 1), 4), layout="constrained")
window = max(3 * radius_deg, 20.0)
# The head's rim, as the eye sees it: its points' azimuth and elevation from the eye.
across = np.cross(FLOWER_NORMAL, [0.0, 1.0, 0.0])
across /= np.linalg.norm(across)
turn = np.linspace(0.0, 2 * np.pi, 73)[:, None]
sight = FLOWER_M + FLOWER_RADIUS_M * (np.cos(turn) * across + np.sin(turn) * np.cross(FLOWER_NORMAL, across)) - position
rim = np.degrees([np.arctan2(sight[:, 1], sight[:, 0]), np.arcsin(sight[:, 2] / np.linalg.norm(sight, axis=1))])
top = max(table.hex_r[table.off_flower_deg < window].max() for table in views.values())
for ax, (species, table) in zip(panels, views.items()):
    near = table[table.off_flower_deg < window]
    dots = ax.scatter(near.azimuth_deg, near.elevation_deg, c=near.hex_r, vmin=0, vmax=top, s=12, cmap="viridis")
    ax.plot(*rim, "k--", lw=1)
    ax.set_xlim(window / np.cos(along), -window / np.cos(along))
    ax.set_ylim(-APPROACH_DEG - window, -APPROACH_DEG + window)
    ax.set_title(f"{species}: {rows[species]['receptors']} receptors on the flower")
    ax.set_xlabel("azimuth (°)")
    ax.set_ylabel("elevation (°)")
fig.colorbar(dots, ax=panels[:-1], label="hexagon distance from the background, hex_r")
hexagon = panels[-1]
hexagon.plot(*np.vstack([HEXAGON_OUTLINE, HEXAGON_OUTLINE[:1]]).T, color="0.5", lw=0.8)
for species, table in views.items():
    on = table[table.on_flower]
    hexagon.scatter(on.hex_x, on.hex_y, s=12, label=species)
hexagon.plot(0, 0, "k+")
hexagon.set_aspect("equal")
hexagon.set_xlabel("hex_x")
hexagon.set_ylabel("hex_y")
hexagon.legend(loc="lower right")
hexagon.set_title("the flower in the colour hexagon")
fig.savefig(OUT / "two_species.png", dpi=150)
